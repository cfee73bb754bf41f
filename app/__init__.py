"""companion: an autonomous social companion robot with moods."""

__version__ = "0.1.0"
