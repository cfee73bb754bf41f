"""``companion eval conversation``: the held-out conversation lines
(``dialogue/data/conversation_test.tsv``, written apart from the training lines, never
trained on and never used to choose a setting) answered through the whole dialogue manager,
each line on its own, in a cheerful and in a gloomy mood.

The rubric (docs/conversation.md). A reply **fits** its line when

1. it answers the line's act: a line sharing something (every act but small talk and talk
   about the robot) gets the robot's own reply for that act, the others are answered as
   that act by any route;
2. it names the line's topic (the held-out set's ``topic`` word, or that word less a plural
   "s"), or asks a question about it (the robot read the same topic and calls it by its
   pronoun); a line without a topic passes;
3. it does not contradict the line's feeling (below); and
4. it is not a non sequitur: the cosine of the all-MiniLM-L6-v2 embeddings of line and reply
   (sentence-transformers, full precision: not the robot's 8-bit encoder) is at least
   ``relevance.min_cosine``.

A reply **contradicts** a sad, painful or frightening line when it has an exclamation mark
or opens with a cheerful mood phrase (``openings.positive`` of ``config/mood_style.yaml``);
a happy line when it has a word of ``fallback.contrary.positive`` ("sorry") or opens with a
gloomy phrase. Care signals: **recall** is the share of the care lines that raise an alert
(of any kind; the right kind is reported beside it), **false alerts** the share of the other
lines that raise one.
"""

from __future__ import annotations

import re
import statistics
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from core.files import read_text
from core.torch_threads import torch_threads
from dialogue.acts.config import ACTS, CARE, ActsConfig, load_acts_config
from dialogue.acts.replies import CompanionTalk
from dialogue.qa.base import DialogueError

CHATTY = ("smalltalk", "about_robot")   # acts any route may answer
BARS = {"act_accuracy": 0.90, "fitting": 0.90, "care_recall": 0.95, "false_alerts": 0.02,
        "latency_ms_median": 100.0}
MOODS = ("positive", "negative")
HELDOUT_FILE = Path(__file__).resolve().parent / "data" / "conversation_test.tsv"


@dataclass(frozen=True)
class Line:
    """One held-out line: its act, care signal, topic word ("-": none) and text."""

    act: str
    care: str
    topic: str
    text: str


def load_heldout(path: str | Path = HELDOUT_FILE) -> list[Line]:
    """The rows of an ``act<TAB>care<TAB>topic<TAB>line`` file (``#`` comments)."""
    rows = []
    for n, raw in enumerate(read_text(path).splitlines(), 1):
        if not raw.strip() or raw.startswith("#"):
            continue
        parts = [p.strip() for p in raw.split("\t")]
        if len(parts) != 4 or parts[0] not in ACTS or parts[1] not in CARE or not all(parts):
            raise DialogueError(f"{path}:{n}: expected '<act><TAB><care><TAB><topic><TAB>"
                                f"<line>' with an act in {', '.join(ACTS)} and care in "
                                f"{', '.join(CARE)}")
        rows.append(Line(*parts))
    return rows


def _phrase_at_start(text: str, phrases: list[str]) -> str | None:
    low = text.lower()
    return next((p for p in phrases if low.startswith(p.lower().rstrip(",!:"))), None)


def contradiction(text: str, emotion: str | None, mood_cfg: Any) -> str | None:
    """Why ``text`` contradicts a line of ``emotion`` (None when it does not)."""
    if emotion == "negative":
        if "!" in text:
            return "an exclamation after sad news"
        hit = _phrase_at_start(text, list(mood_cfg.openings.positive))
        return f"opens cheerfully ({hit!r})" if hit else None
    if emotion == "positive":
        low = f" {re.sub(r'[^a-z ]', ' ', text.lower())} "
        word = next((w for w in mood_cfg.fallback.contrary.positive if f" {w} " in low), None)
        if word:
            return f"says {word!r} to good news"
        hit = _phrase_at_start(text, list(mood_cfg.openings.negative))
        return f"opens gloomily ({hit!r})" if hit else None
    return None


def names_topic(line: Line, text: str, talk: CompanionTalk) -> bool:
    """Rubric 2: the reply names the topic, or asks about the topic the robot read."""
    if line.topic == "-":
        return True
    low = text.lower()
    stems = {line.topic, line.topic.removesuffix("s")}
    if any(re.search(rf"\b{re.escape(s)}", low) for s in stems if len(s) > 2):
        return True
    return "?" in text and talk.finder.find(line.text).word in stems


@contextmanager
def _managers(cfg: ActsConfig) -> Iterator[tuple[Any, Any, CompanionTalk]]:
    """The dialogue before (no act model) and after, with the shipped models."""
    from dialogue.factory import shipped_chitchat, shipped_style
    from dialogue.manager import DialogueManager
    from dialogue.qa.bot import QABot

    talk = CompanionTalk.load(staff=False, cfg=cfg)
    chitchat, style = shipped_chitchat(), shipped_style()
    with tempfile.TemporaryDirectory(prefix="companion-eval-") as tmp:
        qa = QABot.offline(out_dir=tmp)
        yield (DialogueManager(qa, chitchat=chitchat, style=style),
               DialogueManager(qa, chitchat=chitchat, style=style, talk=talk), talk)


def evaluate(path: Path | None = None, config: Path | None = None,
             n_examples: int = 12) -> dict[str, Any]:
    """Every figure of the module docstring, the misses and ``n_examples`` examples."""
    from dialogue.chat.training.relevance import SentenceEmbedder
    from dialogue.manager import DialogueContext
    from dialogue.style.mood_config import load_mood_config

    cfg, mood_cfg = load_acts_config(config), load_mood_config()
    lines = load_heldout(path or HELDOUT_FILE)
    judge = SentenceEmbedder()
    counts: Counter[str] = Counter()
    replies: dict[str, list[str]] = {"before": [], **{m: [] for m in MOODS}}
    judged: dict[str, list[dict[str, Any]]] = {m: [] for m in MOODS}  # rubric 1-3, per reply
    times: list[float] = []
    with torch_threads(1), _managers(cfg) as (before, after, talk):
        for line in lines:
            reading = talk.read(line.text)
            alert = talk.model.alert(reading)
            counts["act_right"] += reading.act == line.act
            care_line = line.care != "none"
            counts["care_lines"] += care_line
            counts["care_raised"] += care_line and alert is not None
            counts["care_kind_right"] += care_line and alert == line.care
            counts["false_alerts"] += not care_line and alert is not None
            replies["before"].append(before.respond(line.text, "positive",
                                                    DialogueContext()).text)
            for mood in MOODS:
                start = time.perf_counter()
                reply = after.respond(line.text, mood, DialogueContext())
                times.append(time.perf_counter() - start)
                replies[mood].append(reply.text)
                clash = contradiction(reply.text, cfg.emotion_of(line.act), mood_cfg)
                shared_right = (line.act in CHATTY and reply.act == line.act) or (
                    reply.route == "companion" and reply.act == line.act)
                judged[mood].append({"line": line.text, "act": line.act, "read": reply.act,
                                     "route": reply.route, "reply": reply.text,
                                     "contradiction": clash, "answers_act": shared_right,
                                     "names_topic": names_topic(line, reply.text, talk)})
        cosines = {k: judge.cosines([li.text for li in lines], v) for k, v in replies.items()}
    n = len(lines)
    non_sequiturs = {k: sum(c < cfg.relevance.min_cosine for c in v) for k, v in cosines.items()}
    for mood in MOODS:
        for row, cosine in zip(judged[mood], cosines[mood], strict=True):
            row["relevance"] = round(cosine, 3)
            row["non_sequitur"] = cosine < cfg.relevance.min_cosine
            row["fits"] = (row["answers_act"] and row["names_topic"]
                           and row["contradiction"] is None and not row["non_sequitur"])
            counts[f"fits_{mood}"] += row["fits"]
            counts["contradictions"] += row["contradiction"] is not None
    misses = [row for row in judged["positive"] if not row["fits"]]
    result: dict[str, Any] = {
        "n": n, "act_accuracy": counts["act_right"] / n,
        "fitting": counts["fits_positive"] / n, "fitting_gloomy": counts["fits_negative"] / n,
        "contradictions": counts["contradictions"], "non_sequiturs": non_sequiturs["positive"]
        + non_sequiturs["negative"], "non_sequiturs_before": non_sequiturs["before"],
        "relevance_mean": statistics.fmean(cosines["positive"]),
        "relevance_mean_before": statistics.fmean(cosines["before"]),
        "care_lines": counts["care_lines"],
        "care_recall": counts["care_raised"] / max(counts["care_lines"], 1),
        "care_kind_accuracy": counts["care_kind_right"] / max(counts["care_lines"], 1),
        "false_alerts": counts["false_alerts"] / max(n - counts["care_lines"], 1),
        "latency_ms_median": 1000 * statistics.median(times),
        "misses": misses,
        "examples": [{"line": li.text, "before": b, "after": a} for li, b, a in
                     list(zip(lines, replies["before"], replies["positive"],
                              strict=True))[:: max(n // max(n_examples, 1), 1)][:n_examples]]}
    result["meets_bars"] = {
        "act_accuracy": result["act_accuracy"] >= BARS["act_accuracy"],
        "fitting": min(result["fitting"], result["fitting_gloomy"]) >= BARS["fitting"],
        "contradictions": result["contradictions"] == 0,
        "non_sequiturs": result["non_sequiturs"] == 0,
        "care_recall": result["care_recall"] >= BARS["care_recall"],
        "false_alerts": result["false_alerts"] <= BARS["false_alerts"],
        "latency": result["latency_ms_median"] <= BARS["latency_ms_median"]}
    return result


def print_report(r: dict[str, Any]) -> str:
    """The result as the lines ``companion eval conversation`` prints."""
    ok = r["meets_bars"]

    def mark(key: str) -> str:
        return "meets" if ok[key] else "BELOW"

    out = [f"held-out conversation lines: {r['n']}",
           f"act accuracy         {r['act_accuracy']:.3f} ({mark('act_accuracy')} 0.90)",
           f"fitting replies      {r['fitting']:.3f} cheerful mood, {r['fitting_gloomy']:.3f} "
           f"gloomy ({mark('fitting')} 0.90)",
           f"mood contradictions  {r['contradictions']} ({mark('contradictions')} 0)",
           f"non sequiturs        {r['non_sequiturs']} ({mark('non_sequiturs')} 0); before: "
           f"{r['non_sequiturs_before']} of {r['n']}",
           f"relevance (mean)     {r['relevance_mean']:.3f}; before "
           f"{r['relevance_mean_before']:.3f}",
           f"care recall          {r['care_recall']:.3f} of {r['care_lines']} "
           f"({mark('care_recall')} 0.95); right kind {r['care_kind_accuracy']:.3f}",
           f"false alerts         {r['false_alerts']:.3f} ({mark('false_alerts')} 0.02)",
           f"reply latency        {r['latency_ms_median']:.1f} ms median, one thread "
           f"({mark('latency')} 100 ms)", "", "examples (before -> after):"]
    for e in r["examples"]:
        out += [f"  {e['line']}", f"    before: {e['before']}", f"    after:  {e['after']}"]
    out += ["", f"replies that do not fit ({len(r['misses'])}):"]
    out += [f"  [{m['act']} read {m['read']} via {m['route']}] {m['line']!r} -> {m['reply']!r}"
            + (f" ({m['contradiction']})" if m["contradiction"] else "")
            + ("" if m["names_topic"] else " (topic not named)")
            + (f" (non sequitur: {m['relevance']})" if m["non_sequitur"] else "")
            for m in r["misses"]]
    return "\n".join(out)
