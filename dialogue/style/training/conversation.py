"""The robot's own conversational lines, for the mood style transfer.

Yelp reviews teach the transfer model sentiment but not conversation, so its training set
gets the lines the robot actually says: the reply side of the chit-chat training pairs
(Papaya and the chatterbot corpus, ``config/chat.yaml``'s split) and the QA bot's
answers to the intent training questions. The held-out lines for ``companion eval
mood-style`` come from the other side of each split: the chit-chat test and validation
replies and the QA bot's answers to the held-out routing and knowledge questions; a
held-out line that is also a training line is dropped.

Every line is in the Yelp files' form (:func:`dialogue.style.text.tokenize`). The QA bot
runs offline with a fixed clock, so its answers do not depend on when this runs.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from datetime import UTC, datetime

from dialogue.chat.config import load_chat_config
from dialogue.chat.text import detokenize as chat_detokenize
from dialogue.chat.training.data import load_chat_data
from dialogue.intent import (
    CHITCHAT,
    HELDOUT_FILE,
    TRAIN_FILE,
    IntentClassifier,
    load_utterances,
)
from dialogue.knowledge_eval import load_questions
from dialogue.qa.bot import QABot
from dialogue.style.config import ConversationConfig
from dialogue.style.text import tokenize

CLOCK_TIME = datetime(2025, 6, 1, 15, 30, tzinfo=UTC)   # the QA bot's fixed "now"


def chat_replies(split: str) -> list[str]:
    """The reply sides of one split of the chit-chat data, as readable text."""
    data = load_chat_data(load_chat_config().data)
    return [chat_detokenize(reply) for _, reply in data.splits[split]]


def qa_answers(questions: Iterable[str]) -> list[str]:
    """What the offline QA bot (fixed clock) answers to each question, routed as it would
    be (questions routed to chit-chat are skipped)."""
    bot, router = QABot.offline(clock=lambda: CLOCK_TIME), IntentClassifier.default()
    answers = []
    for question in questions:
        label = router.classify(question, "qa").label
        if label != CHITCHAT:
            answers.append(bot.answer(label, question).text)
    return answers


def _unique(lines: Iterable[str], max_words: int | None = None) -> list[list[str]]:
    """Tokenised lines with a letter, each once, at most ``max_words`` words when given."""
    seen: dict[tuple[str, ...], None] = {}
    for line in lines:
        words = tuple(tokenize(line))
        if any(c.isalpha() for w in words for c in w) and (
                max_words is None or len(words) <= max_words):
            seen.setdefault(words, None)
    return [list(w) for w in seen]


def training_lines(cfg: ConversationConfig) -> list[list[str]]:
    """The conversational training lines ``cfg`` asks for (chit-chat TRAIN replies, QA
    answers to the intent training questions), tokenised, each once."""
    lines: list[str] = []
    if cfg.chat:
        lines += chat_replies("train")
    if cfg.qa:
        lines += qa_answers(text for label, text in load_utterances(TRAIN_FILE)
                            if label != CHITCHAT)
    return _unique(lines, cfg.max_words)


def heldout_lines(limit: int, exclude: Sequence[Sequence[str]] = ()) -> list[str]:
    """Up to ``limit`` held-out robot lines as the robot says them: the chit-chat test and
    validation replies, then the QA bot's answers to the held-out routing and knowledge
    questions, alternating so both kinds are present; none is in ``exclude`` (tokenised
    training lines)."""
    banned = {tuple(w) for w in exclude}
    chat = chat_replies("test") + chat_replies("valid")
    qa = qa_answers([text for label, text in load_utterances(HELDOUT_FILE)
                     if label != CHITCHAT] + [q for _, q, _ in load_questions()])
    out: dict[tuple[str, ...], str] = {}
    for line in _interleave(chat, qa):
        words = tuple(tokenize(line))
        if words and words not in banned and any(c.isalpha() for c in line):
            out.setdefault(words, line)
    return list(out.values())[:limit]


def _interleave(a: Sequence[str], b: Sequence[str]) -> Iterable[str]:
    """``a[0], b[0], a[1], b[1], ...`` and then the rest of the longer one."""
    for i in range(max(len(a), len(b))):
        yield from (x[i] for x in (a, b) if i < len(x))
