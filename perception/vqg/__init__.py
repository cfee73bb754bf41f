"""Visual question generation: what the robot loads (tooling in ``training/``)."""
