"""Training, evaluation and plots of the decision-making policy (not loaded by the robot)."""
