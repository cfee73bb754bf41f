"""The seq2seq chit-chat bot: what the robot loads (training tooling in ``training/``)."""
