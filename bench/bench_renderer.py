"""The head camera's cost on PyBullet's two offscreen renderers, on household views.

    python bench/bench_renderer.py [--views 24] [--repeat 5] [--json]

For each shipped world: the robot's camera at its start pose turned eight ways, and at
``--views`` seeded random poses in the rooms, rendered 320x240 with depth (what a household
run asks for) by the TinyRenderer the robot uses and by the EGL plugin (Mesa's software
rasteriser on a machine without a GPU). Prints milliseconds per frame for each, and the
mean absolute difference between the two renderers' colour images (0-255): how far EGL
frames are from those the detector was trained on.
"""

from __future__ import annotations

import argparse
import json
import math
import pkgutil
import statistics
import time
from pathlib import Path

import numpy as np
import pybullet as p

from sim.robot import Robot
from sim.scenario import load_scenario
from sim.world import World

WORLDS = ["living_room", "nursing_home", "birthday_party", "low_battery_night"]
ROOT = Path(__file__).resolve().parents[1]


def build(world: str, egl: bool) -> tuple[int, World, Robot]:
    """A DIRECT client with the world and the robot; the EGL plugin is loaded first (it
    only draws bodies made after it)."""
    client = p.connect(p.DIRECT)
    if egl:
        plugin = pkgutil.get_loader("eglRenderer")
        if plugin is None or p.loadPlugin(plugin.get_filename(), "_eglRendererPlugin",
                                          physicsClientId=client) < 0:
            raise RuntimeError("the EGL renderer plugin does not load here")
    w = World(load_scenario(ROOT / "worlds" / f"{world}.yaml"), client)
    start = w.robot_start()
    return client, w, Robot(client, (start.x, start.y, start.yaw))


def poses(w: World, views: int) -> list[tuple[float, float, float]]:
    """The start pose turned eight ways, then seeded random poses inside the rooms."""
    start = w.robot_start()
    out = [(start.x, start.y, start.yaw + k * math.pi / 4) for k in range(8)]
    rng = np.random.default_rng(0)
    rooms = w.scenario.rooms
    for _ in range(views):
        r = rooms[rng.integers(len(rooms))]
        out.append((rng.uniform(r.x[0] + 0.5, r.x[1] - 0.5),
                    rng.uniform(r.y[0] + 0.5, r.y[1] - 0.5), rng.uniform(-math.pi, math.pi)))
    return out


def render(client: int, w: World, robot: Robot, renderer: int) -> np.ndarray:
    """One 320x240 frame with depth from the robot's head camera; its colour image."""
    view, proj = robot.camera.matrices(320, 240)
    rgba = p.getCameraImage(320, 240, view, proj, flags=p.ER_NO_SEGMENTATION_MASK,
                            renderer=renderer, physicsClientId=client,
                            **w.light.camera_kwargs())[2]
    return np.asarray(rgba, dtype=np.uint8).reshape(240, 320, 4)[..., :3]


def measure(world: str, egl: bool, views: int, repeat: int) -> tuple[float, list[np.ndarray]]:
    """Median ms per frame over the views, and each view's frame."""
    client, w, robot = build(world, egl)
    renderer = p.ER_BULLET_HARDWARE_OPENGL if egl else p.ER_TINY_RENDERER
    times, frames = [], []
    for x, y, yaw in poses(w, views):
        robot.base.set_pose(x, y, yaw)
        frames.append(render(client, w, robot, renderer))   # the first one warms up
        t0 = time.perf_counter()
        for _ in range(repeat):
            render(client, w, robot, renderer)
        times.append(1000 * (time.perf_counter() - t0) / repeat)
    p.disconnect(client)
    return statistics.mean(times), frames


def main() -> None:
    """Measure every world on both renderers and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views", type=int, default=24)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    rows = []
    for world in WORLDS:
        tiny, tiny_frames = measure(world, False, args.views, args.repeat)
        egl, egl_frames = measure(world, True, args.views, args.repeat)
        diff = statistics.mean(float(np.abs(a.astype(int) - b).mean())
                               for a, b in zip(tiny_frames, egl_frames, strict=True))
        rows.append({"world": world, "tiny_ms": round(tiny, 2), "egl_ms": round(egl, 2),
                     "mean_abs_diff": round(diff, 1)})
    if args.json:
        print(json.dumps(rows))
        return
    print("| world | TinyRenderer ms/frame | EGL (llvmpipe) ms/frame | colour difference |")
    print("|---|---:|---:|---:|")
    for r in rows:
        print(f"| {r['world']} | {r['tiny_ms']} | {r['egl_ms']} | {r['mean_abs_diff']} |")


if __name__ == "__main__":
    main()
