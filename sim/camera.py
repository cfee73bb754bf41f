"""Photos from the robot's head camera in a scenario's household, saved as PNG files."""

from __future__ import annotations

import itertools
from collections.abc import Callable
from pathlib import Path

import cv2
import pybullet as p

from sim.robot import Robot
from sim.world import World


class ScenarioCamera:
    """The robot standing at its start pose in a scenario's world, taking photos on request.

    The world is built on the first photo (PyBullet DIRECT, TinyRenderer) and kept; each call
    saves ``photo-NNN.png`` in ``out_dir`` and returns its path.
    """

    def __init__(self, scenario_path: str | Path, out_dir: str | Path) -> None:
        self.scenario_path = Path(scenario_path)
        self.out_dir = Path(out_dir)
        self._robot = None
        self._count = itertools.count(1)

    def _build(self) -> None:
        client = p.connect(p.DIRECT)
        world = World.from_file(self.scenario_path, client)
        self._robot = Robot(client, pose=tuple(world.robot_start()))
        self._robot.camera.set_lighting(world.light.camera_kwargs())

    def __call__(self) -> Path:
        """Render the head camera and save the frame; returns the PNG's path."""
        if self._robot is None:
            self._build()
        frame = self._robot.camera.frame()
        self.out_dir.mkdir(parents=True, exist_ok=True)
        path = self.out_dir / f"photo-{next(self._count):03d}.png"
        cv2.imwrite(str(path), cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
        return path


def scenario_camera(scenario_path: str | Path, out_dir: str | Path) -> Callable[[], Path]:
    """A ``take_photo`` callable for the dialogue's QA bot."""
    return ScenarioCamera(scenario_path, out_dir)
