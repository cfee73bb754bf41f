"""py_trees behaviours of the household run: sense, homeostasis tick, decide, act."""
