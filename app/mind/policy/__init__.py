"""Decision making: the abstract training environment, the Dueling Double DQN and baselines."""
