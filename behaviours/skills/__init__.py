"""One skill subtree per action; each module exposes ``build(ctx)``, which only builds the
subtree (cheap); the tree's ``setup()`` does each behaviour's one-time work."""
