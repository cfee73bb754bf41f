"""Homeostasis tick: once per homeostasis step (one simulated second by default) advance the
drives by the running action (Table 4.1 growth, Table 4.2 relief while the skill relieves),
then compute the motivations (eq. 3.4) and the mood (eq. 3.6). The same
:class:`app.mind.homeostasis.Homeostasis` drives the DQN's training environment."""

from __future__ import annotations

import numpy as np
from py_trees.common import Status

from app.mind.personality import ACTIONS, DRIVES, STAND_BY
from behaviours.context import Household
from behaviours.skill import HouseholdBehaviour


class HomeostasisTick(HouseholdBehaviour):
    """Drives, motivations and mood on the blackboard; one history row per step."""

    def __init__(self, house: Household, initial_drives: dict[str, float],
                 name: str = "Homeostasis") -> None:
        super().__init__(name, house, reads=("stimuli", "emotion", "action", "relieving"),
                         writes=("drives", "motivations", "mood", "progress"))
        self.bb.drives = np.array([initial_drives[d] for d in DRIVES], dtype=np.float64)
        self.bb.progress = 0
        self._next = 0.0
        self._publish()

    def _publish(self) -> None:
        h, bb = self.house.homeostasis, self.bb
        stimuli = bb.get("stimuli") if bb.exists("stimuli") else np.zeros(3)
        emotion = bb.get("emotion") if bb.exists("emotion") else 0.0
        bb.motivations = h.motivations(bb.drives, stimuli)
        value = float(h.mood_value(bb.drives, stimuli[2], emotion))
        bb.mood = {"value": value, "positive": bool(h.mood_positive(value))}
        self.house.robot.set_battery(float(1.0 - bb.drives[DRIVES.index("energy")]))

    def update(self) -> Status:
        step = self.house.config.homeostasis_step_s
        while self.now + 1e-9 >= self._next + step:
            self._next += step
            self._step()
        return Status.SUCCESS

    def _step(self) -> None:
        h, bb = self.house.homeostasis, self.bb
        action = bb.get("action") if bb.exists("action") else None
        relieving = bool(bb.get("relieving")) if bb.exists("relieving") else False
        a = STAND_BY if action is None else ACTIONS.index(action)
        bb.drives = h.step(bb.drives, a, relieve=relieving and action is not None)
        if relieving:
            bb.progress = bb.progress + 1
        self._publish()
        self.house.history.append({
            "t": round(self._next, 3), "action": action or "stand_by", "relieving": relieving,
            "drives": bb.drives.copy(), "motivations": bb.motivations.copy(),
            "stimuli": bb.stimuli.copy() if bb.exists("stimuli") else np.zeros(3),
            "mood": bb.mood["value"], "mood_positive": bb.mood["positive"],
            "secure": bool(h.secure(bb.drives))})
