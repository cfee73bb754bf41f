"""Questions about a VQG scene graph: normalisation, parsing to semantic frames, grounding.

* :func:`tokenize` is the one normalisation of question text (lower case, ``?`` and ``'s``
  as their own tokens, other punctuation dropped).
* :func:`parse_question` reads a question into a :class:`Frame` with the templates of
  :mod:`perception.vqg.grammar` (None when no template covers it: no question word, no final
  ``?``, repeated or unknown words). Paraphrases read to the same frame; :func:`frame_key` is
  the hashable meaning.
* :func:`is_grounded`: every thing, attribute, relation and activity the frame refers to is
  true in the graph. A question about something absent ("is there a dog ?" with no dog) is
  not grounded; the data set only asks about what is there.
* :func:`is_on_topic`: the frame is about the scene (its room, occasion or mood), or every
  noun and activity in it belongs to the scene, to its room or to its occasion
  (:func:`topic_words`), even when absent ("is there a present ?" at a birthday party).
* :func:`perception.vqg.training.facts.generate_questions` writes the data set's questions.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from perception.vqg.grammar import (
    NP,
    PARSE_ONLY_TEMPLATES,
    PERSON_NOUNS,
    TEMPLATES,
    compile_template,
    match,
)
from perception.vqg.scene import (
    ACTIVITY_MIX,
    MAIN_SURFACE,
    PALETTE,
    PARTIES,
    POSE_WORDS,
    ROOM_FURNITURE,
    SURFACE_MIX,
    TOYS,
    Node,
    SceneGraph,
)

VALUE_SLOTS = ("act", "actq", "colour", "num", "occ", "occ_time", "room", "mood")
NP_SLOTS = ("the_np", "a_np", "nps", "the_nps", "p_the", "p_pl", "p_any")
GARMENT_KINDS = ("shirt", "trousers")
SIDE_WORDS = ("left", "right", "middle")
OCCASION_THINGS = {"birthday_party": ("cake", "candle", "balloon", "present"),
                   "dance_party": ("balloon",), "playtime": TOYS}


@dataclass(frozen=True)
class Frame:
    """The meaning of a question: its kind (count, exist, colour, where, what_rel, who,
    activity, what_act, wear, lit, occasion, room, mood, why), the thing asked about
    (canonical noun, ``person``, ``shirt``/``trousers`` or empty), its colour attributes,
    a relation ``(on|near, noun)`` or ``(left|right|middle, "")`` and a value (an activity,
    colour, number, occasion, room or mood)."""

    kind: str
    target: str = ""
    attrs: tuple[str, ...] = ()
    relation: tuple[str, str] | None = None
    value: str = ""


def tokenize(text: str) -> list[str]:
    """Lower-case tokens; ``?`` and ``'s`` are tokens of their own."""
    text = text.lower().replace("\u2019", "'")
    text = re.sub(r"'s\b", " 's ", text)
    text = re.sub(r"\?", " ? ", text)
    return re.sub(r"[^a-z0-9'? ]+", " ", text).split()


@cache
def _compiled() -> list[tuple[str, list, dict[str, str]]]:
    return [(kind, compile_template(text), dict(fixed))
            for kind, text, fixed in (*TEMPLATES, *PARSE_ONLY_TEMPLATES)]


def frame_from(kind: str, fixed: dict[str, str], b: dict[str, object]) -> Frame | None:
    """The frame of a template's slot bindings (None when they do not fit together)."""
    np = next((b[k] for k in NP_SLOTS if k in b), None)
    assert np is None or isinstance(np, NP)
    garment = "garment" in b or fixed.get("target") in GARMENT_KINDS
    if garment and (np is None or np.noun != "person"):  # a garment frame has no room for "man"
        return None
    target = fixed.get("target") or str(b.get("garment", "")) or (np.noun if np else "")
    if kind in ("who", "activity", "what_act", "wear", "mood"):
        if target not in PERSON_NOUNS and target:
            return None
        target = target or "person"
    attrs = (str(b["shirt"]),) if "shirt" in b else (np.attrs if np else ())
    value = fixed.get("value") or next((str(b[k]) for k in VALUE_SLOTS if k in b), "")
    rel = b.get("rel")
    return Frame(kind, target, tuple(sorted(attrs)), rel, value)  # type: ignore[arg-type]


def parse_question(text: str) -> Frame | None:
    """The frame of a well-formed question, or None."""
    toks = tokenize(text)
    if len(toks) < 3 or toks[-1] != "?" or toks.count("?") != 1:
        return None
    for kind, pattern, fixed in _compiled():
        if pattern[0][0] != toks[0]:
            continue
        bound = match(pattern, toks)
        if bound is not None and (frame := frame_from(kind, fixed, bound)) is not None:
            return frame
    return None


def about_people(frame: Frame) -> bool:
    """Whether the question refers to a person (its target, garments or relation)."""
    related = frame.relation[1] if frame.relation else ""
    return (frame.target in PERSON_NOUNS or frame.target in GARMENT_KINDS
            or related in PERSON_NOUNS or frame.kind in ("who", "mood"))


def frame_key(frame: Frame) -> tuple:
    """Hashable meaning of a frame (for Diverse Meaning)."""
    return (frame.kind, frame.target, frame.attrs, frame.relation or (), frame.value)


def _does(n: Node, act: str) -> bool:
    if act in POSE_WORDS:
        return (n.pose == "sitting") == (act == "sitting")
    return n.activity == act or (act == "holding" and n.activity == "reading")


def _related(n: Node, rel: tuple[str, str] | None, scene: SceneGraph) -> bool:
    if rel is None:
        return True
    how, what = rel
    if how in SIDE_WORDS:
        return n.side == how
    if how == "on" and what == "floor":
        return n.support == "floor"
    anchors = [scene.node(i) for i in ([n.support] if how == "on" else [*n.near, n.support])]
    return any(a is not None and a in scene.of_kind(what) for a in anchors)


def matches(frame: Frame, scene: SceneGraph) -> list[Node]:
    """Nodes the frame's target, attributes and relation pick out."""
    target = "person" if frame.target in GARMENT_KINDS else frame.target
    nodes = scene.nodes if not target else scene.of_kind(target)
    return [n for n in nodes if all(n.colour == a for a in frame.attrs)
            and _related(n, frame.relation, scene)]


def is_grounded(frame: Frame, scene: SceneGraph) -> bool:
    """Whether everything the frame refers to is true in ``scene`` (RI)."""
    k, v = frame.kind, frame.value
    if k == "room":
        return v in ("", scene.room)
    if k == "occasion":
        cake = frame.target != "cake" or bool(scene.of_kind("cake"))
        return (cake and v in ("", scene.occasion)) or (v == "party" and scene.occasion in PARTIES)
    if k == "what_rel":
        if frame.relation is None:
            return False
        how, what = frame.relation
        anchored = how in SIDE_WORDS or what == "floor" or bool(scene.of_kind(what))
        return anchored and bool(matches(frame, scene))
    found = matches(frame, scene)
    if k in ("mood", "why") and frame.target == "person" and v in ("happy", "calm"):
        return bool(found) and scene.mood == v
    if k == "exist" and v.isdigit():
        return len(found) == int(v)
    if k == "colour" and v:
        part = "trousers" if frame.target == "trousers" else "colour"
        return any(getattr(n, part) == v for n in found)
    if k in ("lit",) or v == "lit":
        return any(n.lit for n in found)
    if v and k in ("count", "where", "who", "activity", "what_act", "why"):
        return any(_does(n, v) for n in found)
    return bool(found)


def topic_words(scene: SceneGraph) -> set[str]:
    """Nouns, activities and values that belong to the scene's topic."""
    occ = scene.occasion
    words = {n.kind for n in scene.nodes} | set(ROOM_FURNITURE[scene.room]) | set(PALETTE)
    words |= {MAIN_SURFACE[scene.room], "chair", "floor", "left", "right", "middle", "person",
              "lit", *GARMENT_KINDS, *POSE_WORDS, *ACTIVITY_MIX[occ], *SURFACE_MIX[occ],
              *OCCASION_THINGS.get(occ, ()), "holding" if "reading" in ACTIVITY_MIX[occ] else ""}
    people = set(PERSON_NOUNS) if scene.people else set()
    return words | people | ({"toy"} if words & set(TOYS) else set())


def is_on_topic(frame: Frame, scene: SceneGraph) -> bool:
    """Whether the frame is about this scene's topic (RS)."""
    if frame.kind in ("room", "occasion", "mood") or is_grounded(frame, scene):
        return True
    words = topic_words(scene)
    used = [frame.target, frame.relation[1] if frame.relation else "", frame.value]
    return all(w in words or w.isdigit() for w in used if w)
