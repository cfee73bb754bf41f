"""The simulated household on PyBullet: the world, its people and sounds, scenarios, and
the simulated robot body the robot's software drives."""
