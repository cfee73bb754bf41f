"""The household language model's corpus and estimation, and the recogniser's evaluation."""
