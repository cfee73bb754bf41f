"""The head camera's frames split between the run's process and a helper process.

Rendering is half of a household run's wall time, on one core: PyBullet holds Python's
lock while it draws, so a thread cannot share the work. :class:`SplitRenderer` starts a
helper process that builds the same world from the same scenario (so every body has the
same id there) and draws the top rows of each frame while this process draws the rest,
through an off-centre projection of the same camera: a frame costs about as long as its
larger band. Before each frame the helper is sent what changed since the last one: each
body's pose and joint angles, and the bodies made or removed during the run, in order
(``World.journal``). The bands meet without a seam; a few edge pixels may differ from
a whole-frame render where two surfaces are equally near. Frames with shadows are drawn
whole in this process (a band's shadow map would be smaller).

A helper that fails (it died, or fell out of step with the world) is dropped, logged, and
every later frame is drawn here whole: the camera never stops a run.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing as mp
import signal
from collections.abc import Sequence
from multiprocessing.connection import Connection
from typing import Any

import numpy as np
import pybullet as p

from sim.people import load_urdf_text
from sim.render import Buffers, band_projection, tiny_render
from sim.robot import Robot
from sim.world import World

log = logging.getLogger(__name__)

HELPER_START_S = 120.0    # the first band waits for the helper to import and build the world
HELPER_TIMEOUT_S = 10.0   # a later band not back by then: the helper is taken for dead


def body_states(client: int) -> dict[int, tuple]:
    """Every body's base position, orientation and joint angles."""
    states = {}
    for i in range(p.getNumBodies(physicsClientId=client)):
        body = p.getBodyUniqueId(i, physicsClientId=client)
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=client)
        n = p.getNumJoints(body, physicsClientId=client)
        joints = tuple(s[0] for s in p.getJointStates(body, range(n), physicsClientId=client)
                       ) if n else ()
        states[body] = (pos, orn, joints)
    return states


class SplitRenderer:
    """Frames drawn by this process (the bottom rows) and a helper process (the top
    ``helper_share`` of the rows) at once; see the module's documentation. ``world`` is
    the run's :class:`~sim.world.World` (its journal of bodies made and removed),
    ``scenario`` and ``robot_config`` what the helper builds its copy from."""

    def __init__(self, client: int, world: Any, scenario: Any, robot_config: Any,
                 helper_share: float) -> None:
        self.client, self.world, self.share = client, world, helper_share
        self._sent: dict[int, tuple] = {}
        self._journal_sent = 0
        self._started = False
        context = mp.get_context("spawn")   # a fresh interpreter: no model threads copied
        self._conn, child = context.Pipe()
        self._proc: Any = context.Process(target=_serve, args=(child, scenario, robot_config),
                                          name="camera-helper", daemon=True)
        self._proc.start()
        child.close()

    @property
    def alive(self) -> bool:
        """Whether the helper still draws its band."""
        return self._proc is not None

    def __call__(self, width: int, height: int, view: Sequence[float],
                 proj: Sequence[float], flags: int, light: dict[str, Any]) -> Buffers:
        """One frame, as :func:`tiny_render` draws it. A frame with shadows is drawn whole
        here: TinyRenderer's shadow map is as large as the image, so a band would get
        other shadows."""
        if self._proc is None or light.get("shadow"):
            return tiny_render(self.client, width, height, view, proj, flags, light)
        split = round(height * self.share)
        try:
            self._conn.send((self._changes(), width, split, height, view, proj, flags, light))
            mine = tiny_render(self.client, width, height - split, view,
                               band_projection(proj, height, split, height), flags, light)
            wait = HELPER_TIMEOUT_S if self._started else HELPER_START_S
            if not self._conn.poll(wait):
                raise TimeoutError(f"no band in {wait:g} s")
            theirs = self._conn.recv()
            self._started = True
            if isinstance(theirs, str):
                raise RuntimeError(theirs)
        except (OSError, EOFError, TimeoutError, RuntimeError) as exc:
            log.warning("camera helper dropped (%s); frames are drawn in one process", exc)
            self.close()
            return tiny_render(self.client, width, height, view, proj, flags, light)
        return tuple(np.concatenate([a, b]) for a, b in zip(theirs, mine, strict=True))

    def _changes(self) -> tuple[list[tuple], list[tuple]]:
        """The journal entries and body states the helper has not been sent."""
        journal = self.world.journal[self._journal_sent:]
        self._journal_sent += len(journal)
        for entry in journal:
            if entry[0] == "remove":
                self._sent.pop(entry[1], None)
        states = body_states(self.client)
        changed = [(body, *state) for body, state in states.items()
                   if self._sent.get(body) != state]
        self._sent = states
        return journal, changed

    def close(self) -> None:
        """Stop the helper (every later frame is drawn here)."""
        proc, self._proc = self._proc, None
        if proc is None:
            return
        with contextlib.suppress(OSError):
            self._conn.send(None)
        proc.join(timeout=5)
        if proc.is_alive():
            proc.kill()
            proc.join()
        self._conn.close()


def _serve(conn: Connection, scenario: Any, robot_config: Any) -> None:
    """The helper: build the world and the robot, then draw bands until told to stop (None)
    or the run's end of the pipe closes. SIGINT is the run's to handle."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    client = p.connect(p.DIRECT)
    world = World(scenario, client)
    start = world.robot_start()
    Robot(client, (start.x, start.y, start.yaw), robot_config)
    while True:
        try:
            request = conn.recv()
        except EOFError:
            return
        if request is None:
            return
        (journal, changed), width, split, height, view, proj, flags, light = request
        try:
            for entry in journal:
                if entry[0] == "make":
                    _, body, name, urdf = entry
                    made = load_urdf_text(client, name, urdf)
                    if made != body:
                        raise RuntimeError(f"helper out of step: {name} is body {made}, "
                                           f"not {body}")
                else:
                    p.removeBody(entry[1], physicsClientId=client)
            for body, pos, orn, joints in changed:
                p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=client)
                for j, angle in enumerate(joints):
                    p.resetJointState(body, j, angle, physicsClientId=client)
            conn.send(tiny_render(client, width, split, view,
                                  band_projection(proj, height, 0, split), flags, light))
        except Exception as exc:   # told to the run, which drops the helper
            conn.send(f"{type(exc).__name__}: {exc}")
            return
