"""Data, training and evaluation of the chit-chat bot (not loaded by the robot)."""
