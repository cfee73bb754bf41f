"""The facing model's rendered crops, training and evaluation (not loaded by the robot)."""
