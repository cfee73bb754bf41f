"""A household run's report: ``metrics.json``, ``timeline.csv`` and the PNG plots."""

from __future__ import annotations

import csv
import io
import json
import math
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

import jiwer
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from app.responses import NOT_ANSWERS, response_metrics
from behaviours.step_record import StepRecord
from core.checkpoint import atomic_write, atomic_write_bytes
from core.events import LineFile
from dialogue.speech.words import spoken_words
from mind.personality import ACTIONS, DRIVES, MOTIVATIONS, STIMULI
from robot.geometry import wrap_angle
from robot.percepts import AUDIENCES

TIMELINE_COLUMNS = ["t", "action", "relieving", *DRIVES, *(f"m_{m}" for m in MOTIVATIONS),
                    *STIMULI, "mood", "mood_positive", "secure"]


class TimelineWriter:
    """``timeline.csv``: the rows of each homeostasis step written whole (a killed run
    leaves no half row)."""

    def __init__(self, path: Path) -> None:
        self._file = LineFile(path)
        self._rows([TIMELINE_COLUMNS])

    def _rows(self, rows: list[list[Any]]) -> None:
        text = io.StringIO()
        csv.writer(text).writerows(rows)
        self._file.write(text.getvalue())

    def write(self, rows: list[dict[str, Any]]) -> None:
        """Append ``rows`` (from :meth:`behaviours.step_record.StepRecord.take`)."""
        if rows:
            self._rows([[r["t"], r["action"], int(r["relieving"]),
                         *np.round(r["drives"], 5), *np.round(r["motivations"], 5),
                         *r["stimuli"].astype(int), round(r["mood"], 5),
                         int(r["mood_positive"]), int(r["secure"])] for r in rows])

    def close(self) -> None:
        """Close the file."""
        self._file.close()


def compute_metrics(steps: StepRecord, events: list[dict[str, Any]]) -> dict[str, Any]:
    """RSR, action counts and time shares, mood share and skill outcomes of one run."""
    n = steps.steps
    started = Counter(e["action"] for e in events if e["kind"] == "action")
    outcomes: dict[str, Counter] = defaultdict(Counter)
    for e in events:
        if e["kind"] == "finished":
            outcomes[e["action"]][e["status"]] += 1
    success = {a: round(c["SUCCESS"] / max(1, c["SUCCESS"] + c["FAILURE"]), 4)
               for a, c in outcomes.items()}
    return {
        "homeostasis_steps": n,
        "rsr": steps.secure_steps / n if n else None,
        "insecure_steps": n - steps.secure_steps,
        "mood_positive_share": steps.mood_positive_steps / n if n else None,
        "actions_started": {a: started.get(a, 0) for a in ACTIONS},
        "action_seconds": {a: steps.action_steps.get(a, 0) for a in ACTIONS},
        "skill_outcomes": {a: dict(c) for a, c in outcomes.items()},
        "skill_success_rate": success,
        "preemptions": sum(e["kind"] == "preempted" for e in events),
        "sentences_said": sum(e["kind"] == "say" for e in events),
        **interaction_metrics(events),
        "max_drive": dict(zip(DRIVES, steps.max_drives.round(4).tolist(), strict=True))
        if steps.max_drives is not None else {},
    }


ANSWERED_WITHIN_S = 15.0  # a line counts as answered when the reply starts this soon


def _original(said: dict[int, dict[str, Any]], line: dict[str, Any]) -> dict[str, Any]:
    """The ``line_said`` event that ``line`` repeats (its speaker's earlier line with the
    same words), or ``line`` itself when it is no repeat."""
    if line["how"] != "repeat":
        return line
    return next((s for s in said.values() if s["line"] < line["line"] and s["how"] != "repeat"
                 and s["person"] == line["person"] and s["text"] == line["text"]), line)


def _a_line_for_the_robot(said: dict[int, dict[str, Any]], line: dict[str, Any]) -> bool:
    """Whether ``line`` (a ``line_said`` event) was said to the robot and is not
    encouragement; a repeat is what it repeats."""
    line = _original(said, line)
    return line["to"] in AUDIENCES and line["how"] != "encourage"


def answer_latencies(events: list[dict[str, Any]]) -> list[float]:
    """Seconds from the end of each line said to the robot (when its speaker's voice
    stopped, which only the scoring knows; for a line typed on the tablet, when it was
    heard) to the start of its reply, for the lines that got one, sorted. Words of
    encouragement, and lines for someone else that the robot took as its own, are not lines
    said to it (what was said is known from the run's ``line_said`` events; a typed line has
    none and counts)."""
    said = {e["line"]: e for e in events if e["kind"] == "line_said"}
    heard = {e["line"]: said.get(e["line"], e).get("ended", e["t"]) for e in events
             if e["kind"] == "heard"
             and (e["line"] not in said or _a_line_for_the_robot(said, said[e["line"]]))}
    first: dict[int, float] = {}
    for e in events:
        if e["kind"] == "say" and e.get("line") in heard and e.get("route") not in NOT_ANSWERS:
            first.setdefault(e["line"], e["t"] - heard[e["line"]])
    return sorted(first.values())


def hearing_metrics(events: list[dict[str, Any]]) -> dict[str, Any]:
    """How the robot heard: lines people said to it (repeats apart), those loud enough to
    make a sound at its microphones, those it made out, those it was unsure of, how often
    it asked for a line again, how often it stopped a reply because someone spoke, and the
    word error rate of its transcripts of lines said to it (against what was said, which
    only the scoring knows); how it made out encouragement and whom lines were for."""
    said = {e["line"]: e for e in events if e["kind"] == "line_said"}
    to_robot = [e for e in said.values() if e["to"] in AUDIENCES and e["how"] == "say"]
    heard = [e for e in events if e["kind"] == "heard" and e["line"] in said]
    refs = [" ".join(spoken_words(said[e["line"]]["text"])) for e in heard]
    return {
        "lines_said": len(to_robot),
        "lines_audible": sum(e["audible"] for e in to_robot),
        "lines_unclear": sum(bool(e.get("unclear")) for e in heard),
        "asked_again": sum(e["kind"] == "say" and e.get("route") == "say_again"
                           for e in events),
        "lines_overheard": sum(e["kind"] == "overheard" for e in events),
        "spoken_over": sum(e["kind"] == "spoken_over" for e in events),   # replies cut
        **encouragement_metrics(said, events),
        **addressee_metrics(said, events),
        "speech_wer": round(jiwer.wer(refs, [e["text"] for e in heard]), 4) if heard else None,
        **bearing_metrics(said, heard),
    }


def bearing_metrics(said: dict[int, dict[str, Any]], heard: list[dict[str, Any]]
                    ) -> dict[str, float | None]:
    """How far (degrees) the robot placed the voices of the lines it heard from where their
    speakers stood (which only the scoring knows): the median and the 90th percentile."""
    errors = [abs(math.degrees(wrap_angle(e["bearing"] - said[e["line"]]["bearing"])))
              for e in heard if "bearing" in said[e["line"]]]
    if not errors:
        return {"bearing_error_deg_median": None, "bearing_error_deg_p90": None}
    return {"bearing_error_deg_median": round(float(np.median(errors)), 1),
            "bearing_error_deg_p90": round(float(np.percentile(errors, 90)), 1)}


def encouragement_metrics(said: dict[int, dict[str, Any]], events: list[dict[str, Any]]
                          ) -> dict[str, int]:
    """The scenario's words of encouragement, and those the robot made out as praise (the
    line itself or the speaker's repeat of it); and every line it took as encouragement."""
    taken = {e["line"] for e in events if e["kind"] == "encouraged"}
    made_out = {_original(said, said[line])["line"] for line in taken if line in said}
    meant = [e["line"] for e in said.values() if e["how"] == "encourage"]
    return {
        "encouragement_said": len(meant),
        "encouragement_made_out": len(made_out.intersection(meant)),
        "encouraged": len(taken),
    }


def addressee_metrics(said: dict[int, dict[str, Any]], events: list[dict[str, Any]]
                      ) -> dict[str, int]:
    """Whom the robot took lines to be for, against whom they were for: lines said to
    someone else, those it took as its own, and lines for it that it took as someone
    else's."""
    last = {e["line"]: e["kind"] for e in events   # the chat may overhear a line Sense took
            if e["kind"] in ("heard", "overheard") and e["line"] in said}
    judged = [(kind, said[line]["to"] in AUDIENCES) for line, kind in last.items()]
    return {
        "lines_for_others": sum(e["to"] not in AUDIENCES for e in said.values()),
        "lines_for_others_taken": judged.count(("heard", False)),
        "lines_for_robot_overheard": judged.count(("overheard", True)),
    }


def interaction_metrics(events: list[dict[str, Any]]) -> dict[str, Any]:
    """How the robot dealt with people: lines said to it, answered within
    :data:`ANSWERED_WITHIN_S` and at all, the median time to the answer, find-people tries
    and successes, questions asked, and answers that were "I don't know"."""
    heard = {e["line"] for e in events if e["kind"] == "heard"}
    replies = [e for e in events if e["kind"] == "say" and e.get("line") in heard
               and e.get("route") not in NOT_ANSWERS]
    latency = answer_latencies(events)
    return {
        **hearing_metrics(events),
        **response_metrics(events),
        "lines_heard": len(heard),
        "lines_answered": sum(d <= ANSWERED_WITHIN_S for d in latency),
        "lines_replied": len(latency),
        "answer_latency_s_median": round(float(np.median(latency)), 2) if latency else None,
        "find_people_tries": sum(e["kind"] == "action" and e["action"] == "find_people"
                                 for e in events),
        "find_people_found": sum(e["kind"] == "person_found" for e in events),
        "questions_asked": sum(e["kind"] == "question" for e in events),
        "questions_grounded": sum(e["kind"] == "question_truth" and e["grounded"]
                                  for e in events),
        "dont_know_answers": sum(e.get("found") is False for e in replies),
        "feedback_given": sum(e["kind"] == "feedback" for e in events),
        "feedback_credited": dict(Counter(f"{e['action']} {'+' if e['reward'] > 0 else '-'}"
                                          for e in events if e["kind"] == "credited")),
        "choices_by_preference": sum(e["kind"] == "action" and e.get("reason") == "preference"
                                     for e in events),
        **conversation_metrics(events),
    }


def conversation_metrics(events: list[dict[str, Any]]) -> dict[str, Any]:
    """What people shared and how the robot met it: the acts of the lines it answered,
    its own replies to them, the feelings heard in them, and the care alerts raised, by
    person and signal."""
    said = [e for e in events if e["kind"] == "say" and e.get("act")]
    alerts = [e for e in events if e["kind"] == "care_alert"]
    return {"acts_answered": dict(Counter(e["act"] for e in said)),
            "companion_replies": sum(e.get("route") == "companion" for e in said),
            "feelings_heard": sum(e["kind"] == "emotion" and bool(e.get("heard"))
                                  for e in events),
            "care_alerts": len(alerts),
            "care_alerts_by": dict(Counter(f"{e['person']} {e['care']}" for e in alerts))}


def write_metrics(metrics: dict[str, Any], path: Path) -> None:
    """Write ``metrics.json`` atomically."""
    atomic_write_bytes(path, (json.dumps(metrics, indent=2) + "\n").encode())


def read_timeline(path: Path) -> dict[str, np.ndarray]:
    """The columns of a ``timeline.csv`` (:data:`TIMELINE_COLUMNS`): ``action`` as text,
    the others as numbers."""
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], rows[1:]
    columns = {name: [r[i] for r in body] for i, name in enumerate(header)}
    return {name: np.array(v) if name == "action" else np.array(v, float)
            for name, v in columns.items()}


def plot_run(timeline: Path, lower: np.ndarray, upper: np.ndarray, threshold: float,
             out: Path) -> list[Path]:
    """``motivations.png``, ``actions.png`` and ``mood.png`` in ``out``, from the run's
    ``timeline.csv``."""
    out.mkdir(parents=True, exist_ok=True)
    series = read_timeline(timeline)
    t = series["t"]
    if not len(t):
        return []
    m = np.stack([series[f"m_{name}"] for name in MOTIVATIONS], axis=1)
    paths = []

    fig, axes = plt.subplots(len(MOTIVATIONS), 1, figsize=(9, 10), sharex=True)
    for i, (ax, name) in enumerate(zip(axes, MOTIVATIONS, strict=True)):
        ax.axhspan(lower[i], upper[i], color="tab:green", alpha=0.15)
        ax.plot(t, m[:, i], lw=1)
        ax.set_ylabel(name.replace("_", "\n"), fontsize=8)
        ax.set_ylim(-0.1, 1.1)
    axes[-1].set_xlabel("simulated time (s)")
    fig.suptitle("Motivations (green: desired range)")
    paths.append(_save(fig, out / "motivations.png"))

    fig, ax = plt.subplots(figsize=(9, 3))
    codes = np.array([ACTIONS.index(a) for a in series["action"]])
    for a in range(len(ACTIONS)):
        on = codes == a
        if on.any():
            ax.broken_barh(_spans(t, on), (a - 0.4, 0.8), color=f"C{a}")
    ax.set_yticks(range(len(ACTIONS)), ACTIONS, fontsize=8)
    ax.set_xlabel("simulated time (s)")
    ax.set_title("Actions")
    paths.append(_save(fig, out / "actions.png"))

    fig, ax = plt.subplots(figsize=(9, 3))
    ax.plot(t, series["mood"], lw=1)
    ax.axhline(threshold, color="k", ls="--", lw=0.8, label="threshold (positive below)")
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("v_mood")
    ax.legend(fontsize=8)
    ax.set_title("Mood (eq. 3.6)")
    paths.append(_save(fig, out / "mood.png"))
    return paths


def _spans(t: np.ndarray, on: np.ndarray) -> list[tuple[float, float]]:
    step = float(t[1] - t[0]) if len(t) > 1 else 1.0
    edges = np.flatnonzero(np.diff(np.r_[0, on.astype(int), 0]))
    return [(float(t[a]) - step, float(t[b - 1] - t[a]) + step)
            for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _save(fig: Any, path: Path) -> Path:
    fig.tight_layout()
    atomic_write(path, lambda fh: fig.savefig(fh, dpi=90, format="png"))
    plt.close(fig)
    return path
