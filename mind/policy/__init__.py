"""Decision making: the Dueling Double DQN the robot loads (training tooling in ``training/``)."""
