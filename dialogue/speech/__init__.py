"""Speech recognition: pocketsphinx with the household language model (docs/speech.md)."""
