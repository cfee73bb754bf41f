"""The VQG data set renderer, training, evaluation and ablations (not loaded by the robot)."""
