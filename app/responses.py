"""Whether anyone who spoke to the robot was left without a response: per line said to
it, whether the robot responded within :data:`RESPONDED_WITHIN_S` of its end (an answer,
a request to say it again or come closer, or word that it is coming over), whether it was
answered (after at most one repeat: people here repeat a line once when asked), and how
the robot dealt with the voices it picked up. Scored from a run's events; what was said,
to whom and when it ended only the scoring knows (``line_said``)."""

from __future__ import annotations

from typing import Any

from robot.percepts import AUDIENCES

RESPONDED_WITHIN_S = 15.0
NOT_ANSWERS = ("say_again", "not_understood", "coming_over")   # responses, not answers


def _repeats_of(said: dict[int, dict[str, Any]], first: dict[str, Any]) -> set[int]:
    """The line numbers of ``first`` and of its speaker's repeats of it (the same words,
    later, said as a repeat)."""
    return {first["line"]} | {s["line"] for s in said.values()
                              if s["how"] == "repeat" and s["line"] > first["line"]
                              and s["person"] == first["person"] and s["text"] == first["text"]}


def response_metrics(events: list[dict[str, Any]]) -> dict[str, int | float | None]:
    """Lines said to the robot (not repeats, not encouragement), those it responded to
    within :data:`RESPONDED_WITHIN_S`, those it answered, and those it ignored (no response
    at all); the voices it picked up (any line, any addressee), those it made words of, those
    of which it made none, the requests to say a line again, and its walks over to a voice
    it could not make out."""
    said = {e["line"]: e for e in events if e["kind"] == "line_said"}
    says = [e for e in events if e["kind"] == "say" and e.get("line") is not None]
    firsts = [s for s in said.values() if s["how"] == "say" and s["to"] in AUDIENCES]
    responded = answered = ignored = 0
    for first in firsts:
        lines = _repeats_of(said, first)
        replies = [e for e in says if e["line"] in lines]
        responded += any(e["t"] - first["ended"] <= RESPONDED_WITHIN_S for e in replies)
        answered += any(e.get("route") not in NOT_ANSWERS for e in replies)
        ignored += not replies
    made_out = {e["line"] for e in events if e["kind"] in ("heard", "overheard")}
    unmade = {e["line"] for e in events if e["kind"] == "not_made_out"}
    return {
        "lines_responded": responded,
        "lines_responded_share": round(responded / len(firsts), 4) if firsts else None,
        "lines_answered_at_all": answered,
        "lines_ignored": ignored,
        "voices_detected": len(made_out | unmade),
        "voices_made_out": len(made_out),
        "voices_not_made_out": len(unmade - made_out),
        "voices_asked_again": sum(e.get("route") == "say_again" for e in says),
        "voices_approached": sum(e["kind"] == "action" and e["action"] == "find_people"
                                 and e.get("reason") == "asked" for e in events),
    }
