"""The simulated household: the robot, the world, its people, scenarios and navigation."""
