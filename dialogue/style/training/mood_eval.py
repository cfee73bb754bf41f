"""``companion eval mood-style``: what the robot finally says in each mood, on its own lines.

The lines are held out from everything the style model and the gate's language model learnt
(:func:`dialogue.style.training.conversation.heldout_lines`, less any line that is also a
Yelp training sentence, such as "Are you serious?"). Each is said in both moods
through :class:`dialogue.style.mood.MoodStyler`; per mood the result holds

* ``flip_rate``: share of spoken outputs the judge puts on the mood's side (bar >= 80 %),
  and ``flip_rate_needed`` among the lines the judge put on the other side before;
* ``perplexity_ratio``: bigram corpus perplexity of the outputs over that of the unstyled
  lines (bar <= 1.2), with the median of the per-line ratios;
* ``content_kept``: mean share of each line's content words the output keeps (bar >= 70 %);
* ``share``: where the outputs came from (model, fallback, kept, unchanged).
"""

from __future__ import annotations

import math
import statistics
from typing import Any

from dialogue.style.config import load_style_config
from dialogue.style.mood import SOURCES, MoodReply, MoodStyler, content_kept
from dialogue.style.ngram import BigramLM
from dialogue.style.text import STYLES, tokenize
from dialogue.style.training.conversation import heldout_lines, training_lines
from dialogue.style.training.data import load_splits
from dialogue.style.training.mood_lm import ALL_CONVERSATION

BARS = {"flip_rate": (">=", 0.8), "perplexity_ratio": ("<=", 1.2), "content_kept": (">=", 0.7)}


def corpus_perplexity(lm: BigramLM, sentences: list[list[str]]) -> float:
    """``exp(total NLL / total words)`` with each sentence's end counted as a word."""
    nll = -sum(lm.logprob(s) for s in sentences)
    return math.exp(nll / sum(len(s) + 1 for s in sentences))


def mood_figures(styler: MoodStyler, lines: list[str], replies: list[MoodReply], mood: str
                 ) -> dict[str, Any]:
    """The figures of one mood (module docstring)."""
    needed = [r for r, s in zip(replies, lines, strict=True)
              if styler.side(tokenize(s)) != mood]
    said = [tokenize(r.text) for r in replies]
    unstyled = [tokenize(s) for s in lines]
    ratio = corpus_perplexity(styler.lm, said) / corpus_perplexity(styler.lm, unstyled)
    return {
        "flip_rate": sum(r.judged == mood for r in replies) / len(replies),
        "flip_rate_needed": (sum(r.judged == mood for r in needed) / len(needed)
                             if needed else float("nan")),
        "needed": len(needed),
        "perplexity_ratio": ratio,
        "perplexity_ratio_median": statistics.median(r.perplexity_ratio for r in replies),
        "content_kept": statistics.fmean(r.content_kept for r in replies),
        "changed": _changed(replies),
        "raw_model": _raw(styler, lines, replies, mood),
        "share": {s: sum(r.source == s for r in replies) / len(replies)
                  for s in SOURCES},
        "refusals": _refusal_kinds(replies),
    }


def _changed(replies: list[MoodReply]) -> dict[str, float]:
    """Median perplexity ratio and mean content kept of the outputs that differ from the
    unstyled line (the model's and the fallback's), so unchanged lines do not flatter them."""
    changed = [r for r in replies if r.source in ("model", "fallback")]
    if not changed:
        return {"lines": 0}
    return {"lines": len(changed),
            "perplexity_ratio_median": statistics.median(r.perplexity_ratio for r in changed),
            "perplexity_ratio_model_median": statistics.median(
                [r.perplexity_ratio for r in changed if r.source == "model"] or [float("nan")]),
            "content_kept": statistics.fmean(r.content_kept for r in changed)}


def _raw(styler: MoodStyler, lines: list[str], replies: list[MoodReply], mood: str
         ) -> dict[str, float]:
    """The model's own replies, before the gate, on the lines that needed a change and that
    it decoded: what the robot would say without the gate."""
    pairs = [(tokenize(s), tokenize(r.candidate)) for s, r in zip(lines, replies, strict=True)
             if r.source != "unchanged" and r.candidate]
    if not pairs:
        return {"lines": 0}
    return {"lines": len(pairs),
            "flip_rate": sum(styler.side(b) == mood for _, b in pairs if b) / len(pairs),
            "content_kept": statistics.fmean(content_kept(a, b) for a, b in pairs),
            "perplexity_ratio_median": statistics.median(styler.ratio(a, b) for a, b in pairs),
            "said": sum(r.source == "model" for r in replies) / len(pairs)}


def _refusal_kinds(replies: list[MoodReply]) -> dict[str, int]:
    """How often each gate condition refused the model's reply."""
    kinds = {"judge": "judge", "question": "question", "number": "number",
             "content": "content words", "word pair": "never seen", "perplexity": "perplexity"}
    counts = dict.fromkeys([*kinds, "not decoded"], 0)
    for r in replies:
        if r.source != "fallback":
            continue
        kind = next((k for k, w in kinds.items() if w in (r.reason or "")), "not decoded")
        counts[kind] += 1
    return counts


def evaluate_mood(styler: MoodStyler, limit: int = 500, examples: int = 30) -> dict[str, Any]:
    """Say ``limit`` held-out robot lines in both moods and score them."""
    yelp = load_splits(load_style_config().data)["train"].sentences
    lines = heldout_lines(limit, training_lines(ALL_CONVERSATION) + yelp)
    replies = {mood: [styler.style(s, mood) for s in lines] for mood in STYLES}
    result: dict[str, Any] = {"lines": len(lines)}
    for mood in STYLES:
        result[mood] = mood_figures(styler, lines, replies[mood], mood)
    result["bars_met"] = all(_meets(result[m][k], *BARS[k]) for m in STYLES for k in BARS)
    result["examples"] = [
        [lines[i], *(replies[m][i].text for m in ("positive", "negative")),
         *(replies[m][i].source for m in ("positive", "negative")),
         *(replies[m][i].candidate for m in ("positive", "negative"))]
        for i in example_rows(replies, len(lines), examples)]
    return result


def example_rows(replies: dict[str, list[MoodReply]], n: int, examples: int) -> list[int]:
    """Rows to show: the first lines where the model's reply was said (a fifth of them at
    most), then lines spread evenly over the rest."""
    said = [i for i in range(n) if any(replies[m][i].source == "model" for m in STYLES)]
    rows = said[:examples // 5]
    step = max(1, n // examples)
    rows += [i for i in range(0, n, step) if i not in rows][:examples - len(rows)]
    return sorted(rows)


def _meets(value: float, op: str, bar: float) -> bool:
    return value >= bar if op == ">=" else value <= bar


def format_mood(result: dict[str, Any]) -> str:
    """Plain-text lines with each mood's figures against the bars."""
    lines = [f"{result['lines']} held-out robot lines; bars: flip >= 80 %, perplexity ratio "
             "<= 1.2, content kept >= 70 %"]
    for mood in STYLES:
        r = result[mood]
        share = ", ".join(f"{k} {v * 100:.1f} %" for k, v in r["share"].items())
        changed = r["changed"].get("perplexity_ratio_median", 1.0)
        lines.append(f"{mood:8s} flip {r['flip_rate'] * 100:5.1f} % (of the {r['needed']} "
                     f"that needed it: {r['flip_rate_needed'] * 100:5.1f} %), perplexity ratio "
                     f"{r['perplexity_ratio']:.3f} (median {r['perplexity_ratio_median']:.3f}), "
                     f"content kept {r['content_kept'] * 100:5.1f} %; {share}; changed lines: "
                     f"median perplexity ratio {changed:.3f}")
        raw = r["raw_model"]
        if raw["lines"]:
            lines.append(f"{'':8s} the model alone on the {raw['lines']} it decoded: flip "
                         f"{raw['flip_rate'] * 100:.1f} %, content kept "
                         f"{raw['content_kept'] * 100:.1f} %, median perplexity ratio "
                         f"{raw['perplexity_ratio_median']:.3f}; the gate let "
                         f"{raw['said'] * 100:.1f} % through")
    lines.append("all bars met" if result["bars_met"] else "some bar NOT met")
    return "\n".join(lines)


def _cell(text: str, source: str, model: str) -> str:
    """A table cell: the spoken text, where it came from and, after a fallback, the model's
    refused reply."""
    out = text + (f" ({source})" if source else "")
    if source == "fallback" and model:
        out += f" [model: {model}]"
    return out.replace("|", "\\|")


def examples_table(result: dict[str, Any]) -> str:
    """A Markdown table of the examples: unstyled, positive and negative output."""
    rows = ["| Unstyled | Positive mood | Negative mood |", "| --- | --- | --- |"]
    for s, pos, neg, pos_src, neg_src, pos_model, neg_model in result["examples"]:
        cells = [_cell(s, "", ""), _cell(pos, pos_src, pos_model), _cell(neg, neg_src, neg_model)]
        rows.append(f"| {' | '.join(cells)} |")
    return "\n".join(rows) + "\n"
