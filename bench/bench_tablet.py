"""The tablet's bars (docs/tablet.md, docs/BENCHMARKS.md "Tablet").

    python bench/bench_tablet.py buttons --rounds 20
        every conversation button pressed in headless Chromium against `companion tablet`'s
        app; the latency from the press to the reply and its card on screen, measured by the
        page itself (p50/p95 per button and over all presses)
    python bench/bench_tablet.py buttons --rounds 5 --run runs/bench-tablet/buttons-run
        the same during a run of the living room: the robot hears each line and answers
    python bench/bench_tablet.py run --out runs/bench-tablet/plain
    python bench/bench_tablet.py run --tablet --clients 1 --out runs/bench-tablet/tablet
    python bench/bench_tablet.py run --tablet --clients 50 --out runs/bench-tablet/load
        `companion run worlds/nursing_home.yaml --duration 600 --seed 3` (as a subprocess),
        without or with --tablet and N live-view clients (Server-Sent Events on loopback,
        from this process) for the whole run: the run's wall time, its ticks (timeline rows,
        events by kind: the same as without the tablet means none was dropped or changed),
        its CPU time (a shared machine's load moves the wall time; the CPU time counts
        the server thread too), its resident memory sampled every wall second, and per
        client the snapshots received per wall second (and the share of whole wall seconds
        with two or more), the longest gap between two, the delay from a snapshot's
        building in the run to its arrival, and the longest gap between two snapshots
        built (a tick that took that long)
    python bench/bench_tablet.py ticks --out runs/bench-tablet/ticks
        the same run without the tablet, in this process, each tick timed: its longest ticks
    python bench/bench_tablet.py compare runs/bench-tablet/plain runs/bench-tablet/tablet
        the wall-time growth and whether the two runs' events match

Each `run` writes `bench.json` beside the run folder's own files.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import itertools
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
PORT = 8799
WALL = re.compile(r'data: \{"wall":([0-9.]+),"t":([0-9.]+)')


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * len(ordered) + 0.5) - 1))]


def _browser() -> Any:
    import shutil

    from selenium import webdriver

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        options.add_argument(arg)
    return webdriver.Chrome(options=options,
                            service=webdriver.ChromeService(shutil.which("chromedriver")))


def _press_all(driver: Any, base: str, rounds: int, pause_s: float) -> dict[str, list[float]]:
    """Press every button ``rounds`` times; the page's latencies (ms) by button."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    from app.tablet.config import KINDS

    latencies: dict[str, list[float]] = collections.defaultdict(list)
    driver.get(base)
    body = driver.find_element(By.TAG_NAME, "body")
    WebDriverWait(driver, 60).until(lambda _: body.get_attribute("data-ready"))
    for _ in range(rounds):
        for kind in KINDS:
            driver.find_element(By.ID, f"btn-{kind}").click()
            WebDriverWait(driver, 120, poll_frequency=0.01).until(
                lambda _: body.get_attribute("data-latency"))
            latencies[kind].append(float(body.get_attribute("data-latency")))
            driver.execute_script("delete document.body.dataset.latency")
            time.sleep(pause_s)
    return latencies


def _summary(latencies: dict[str, list[float]], rounds: int) -> dict[str, Any]:
    every = [v for vs in latencies.values() for v in vs]
    return {"rounds": rounds, "presses": len(every),
            "p50_ms": round(percentile(every, 0.5), 1), "p95_ms": round(percentile(every, 0.95), 1),
            "max_ms": round(max(every), 1),
            "per_button": {k: {"p50_ms": round(percentile(v, 0.5), 1),
                               "p95_ms": round(percentile(v, 0.95), 1)}
                           for k, v in latencies.items()}}


def buttons(rounds: int) -> dict[str, Any]:
    """Press every button ``rounds`` times in headless Chromium against the tablet alone
    (`companion tablet`'s app over the living room); latencies in ms."""
    from app.tablet.chat_link import ChatTablet
    from app.tablet.config import load_tablet_config
    from app.tablet.serve import TabletServer

    driver = _browser()
    with tempfile.TemporaryDirectory() as tmp:
        tablet = ChatTablet.from_scenario(ROOT / "worlds" / "living_room.yaml",
                                          load_tablet_config(), Path(tmp))
        with TabletServer(tablet, "127.0.0.1", 0) as server:
            latencies = _press_all(driver, f"http://127.0.0.1:{server.port}/", rounds, 0.0)
        tablet.close()
    driver.quit()
    return _summary(latencies, rounds)


def buttons_in_a_run(rounds: int, out: Path) -> dict[str, Any]:
    """The same presses during a run of the living room with nobody else talking (a pause
    of 2 wall s after each reply, so a song or a photo can begin): the robot hears each
    line, turns to it and answers; the run is stopped (SIGTERM) once all are answered."""
    import signal

    from app.run import RunOptions, run_scenario
    from app.tablet.config import load_tablet_config
    from app.tablet.run_link import RunTablet
    from app.tablet.serve import TabletServer
    from sim.scenario import load_scenario

    base = load_scenario(ROOT / "worlds" / "living_room.yaml")
    quiet = base.model_copy(update={"duration": 3600.0, "people": tuple(
        q.model_copy(update={"events": ()}) for q in base.people)})
    tablet = RunTablet(load_tablet_config())
    driver = _browser()
    found: dict[str, Any] = {}

    def press(url: str) -> None:
        try:
            while tablet.slot.seq == 0:   # the run is still loading its models
                time.sleep(0.1)
            found["latencies"] = _press_all(driver, url, rounds, 2.0)
        finally:
            os.kill(os.getpid(), signal.SIGTERM)   # ends the run, which writes its report

    with TabletServer(tablet, "127.0.0.1", 0) as server:
        presser = threading.Thread(target=press, args=(f"http://127.0.0.1:{server.port}/",))
        presser.start()
        metrics = run_scenario(quiet, out, RunOptions(tablet=tablet, adapt=False),
                               progress=False, overwrite=True)
        presser.join()
    driver.quit()
    return {**_summary(found["latencies"], rounds), "simulated_s": metrics["duration_s"],
            "wall_s": metrics["wall_s"]}


async def _client(url: str, stats: dict[str, Any], done: threading.Event) -> None:
    import httpx

    arrivals: list[float] = []
    delays: list[float] = []   # wall s from a snapshot's building to its arrival here
    made: list[tuple[float, float]] = []   # each snapshot's building: (wall, simulated) s
    stats.update(arrivals=arrivals, delays=delays, made=made)
    async with httpx.AsyncClient(timeout=None) as client:
        while not done.is_set():
            try:
                async with client.stream("GET", url) as response:
                    async for line in response.aiter_lines():
                        if line.startswith("data:"):
                            arrivals.append(time.monotonic())
                            built = WALL.match(line)
                            if built:
                                delays.append(time.time() - float(built[1]))
                                made.append((float(built[1]), float(built[2])))
                        if done.is_set():
                            return
            except (httpx.HTTPError, OSError):
                await asyncio.sleep(0.2)   # the server is not up yet, or has gone


def _watch(url: str, n: int, done: threading.Event) -> list[dict[str, Any]]:
    stats = [{} for _ in range(n)]

    async def main() -> None:
        await asyncio.gather(*(_client(url, s, done) for s in stats))

    asyncio.run(main())
    return stats


def _rss_mb(pid: int) -> float | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        return None
    return None


def run(args: argparse.Namespace) -> dict[str, Any]:
    """One `companion run`, with the tablet and live-view clients as asked."""
    cmd = [sys.executable, "-m", "app.cli", "run", args.world, "--duration", str(args.duration),
           "--seed", str(args.seed), "--out", str(args.out), "--overwrite", "--no-progress",
           "--json"]
    if args.tablet:
        cmd += ["--tablet", "--port", str(PORT)]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cpu0 = _children_cpu_s()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env,
                            text=True)
    done = threading.Event()
    result: dict[str, Any] = {}
    watcher = None
    if args.clients:
        def watch() -> None:
            result["clients"] = _watch(f"http://127.0.0.1:{PORT}/api/stream", args.clients, done)
        watcher = threading.Thread(target=watch)
        watcher.start()
    rss = []
    while proc.poll() is None:
        value = _rss_mb(proc.pid)
        if value is not None:
            rss.append(round(value, 1))
        time.sleep(1.0)
    done.set()
    cpu_s = round(_children_cpu_s() - cpu0, 1)   # the run's own CPU time, helper included
    metrics = json.loads(proc.stdout.read().strip().splitlines()[-1])
    if watcher is not None:
        watcher.join(timeout=30)
    out = {"command": " ".join(cmd[2:]), "wall_s": metrics["wall_s"], "cpu_s": cpu_s,
           "duration_s": metrics["duration_s"], "peak_rss_mb": metrics["peak_rss_mb"],
           "rss_mb_first_10s_max": max(rss[:10], default=None),
           "rss_mb_last_10s_max": max(rss[-10:], default=None), "rss_samples": len(rss),
           "timeline_rows": sum(1 for _ in (args.out / "timeline.csv").open()) - 1,
           "events": _event_counts(args.out)}
    if args.clients:
        out["clients"] = _client_summary(result.get("clients", []))
    (args.out / "bench.json").write_text(json.dumps(out, indent=1))
    return out


def ticks(args: argparse.Namespace) -> dict[str, Any]:
    """The run of ``run`` without the tablet, in this process, each tick timed: the longest
    ticks (wall s and simulated t), to tell the run's own long ticks from the tablet's."""
    from app.run import build_run, prepare_scenario

    scenario = prepare_scenario(Path(args.world), duration=args.duration, seed=args.seed)
    run = build_run(scenario, args.out)
    times: list[tuple[float, float]] = []
    last = time.perf_counter()

    def clock() -> None:
        nonlocal last
        now = time.perf_counter()
        times.append((now - last, run.sim.t))
        last = now

    with run.sim:
        last = time.perf_counter()
        run.tree.run(steps=round(scenario.duration / scenario.step), after_tick=clock)
    longest = sorted(times, reverse=True)[:5]
    return {"ticks": len(times), "longest": [[round(w, 2), t] for w, t in longest],
            "p99_ms": round(1000 * percentile([w for w, _ in times], 0.99), 1)}


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _event_counts(folder: Path) -> dict[str, int]:
    counts = collections.Counter(json.loads(line)["kind"] for line in
                                 (folder / "events.jsonl").read_text().splitlines())
    return dict(sorted(counts.items()))


def _client_summary(stats: list[dict[str, Any]]) -> dict[str, Any]:
    rates, gaps, counts, twice = [], [], [], []
    for s in stats:
        a = s.get("arrivals", [])
        counts.append(len(a))
        if len(a) >= 2:
            rates.append((len(a) - 1) / (a[-1] - a[0]))
            gaps.append(max(b - x for x, b in itertools.pairwise(a)))
            per_second = collections.Counter(int(t - a[0]) for t in a)
            seconds = range(int(a[-1] - a[0]))   # whole wall seconds of the stream
            twice.append(sum(per_second[k] >= 2 for k in seconds) / max(len(seconds), 1))
    delays = [d for s in stats for d in s.get("delays", [])]
    made = stats[0].get("made", []) if stats else []
    return {"n": len(stats), "all_received": all(c > 0 for c in counts),
            "delivery_delay_s_p50": round(percentile(delays, 0.5), 3) if delays else None,
            "delivery_delay_s_p99": round(percentile(delays, 0.99), 3) if delays else None,
            "built_longest_gaps": [  # (wall s, simulated t before, after): the longest ticks
                [round(b[0] - a[0], 2), a[1], b[1]] for a, b in
                sorted(itertools.pairwise(made), key=lambda p: p[0][0] - p[1][0])[:3]],
            "snapshots_min": min(counts, default=0),
            "rate_per_s_min": round(min(rates), 2) if rates else 0.0,
            "rate_per_s_median": round(statistics.median(rates), 2) if rates else 0.0,
            "max_gap_s": round(max(gaps), 2) if gaps else None,
            "seconds_with_2_plus_pct_min": round(100 * min(twice), 1) if twice else 0.0}


def _actions(folder: Path) -> list[tuple[float, str]]:
    return [(e["t"], e["action"]) for e in map(json.loads, (folder / "events.jsonl")
                                                .read_text().splitlines())
            if e["kind"] == "action"]


def compare(base: Path, other: Path) -> dict[str, Any]:
    """Wall-time growth of ``other`` over ``base`` and whether their runs match."""
    a = json.loads((base / "bench.json").read_text())
    b = json.loads((other / "bench.json").read_text())
    ignore = {"tablet_line", "tablet_feedback"}
    same = ({k: v for k, v in a["events"].items() if k not in ignore}
            == {k: v for k, v in b["events"].items() if k not in ignore})
    return {"wall_s": [a["wall_s"], b["wall_s"]],
            "growth_pct": round(100 * (b["wall_s"] / a["wall_s"] - 1), 1),
            "cpu_s": [a["cpu_s"], b["cpu_s"]],
            "cpu_growth_pct": round(100 * (b["cpu_s"] / a["cpu_s"] - 1), 1),
            "same_ticks": a["timeline_rows"] == b["timeline_rows"],
            "same_events": same, "same_actions": _actions(base) == _actions(other)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="what", required=True)
    b = sub.add_parser("buttons")
    b.add_argument("--rounds", type=int, default=20)
    b.add_argument("--run", type=Path, help="press them during a run kept in this folder")
    r = sub.add_parser("run")
    r.add_argument("--world", default="worlds/nursing_home.yaml")
    r.add_argument("--duration", type=float, default=600)
    r.add_argument("--seed", type=int, default=3)
    r.add_argument("--tablet", action="store_true")
    r.add_argument("--clients", type=int, default=0)
    r.add_argument("--out", type=Path, required=True)
    t = sub.add_parser("ticks")
    t.add_argument("--world", default="worlds/nursing_home.yaml")
    t.add_argument("--duration", type=float, default=600)
    t.add_argument("--seed", type=int, default=3)
    t.add_argument("--out", type=Path, required=True)
    c = sub.add_parser("compare")
    c.add_argument("base", type=Path)
    c.add_argument("other", type=Path)
    args = parser.parse_args()
    if args.what == "buttons":
        result = buttons_in_a_run(args.rounds, args.run) if args.run else buttons(args.rounds)
    elif args.what == "run":
        result = run(args)
    elif args.what == "ticks":
        result = ticks(args)
    else:
        result = compare(args.base, args.other)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
