"""``companion train mood-lm``: the bigram language model of the mood gate.

It learns from the Yelp training split of the style-transfer data (``config/style.yaml``)
and from the robot's conversational training lines (the chit-chat TRAIN split's replies and
the QA bot's answers to the intent training questions, any length), the latter counted
``bigram.conversation_repeat`` times so that conversation weighs more than its size. No line
that ``companion eval mood-style`` scores is among them.
"""

from __future__ import annotations

from pathlib import Path

from dialogue.style.config import ConversationConfig, load_style_config
from dialogue.style.mood_config import MoodStyleConfig
from dialogue.style.ngram import BigramLM
from dialogue.style.training.conversation import training_lines
from dialogue.style.training.data import load_splits

ALL_CONVERSATION = ConversationConfig(chat=True, qa=True, max_words=1000)


def train_bigram(cfg: MoodStyleConfig, out: Path) -> dict:
    """Count the bigram model into ``out``; returns what it learnt from."""
    yelp = load_splits(load_style_config().data)["train"].sentences
    talk = training_lines(ALL_CONVERSATION)
    b = cfg.bigram
    lm = BigramLM.train([*yelp, *talk * b.conversation_repeat], b.min_count, b.discount,
                        b.keep_min)
    lm.save(out)
    return {"yelp_sentences": len(yelp), "conversation_lines": len(talk),
            "vocabulary": len(lm.words), "bigrams_stored": len(lm.keys),
            "bytes": out.stat().st_size}
