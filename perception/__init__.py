"""Rendering helpers, the person/face detector and visual question generation."""
