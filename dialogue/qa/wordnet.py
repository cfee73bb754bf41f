"""A reader of the WordNet 3.0 database files, read in place from the folder the Debian
package ``wordnet-base`` installs (``/usr/share/wordnet``): noun and verb synsets with their
lemmas, glosses and pointers, and WordNet's own rules for plural and past forms.

The files are parsed once per process, when the first question needs them (about a second);
nothing is copied into the project or downloaded.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cache, lru_cache
from pathlib import Path
from typing import BinaryIO

FILES = {"n": "noun", "v": "verb", "a": "adj", "r": "adv"}
PERSON = 18  # lexicographer file noun.person
NOUN_RULES = (("ses", "s"), ("xes", "x"), ("zes", "z"), ("ches", "ch"), ("shes", "sh"),
              ("men", "man"), ("ies", "y"), ("s", ""))
VERB_RULES = (("ies", "y"), ("es", "e"), ("es", ""), ("ed", "e"), ("ed", ""), ("ing", "e"),
              ("ing", ""), ("s", ""))
ADJ_RULES = (("er", ""), ("est", ""), ("er", "e"), ("est", "e"))
RULES = {"n": NOUN_RULES, "v": VERB_RULES, "a": ADJ_RULES}  # WordNet's own (morphy)


@dataclass(frozen=True)
class Pointer:
    """A link from a synset (or one of its lemmas) to another synset (or one of its lemmas)."""

    symbol: str   # "@" hypernym, "@i" instance of, "+" derivationally related, ...
    offset: int
    pos: str      # "n", "v", "a", "r" ("s", a satellite adjective, is not followed)
    source: int   # 0: the whole synset, else the 1-based lemma number
    target: int


@dataclass(frozen=True)
class Synset:
    """One sense: its lemmas as written (spaces for underscores), gloss and pointers."""

    offset: int
    pos: str
    lexfile: int
    lemmas: tuple[str, ...]
    gloss: str
    pointers: tuple[Pointer, ...]

    @property
    def instance(self) -> bool:
        """Whether this is a named individual (a person, a place, a work), not a kind."""
        return any(p.symbol == "@i" for p in self.pointers)

    @property
    def person(self) -> bool:
        """Whether this is a named person."""
        return self.instance and self.lexfile == PERSON


def _parse(line: str, pos: str) -> Synset:
    head, _, gloss = line.partition(" | ")
    f = head.split()
    n_words = int(f[3], 16)
    lemmas = tuple(f[4 + 2 * i].replace("_", " ") for i in range(n_words))
    lemmas = tuple(w.rsplit("(", 1)[0] if w.endswith(")") else w for w in lemmas)  # adj. marks
    at = 4 + 2 * n_words
    pointers = []
    for i in range(int(f[at])):
        sym, off, p, st = f[at + 1 + 4 * i: at + 5 + 4 * i]
        pointers.append(Pointer(sym, int(off), p, int(st[:2], 16), int(st[2:], 16)))
    return Synset(int(f[0]), pos, int(f[1]), lemmas, gloss.strip(), tuple(pointers))


def _line_after(fh: BinaryIO, pos: int) -> bytes:
    """The first whole line of ``fh`` that starts at or after byte ``pos``."""
    fh.seek(max(pos - 1, 0))
    if pos:
        fh.readline()
    return fh.readline()


class WordNet:
    """Noun and verb synsets of a WordNet 3.0 database folder, read where they lie: a synset's
    offset is its byte position in ``data.<pos>``, and ``index.<pos>`` is sorted, so a lemma
    is found by binary search. Only the irregular forms are held in memory."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.exceptions: dict[str, dict[str, str]] = {}
        for pos, name in FILES.items():
            exc: dict[str, str] = {}
            with (folder / f"{name}.exc").open(encoding="utf-8") as fh:
                for line in fh:
                    f = line.split()
                    if len(f) >= 2:
                        exc.setdefault(f[0].replace("_", " "), f[1].replace("_", " "))
            self.exceptions[pos] = exc

    @staticmethod
    @cache
    def load(folder: str | Path) -> WordNet | None:
        """The database in ``folder`` (opened once per process), or None when it is missing."""
        path = Path(folder)
        if not all((path / f"{kind}.{name}").is_file() for name in FILES.values()
                   for kind in ("data", "index")):
            return None
        return WordNet(path)

    @lru_cache(maxsize=4096)  # noqa: B019 - one database per process, see load
    def synset(self, pos: str, offset: int) -> Synset:
        """The synset at ``offset`` of ``data.<pos>``."""
        with (self.folder / f"data.{FILES[pos]}").open("rb") as fh:
            fh.seek(offset)
            return _parse(fh.readline().decode("utf-8"), pos)

    @lru_cache(maxsize=4096)  # noqa: B019
    def offsets(self, lemma: str, pos: str = "n") -> tuple[int, ...]:
        """The synset offsets of ``lemma`` (lower case), most common sense first."""
        key = lemma.replace(" ", "_").encode("utf-8")
        with (self.folder / f"index.{FILES[pos]}").open("rb") as fh:
            lo, hi = 0, fh.seek(0, 2)
            while lo < hi:  # the first position whose next line's lemma is not before key
                mid = (lo + hi) // 2
                line = _line_after(fh, mid)
                if line and line.split(b" ", 1)[0] < key:
                    lo = mid + 1
                else:
                    hi = mid
            f = _line_after(fh, lo).split()
        return tuple(int(o) for o in f[-int(f[2]):]) if f and f[0] == key else ()

    def base_forms(self, word: str, pos: str = "n") -> list[str]:
        """The lemmas ``word`` (lower case) may be a form of: itself, an irregular form's
        base, then WordNet's suffix rules; only lemmas the database has."""
        candidates = [word, self.exceptions[pos].get(word)]
        for suffix, repl in RULES.get(pos, ()):
            if word.endswith(suffix) and len(word) > len(suffix) + 1:
                candidates.append(word[: len(word) - len(suffix)] + repl)
        out: list[str] = []
        for c in candidates:
            if c and c not in out and self.offsets(c, pos):
                out.append(c)
        return out

    def inflections(self, verb: str) -> set[str]:
        """The forms of ``verb``: regular endings and the irregular forms WordNet lists."""
        irregular = {f for f, base in self.exceptions["v"].items() if base == verb}
        stem = verb[:-1] if verb.endswith("e") else verb
        sibilant = verb.endswith(("s", "x", "z", "ch", "sh", "o"))
        forms = {verb, f"{verb}es" if sibilant else f"{verb}s", f"{stem}ing"}
        return forms | (irregular or {f"{stem}ed"})

    def senses(self, phrase: str, pos: str = "n") -> list[Synset]:
        """The senses of ``phrase`` (lower case; plural or inflected forms too), most common
        first."""
        out: list[Synset] = []
        for lemma in self.base_forms(phrase, pos):
            out += [s for s in (self.synset(pos, o) for o in self.offsets(lemma, pos))
                    if s not in out]
        return out

    def related(self, synset: Synset, symbol: str, lemma: str | None = None
                ) -> Iterator[tuple[Synset, str | None]]:
        """Synsets linked from ``synset`` by ``symbol``, with the linked lemma for lexical
        links (None for whole-synset ones); ``lemma`` keeps only the links of that lemma."""
        number = (synset.lemmas.index(lemma) + 1) if lemma in synset.lemmas else None
        for p in synset.pointers:
            if p.symbol != symbol or p.pos not in ("n", "v", "a"):
                continue
            if lemma is not None and p.source not in (0, number):
                continue
            target = self.synset(p.pos, p.offset)
            yield target, (target.lemmas[p.target - 1] if p.target else None)

    def people(self) -> Iterator[Synset]:
        """Every named person (a pass over ``data.noun``: about 0.1 s)."""
        with (self.folder / "data.noun").open(encoding="utf-8") as fh:
            for line in fh:
                if line[9:12] == f"{PERSON} " and " @i " in line.partition(" | ")[0]:
                    yield _parse(line, "n")
