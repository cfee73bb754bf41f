"""Simulated users with hidden tastes, and how fast and safely the robot adapts to them."""
