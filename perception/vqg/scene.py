"""Scene graphs of the visual-question-generation (VQG) renders, and the household vocabulary.

A :class:`SceneGraph` says what one rendered head-camera frame shows: the room type, the
occasion (the scene's topic), and one :class:`Node` per visible furniture item, small object,
candle and person, with its colour name, what it stands or sits on, which furniture it is
near, which third of the image it is in, and (people) pose, clothes and activity. Colours are
drawn from :data:`PALETTE`, so a node's colour name is the colour it was rendered with.
:mod:`perception.vqg.training.layout` draws the scenes and
:mod:`perception.vqg.training.render` renders them.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

Rgb = tuple[float, float, float]

PALETTE: dict[str, Rgb] = {
    "red": (0.85, 0.12, 0.12), "green": (0.15, 0.6, 0.2), "blue": (0.15, 0.3, 0.85),
    "yellow": (0.95, 0.85, 0.15), "orange": (0.95, 0.5, 0.1), "purple": (0.55, 0.2, 0.7),
    "pink": (0.95, 0.55, 0.7), "white": (0.93, 0.93, 0.93), "black": (0.1, 0.1, 0.1),
    "brown": (0.5, 0.3, 0.15), "grey": (0.55, 0.55, 0.55),
}
FURNITURE = ("table", "coffee_table", "cake_table", "chair", "armchair", "sofa", "shelf",
             "plant", "tv", "bed")
OBJECTS = ("mug", "plate", "book", "ball", "cake", "candle", "duck", "teddy", "tray",
           "balloon", "present", "block")
TOYS = ("duck", "teddy", "ball", "block")
SEATS = ("chair", "armchair", "sofa")
SURFACES = ("table", "coffee_table", "cake_table")
ACTIVITIES = ("eating", "sitting", "dancing", "celebrating", "reading", "talking",
              "watching_tv", "playing")
POSE_WORDS = ("standing", "sitting")

ROOMS = ("living_room", "dining_room", "bedroom", "party_room")
# occasions that can happen in each room
ROOM_OCCASIONS: dict[str, tuple[str, ...]] = {
    "living_room": ("quiet_afternoon", "reading_time", "dance_party", "birthday_party",
                    "playtime"),
    "dining_room": ("family_dinner", "tea_time", "birthday_party"),
    "bedroom": ("reading_time", "playtime", "quiet_afternoon"),
    "party_room": ("birthday_party", "dance_party"),
}
PARTIES = ("birthday_party", "dance_party")
FESTIVE = ("birthday_party", "dance_party", "family_dinner")  # everyone looks happy


@dataclass
class Node:
    """One visible thing. ``support`` is the id of what it stands or sits on (``floor`` for
    the floor, empty when held or floating); ``near`` lists ids of furniture next to it."""

    id: str
    kind: str
    colour: str
    x: float
    y: float
    z: float = 0.0
    yaw: float = 0.0
    size: tuple[float, ...] = ()
    support: str = ""
    near: list[str] = field(default_factory=list)
    side: str = ""          # left, middle or right third of the image (mask centroid)
    distance: float = 0.0   # m from the robot on the floor
    pixels: int = 0         # visible pixels in the frame
    pose: str = ""          # people: standing, sitting or arms_raised
    activity: str = ""      # people: one of ACTIVITIES
    trousers: str = ""      # people: trousers colour (``colour`` is the shirt)
    candles: int = 0        # cakes: visible candles
    lit: bool = False       # cakes and candles: flames on

    @property
    def category(self) -> str:
        """``person``, ``furniture`` or ``object``."""
        if self.kind == "person":
            return "person"
        return "furniture" if self.kind in FURNITURE else "object"


@dataclass
class SceneGraph:
    """Everything a question may refer to in one frame."""

    room: str
    occasion: str
    nodes: list[Node] = field(default_factory=list)
    width: int = 320
    height: int = 240

    @property
    def mood(self) -> str:
        """``happy`` for festive occasions, else ``calm``."""
        return "happy" if self.occasion in FESTIVE else "calm"

    def node(self, node_id: str) -> Node | None:
        """The node with this id, or None."""
        return next((n for n in self.nodes if n.id == node_id), None)

    def of_kind(self, kind: str) -> list[Node]:
        """Nodes of one kind (``toy`` and ``furniture`` name groups of kinds)."""
        if kind == "toy":
            return [n for n in self.nodes if n.kind in TOYS]
        if kind == "furniture":
            return [n for n in self.nodes if n.category == "furniture"]
        return [n for n in self.nodes if n.kind == kind]

    @property
    def people(self) -> list[Node]:
        """The visible people."""
        return self.of_kind("person")

    def to_dict(self) -> dict:
        """A JSON-ready dict."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> SceneGraph:
        """Inverse of :meth:`to_dict`."""
        nodes = [Node(**{**n, "size": tuple(n.get("size", ())), "near": list(n.get("near", []))})
                 for n in data.get("nodes", [])]
        return cls(data["room"], data["occasion"], nodes, data.get("width", 320),
                   data.get("height", 240))

    def to_json(self) -> str:
        """Compact JSON text."""
        return json.dumps(self.to_dict(), separators=(",", ":"))


def load_scene(path: str | Path) -> SceneGraph:
    """Read a scene graph written by :func:`perception.vqg.training.data.write_vqg_dataset`."""
    return SceneGraph.from_dict(json.loads(Path(path).read_text(encoding="utf-8")))


# what the people of each occasion do (relative weights)
ACTIVITY_MIX: dict[str, dict[str, float]] = {
    "birthday_party": {"celebrating": 4, "dancing": 2, "talking": 2, "eating": 2},
    "dance_party": {"dancing": 7, "talking": 3},
    "family_dinner": {"eating": 8, "talking": 2},
    "tea_time": {"eating": 3, "talking": 4, "sitting": 3},
    "quiet_afternoon": {"sitting": 3, "watching_tv": 3, "reading": 3, "talking": 1},
    "reading_time": {"reading": 8, "sitting": 2},
    "playtime": {"playing": 6, "sitting": 2, "talking": 2},
}


# small objects on the surfaces (relative weights)
SURFACE_MIX: dict[str, dict[str, float]] = {
    "birthday_party": {"plate": 3, "mug": 3, "present": 2, "tray": 1},
    "dance_party": {"mug": 6, "tray": 2, "plate": 2},
    "family_dinner": {"plate": 4, "mug": 4, "tray": 2},
    "tea_time": {"mug": 5, "plate": 3, "tray": 2},
    "quiet_afternoon": {"mug": 4, "book": 4, "plate": 1, "tray": 1},
    "reading_time": {"book": 7, "mug": 3},
    "playtime": {"duck": 2, "teddy": 2, "ball": 1, "block": 3},
}


MAIN_SURFACE = {"living_room": "coffee_table", "dining_room": "table", "bedroom": "coffee_table",
                "party_room": "table"}


ROOM_FURNITURE = {"living_room": ("sofa", "armchair", "tv", "plant", "shelf"),
                  "dining_room": ("chair", "shelf", "plant"),
                  "bedroom": ("bed", "shelf", "chair", "plant"),
                  "party_room": ("sofa", "chair", "plant")}
