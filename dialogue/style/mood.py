"""``MoodStyler``: say a reply in the robot's mood without losing its meaning or grammar.

The style-transfer model proposes a styled reply; the gate accepts it only when

(a) the sentiment judge (the TextCNN classifier) puts it on the mood's side,
(b) it keeps at least ``gate.min_content_kept`` of the unstyled reply's *content words*
    (words with a letter that are not stop words: sentiment words count too, so trading
    "thank" for "disappointed" is a loss), and
(c) its bigram perplexity is at most ``gate.max_perplexity_ratio`` times the unstyled
    reply's (a language model that knows conversation, :mod:`dialogue.style.ngram`), and
    every word pair it has that the reply did not was counted at least
    ``gate.min_new_bigram_count`` times in that model's data ("I am a great trained to
    chat" has "great trained", which neither reviews nor conversation say),

and, with ``gate.keep_questions``, a question stays a question ("Where have you been?" must
not become "Always have you been!": every word of it is a stop word, so (b) cannot see it),
and it has as many numbers as the reply (put back as the reply wrote them).

Otherwise the robot says the unstyled reply after an opening of the mood ("Sadly, ..."),
and with a closing of the mood too when no opening alone convinces the judge (both lists
in ``config/mood_style.yaml``), except where such a phrase would contradict the
reply: a reply with a word of ``fallback.contrary`` (an apology in a cheerful mood, thanks
in a gloomy one), or a question unless ``fallback.questions``, is said as it is (``kept``),
and not offered to the model either, whose rewrite would turn its meaning round ("I
apologize, but..." became "I love, but..."). A reply the judge already puts
on the mood's side is said unchanged. Each result says where its text came from (:data:`SOURCES`).
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Sequence
from dataclasses import dataclass

import torch

from core.torch_threads import torch_threads
from dialogue.style.config import CLASSIFIER_FILE, STYLE_FILE
from dialogue.style.files import STOPWORDS, load_classifier
from dialogue.style.mood_config import BIGRAM_FILE, MoodStyleConfig, load_mood_config
from dialogue.style.nets import SentimentClassifier
from dialogue.style.ngram import BOS, EOS, BigramLM
from dialogue.style.text import NUMBER, STYLES, numbers, tokenize
from dialogue.style.transfer import StyleTransfer, readable
from textnets.batch import make_batch
from textnets.vocab import Vocab

SOURCES = ("model", "fallback", "kept", "unchanged")
_OPENERS_TEXT = ("yes no okay ok well sure nothing hey sorry thanks thank please oh hmm maybe "
                 "because good great fine pretty really although let")
OPENERS = frozenset(_OPENERS_TEXT.split())   # first words that start no name
_HAS_LETTER = re.compile(r"[a-z]")


@dataclass(frozen=True)
class MoodReply:
    """What to say, where it came from (``model``, ``fallback`` or ``unchanged``), the
    model's candidate (readable; "" when it was not decoded), why the candidate was refused
    (None when said or not needed) and the figures of ``text`` against the unstyled reply."""

    text: str
    source: str
    candidate: str
    reason: str | None
    judged: str
    content_kept: float
    perplexity_ratio: float


def content_words(words: Sequence[str]) -> set[str]:
    """Words with a letter that are not stop words."""
    return {w for w in words if _HAS_LETTER.search(w) and w not in STOPWORDS}


def content_kept(source: Sequence[str], output: Sequence[str]) -> float:
    """Share of the source's content words that the output has (1.0 when it has none)."""
    content = content_words(source)
    return len(content & set(output)) / len(content) if content else 1.0


def with_numbers(words: Sequence[str], written: Sequence[str]) -> list[str]:
    """The words with each ``_num_`` replaced by the reply's numbers as written, in order."""
    pending = list(written)
    return [pending.pop(0) if w == NUMBER and pending else w for w in words]


def with_opening(opening: str, text: str) -> str:
    """``text`` after ``opening``. Its first word is lowered only when it is a stop word or a
    common opener ("The", "Yes", "Okay"), never "I": any other capital may start a name."""
    lower = next(iter(tokenize(text)), "")
    if (lower in STOPWORDS or lower in OPENERS) and lower != "i":
        text = text[:1].lower() + text[1:]
    return f"{opening} {text}".strip()


def capital_i(text: str) -> str:
    """The pronoun "i" written "I" (the model writes lower case): "i'm" -> "I'm"."""
    return re.sub(r"\bi\b", "I", text)


class MoodStyler:
    """The gate around :class:`StyleTransfer` (module docstring); ``translate`` makes it a
    drop-in style for :class:`dialogue.manager.DialogueManager`."""

    def __init__(self, transfer: StyleTransfer, judge: SentimentClassifier, judge_vocab: Vocab,
                 lm: BigramLM, cfg: MoodStyleConfig) -> None:
        self.transfer, self.judge, self.judge_vocab = transfer, judge.eval(), judge_vocab
        self.lm, self.cfg = lm, cfg

    @classmethod
    def load(cls, cfg: MoodStyleConfig | None = None) -> MoodStyler:
        """The models of ``cfg.model_dir``; a missing or bad file raises a ``UserError``."""
        cfg = cfg or load_mood_config()
        folder = cfg.resolved_model_dir()
        judge, vocab, _ = load_classifier(folder / CLASSIFIER_FILE)
        return cls(StyleTransfer.load(folder / STYLE_FILE), judge, vocab,
                   BigramLM.load(folder / BIGRAM_FILE), cfg)

    @torch.no_grad()
    def side(self, words: Sequence[str]) -> str:
        """The judge's verdict on a tokenised sentence: "negative" or "positive"."""
        with torch_threads(1):
            batch = make_batch([self.judge_vocab.encode(words)], [0])
            return STYLES[int(self.judge(batch).argmax(1)[0])]

    def ratio(self, source: Sequence[str], output: Sequence[str]) -> float:
        """Bigram perplexity of ``output`` over that of ``source``."""
        return self.lm.perplexity(output) / self.lm.perplexity(source)

    def unseen_bigrams(self, source: Sequence[str], words: Sequence[str]
                       ) -> list[tuple[str, str]]:
        """The word pairs of ``words`` that ``source`` does not have and that the bigram
        model saw fewer than ``gate.min_new_bigram_count`` times."""
        had = set(itertools.pairwise([BOS, *source, EOS]))
        return [p for p in itertools.pairwise([BOS, *words, EOS]) if p not in had
                and self.lm.seen(*p) < self.cfg.gate.min_new_bigram_count]

    def refusal(self, source: Sequence[str], words: Sequence[str], mood: str) -> str | None:
        """Why the gate refuses the styled ``words`` (None when it accepts them)."""
        if not words:
            return "the model wrote nothing"
        if self.side(words) != mood:
            return f"the judge does not find it {mood}"
        if words.count(NUMBER) != source.count(NUMBER):
            return "it does not have the reply's numbers"
        if self.cfg.gate.keep_questions and ("?" in source) != ("?" in words):
            return "a question would become a statement, or a statement a question"
        kept = content_kept(source, words)
        if kept < self.cfg.gate.min_content_kept:
            return (f"it keeps {kept:.0%} of the content words, fewer than "
                    f"{self.cfg.gate.min_content_kept:.0%}")
        if unseen := self.unseen_bigrams(source, words):
            return f"it says {' '.join(unseen[0])!r}, never seen in conversation or reviews"
        ratio = self.ratio(source, words)
        if ratio > self.cfg.gate.max_perplexity_ratio:
            return (f"its perplexity is {ratio:.2f}x the unstyled reply's, more than "
                    f"{self.cfg.gate.max_perplexity_ratio:.2f}x")
        return None

    def style(self, text: str, mood: str) -> MoodReply:
        """``text`` said in ``mood`` ("positive" or "negative"), through the gate."""
        if mood not in STYLES:
            raise ValueError(f"mood must be one of {STYLES}, got {mood!r}")
        source = tokenize(text)
        judged = self.side(source) if source else mood
        if judged == mood or not any(_HAS_LETTER.search(w) for w in source):
            return MoodReply(text, "unchanged", "", None, judged, 1.0, 1.0)
        if clash := self.contradicted(source, mood):   # the model would flip its meaning
            return MoodReply(text, "kept", "", clash, judged, 1.0, 1.0)
        result = self.transfer.translate_detailed([text], mood)[0]
        words = result.transferred.split()
        candidate = capital_i(readable(with_numbers(words, numbers(text)), text)) if words else ""
        why = self.refusal(source, words, mood) if words else result.reason
        if why is None:
            return MoodReply(candidate, "model", candidate, None, mood,
                             content_kept(source, words), self.ratio(source, words))
        said = self.fallback(text, mood)
        said_words = tokenize(said)
        return MoodReply(said, "fallback", candidate, why, self.side(said_words),
                         content_kept(source, said_words), self.ratio(source, said_words))

    def contradicted(self, words: Sequence[str], mood: str) -> str | None:
        """Why a phrase of ``mood`` before or after the reply ``words`` would contradict it
        (None when it would not): a question, with ``fallback.questions`` off, or a word of
        ``fallback.contrary`` for the mood ("sorry" in a cheerful mood)."""
        if not self.cfg.fallback.questions and "?" in words:
            return "a mood phrase does not go with a question"
        said = f" {' '.join(words)} "
        hit = next((c for c in getattr(self.cfg.fallback.contrary, mood)
                    if f" {' '.join(tokenize(c))} " in said), None)
        return None if hit is None else f"a {mood} phrase would contradict {hit!r}"

    def fallback(self, text: str, mood: str) -> str:
        """The unstyled reply after an opening of ``mood``: the most fluent of those that put
        the judge on the mood's side; when none does, the most fluent opening-and-closing
        pair that does; failing that too, the most fluent opening."""
        openings = [with_opening(o, text) for o in getattr(self.cfg.openings, mood)]
        closed = [f"{o} {c}" for o in openings for c in getattr(self.cfg.closings, mood)]
        for options in (openings, closed):
            flipping = [o for o in options if self.side(tokenize(o)) == mood]
            if flipping:
                return self.most_fluent(flipping)
        return self.most_fluent(openings)

    def most_fluent(self, options: Sequence[str]) -> str:
        """The option of the lowest bigram perplexity."""
        return min(options, key=lambda o: self.lm.perplexity(tokenize(o)))

    def translate(self, sentences: Sequence[str], to: str) -> list[str]:
        """Each sentence said in the ``to`` mood (the ``StyleTransfer`` protocol)."""
        return [self.style(s, to).text for s in sentences]
