"""Ground truth of the robot's own head-camera frames in a household run.

The VQG data set renders scenes of its own; the robot asks about the frames its camera takes
in a household. :func:`household_scene` describes such a frame from the world, in the same
:class:`~perception.vqg.scene.SceneGraph` terms: every furniture item, object and person of
the scenario becomes a node (kind, colour named by the nearest palette colour, what it
stands on, pose and clothes), and the segmentation mask of the robot's camera keeps the
ones the frame shows (the data set's visibility rule). It is evaluation tooling: a run uses
it to score the questions the robot asked (``questions_grounded``) and ``companion eval vqg
--household`` to score the model; the robot itself never sees it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from core.config_files import ConfigError
from perception.vqg.config import VqgConfig
from perception.vqg.generator import VqgQuestionGenerator
from perception.vqg.questions import is_grounded, parse_question
from perception.vqg.scene import (
    ACTIVITY_MIX,
    FURNITURE,
    OBJECTS,
    PALETTE,
    ROOMS,
    Node,
    Rgb,
    SceneGraph,
    load_scene,
)
from perception.vqg.training.data_config import VisibilityConfig
from perception.vqg.training.dataset import VqgDataError, read_image
from perception.vqg.training.evaluate import Item, question_metrics
from perception.vqg.training.render import visible_graph
from sim.furnishings import FURNITURE_COLOURS, OBJECT_COLOURS
from sim.head_camera import decode_segmentation
from sim.layout import rgb
from sim.scenario import Scenario
from sim.simulation import Simulation

# objects the world loads from pybullet_data keep their own colours; "sphere" is a red ball
URDF_LOOKS = {"duck": ("duck", "yellow"), "teddy": ("teddy", "brown"), "tray": ("tray", "grey"),
              "sphere": ("ball", "red")}


def palette_name(colour: Rgb) -> str:
    """The name of the palette colour nearest to ``colour`` (RGB in [0, 1])."""
    return min(PALETTE, key=lambda name: sum((a - b) ** 2
                                             for a, b in zip(PALETTE[name], colour, strict=True)))


def _room_kind(sim: Simulation) -> str:
    """The kind of the room the robot stands in; a living room when it is no kind the
    scenes know (a corridor, a hall)."""
    x, y, _ = sim.robot.base.pose()
    for room in sim.scenario.rooms:
        if room.x[0] <= x <= room.x[1] and room.y[0] <= y <= room.y[1]:
            kind = room.kind or room.name
            return kind if kind in ROOMS else "living_room"
    return "living_room"


def world_nodes(sim: Simulation) -> tuple[list[Node], dict[str, int]]:
    """Every furniture item, object and person of the world as a node (positions relative to
    the robot), and the PyBullet body of each."""
    world, scenario = sim.world, sim.scenario
    rx, ry, _ = sim.robot.base.pose()
    nodes: list[Node] = []
    for f in scenario.furniture:
        if f.type in FURNITURE:
            colour = palette_name(rgb(f.colour or FURNITURE_COLOURS[f.type]))
            nodes.append(Node(f.name, f.type, colour, f.x - rx, f.y - ry, yaw=math.radians(f.yaw),
                              size=f.dims, support="floor"))
    for i, o in enumerate(scenario.objects):
        name = o.name or f"{o.type}_{i}"
        kind, colour = URDF_LOOKS.get(o.type, (o.type, ""))
        if o.colour is not None or not colour:
            colour = palette_name(rgb(o.colour or OBJECT_COLOURS[o.type]))
        if kind not in OBJECTS:
            continue
        pos = world.position_of(name)
        nodes.append(Node(name, kind, colour, pos[0] - rx, pos[1] - ry, pos[2],
                          support=o.on_top_of or "floor", candles=o.candles,
                          lit=o.lit and o.candles > 0))
    specs = {s.name: s for s in scenario.people}
    for name, person in world.people.items():
        looks = specs[name].body
        nodes.append(Node(name, "person", palette_name(rgb(looks.shirt)), person.x - rx,
                          person.y - ry, pose="sitting" if person.pose == "sitting" else "standing",
                          trousers=palette_name(rgb(looks.trousers)), support="floor"))
    ids = {**{n.id: world.bodies[n.id] for n in nodes if n.kind != "person"},
           **{name: person.body_id for name, person in world.people.items()}}
    return nodes, ids


def check_occasion(scenario: Scenario) -> None:
    """Raise :class:`ConfigError` unless the scenario's ``occasion`` is one the scenes know."""
    if scenario.occasion not in ACTIVITY_MIX:
        raise ConfigError(f"scenario {scenario.name!r}", [
            f"occasion: {scenario.occasion!r} is not one of {', '.join(ACTIVITY_MIX)}"])


def household_scene(sim: Simulation, visibility: VisibilityConfig
                    ) -> tuple[np.ndarray, SceneGraph]:
    """The robot's head-camera frame now and the scene graph of what it shows."""
    check_occasion(sim.scenario)
    frame, mask = sim.robot.camera.frame_with_segmentation()
    bodies, links = decode_segmentation(mask)
    nodes, ids = world_nodes(sim)
    graph = SceneGraph(_room_kind(sim), sim.scenario.occasion, nodes,
                       frame.shape[1], frame.shape[0])
    return frame, visible_graph(graph, ids, bodies, links, visibility)


def judge_question(text: str, scene: SceneGraph) -> dict[str, Any]:
    """Whether the question ``text`` is true of the frame ``scene`` describes: ``parsed``
    (the grammar reads it), ``grounded`` (everything it refers to is in the frame) and what
    the frame shows (``in_view``)."""
    frame = parse_question(text)
    return {"parsed": frame is not None,
            "grounded": frame is not None and is_grounded(frame, scene),
            "in_view": sorted({n.kind for n in scene.nodes})}


def household_items(runs: Sequence[Path], width: int, height: int) -> list[Item]:
    """The frames household runs saved with their ground truth (``frames/*.png`` with a
    ``.json`` scene graph beside; ``runs`` are run folders or folders holding them)."""
    pngs = sorted(png for root in runs for png in Path(root).glob("**/frames/*.png")
                  if png.with_suffix(".json").is_file())
    return [Item(read_image(png, width, height), load_scene(png.with_suffix(".json")), [], png)
            for png in pngs]


def evaluate_household(model: Path, cfg: VqgConfig, runs: Sequence[Path], samples: int
                       ) -> dict[str, Any]:
    """The question metrics (no BLEU: there are no reference questions) on the frames of
    household runs, with the household bars of ``eval.household_bars`` checked."""
    gen = VqgQuestionGenerator.load(model, seed=cfg.train.seed, decode=cfg.decode)
    items = household_items(runs, cfg.data.image_width, cfg.data.image_height)
    if not items:
        raise VqgDataError(f"no frames with scene graphs under {', '.join(map(str, runs))} "
                           "(household runs write them: companion bench household)")
    out = question_metrics(gen, items, samples, bleu=False)
    bars = cfg.eval.household_bars
    out["pass"] = {k: out[k] is not None and out[k] >= v for k, v in bars.items()}
    out["model"], out["runs"] = str(model), [str(r) for r in runs]
    return out
