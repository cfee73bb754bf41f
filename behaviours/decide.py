"""Decide: whenever the running action has finished (or failed, or nothing runs yet) the DQN
picks the next one from the motivations. A critical energy drive pre-empts whatever runs:
the action switches to charge, and the act subtree's guard stops the old skill cleanly."""

from __future__ import annotations

from typing import Protocol

import numpy as np
from py_trees.common import Status

from app.mind.personality import DRIVES
from behaviours.context import Context
from behaviours.skill import ContextBehaviour

ENERGY = DRIVES.index("energy")


class Policy(Protocol):
    """What the tree needs from a decision maker (``app.mind.policy.agent.DQNPolicy``)."""

    def act(self, motivations: np.ndarray) -> str:
        """The action to run for these motivations."""
        ...


class Decide(ContextBehaviour):
    """Set ``action`` on the blackboard when a new one is due."""

    def __init__(self, ctx: Context, policy: Policy, name: str = "Decide") -> None:
        super().__init__(name, ctx, reads=("motivations", "drives"),
                         writes=("action", "progress", "act_status"))
        self.policy = policy

    def _start(self, action: str, reason: str) -> None:
        self.bb.action, self.bb.progress, self.bb.act_status = action, 0, None
        self.emit("action", action=action, reason=reason, motivations=self.bb.motivations,
                  drives=self.bb.drives)

    def update(self) -> Status:
        action, status = self.bb.action, self.bb.act_status
        critical = self.bb.drives[ENERGY] >= self.ctx.config.preempt_energy
        if critical and action != "charge":
            if action is not None and status == Status.RUNNING:
                self.emit("preempted", action=action, energy=self.bb.drives[ENERGY])
            self._start("charge", "critical energy")
        elif action is None or status in (Status.SUCCESS, Status.FAILURE):
            if action is not None:
                self.emit("finished", action=action, status=str(status.value))
            if status == Status.FAILURE and action != "stand_by":
                self._start("stand_by", f"{action} failed")
            else:
                self._start(self.policy.act(self.bb.motivations), "policy")
        return Status.SUCCESS
