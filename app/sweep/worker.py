"""One run of a sweep, as a Ray task executes it in its own worker process."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from app.faults import load_faults
from app.run import prepare_scenario, run_scenario
from app.sweep.spec import Run


def execute(run: Run, folder: Path, collect: bool) -> dict[str, Any]:
    """Run ``run`` into ``folder`` (an earlier, unfinished attempt there is replaced) and
    return its metrics, and with ``collect`` the text of its ``events.jsonl`` (for a
    driver that does not share the worker's disk)."""
    scenario = prepare_scenario(Path(run.world), duration=run.duration, seed=run.seed,
                                personality=Path(run.personality) if run.personality else None)
    faults = load_faults(run.faults) if run.faults else None
    metrics = run_scenario(scenario, folder, progress=False, overwrite=True, faults=faults,
                           policy_path=Path(run.policy) if run.policy else None,
                           tags={"sweep_key": run.key})
    events = (folder / "events.jsonl").read_text(encoding="utf-8") if collect else None
    return {"metrics": metrics, "events": events}
