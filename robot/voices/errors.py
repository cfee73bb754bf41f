"""The error of every voice engine."""


class VoiceError(ValueError):
    """A voice an engine does not have, or a sentence it could not say."""
