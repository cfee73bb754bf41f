"""What the robot perceives: the person-and-face detector and visual question generation."""
