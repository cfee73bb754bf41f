"""Mood style transfer: what the robot loads (training tooling in ``training/``)."""
