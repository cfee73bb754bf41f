"""The robot's mind: the homeostasis model, its personality file and the decision policy."""
