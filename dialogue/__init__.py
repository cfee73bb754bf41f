"""Dialogue manager, QA bot, chit-chat and mood-driven style transfer."""
