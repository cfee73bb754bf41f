"""``companion sweep``: many household runs spread over a Ray cluster (docs/sweeps.md)."""
