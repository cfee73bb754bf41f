"""The detector's rendered data set, training, export and evaluation (not loaded by the robot)."""
