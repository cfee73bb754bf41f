"""Which way a person faces, from a crop of their box: what the robot loads (tooling in
``training/``)."""
