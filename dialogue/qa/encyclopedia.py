"""Everyday knowledge from WordNet (read in place, see :mod:`dialogue.qa.wordnet`): what a
thing is, who a person was, and who made something.

"What is X" and "who was X" speak the first sentence of the gloss of X's best sense, with the
word and an article in front ("A volcano is a fissure in the earth's crust ..."): a "who"
question takes a person's sense, a "what" question any other first. "Who invented X" (or
wrote, composed, discovered, ...) looks both ways between X and the named people of WordNet:
people whose gloss names X (or a synonym of one of X's senses), and people named in the
glosses of X's senses; a cue word of the verb (invent, inventor, invention; write, writer;
"by" for works) makes a candidate stronger. Docs: docs/knowledge.md.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass
from functools import cache, cached_property

from dialogue.conversation import load_conversation_config
from dialogue.qa.text import STOPWORDS, normalise
from dialogue.qa.wordnet import PERSON, Synset, WordNet

DETERMINERS = frozenset({"a", "an", "the", "any", "one", "some", "someone", "something",
                         "anything", "all", "each", "either", "no", "two", "several", "many",
                         "various", "its", "his", "her", "their"})
PARENS = re.compile(r"\s*\([^()]*\)")
YEARS = re.compile(r"\(([^()]*\d{3,4}[^()]*)\)")
NAME_WORD = re.compile(r"[^\W\d_][\w'\u2019.-]*")
MAX_SENSES = 3  # senses of X whose synonyms or glosses the "who made X" search reads


log = logging.getLogger("companion.dialogue")


@dataclass(frozen=True)
class Fact:
    """A spoken answer and the name of what it is about."""

    text: str
    topic: str


def clean_gloss(gloss: str) -> str:
    """The gloss's first sentence (before any ';' or example), without parentheticals."""
    first = gloss.split(";")[0]
    return " ".join(PARENS.sub("", first).split()).strip(" ,.:")


def _rest(gloss: str) -> str:
    """The gloss's further sentences, after the first, without examples or parentheticals."""
    parts = [clean_gloss(p) for p in gloss.split(";")[1:] if not p.strip().startswith('"')]
    return " ".join(f"{p[0].upper()}{p[1:]}." for p in parts if p)


def article(phrase: str) -> str:
    """``phrase`` with "a" or "an" in front (by its first letter's sound, roughly)."""
    first = phrase.split()[0].lower() if phrase.split() else ""
    vowel = first[:1] in tuple("aeio") or (first[:1] == "u" and not first.startswith("uni"))
    return f"{'an' if vowel or first in ('hour', 'honest') else 'a'} {phrase}"


def _predicate(synset: Synset) -> str:
    text = clean_gloss(synset.gloss)
    words = text.split()
    if synset.instance and words and words[0].lower() not in DETERMINERS:
        text = article(text)
    return text


def _verb(synset: Synset, plural: bool) -> str:
    years = YEARS.search(synset.gloss)
    if synset.person and years and re.search(r"\d\s*-\s*\d", years.group(1)):
        return "was"
    return "are" if plural else "is"


def _person_name(synset: Synset) -> str:
    """The fullest name that ends with the headword (a surname): "Albert Einstein"."""
    head = synset.lemmas[0]
    return max((w for w in synset.lemmas if w.endswith(head)), key=len)


class Encyclopedia:
    """Answers from one WordNet database."""

    def __init__(self, wordnet: WordNet) -> None:
        self.wn = wordnet

    @staticmethod
    def shipped() -> Encyclopedia | None:
        """Over the WordNet folder of ``config/conversation.yaml``; None (with a warning
        in the log) when it is not installed."""
        folder = load_conversation_config().knowledge.wordnet_dir
        wordnet = WordNet.load(folder)
        if wordnet is None:
            log.warning("no WordNet database in %s (Debian package wordnet-base): only the "
                        "knowledge base answers questions", folder)
            return None
        return _shipped(wordnet)

    def senses(self, phrase: str, who: bool) -> list[Synset]:
        """The senses of ``phrase``, people first for a "who" question and last otherwise."""
        senses = self.wn.senses(normalise(phrase).removeprefix("the "))
        if not senses:
            return []
        people = [s for s in senses if s.lexfile == PERSON]
        others = [s for s in senses if s.lexfile != PERSON]
        return people if who else others + people

    def describe(self, phrase: str, who: bool = False, asked: str | None = None,
                 more: bool = False) -> Fact | None:
        """What ``phrase`` is (or who, for ``who``), or None when WordNet has no such sense.
        ``asked`` is how the question wrote the thing ("a volcano"), used as the subject;
        ``more`` asks for the rest of the gloss (a follow-up: "tell me more about him")."""
        senses = self.senses(phrase, who)
        if not senses:
            return None
        best = senses[0]
        if best.instance and (best.person or phrase[:1].isupper()):
            subject = _person_name(best) if best.person else best.lemmas[0]
        else:
            subject = asked or phrase
        key = normalise(phrase).removeprefix("the ")
        lemma = next((w for w in best.lemmas if normalise(w) == key), best.lemmas[0])
        if more:
            return Fact(_rest(best.gloss) or "That's all I know about it for now.", lemma)
        plural = not best.instance and key not in {normalise(w) for w in best.lemmas}
        text = f"{subject} {_verb(best, plural)} {_predicate(best)}."
        return Fact(text[0].upper() + text[1:], lemma)

    def who_made(self, cue: str, phrase: str) -> Fact | None:
        """Who ``cue`` (a verb such as "invented", or an agent noun such as "author") the
        thing called ``phrase``, or None when no named person fits."""
        cues = self.cue_words(cue)
        senses = self.senses(phrase, who=False)[:MAX_SENSES]
        scores: dict[int, tuple[float, Synset]] = {}

        def credit(person: Synset, score: float) -> None:
            if person.offset not in scores or scores[person.offset][0] < score:
                scores[person.offset] = (score, person)

        for rank, sense in enumerate(senses):  # people named in the thing's glosses
            gloss = f" {normalise(sense.gloss)} "
            cued = " by " in gloss or any(f" {c} " in gloss for c in cues)
            if sense.person and any(f" {c} " in gloss for c in cues):
                credit(sense, 2.0 - 0.1 * rank)  # named after its maker: braille, Braille
            for person, possessive in self.named_people(sense.gloss):
                if person != sense:  # "by Shakespeare", "Shakespeare's tragedy": its maker
                    credit(person, (2.0 if cued or possessive else 1.0) - 0.1 * rank)
        names = [normalise(phrase).removeprefix("the ")]
        names += [normalise(lemma) for s in senses for lemma in s.lemmas]
        for rank, name in enumerate(dict.fromkeys(names)):  # people whose gloss names it
            for person in self.people_mentioning(name):
                gloss = set(normalise(person.gloss).split())
                credit(person, (2.0 if gloss & cues else 1.0) - (0.05 if rank else 0.0))
        if not scores:
            return None
        score, person = max(scores.values(), key=lambda v: v[0])
        if score < 1.5:  # named without any cue of making it: not an answer to "who made"
            return None
        text = f"That was {_person_name(person)}, {_predicate(person)}."
        return Fact(text, _person_name(person))

    def cue_words(self, cue: str) -> frozenset[str]:
        """The words that say "made it" for ``cue``: the verb's forms, its synonyms and the
        nouns WordNet derives from it (invent: invented, devise, inventor); for an agent noun
        (author), its synonyms and the verbs they come from."""
        cue = normalise(cue)
        words = {cue}
        verbs = set(self.wn.base_forms(cue, "v"))
        for sense in self.wn.senses(cue)[:1]:
            words |= {normalise(w) for w in sense.lemmas}
            for lemma in sense.lemmas:
                verbs |= {v for t, v in self.wn.related(sense, "+", lemma) if t.pos == "v" and v}
        for verb in verbs:
            words |= self.wn.inflections(verb)
            for sense in self.wn.senses(verb, "v"):
                for synonym in sense.lemmas:  # develop: formulated
                    words |= self.wn.inflections(normalise(synonym))
                words |= {normalise(n) for t, n in self.wn.related(sense, "+", verb)
                          if t.pos == "n" and n}
        return frozenset(w for w in words if w and w not in STOPWORDS)

    @cached_property
    def _people(self) -> tuple[dict[str, list[Synset]], dict[str, set[int]], dict[int, Synset]]:
        """(name -> people, gloss word -> people, offset -> person), built on first use."""
        by_name: dict[str, list[Synset]] = {}
        by_word: dict[str, set[int]] = {}
        by_offset: dict[int, Synset] = {}
        for person in self.wn.people():
            by_offset[person.offset] = person
            for lemma in person.lemmas:
                by_name.setdefault(normalise(lemma), []).append(person)
            for word in set(normalise(person.gloss).split()) - STOPWORDS:
                by_word.setdefault(word, set()).add(person.offset)
        return by_name, by_word, by_offset

    def named_people(self, gloss: str) -> list[tuple[Synset, bool]]:
        """The people a gloss names, written with capitals ("by William Shakespeare",
        "Shakespeare's tragedy"), longest names first, each name once, with whether the name
        is in the possessive; a one-word name that is also an adjective ("French") is taken
        as the adjective."""
        by_name = self._people[0]
        found_raw = NAME_WORD.findall(gloss)
        raw = [re.sub(r"['\u2019]s$", "", w) for w in found_raw]
        words = [normalise(w) for w in raw]
        found: list[tuple[Synset, bool]] = []
        used: set[int] = set()
        for n in range(4, 0, -1):
            for i in range(len(words) - n + 1):
                span = set(range(i, i + n))
                name = " ".join(words[i:i + n])
                if (name in by_name and not used & span and raw[i][:1].isupper()
                        and raw[i + n - 1][:1].isupper()
                        and (n > 1 or not self.wn.offsets(name, "a"))):  # "French" painter
                    found.append((by_name[name][0], raw[i + n - 1] != found_raw[i + n - 1]))
                    used |= span
        return found

    def people_mentioning(self, name: str) -> list[Synset]:
        """People whose gloss contains the words of ``name`` in a row (or its plural)."""
        _, by_word, by_offset = self._people
        words = name.split()
        ids = set.intersection(*(by_word.get(w, set()) for w in words)) if words else set()
        out = []
        for offset in sorted(ids):
            gloss = f" {normalise(by_offset[offset].gloss)} "
            if f" {name} " in gloss or f" {name}s " in gloss:
                out.append(by_offset[offset])
        return out


@cache
def _shipped(wordnet: WordNet) -> Encyclopedia:
    return Encyclopedia(wordnet)  # one index of people per process
