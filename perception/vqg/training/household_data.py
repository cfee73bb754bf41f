"""Household frames for the VQG data set: the shipped worlds seen by the robot's own camera.

The rendered scenes of :mod:`perception.vqg.training.data` look at a table from a little
above; in a run the robot looks up at the faces of the people it talks to, sees them close
up, and stands anywhere in a room of the shipped worlds. This module renders such frames:
each run of a world (``household.frames_per_run`` frames) plays the scenario forward
(people enter, walk, sit) and at each moment puts the robot down at free places. A share
of the frames frame one person close up, from the side their face is on, with the head
pitched at the face; the rest stand anywhere with the head pitch of a search or a rest.
The ground truth is the same as for a household run's saved frame
(:func:`perception.vqg.training.household.household_scene`), so the questions come from
the same grammar. Frames are written as ``h``-prefixed ids into the data set's split
folders; a run whose frames all exist is skipped, so writing resumes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import closing
from pathlib import Path

import numpy as np

from perception.vqg.scene import SceneGraph
from perception.vqg.training.data_config import SPLITS, HouseholdConfig, VqgDataConfig
from perception.vqg.training.frames_io import frame_done, questions_for, write_frame
from perception.vqg.training.household import household_scene
from sim.scenario import load_scenario
from sim.simulation import Simulation
from sim.world import World

Frame = tuple[np.ndarray, SceneGraph]


def _free(world: World, x: float, y: float, clearance: float) -> bool:
    """Whether the robot's centre at ``(x, y)`` is inside a room and clear of every wall,
    furniture item, object, the dock and every person by ``clearance``."""
    inside = any(x0 + clearance <= x <= x1 - clearance and y0 + clearance <= y <= y1 - clearance
                 for x0, y0, x1, y1 in world.house.room_bounds().values())
    return inside and not any(f.contains(x, y, clearance)
                              for f in world.obstacles(include_people=True))


def _room_pose(sim: Simulation, hh: HouseholdConfig, rng: np.random.Generator) -> bool:
    """Put the robot at a free place of a random room, any heading, a search or rest head."""
    rooms = list(sim.world.house.room_bounds().values())
    for _ in range(hh.attempts):
        x0, y0, x1, y1 = rooms[rng.integers(len(rooms))]
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        if _free(sim.world, x, y, hh.clearance_m):
            sim.robot.base.set_pose(x, y, rng.uniform(-math.pi, math.pi))
            sim.robot.joints.set_positions({"HeadPitch": rng.uniform(*hh.head_pitch),
                                           "HeadYaw": rng.uniform(*hh.head_yaw)})
            return True
    return False


def _person_pose(sim: Simulation, hh: HouseholdConfig, rng: np.random.Generator) -> bool:
    """Put the robot in front of a random person (within ``person_angle_deg`` of where they
    look), turned to them, the head pitched at their face."""
    people = list(sim.world.people.values())
    if not people:
        return False
    person = people[rng.integers(len(people))]
    for _ in range(hh.attempts):
        d = rng.uniform(*hh.person_distance)
        off = math.radians(rng.uniform(-hh.person_angle_deg, hh.person_angle_deg))
        x = person.x + d * math.cos(person.yaw + off)
        y = person.y + d * math.sin(person.yaw + off)
        if not _free(sim.world, x, y, hh.clearance_m):
            continue
        aim = math.atan2(person.y - y, person.x - x)
        sim.robot.base.set_pose(x, y, aim + math.radians(rng.uniform(-hh.aim_jitter_deg,
                                                                  hh.aim_jitter_deg)))
        sim.robot.joints.set_positions({"HeadPitch": 0.0, "HeadYaw": 0.0})
        eye = sim.robot.camera.pose()[0]
        face_z = person.aabb()[1][2] - 0.12
        pitch = math.atan2(eye[2] - face_z, math.hypot(person.x - x, person.y - y))
        sim.robot.joints.set_positions({
            "HeadPitch": pitch + rng.uniform(-hh.face_pitch_jitter, hh.face_pitch_jitter)})
        return True
    return False


def run_frames(cfg: VqgDataConfig, world: int, seed: np.random.SeedSequence, count: int
               ) -> Iterator[Frame]:
    """``count`` frames of one run of the ``world``-th shipped world (fewer when the robot
    finds no free place at a moment)."""
    hh = cfg.household
    rng = np.random.default_rng(seed)
    scenario = load_scenario(hh.world_paths()[world])
    scenario = scenario.model_copy(update={"seed": int(rng.integers(2**31))})
    sim = Simulation(scenario)
    try:
        made = 0
        while made < count and sim.t < scenario.duration:
            until = sim.t + rng.uniform(*hh.advance_s)
            while sim.t < min(until, scenario.duration):
                sim.step()
            for _ in range(min(hh.frames_per_moment, count - made)):
                pose = _person_pose if rng.random() < hh.person_share else _room_pose
                if pose(sim, hh, rng):
                    made += 1
                    yield household_scene(sim, cfg.visibility)
    finally:
        sim.close()


def write_household_frames(out: Path, cfg: VqgDataConfig, splits: dict[str, int],
                           tick: Callable[[int], None]) -> dict[str, int]:
    """Write ``splits`` (split -> household frames) into the data set folder ``out``; return
    the frames written now. ``tick`` is called with 1 per frame done or skipped."""
    hh = cfg.household
    per_run = hh.frames_per_run
    done = dict.fromkeys(splits, 0)
    for split, n in splits.items():
        k = SPLITS.index(split)
        for run in range(math.ceil(n / per_run)):
            names = [f"h{i:06d}" for i in range(run * per_run, min(n, (run + 1) * per_run))]
            if all(frame_done(out, split, name) for name in names):
                tick(len(names))
                continue
            seed = np.random.SeedSequence([cfg.seed, 10 + k, run])
            with closing(run_frames(cfg, run % len(hh.worlds), seed, len(names))) as frames:
                for j, (name, (rgb, graph)) in enumerate(zip(names, frames, strict=False)):
                    qseed = np.random.SeedSequence([cfg.seed, 10 + k, run, j])
                    write_frame(out, split, name, rgb, graph, questions_for(graph, qseed, cfg))
                    done[split] += 1
                    tick(1)
    return done
