"""The questions of the VQG data set: true frames of a scene graph, written out by templates.

:func:`facts` lists grounded frames of a graph (counts, colours, existence, places,
relations, what the people do and wear, the occasion, the room, the mood and why).
:func:`realise` writes one frame with one template, choosing synonyms, determiners and
fillers at random; a realisation is kept only when :func:`parse_question` reads it back to
the same frame. :func:`generate_questions` picks frames round-robin over their kinds and a few
paraphrases of each.
"""

from __future__ import annotations

import zlib
from collections import defaultdict
from dataclasses import dataclass

import numpy as np

from perception.vqg.grammar import (
    ACTQ,
    ACTS,
    COLOURS,
    FILLERS,
    GARMENTS,
    MOODS,
    NEAR,
    NOUNS,
    NUMBERS,
    OCCASION_TIMES,
    OCCASIONS,
    ROOM_WORDS,
    SIDES,
    TEMPLATES,
    compile_template,
)
from perception.vqg.questions import (
    GARMENT_KINDS,
    NP_SLOTS,
    OCCASION_THINGS,
    VALUE_SLOTS,
    Frame,
    frame_key,
    is_grounded,
    matches,
    parse_question,
    tokenize,
)
from perception.vqg.scene import PARTIES, SURFACES, TOYS, Node, SceneGraph


def _inverse(table: dict[str, str]) -> dict[str, list[str]]:
    out: dict[str, list[str]] = defaultdict(list)
    for surface, canonical in table.items():
        out[canonical].append(surface)
    return out


_WORDS = {name: _inverse(t) for name, t in (
    ("act", ACTS), ("actq", ACTQ), ("occ", OCCASIONS), ("occ_time", OCCASION_TIMES),
    ("room", ROOM_WORDS), ("mood", MOODS),
    ("colour", COLOURS), ("garment", GARMENTS))}
_WORDS["num"] = _inverse({k: v for k, v in NUMBERS.items() if v != "0"})
_SIDE_WORDS = _inverse(SIDES)
PRONOUN_CHOICES = {"p_the": ("everyone", "everybody"), "p_pl": ("they", "the people"),
                   "p_any": ("anyone", "someone", "anybody", "somebody")}
PLURAL_SLOTS = ("nps", "the_nps", "p_pl")
Rng = np.random.Generator


@dataclass(frozen=True)
class Style:
    """How a scene may be talked about: plural forms for a single thing (only in counting and
    existence questions), ``guest`` for a person (parties only)."""

    plural: bool = True
    guests: bool = True


def _pick(rng: Rng, options: list[str] | tuple[str, ...]) -> str:
    return options[int(rng.integers(len(options)))]


def _np(slot: str, frame: Frame, rng: Rng, with_attrs: bool, style: Style) -> str | None:
    noun = "person" if frame.target in GARMENT_KINDS else frame.target
    if not noun or (slot.startswith("p_") and noun != "person"):
        return None
    plural = slot in ("nps", "the_nps", "p_pl")
    attrs = frame.attrs if with_attrs else ()
    if slot.startswith("p_") and not attrs and frame.target not in GARMENT_KINDS \
            and rng.random() < 0.5:
        return _pick(rng, PRONOUN_CHOICES[slot])
    det = "" if slot == "nps" else "a" if slot in ("a_np", "p_any") else "the"
    words = [det] if det else []
    if attrs and noun != "person":
        words.append(attrs[0])
    nouns = NOUNS[noun][plural]
    words.append(_pick(rng, nouns if style.guests or noun != "person" else nouns[:1]))
    if attrs and noun == "person":
        wearing = "wearing" + ("" if plural else " a")
        lead = "in the" if not with_attrs or rng.random() < 0.5 else wearing
        words.append(f"{lead} {attrs[0]} shirt" + ("s" if plural else ""))
    return " ".join(words)


def _relation(frame: Frame, rng: Rng) -> str | None:
    if frame.relation is None:
        return None
    how, what = frame.relation
    if what == "":
        return _pick(rng, _SIDE_WORDS[how])
    noun = "ground" if what == "floor" and rng.random() < 0.3 else \
        "floor" if what == "floor" else _pick(rng, NOUNS[what][0])
    if how == "on":
        tops = ("on", "on top of") if what != "floor" and frame.target != "person" else ("on",)
        return _pick(rng, tops) + " the " + noun
    leads = [w for w in NEAR if w != "at" or what in SURFACES] + ["in front of"]
    return f"{_pick(rng, leads)} the {noun}"


def _slot(name: str, frame: Frame, rng: Rng, with_attrs: bool, style: Style) -> str | None:
    if name in NP_SLOTS:
        return _np(name, frame, rng, with_attrs, style)
    if name == "rel":
        return _relation(frame, rng)
    if name == "fill":
        return _pick(rng, FILLERS) if rng.random() < 0.3 else None
    if name == "shirt":
        return frame.attrs[0] if frame.attrs else None
    key = frame.target if name == "garment" else frame.value
    options = _WORDS[name].get(key)
    return _pick(rng, options) if options else None


def realise(kind: str, text: str, fixed: dict[str, str], frame: Frame, rng: Rng,
            style: Style = Style()) -> str | None:
    """``frame`` written with one template, or None when the template cannot say it."""
    if kind != frame.kind or any(getattr(frame, f) != v for f, v in fixed.items()):
        return None
    pattern = compile_template(text)
    slots = {name for name, is_slot, _ in pattern if is_slot}
    if not style.plural and kind not in ("count", "exist") and slots & set(PLURAL_SLOTS):
        return None
    if (frame.relation and "rel" not in slots) \
            or (frame.attrs and not slots & {*NP_SLOTS, "shirt"}) \
            or (frame.value and "value" not in fixed and not slots & set(VALUE_SLOTS)):
        return None
    words = []
    for name, is_slot, optional in pattern:
        with_attrs = "shirt" not in slots and "wearing" not in text
        part = _slot(name, frame, rng, with_attrs, style) if is_slot else name
        if part is None and not optional:
            return None
        words += part.split() if part else []
    for i, w in enumerate(words[:-1]):
        if w in ("a", "an"):
            words[i] = "an" if words[i + 1][0] in "aeiou" else "a"
    out = " ".join(words)
    return out if parse_question(out) == frame else None


def _rels(n: Node, scene: SceneGraph) -> set[tuple[str, str]]:
    out = {(n.side, "")} if n.side else set()
    support = scene.node(n.support)
    if n.support == "floor" or support is not None:
        out.add(("on", "floor" if support is None else support.kind))
    return out | {("near", f.kind) for i in n.near if (f := scene.node(i)) is not None}


def _acts(n: Node) -> set[str]:
    return {n.activity, "sitting" if n.pose == "sitting" else "standing"}


def facts(scene: SceneGraph) -> list[Frame]:
    """Grounded frames about ``scene``."""
    out: set[Frame] = set()
    F = Frame  # noqa: N806
    kinds = {n.kind for n in scene.nodes if n.kind != "person"}
    if kinds & set(TOYS):
        kinds.add("toy")
    for k in kinds:
        nodes = scene.of_kind(k)
        why = k in OCCASION_THINGS.get(scene.occasion, ())
        for rel in [None, *{r for n in nodes for r in _rels(n, scene)}]:
            out |= {F("count", k, (), rel), F("exist", k, (), rel), F("colour", k, (), rel),
                    F("what_rel", "", (), rel)} | ({F("why", k, (), rel)} if why else set())
        out |= {F("where", k), F("lit", k), F("why", k, (), None, "lit")}
        if len(nodes) > 1:
            out.add(F("exist", k, (), None, str(len(nodes))))
        for c in {n.colour for n in nodes}:
            out |= {F("count", k, (c,)), F("exist", k, (c,)), F("where", k, (c,)),
                    F("colour", k, (), None, c)}
    people = scene.people
    for n in people:
        acts = _acts(n)
        for rel in [None, *_rels(n, scene)]:
            for attrs in [(), (n.colour,)]:
                out |= {F("activity", "person", attrs, rel), F("wear", "person", attrs, rel),
                        F("count", "person", attrs, rel), F("where", "person", attrs),
                        F("exist", "person", attrs, rel)}
                out |= {F(kind, "person", attrs, rel, a) for a in acts
                        for kind in ("activity", "count", "who")}
                out.add(F("why", "person", attrs, rel, n.activity))
            out |= {F("colour", g, (), rel, c) for g, c in (("shirt", n.colour),
                                                           ("trousers", n.trousers))}
            out |= {F("colour", g, (), rel) for g in GARMENT_KINDS} | {F("who", "person", (), rel)}
        out |= {F("what_act", "person", (), None, a) for a in acts | {"holding"}}
        out |= {F("where", "person", (), None, a) for a in acts}
    if people:
        out |= {F("exist", "person", (), None, str(len(people)))} if len(people) > 1 else set()
        out |= {F("mood", "person"),
                F("mood", "person", (), None, scene.mood), F("why", "person", (), None, "happy")}
    out |= {F("occasion"), F("occasion", "", (), None, scene.occasion), F("room"),
            F("room", "", (), None, scene.room), F("occasion", "cake", (), None, "birthday_party")}
    if scene.occasion in PARTIES:
        out.add(F("occasion", "", (), None, "party"))
    return sorted((f for f in out if is_grounded(f, scene)), key=repr)


def _seeded(*key: object) -> Rng:
    return np.random.default_rng(zlib.crc32(repr(key).encode()))


def wordings(frame: Frame, style: Style, rng: Rng, n: int, fixed: bool) -> list[str]:
    """Up to ``n`` distinct texts of ``frame``. Random ones from ``rng``; or, when ``fixed``,
    the texts of the first templates, in an order seeded by the meaning alone, that can say
    it in this ``style``, each with synonyms seeded by the meaning and the template, so that
    a meaning reads the same in every scene that allows that template."""
    if not fixed:
        texts = {t for kind, text, slots in TEMPLATES
                 if (t := realise(kind, text, dict(slots), frame, rng, style)) is not None}
        picked = sorted(texts)
        return [picked[i] for i in rng.permutation(len(picked))[:n]]
    key = frame_key(frame)
    out: list[str] = []
    for i in _seeded(key).permutation(len(TEMPLATES)):
        kind, text, slots = TEMPLATES[i]
        t = realise(kind, text, dict(slots), frame, _seeded(key, int(i)), style)
        if t is not None and t not in out:
            out.append(t)
            if len(out) == n:
                break
    return out


def generate_questions(scene: SceneGraph, rng: Rng, max_frames: int, paraphrases: int,
                       max_questions: int, fixed_wording: bool = False) -> list[str]:
    """Tokenised questions about ``scene``: up to ``max_frames`` frames, drawn round-robin over
    the frame kinds, each written ``paraphrases`` ways at most (see :func:`wordings`)."""
    by_kind: dict[str, list[Frame]] = defaultdict(list)
    for f in facts(scene):
        by_kind[f.kind].append(f)
    queues = [[q[i] for i in rng.permutation(len(q))] for _, q in sorted(by_kind.items())]
    questions: list[str] = []
    chosen = 0
    while chosen < max_frames and any(queues) and len(questions) < max_questions:
        for queue in queues:
            if not queue or chosen >= max_frames:
                continue
            frame = queue.pop()
            style = Style(len(matches(frame, scene)) != 1, scene.occasion in PARTIES)
            texts = wordings(frame, style, rng, paraphrases, fixed_wording)
            if texts:
                chosen += 1
                questions += [" ".join(tokenize(t)) for t in texts]
    return questions[:max_questions]
