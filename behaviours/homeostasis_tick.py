"""Homeostasis tick: once per homeostasis step (one simulated second by default) advance the
drives by the running action (Table 4.1 growth, Table 4.2 relief while the skill relieves),
then compute the motivations (eq. 3.4) and the mood (eq. 3.6). The same
:class:`mind.homeostasis.Homeostasis` drives the DQN's training environment."""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from behaviours.blackboard import motivations_and_mood
from behaviours.context import Context
from behaviours.skill import ContextBehaviour
from mind.personality import ACTIONS, DRIVES, STAND_BY

BATTERY_TOLERANCE = 0.02   # charge the battery may differ from 1 - energy before it counts


class HomeostasisTick(ContextBehaviour):
    """Drives, motivations and mood on the blackboard; one row per step in the run's
    :class:`~behaviours.step_record.StepRecord`. The blackboard's seed
    (:func:`behaviours.blackboard.seed`) holds the initial drives with their motivations and
    mood, so they are there before the first tick."""

    def __init__(self, ctx: Context, name: str = "Homeostasis") -> None:
        super().__init__(name, ctx, reads=("stimuli", "emotion", "action", "relieving"),
                         writes=("drives", "motivations", "mood", "progress"))
        self._next = 0.0

    def setup(self, **kwargs: Any) -> None:
        """The robot's battery follows the initial energy drive (one quantity)."""
        self._battery()

    def _battery(self) -> None:
        self.ctx.robot.battery.set_level(float(1.0 - self.bb.drives[DRIVES.index("energy")]))

    def _publish(self) -> None:
        bb = self.bb
        values = motivations_and_mood(self.ctx.homeostasis, bb.drives, bb.stimuli, bb.emotion)
        bb.motivations, bb.mood = values["motivations"], values["mood"]
        self._battery()

    def update(self) -> Status:
        step = self.ctx.config.homeostasis_step_s
        while self.now + 1e-9 >= self._next + step:
            self._next += step
            self._step()
        return Status.SUCCESS

    def _read_battery(self) -> None:
        """The energy drive follows a battery that lost charge on its own (a failing cell):
        charging then pre-empts as for any low battery (a ``fault`` event says so)."""
        i, battery = DRIVES.index("energy"), self.ctx.robot.battery.level
        if battery < 1.0 - self.bb.drives[i] - BATTERY_TOLERANCE:
            self.emit("fault", fault="battery_drop", battery=round(battery, 3),
                      expected=round(1.0 - float(self.bb.drives[i]), 3),
                      recovery="the energy drive follows the battery; charging pre-empts")
            drives = self.bb.drives.copy()
            drives[i] = 1.0 - battery
            self.bb.drives = drives

    def _step(self) -> None:
        self._read_battery()
        h, bb = self.ctx.homeostasis, self.bb
        action, relieving = bb.action, bool(bb.relieving)
        a = STAND_BY if action is None else ACTIONS.index(action)
        bb.drives = h.step(bb.drives, a, relieve=relieving and action is not None)
        if relieving:
            bb.progress = bb.progress + 1
        self._publish()
        self.ctx.steps.append({
            "t": round(self._next, 3), "action": action or "stand_by", "relieving": relieving,
            "drives": bb.drives.copy(), "motivations": bb.motivations.copy(),
            "stimuli": bb.stimuli.copy(),
            "mood": bb.mood["value"], "mood_positive": bb.mood["positive"],
            "secure": bool(h.secure(bb.drives))})
