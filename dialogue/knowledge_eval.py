"""``companion eval knowledge``: the held-out knowledge questions
(``dialogue/data/knowledge_questions.tsv``) asked through the whole dialogue manager, each
reply marked by the question's answer keywords (docs/knowledge.md)."""

from __future__ import annotations

import statistics
import tempfile
import time
from collections import Counter
from pathlib import Path

from core.files import read_text
from dialogue.qa.base import DialogueError

QUESTIONS_FILE = Path(__file__).resolve().parent / "data" / "knowledge_questions.tsv"
KNOWLEDGE_BAR = 0.80
NOTHING = "-"  # the keywords of a question with nothing real to know: "I don't know" is right


def load_questions(path: str | Path = QUESTIONS_FILE) -> list[tuple[str, str, list[str]]]:
    """``(kind, question, keywords)`` rows of a ``kind<TAB>question<TAB>a|b|c`` file."""
    rows = []
    for n, line in enumerate(read_text(path).splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        parts = line.split("\t")
        if len(parts) != 3 or not all(p.strip() for p in parts):
            raise DialogueError(f"{path}:{n}: expected '<kind><TAB><question><TAB><keywords>'")
        kind, question, keywords = (p.strip() for p in parts)
        rows.append((kind, question, [k.strip().lower() for k in keywords.split("|")]))
    return rows


def mark(reply_text: str, found: bool, keywords: list[str]) -> str:
    """``correct``, ``wrong`` (an answer without any keyword, or one where none was due) or
    ``unanswered`` (the robot said it does not know)."""
    if keywords == [NOTHING]:
        return "correct" if not found else "wrong"
    if not found:
        return "unanswered"
    text = reply_text.lower()
    return "correct" if any(k in text for k in keywords) else "wrong"


def evaluate_knowledge(path: str | Path = QUESTIONS_FILE) -> dict:
    """Each question asked in a fresh conversation of a manager without chit-chat (a question
    routed to chit-chat counts as unanswered), with its mark; totals overall and per kind."""
    from dialogue.manager import DialogueContext, DialogueManager
    from dialogue.qa.bot import QABot

    rows = load_questions(path)
    results = []
    with tempfile.TemporaryDirectory(prefix="companion-eval-") as tmp:
        manager = DialogueManager(QABot.offline(out_dir=tmp))
        times = []
        for kind, question, keywords in rows:
            t0 = time.perf_counter()
            reply = manager.respond(question, "positive", DialogueContext())
            times.append((time.perf_counter() - t0) * 1000)
            results.append({"kind": kind, "question": question, "keywords": keywords,
                            "route": reply.route, "answer": reply.text,
                            "mark": mark(reply.text, reply.found, keywords)})
    total, correct = Counter(r["kind"] for r in results), Counter()
    for r in results:
        correct[r["kind"]] += r["mark"] == "correct"
    marks = Counter(r["mark"] for r in results)
    return {"accuracy": marks["correct"] / max(len(results), 1), "n": len(results),
            "marks": dict(marks), "latency_ms_median": statistics.median(times) if times else 0.0,
            "latency_ms_max": max(times, default=0.0),
            "per_kind": {k: correct[k] / total[k] for k in total}, "results": results}
