"""Data, training and evaluation of the style transfer (not loaded by the robot)."""
