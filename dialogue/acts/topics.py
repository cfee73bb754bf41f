"""What a line is about: the person, pet, body part, day or thing it names, how the robot
says it back ("my wife" -> "your wife", "our Susan" -> "Susan"), and the line's first clause
said back to the speaker ("my hip's playing up again" -> "your hip's playing up again").

The words of each kind are listed under ``topics`` in ``config/acts.yaml``; any other noun
(WordNet's, when it is installed) after "my", "our", "the" or "a" is a thing, and failing
that the first noun of the line. A capitalised word that does not start the line names a
person (a transcript has no capitals, so spoken names are only found after a relative:
"my daughter Susan"). "I was a teacher" names a job.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from dialogue.acts.config import TopicWords
from dialogue.qa.text import STOPWORDS, word_set
from dialogue.qa.wordnet import WordNet

WORD = re.compile(r"[A-Za-z][A-Za-z'-]*")
JOB = re.compile(r"\bi (?:was|used to be|worked as|trained as|started as) (an?) ([a-z]+)"
                 r"(?: ([a-z]+))?", re.I)
CLAUSE = re.compile(r"[.;:!?]| - | but | because | and then ", re.I)
OWNERS = {"my": "your", "our": "your", "me": "your"}   # "me mam" is "my mum"
THING_OWNERS = word_set("my our")                      # "make me sell the house"
FEELS = word_set("hurts hurt aches ache is are feels feel was were pain pains killing sore")
ARTICLES = word_set("the a an this that these those")
PRONOUNS = {"female": ("she", "her", "her"), "male": ("he", "him", "his"),
            "it": ("it", "it", "its"), "people": ("they", "them", "their")}
NOT_TOPICS = word_set("""i im i'm ive i've id i'd ill i'll you robot pip everything something
nothing anything everyone someone anyone nobody lot bit today day days time thing things way
oh well yes no dear love darling sweetheart pet please thanks thank okay ok hello hi hey
bye goodbye goodnight night morning evening afternoon sorry mr mrs ms miss dr january
february march april may june july august september october november december""")
NOT_JOBS = word_set("girl boy child kid lad lass teenager baby youngster")  # "when I was a girl"
FILLERS = word_set("well oh um uh er erm ah so now look honestly you know")
FIRST_PERSON = word_set("i i'm im i've ive i'd i'll my me our we we're we've")
STARTERS = word_set("""the a an this that these those everything everyone everybody nobody
it's there's it there his her their he she he's she's they they're""")  # sentences
REFLECT = {"i": "you", "i'm": "you're", "im": "you're", "i've": "you've", "ive": "you've",
           "i'd": "you'd", "i'll": "you'll", "my": "your", "me": "you", "mine": "yours",
           "myself": "yourself", "our": "your", "ours": "yours", "we": "you",
           "we're": "you're", "we've": "you've", "us": "you", "am": "are"}
ECHO_WORDS = 14
TAIL_WORDS = 3   # a last part after a comma this short is an aside, not said back


def reflect(text: str) -> str:
    """The first clause of ``text`` said back to its speaker ("I fell in the bathroom" ->
    "you fell in the bathroom"), or "" when it neither starts with the speaker ("I", "my",
    "we") nor is a sentence about them ("the doctor says my results are clear"), or is
    shorter than three words or longer than ``ECHO_WORDS``."""
    first = CLAUSE.split(text.replace("\u2019", "'"), maxsplit=1)[0]
    head, comma, tail = first.rpartition(",")
    if comma and len(tail.split()) <= TAIL_WORDS:
        first = head                           # "..., see you later", "..., love"
    clause = first.split()
    while clause and clause[0].lower().strip("'") in FILLERS:
        clause = clause[1:]
    first = clause[0].lower() if clause else ""
    starts = first in FIRST_PERSON or (first in STARTERS and any(
        w.lower().strip("'") in FIRST_PERSON for w in clause))
    if not 3 <= len(clause) <= ECHO_WORDS or not starts:
        return ""
    out = []
    for i, said in enumerate(clause):
        w = said.rstrip(",")
        low = w.lower()
        if w != said:
            out.append(reflect_word(clause, i, w, low) + ",")
            continue
        out.append(reflect_word(clause, i, w, low))
    return " ".join(out)


def reflect_word(clause: list[str], i: int, w: str, low: str) -> str:
    """The word ``w`` (``low`` in lower case) at ``i`` of ``clause``, said back."""
    if low == "was" and i and clause[i - 1].lower() in ("i", "we"):
        return "were"
    if low == "me" and i == 0:
        return "your"                           # "me knee's swollen"
    if low == "mine" and i and clause[i - 1].lower() in ARTICLES:
        return w                                # "down the mine"
    return REFLECT.get(low, w if w[:1].isupper() and i else low)


@dataclass(frozen=True)
class Topic:
    """What a line is about: its ``word`` as said, the ``kind`` (a key of ``topics``, or
    ``job``, ``thing``, ``any``), how the robot says it (``said``), the pronoun kind, a day
    it names (`` on Sunday``) and the line said back (``echo``, "" when it cannot be)."""

    word: str
    kind: str
    said: str
    pronoun: str = "it"
    when: str = ""
    echo: str = ""

    def slots(self) -> dict[str, str]:
        """The template slots of ``config/acts.yaml`` this topic fills."""
        they, them, their = PRONOUNS[self.pronoun]
        return {"topic": self.said, "Topic": self.said[:1].upper() + self.said[1:],
                "word": self.word, "they": they, "them": them, "their": their,
                "They": they.title(), "Their": their.title(), "when": self.when,
                "echo": self.echo}


NO_TOPIC = Topic("", "any", "that", "it")


class TopicFinder:
    """Finds the :class:`Topic` of a line; see :meth:`find`."""

    def __init__(self, words: TopicWords, wordnet: WordNet | None) -> None:
        self.kinds = {w: kind for kind in ("female", "male", "people", "pet", "body", "time")
                      for w in getattr(words, kind)}
        self.wordnet = wordnet

    def _noun(self, word: str) -> bool:
        if word in STOPWORDS or word in NOT_TOPICS or word in NOT_JOBS or len(word) < 3:
            return False
        return self.wordnet is None or bool(self.wordnet.base_forms(word, "n"))

    def _only_noun(self, word: str) -> bool:
        """A noun that is no verb, adjective or adverb ("have" and "down" are)."""
        if not self._noun(word):
            return False
        return self.wordnet is None or not any(self.wordnet.base_forms(word, pos)
                                               for pos in ("v", "a", "r"))

    def _adjective(self, word: str) -> bool:
        return self.wordnet is not None and word not in STOPWORDS \
            and bool(self.wordnet.base_forms(word, "a"))

    def find(self, text: str) -> Topic:
        """The topic of ``text`` (:data:`NO_TOPIC` when it names none)."""
        raw = WORD.findall(text.replace("\u2019", "'"))
        words = [w.lower().removesuffix("'s") for w in raw]
        day = next((w for w in words if self.kinds.get(w) == "time"
                    and w not in ("morning", "evening", "afternoon", "week", "month")), "")
        when = "" if not day else f" {day}" if day in ("tomorrow", "tonight") else \
            f" on {day.title()}" if day not in ("weekend", "birthday") else f" at the {day}"
        topic = self._topic(raw, words, day, when)
        return Topic(topic.word, topic.kind, topic.said, topic.pronoun, when, reflect(text))

    def _topic(self, raw: list[str], words: list[str], day: str, when: str) -> Topic:
        job = JOB.search(" ".join(raw))
        if job and self._noun(job.group(2).lower()):
            article, head, more = (g.lower() if g else "" for g in job.groups())
            if more and self._only_noun(more):             # "a train driver"
                head = f"{head} {more}"
            return Topic(head.split()[-1], "job", f"{article} {head}")
        for i, w in enumerate(words):
            kind = self.kinds.get(w)
            if kind in ("female", "male", "people", "pet") or (
                    kind == "body" and self._bodily(raw, words, i)):
                return self._known(raw, words, i, kind)
        name = self._name(raw, words)
        if name is not None:
            return Topic(name.lower(), "people", name, "people")
        for i, w in enumerate(words[1:], 1):
            det = i - 1
            while det > 0 and i - det <= 2 and self._adjective(words[det]):
                det -= 1                       # "these new tablets"
            if words[det] in (*THING_OWNERS, *ARTICLES) and self._noun(w) and w not in self.kinds \
                    and not self._adjective(w):
                before = words[det]
                owner = "your" if before in OWNERS else before if before in ("a", "an") \
                    else "the"
                return Topic(w, "thing", f"{owner} {self._phrase(words, i)}")
        noun = next((i for i, w in enumerate(words) if self._only_noun(w)
                     and w not in self.kinds), None)
        if noun is not None:                      # what is planned before when
            return Topic(words[noun], "thing", f"the {self._phrase(words, noun)}")
        if day:
            return Topic(day, "time", day.title() if when.startswith(" on") else day)
        return NO_TOPIC

    def _phrase(self, words: list[str], i: int) -> str:
        """The noun at ``i`` with the nouns right after it and an "of" noun ("cup of tea",
        "number nine bus")."""
        end = i + 1
        while end < len(words) and end - i < 3 and words[end] not in self.kinds and (
                self._only_noun(words[end]) or words[end].isdigit()):
            end += 1
        if end + 1 < len(words) and words[end] == "of" and self._noun(words[end + 1]):
            end += 2
        return " ".join(words[i:end])

    @staticmethod
    def _bodily(raw: list[str], words: list[str], i: int) -> bool:
        """Whether the body word at ``i`` names the body: owned ("my back", "me knee"), or
        said to hurt ("throat's sore", "knee hurts"); not "back then" nor "head down"."""
        before = words[i - 1] if i else ""
        after = words[i + 1] if i + 1 < len(words) else ""
        owned = before in OWNERS or before in ARTICLES or before in ("his", "her", "your")
        adjective_owned = i > 1 and words[i - 2] in OWNERS   # "my bad knee"
        return owned or adjective_owned or raw[i].lower().endswith("'s") or after in FEELS

    def _known(self, raw: list[str], words: list[str], i: int, kind: str) -> Topic:
        """A word of a listed kind at ``i``, with the words between its owner and it ("my
        little sister") and a name said after it ("my daughter Susan")."""
        w = words[i]
        pronoun = kind if kind in ("female", "male", "people") else \
            "people" if kind == "body" and w.endswith("s") else "it"
        start = i
        while start > 0 and i - start < 2 and words[start - 1] not in (*OWNERS, *ARTICLES) \
                and words[start - 1] not in STOPWORDS and words[start - 1].isalpha():
            start -= 1
        before = words[start - 1] if start > 0 else ""
        phrase = " ".join(words[start:i + 1]) if before in OWNERS else w
        owner = "the" if before in ARTICLES else "your"
        after = raw[i + 1] if i + 1 < len(raw) else ""
        if kind in ("female", "male") and after[:1].isupper() and after.lower() not in STOPWORDS:
            return Topic(w, kind, f"{owner} {phrase} {after}", pronoun)
        return Topic(w, kind, f"{owner} {phrase}", pronoun)

    def _name(self, raw: list[str], words: list[str]) -> str | None:
        """A capitalised word, not "I" nor a listed word, that does not start the line, or
        does but is no English word ("Margaret would have been eighty")."""
        for k, (w, low) in enumerate(zip(raw, words, strict=True)):
            base = w.removesuffix("'s")
            if (base[:1].isupper() and not base.isupper() and low not in STOPWORDS
                    and low not in NOT_TOPICS and low not in self.kinds
                    and (k > 0 or self._unknown(low))):
                return base
        return None

    def _unknown(self, word: str) -> bool:
        """Not a word of WordNet's in any part of speech (False without WordNet)."""
        return self.wordnet is not None and not any(self.wordnet.base_forms(word, pos)
                                                    for pos in ("n", "v", "a", "r"))
