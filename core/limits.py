"""Bounds every parser shares, so that a number accepted on the command line is accepted in
a YAML file and the other way round."""

MAX_DURATION_S = 7 * 24 * 3600.0   # a simulated week: longer runs are refused, not run for ever
SEED_MAX = 2**32 - 1               # numpy's and PyBullet's seeds are 32-bit
