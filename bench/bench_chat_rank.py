"""The reply ranking's weights on the chit-chat VALIDATION split (the test split stays unseen).

Each validation line's candidates (beam and retrieved, ``dialogue/chat/rank.py``) and their
score parts are computed once with the most retrieved pairs of the grid; every setting then
keeps its share of them (the ``retrieve`` most similar inputs at ``min_similarity`` or more)
and picks its reply. For each setting: the share of generic replies, distinct-2 and the mean MiniLM
relevance of line and reply (``dialogue/chat/training/relevance.py``), beside plain beam
search. The shipped weights in ``config/chat.yaml`` were chosen from this table.

Usage: python bench/bench_chat_rank.py [--model assets/models/chat.pt] [--json PATH]
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
from pathlib import Path

from dialogue.chat.config import DEFAULT_CHAT_MODEL, ChatDataConfig, load_chat_config
from dialogue.chat.model import ChitChatModel
from dialogue.chat.rank import generic_replies, generic_share
from dialogue.chat.text import detokenize, tokenize
from dialogue.chat.training.data import load_chat_data
from dialogue.chat.training.evaluate import distinct_n
from dialogue.chat.training.relevance import SentenceEmbedder

GRID = {"retrieve": [4, 8, 12], "min_similarity": [0.15, 0.25],
        "match": [0.0, 2.0, 4.0, 6.0], "topic": [0.0, 1.0, 2.0, 4.0],
        "generic_penalty": [0.0, 1.0, 3.0]}


def main() -> None:
    """Print one row per weight setting, best mean relevance first."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", type=Path, default=DEFAULT_CHAT_MODEL)
    ap.add_argument("--json", type=Path, help="also write the rows here")
    args = ap.parse_args()
    most = load_chat_config().rank.model_copy(update={
        "retrieve": max(GRID["retrieve"]), "min_similarity": min(GRID["min_similarity"])})
    model = ChitChatModel.load(args.model, rank=most)
    valid = load_chat_data(ChatDataConfig(**model.config["data"])).splits["valid"]
    lines = [detokenize(src) for src, _ in valid]
    cands = [model.ranker.candidates(model.line_tokens(t), tokenize(t)) for t in lines]
    beam = [model.decoded_reply(t) for t in lines]
    texts = sorted({detokenize(c.tokens) for cs in cands for c in cs} | set(beam))
    embedder = SentenceEmbedder()
    index = {t: i for i, t in enumerate(texts)}
    emb, line_emb = embedder.embed(texts), embedder.embed(lines)
    generic = generic_replies(model.ranker.cfg.generic)

    def figures(name: str, replies: list[str]) -> dict:
        rel = [float(line_emb[i] @ emb[index[r]]) for i, r in enumerate(replies)]
        toks = [tokenize(r) for r in replies]
        return {"setting": name, "relevance": round(statistics.fmean(rel), 4),
                "generic_share": round(statistics.fmean(generic_share(t, generic) == 1.0
                                                        for t in toks), 4),
                "distinct_2": round(distinct_n(toks, 2), 4)}

    rows = []
    for k, least, match, topic, penalty in itertools.product(*GRID.values()):
        picked = []
        for cs in cands:
            found = sorted((c for c in cs if c.source == "retrieved"), key=lambda c: -c.match)
            kept = [c for c in cs if c.source == "beam"] + [
                c for c in found[:k] if c.match >= least]
            picked.append(detokenize(max(kept, key=lambda c, m=match, t=topic, p=penalty:
                                         c.log_p + m * c.match + t * c.topic
                                         - p * c.generic).tokens))
        rows.append(figures(f"retrieve {k}, min_similarity {least:g}, match {match:g}, "
                            f"topic {topic:g}, generic {penalty:g}", picked))
    rows.sort(key=lambda r: -r["relevance"])
    print(json.dumps(figures("beam search alone", beam)))
    for r in rows:
        print(json.dumps(r))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
