"""What people share with the robot, and the robot's own replies to it (docs/conversation.md)."""
