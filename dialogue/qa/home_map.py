"""Map category: a top-down render of the household with the asked room or object marked,
or a city's (or landmark's) coordinates.

The household is plain data, so any caller can build it::

    rooms = [{"name": "living_room", "x": [0, 6], "y": [0, 5]}]
    items = [{"name": "sofa", "x": 3.0, "y": 4.45, "kind": "furniture", "type": "sofa"},
             {"name": "mug_0", "x": 2.8, "y": 3.25, "kind": "object", "type": "mug",
              "on": "coffee_table"},
             {"name": "Grace", "x": 1.05, "y": 3.0, "kind": "person"}]

``kind`` is ``furniture``, ``object``, ``person``, ``dock`` or ``robot`` (default
``object``); ``type`` and ``on`` (the furniture it stands on) are optional.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from dialogue.qa.base import Answer
from dialogue.qa.places import find_place
from dialogue.qa.text import normalise, strip_frame

SYNONYMS = {"tv": ["television", "telly"], "dock": ["charger", "charging station",
            "charging dock"], "teddy": ["teddy bear"], "sofa": ["couch", "settee"],
            "shelf": ["bookshelf", "bookcase", "shelves"], "plant": ["pot plant", "houseplant"],
            "cake_table": ["cake table"], "mug": ["cup"], "bed": ["my bed"]}
MAP_FRAMES = [r"where (?:is|are|was|can i find)", r"where's", r"show me(?: where)?",
              r"how do i get to", r"location of", r"find", r"map of", r"on the map"]
PX_PER_M = 60
MARGIN = 50
COLOURS = {"furniture": (150, 150, 150), "object": (200, 120, 40), "person": (60, 160, 60),
           "dock": (0, 140, 255), "robot": (160, 60, 160)}


@dataclass(frozen=True)
class Household:
    """Rooms (``name``, ``x``, ``y`` extents) and items (``name``, ``x``, ``y``, ...)."""

    rooms: list[dict[str, Any]]
    items: list[dict[str, Any]]

    def room_of(self, x: float, y: float) -> dict[str, Any] | None:
        """The room containing the point, if any."""
        return next((r for r in self.rooms
                     if r["x"][0] <= x <= r["x"][1] and r["y"][0] <= y <= r["y"][1]), None)

    def find(self, text: str) -> dict[str, Any] | None:
        """The room or item a sentence names (longest name wins; items before rooms)."""
        t = f" {normalise(text)} "
        best: tuple[int, int, dict[str, Any]] | None = None
        for rank, thing in [(1, i) for i in self.items] + [(0, r) for r in self.rooms]:
            for name in _names(thing):
                if f" {name} " in t and (best is None or (len(name), rank) > best[:2]):
                    best = (len(name), rank, thing)
        return best[2] if best else None


def _names(thing: dict[str, Any]) -> set[str]:
    raw = [thing["name"], thing.get("type") or ""]
    raw += [s for key in raw for s in SYNONYMS.get(key, [])]
    names = {normalise(n.replace("_", " ")) for n in raw if n}
    names |= {n.rstrip("0123456789 ") for n in names}
    return {n for n in names if n}


def _label(name: str) -> str:
    return name.replace("_", " ")


def plan_from_scenario(scenario: Any) -> Household:
    """The household of an ``sim.scenario.Scenario`` as plain data (people at their start)."""
    furniture = {f.name: f for f in scenario.furniture}
    rooms = [{"name": r.name, "x": list(r.x), "y": list(r.y)} for r in scenario.rooms]
    items = [{"name": f.name, "x": f.x, "y": f.y, "kind": "furniture", "type": f.type}
             for f in scenario.furniture]
    for i, o in enumerate(scenario.objects):
        base = furniture.get(o.on_top_of) if o.on_top_of else None
        x = o.x if o.x is not None else base.x  # type: ignore[union-attr]
        y = o.y if o.y is not None else base.y  # type: ignore[union-attr]
        items.append({"name": o.name or f"{o.type}_{i}", "x": x, "y": y, "kind": "object",
                      "type": o.type, "on": o.on_top_of})
    items.append({"name": "dock", "x": scenario.dock.x, "y": scenario.dock.y, "kind": "dock",
                  "type": "dock"})
    items += [{"name": p.name, "x": p.start.x, "y": p.start.y, "kind": "person"}
              for p in scenario.people if p.start is not None]
    return Household(rooms, items)


def render_plan(rooms: list[dict[str, Any]], items: list[dict[str, Any]], path: str | Path,
                mark: str | None = None) -> Path:
    """Draw the household from above (north up) as a PNG, ``mark`` (a name) highlighted."""
    xs = [v for r in rooms for v in r["x"]] + [i["x"] for i in items]
    ys = [v for r in rooms for v in r["y"]] + [i["y"] for i in items]
    x0, y0, x1, y1 = min(xs), min(ys), max(xs), max(ys)
    w, h = int((x1 - x0) * PX_PER_M) + 2 * MARGIN, int((y1 - y0) * PX_PER_M) + 2 * MARGIN
    img = np.full((h, w, 3), 255, np.uint8)

    def px(x: float, y: float) -> tuple[int, int]:
        return int(MARGIN + (x - x0) * PX_PER_M), int(h - MARGIN - (y - y0) * PX_PER_M)

    font = cv2.FONT_HERSHEY_SIMPLEX
    for r in rooms:
        fill = (170, 235, 255) if r["name"] == mark else (225, 235, 240)
        a, b = px(r["x"][0], r["y"][1]), px(r["x"][1], r["y"][0])
        cv2.rectangle(img, a, b, fill, -1)
        cv2.rectangle(img, a, b, (60, 60, 60), 2)
        cv2.putText(img, _label(r["name"]), (a[0] + 6, a[1] + 18), font, 0.5, (60, 60, 60), 1)
    for it in items:
        c = px(it["x"], it["y"])
        kind = it.get("kind", "object")
        colour = COLOURS.get(kind, COLOURS["object"])
        if kind == "furniture":
            cv2.rectangle(img, (c[0] - 7, c[1] - 7), (c[0] + 7, c[1] + 7), colour, -1)
        else:
            cv2.circle(img, c, 5, colour, -1)
        if kind in ("furniture", "person", "dock") and it["name"] != mark:
            cv2.putText(img, _label(it["name"]), (c[0] + 9, c[1] + 4), font, 0.38, colour, 1)
        if it["name"] == mark:
            cv2.circle(img, c, 16, (0, 0, 230), 3)
            cv2.putText(img, _label(it["name"]), (c[0] + 18, c[1] + 5), font, 0.55,
                        (0, 0, 200), 2)
    for k, (kind, colour) in enumerate(COLOURS.items()):
        cv2.circle(img, (12 + 95 * k, h - 14), 5, colour, -1)
        cv2.putText(img, kind, (22 + 95 * k, h - 10), font, 0.4, (60, 60, 60), 1)
    cv2.arrowedLine(img, (w - 25, 40), (w - 25, 15), (0, 0, 0), 2, tipLength=0.4)
    cv2.putText(img, "N", (w - 30, 55), font, 0.5, (0, 0, 0), 1)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(path), img):
        raise OSError(f"could not write {path}")
    return path


def _part(value: float, low: float, high: float, names: tuple[str, str]) -> str:
    f = (value - low) / max(high - low, 1e-9)
    return names[0] if f < 1 / 3 else names[1] if f > 2 / 3 else ""


def _where_in(x: float, y: float, room: dict[str, Any]) -> str:
    ns = _part(y, *room["y"], ("south", "north"))
    ew = _part(x, *room["x"], ("west", "east"))
    side = f"{ns}-{ew}" if ns and ew else ns or ew
    return f"in the {side} of" if side else "in the middle of"


def _osm(lat: float, lon: float) -> str:
    return f"https://www.openstreetmap.org/?mlat={lat:.4f}&mlon={lon:.4f}#map=12/{lat:.4f}/{lon:.4f}"


def _coords(lat: float, lon: float) -> str:
    return (f"{abs(lat):.2f} degrees {'north' if lat >= 0 else 'south'}, "
            f"{abs(lon):.2f} degrees {'east' if lon >= 0 else 'west'}")


def answer_map(text: str, household: Household | None, out_dir: Path,
               landmarks: Any = None) -> Answer:
    """Mark the asked room or object on a map of the house, or give a place's coordinates.

    ``landmarks`` is anything with ``find(text)`` returning an entry with ``title``,
    ``lat`` and ``lon`` (the knowledge base).
    """
    thing = household.find(text) if household else None
    if household and thing:
        name = thing["name"]
        path = render_plan(household.rooms, household.items,
                           Path(out_dir) / f"map_{normalise(name).replace(' ', '_')}.png",
                           mark=name)
        if "x" in thing and not isinstance(thing["x"], list):
            room = household.room_of(thing["x"], thing["y"])
            on = f"on the {_label(thing['on'])} " if thing.get("on") else ""
            where = (f"{on}{_where_in(thing['x'], thing['y'], room)} the "
                     f"{_label(room['name'])}" if room else "outside the rooms")
            kind = _label(thing.get("type") or name)
            what = name if thing.get("kind") == "person" else f"The {kind}"
            text_out = f"{what} is {where}. I've marked it on the map."
        else:
            text_out = f"Here is the {_label(name)}; I've marked it on the map of the house."
        spoken = name if thing.get("kind") == "person" else thing.get("type") or name
        return Answer(text_out, tablet=str(path), topic=_label(spoken))
    whole = strip_frame(text, MAP_FRAMES) in {"", "map", "plan"} or re.search(
        r"\b(?:house|home|flat|apartment|floor plan)\b", normalise(text))
    if household and whole:
        path = render_plan(household.rooms, household.items, Path(out_dir) / "map_house.png")
        rooms = ", ".join(_label(r["name"]) for r in household.rooms)
        return Answer(f"Here is the map of the house: {rooms}.", tablet=str(path),
                      topic="house")
    place, unknown = find_place(text)
    if place:
        country = f", in {place.country}" if place.country else ""
        return Answer(f"{place.name} is at {_coords(place.latitude, place.longitude)}{country}.",
                      tablet=_osm(place.latitude, place.longitude), topic=place.name)
    entry = landmarks.find(text) if landmarks is not None else None
    if entry is not None and entry.lat is not None:
        return Answer(f"{entry.title} is at {_coords(entry.lat, entry.lon)}.",
                      tablet=_osm(entry.lat, entry.lon), topic=entry.title)
    asked = unknown or strip_frame(text, MAP_FRAMES) or "that"
    if household is None:
        return Answer(f"I'm sorry, I have no map of this house, and I don't know a place "
                      f"called {asked}.", found=False)
    return Answer(f"I'm sorry, I can't find {asked} on my map.", found=False)
