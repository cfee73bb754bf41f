"""The robot's own software, apart from any simulator: geometry on the floor, the map and
paths on it, what its sensors report (percepts, laser scans, recordings), its voice and
its dances. A real robot would run these unchanged; ``sim/`` implements the body they
drive."""
