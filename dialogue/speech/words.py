"""Text as the recogniser's words: lower case, numbers spelt out, punctuation gone.

The language model is estimated on these words and word error rates compare them, so a
written "101" and a recognised "one hundred and one" are the same words.
"""

from __future__ import annotations

import re

from num2words import num2words

NUMBER = re.compile(r"\d+")
WORD = re.compile(r"[a-z]+(?:'[a-z]+)*")


def spoken_words(text: str) -> list[str]:
    """The words of ``text`` as they are said: ``"It's 5 o'clock!"`` -> ``["it's", "five",
    "o'clock"]``."""
    text = text.lower().replace("\u2019", "'")
    text = NUMBER.sub(lambda m: f" {num2words(int(m.group()))} ", text)
    return WORD.findall(text)
