"""One skill subtree per action; each module exposes ``build(house)``."""
