"""A look at a heard line before the robot answers it: a line of symbols, one far too long,
one in another script or one made of words nobody knows gets a short honest reply instead of
a guess from chit-chat.

Known words are WordNet's lemmas (any part of speech, any inflected form; nouns only where
WordNet writes them in lower case, so abbreviations and names such as "Es" or "VA" are not
words of a sentence), the function
words of :data:`dialogue.qa.text.STOPWORDS`, a few words of conversation from
``config/conversation.yaml`` and names (capitalised words after the first). A line
whose letters are mostly of a script other than Latin is not English; a Latin-script line
of mostly unknown words is not understood (gibberish such as "asdf qwer", or another
language; said so as "not English" when it carries accented letters).
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass

from dialogue.conversation import InputCheckConfig, load_conversation_config
from dialogue.qa.text import STOPWORDS, normalise
from dialogue.qa.wordnet import WordNet

REPLIES = {
    "no_words": "I didn't catch any words there.",
    "too_long": "That's a lot at once. Could you tell me in a shorter way?",
    "not_english": "I only speak English, I'm afraid.",
    "not_understood": "Sorry, I didn't understand those words. Could you say it another way?",
}
CLITIC = re.compile(r"(?:'s|'m|'re|'ll|'ve|'d|n't)$")
RAW_WORD = re.compile(r"[^\W_]+(?:['\u2019][^\W_]+)?")


@dataclass(frozen=True)
class Unclear:
    """Why a line is not answered as said, and what the robot says instead."""

    reason: str  # a key of REPLIES

    @property
    def text(self) -> str:
        """The robot's reply."""
        return REPLIES[self.reason]

    @property
    def route(self) -> str:
        """The reply's route in logs: ``input_<reason>``."""
        return f"input_{self.reason}"


class InputCheck:
    """Checks one line at a time; see :meth:`check`."""

    def __init__(self, config: InputCheckConfig, wordnet: WordNet | None) -> None:
        self.config = config
        self.wordnet = wordnet
        self.extra = frozenset(normalise(w) for w in config.extra_words)

    @classmethod
    def default(cls) -> InputCheck:
        """With the packaged settings and the installed WordNet (without WordNet only the
        script, length and no-words checks run)."""
        config = load_conversation_config()
        return cls(config.input_check, WordNet.load(config.knowledge.wordnet_dir))

    def check(self, said: str) -> Unclear | None:
        """Why ``said`` (a cleaned, non-empty line) should not be answered as it is, or None."""
        letters = [c for c in said if c.isalpha()]
        if not letters and not any(c.isdigit() for c in said):
            return Unclear("no_words")
        foreign = sum(not unicodedata.name(c, "").startswith("LATIN") for c in letters)
        if letters and foreign / len(letters) > self.config.max_foreign_letters:
            return Unclear("not_english")
        raw = RAW_WORD.findall(said)
        if len(raw) > self.config.max_words:
            return Unclear("too_long")
        if self.wordnet is None or not raw:
            return None
        known = sum(self.known(w) or (i > 0 and w[:1].isupper()) for i, w in enumerate(raw))
        if known / len(raw) >= self.config.min_known_share:
            return None
        accented = any(not c.isascii() for c in letters)
        return Unclear("not_english" if accented else "not_understood")

    def known(self, word: str) -> bool:
        """Whether ``word`` is an English word the robot knows (or a number)."""
        w = normalise(word).replace(" ", "")
        if not w or w.isdigit() or w in STOPWORDS or w in self.extra:
            return True
        w = CLITIC.sub("", w) or w
        if w in STOPWORDS or w in self.extra:
            return True
        wn = self.wordnet
        if wn is None:
            return False
        if any(wn.base_forms(w, pos) for pos in ("v", "a", "r")):
            return True
        # a noun written in lower case somewhere: "ca" (Ca, calcium) and "es" (Es) are not
        return any(base in s.lemmas for base in wn.base_forms(w) for s in wn.senses(base))
