"""The sweep driver: every run of a spec as its own Ray task, results as they finish.

Each task runs in a fresh worker process (``max_calls=1``), so no two runs share a
PyBullet client or a py_trees blackboard. A run is complete when its ``metrics.json``
exists, was not interrupted and carries its entry's hash (``sweep_key``); a new start of the
sweep skips complete runs. A failed run is recorded with its error and the others go on.
SIGINT or SIGTERM cancels what is still running (each such run writes its interrupted
report) and the report covers what finished.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from tqdm import tqdm

from app.sweep.spec import Run, TrainRun
from app.sweep.worker import execute, execute_training
from core.checkpoint import atomic_write_bytes
from core.errors import UserError
from core.run_folder import lock_folder
from core.signals import terminable

CANCEL_WAIT_S = 60.0   # how long cancelled runs get to write their interrupted reports
RAY_TOKEN_FILE = Path.home() / ".ray" / "auth_token"   # where `ray start` keeps its token


class SweepError(UserError):
    """The Ray cluster named by ``--address`` could not be joined."""


def use_token(address: str | None) -> None:
    """Before Ray is imported (it reads its settings then): a head started with ``ray start``
    requires its token. ``auto`` finds that out from the local session; a driver given
    HOST:PORT does not, so it sends the token when it has one (``RAY_AUTH_TOKEN``,
    ``RAY_AUTH_TOKEN_PATH`` or Ray's token file) unless ``RAY_AUTH_MODE`` says otherwise. A
    cluster without authentication accepts it too."""
    has_token = ("RAY_AUTH_TOKEN" in os.environ or "RAY_AUTH_TOKEN_PATH" in os.environ
                 or RAY_TOKEN_FILE.is_file())
    if address not in (None, "auto") and has_token:
        os.environ.setdefault("RAY_AUTH_MODE", "token")


def join_ray(address: str | None) -> None:
    """Start a new local Ray (``address`` None, even when another one runs here) or join a
    cluster (``auto`` or HOST:PORT), after :func:`use_token`."""
    import ray

    try:
        ray.init(address=address or "local", include_dashboard=False, log_to_driver=False,
                 configure_logging=False)
    except (ConnectionError, ray.exceptions.AuthenticationError) as exc:
        raise SweepError(f"--address {address}: could not join the Ray cluster "
                         f"({str(exc).splitlines()[0]}); a cluster started with `ray start` "
                         "needs its token (`ray get-auth-token` on the head) in "
                         f"{RAY_TOKEN_FILE} or RAY_AUTH_TOKEN (docs/sweeps.md)") from None


def complete(folder: Path, run: Run | TrainRun) -> dict[str, Any] | None:
    """The metrics of ``run`` in ``folder`` when it finished there, else None."""
    try:
        metrics = json.loads((folder / "metrics.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    ok = isinstance(metrics, dict) and not metrics.get("interrupted")
    return metrics if ok and metrics.get("sweep_key") == run.key else None


def _task(run: Run | TrainRun, folder: str, collect: bool, threads: int) -> dict[str, Any]:
    if isinstance(run, TrainRun):
        return execute_training(run, Path(folder))
    return execute(run, Path(folder), collect, threads)


def sweep(runs: list[Run | TrainRun], out: Path, *, address: str | None, cpus_per_run: float,
          worker_dir: Path | None = None, progress: bool = True
          ) -> tuple[list[dict[str, Any]], BaseException | None]:
    """Run what is not complete yet; return one row per run (``run``, ``metrics`` or
    ``error``) and the interrupt that stopped the sweep (None when it ran to its end)."""
    use_token(address)
    import ray  # heavy: only a sweep pays for it

    out.mkdir(parents=True, exist_ok=True)
    lock = lock_folder(out)
    rows = {r.name: {"run": r, "metrics": complete(out / r.name, r)} for r in runs}
    todo = [r for r in runs if rows[r.name]["metrics"] is None]
    interrupt: BaseException | None = None
    try:
        if todo:
            join_ray(address)
            task = ray.remote(max_calls=1)(_task)
            threads = max(1, int(cpus_per_run))   # a run's models stay within its cores
            pending = {task.options(num_cpus=cpus_per_run).remote(
                r, str((worker_dir or out) / r.name), worker_dir is not None, threads): r
                for r in todo}
            with terminable() as received, tqdm(
                    total=len(runs), initial=len(runs) - len(todo), unit="run",
                    disable=None if progress else True) as bar:
                try:
                    _collect(pending, rows, out, worker_dir is not None, bar)
                except KeyboardInterrupt as exc:   # Ray's wait turns SIGTERM's into a plain one
                    interrupt = received.interrupt(exc)
                    for ref in pending:   # each run stops as at Ctrl-C: its report is written
                        ray.cancel(ref)
                    ray.wait(list(pending), num_returns=len(pending), timeout=CANCEL_WAIT_S)
    finally:
        if ray.is_initialized():
            ray.shutdown()
        os.close(lock)
    return list(rows.values()), interrupt


def _collect(pending: dict[Any, Run | TrainRun], rows: dict[str, dict[str, Any]], out: Path,
             collect: bool, bar: tqdm) -> None:
    """Take results as runs finish (``ray.wait``), until none is pending."""
    import ray

    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        for ref in ready:
            run = pending.pop(ref)
            try:
                result = ray.get(ref)
            except Exception as exc:   # the run failed: record why, the others go on
                rows[run.name]["error"] = _one_line(exc)
            else:
                rows[run.name]["metrics"] = result["metrics"]
                if collect:   # the worker's disk is not ours: keep its report here
                    folder = out / run.name
                    if result["events"] is not None:
                        atomic_write_bytes(folder / "events.jsonl", result["events"].encode())
                    atomic_write_bytes(folder / "metrics.json",
                                       json.dumps(result["metrics"], indent=2).encode())
            bar.update()


def _one_line(exc: BaseException) -> str:
    cause = getattr(exc, "cause", None) or exc
    return " ".join(f"{type(cause).__name__}: {cause}".split())[:500]
