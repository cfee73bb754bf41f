"""The person-and-face detector: what the robot loads (tooling in ``training/``)."""
