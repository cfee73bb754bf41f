"""Decide: which action runs, in three priorities.

1. **Safety.** A critical energy drive pre-empts whatever runs: the action switches to
   charge. That charge, and a rest begun while the motors are overheated, must finish
   (``must_finish``): a line said meanwhile is answered by voice from where the robot is
   (:class:`behaviours.listening.Promise`); a song it asks for is promised for afterwards.
2. **Spoken to.** A line waiting to be answered pre-empts any other action: the action
   switches to chat, which turns to the voice and answers. Once a reply has asked for
   something (a song: ``request``), that action starts next.
3. **The policy's choice.** Whenever the running action has finished (or failed, or nothing
   runs yet) the DQN picks the next one from the motivations. With a household memory
   (``ctx.memory``) the pick adds what the person likes to the DQN's action values, among
   the actions that cannot let a drive near the secure bound
   (:mod:`mind.preferences.adaptation`); the reason is then ``preference``.

The act subtree's guards stop a pre-empted skill cleanly (docs/behaviours.md explains the
order).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from py_trees.common import Status

from behaviours.context import Context
from behaviours.listening import pending
from behaviours.skill import ContextBehaviour
from mind.personality import ACTIONS, DRIVES, STIMULI
from mind.preferences.adaptation import choose

ENERGY = DRIVES.index("energy")
OVERHEAT = STIMULI.index("overheat")


class Policy(Protocol):
    """What the tree needs from a decision maker (``mind.policy.agent.DQNPolicy``)."""

    def act(self, motivations: np.ndarray) -> str:
        """The action to run for these motivations."""
        ...

    def q_values(self, motivations: np.ndarray) -> np.ndarray:
        """The value of each action (adaptation to feedback adds preferences to them)."""
        ...


class Decide(ContextBehaviour):
    """Set ``action`` on the blackboard when a new one is due."""

    def __init__(self, ctx: Context, policy: Policy, name: str = "Decide") -> None:
        super().__init__(name, ctx, reads=("motivations", "drives", "stimuli", "heard",
                                           "person"),
                         writes=("action", "progress", "relieving", "act_status",
                                 "must_finish", "request"))
        self.policy = policy
        self._reason = ""

    def _start(self, action: str, reason: str) -> None:
        if reason != "asked":
            self.bb.request = None    # the skill a request started has read it by now
        self._reason = reason
        self.bb.action, self.bb.progress, self.bb.act_status = action, 0, None
        self.bb.relieving = False
        self.bb.must_finish = (reason == "critical energy"
                               or (action == "rest" and self.bb.stimuli[OVERHEAT] > 0))
        self.emit("action", action=action, reason=reason, motivations=self.bb.motivations,
                  drives=self.bb.drives)

    def update(self) -> Status:
        action, status = self.bb.action, self.bb.act_status
        running = action is not None and status not in (Status.SUCCESS, Status.FAILURE)
        critical = self.bb.drives[ENERGY] >= self.ctx.config.preempt_energy
        spoken = bool(pending(self.bb.heard, self.now, self.ctx.config.chat.max_heard_age_s))
        if critical and action != "charge":
            if running:
                self.emit("preempted", action=action, energy=self.bb.drives[ENERGY])
            self._start("charge", "critical energy")
        elif running and (self.bb.must_finish or not spoken or action == "chat"):
            pass
        elif running:
            self.emit("preempted", action=action, reason="spoken to")
            self._start("chat", "spoken to")
        else:
            if action is not None:
                self.emit("finished", action=action, status=str(status.value))
            self._next(action, status, spoken)
        return Status.SUCCESS

    def _next(self, action: str | None, status: Status | None, spoken: bool) -> None:
        """Start the next action once the last one has ended."""
        if self.bb.request is not None and self._reason != "asked":
            self._start(self.bb.request.name, "asked")
        elif spoken:
            self._start("chat", "spoken to")
        elif status == Status.FAILURE and action != "stand_by":
            self._start("stand_by", f"{action} failed")
        else:
            self._start(*self._choice())

    def _choice(self) -> tuple[str, str]:
        """The policy's pick, and with a memory the pick adapted to the person's tastes."""
        memory, motivations = self.ctx.memory, self.bb.motivations
        if memory is None:
            return self.policy.act(motivations), "policy"
        cfg, person = self.ctx.adaptation, self.bb.person
        who = person[0] if person and self.now - person[1] <= cfg.person_window_s else None
        q = self.policy.q_values(motivations)[None]
        pick = int(choose(self.ctx.homeostasis, q, memory.table(who)[None],
                          self.bb.drives[None], cfg)[0])
        return ACTIONS[pick], "policy" if pick == int(q.argmax()) else "preference"
