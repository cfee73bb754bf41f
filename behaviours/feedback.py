"""Credit: each praise or scolding becomes an external reward (eq. 3.7's r_external, +1 or
-1) for the action it follows, and the household's memory learns from it.

The credit rule (docs/feedback.md): feedback ``about`` an action goes to that action when it
is running or ended within ``credit_window_s``; otherwise it is dropped (a ``feedback``
event without a ``credited`` one). Feedback about nothing in particular goes to the running
action, unless that is standing by and another action ended within the window: people
react to what the robot did, not to it standing still.
"""

from __future__ import annotations

from py_trees.common import Status

from behaviours.context import Context
from behaviours.skill import ContextBehaviour
from mind.preferences.memory import save_memory


class Credit(ContextBehaviour):
    """Credit queued feedback to actions; teach and save the memory (when there is one)."""

    def __init__(self, ctx: Context, name: str = "Credit") -> None:
        super().__init__(name, ctx, reads=("action",), writes=("feedback",))
        self._running: str | None = None
        self._ended: dict[str, float] = {}    # action -> when it last ended

    def update(self) -> Status:
        action = self.bb.action
        if action != self._running:
            if self._running is not None:
                self._ended[self._running] = self.now
            self._running = action
        for fb in self.bb.feedback:
            target = self._target(fb.about)
            if target is None:
                continue
            self.emit("credited", person=fb.person, action=target, reward=fb.value)
            memory = self.ctx.memory
            if memory is not None:
                memory.learn(fb.person, target, fb.value, self.ctx.adaptation.learning_rate)
                if self.ctx.memory_path is not None:
                    save_memory(memory, self.ctx.memory_path)
        self.bb.feedback = []
        return Status.SUCCESS

    def _recent(self, action: str) -> bool:
        ended = self._ended.get(action)
        return ended is not None and self.now - ended <= self.ctx.adaptation.credit_window_s

    def _target(self, about: str | None) -> str | None:
        if about is not None:
            return about if about == self._running or self._recent(about) else None
        if self._running not in (None, "stand_by"):
            return self._running
        recent = [(t, a) for a, t in self._ended.items() if a != "stand_by" and self._recent(a)]
        return max(recent)[1] if recent else self._running
