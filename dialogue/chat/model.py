"""The chit-chat bot the robot loads: :class:`ChitChatModel` wraps a trained model file (the
:class:`dialogue.chat.seq2seq.Seq2Seq` network, its vocabulary and config) and implements the
dialogue manager's ``ChitChat`` protocol; decoding is :mod:`dialogue.chat.decode`'s, the
choice among beam and retrieved replies :mod:`dialogue.chat.rank`'s, and the reading of
follow-up lines :mod:`dialogue.chat.follow_up`'s.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import torch

from core.checkpoint import atomic_torch_save, read_weights
from core.errors import UserError
from core.torch_threads import torch_threads
from dialogue.chat.config import (
    ChatDataConfig,
    ChatDecodeConfig,
    ChatFollowUpConfig,
    ChatModelConfig,
    ChatRankConfig,
    load_chat_config,
)
from dialogue.chat.decode import beam_search, sample
from dialogue.chat.follow_up import resolve
from dialogue.chat.pool import pool_path, read_pool
from dialogue.chat.rank import ReplyRanker
from dialogue.chat.seq2seq import Seq2Seq
from dialogue.chat.text import Pair, detokenize, tokenize
from textnets.vocab import UNK_ID, Vocab

FORMAT = "companion-chat-1"
FALLBACK = "I see. Tell me more."
MAX_CHARS = 2000  # longer input is cut before tokenising
log = logging.getLogger("companion.chat")


class ChatModelError(UserError):
    """A chit-chat model file is missing, unreadable or inconsistent."""


def save_chat_model(path: Path, net: Seq2Seq, vocab: Vocab, config: dict[str, Any],
                    meta: dict[str, Any]) -> None:
    """Write a model file loadable with ``torch.load(weights_only=True)``.

    ``config`` is the run's resolved config as plain data (its ``model``, ``data`` and
    ``decode`` sections are kept, so evaluation can rebuild the same test split).
    """
    atomic_torch_save({"format": FORMAT, "vocab": list(vocab.itos),
                       "config": {k: config[k] for k in ("data", "model", "decode")},
                       "state_dict": net.state_dict(), "meta": meta}, path)


def read_chat_file(path: str | Path) -> dict[str, Any]:
    """The stored dict of a chit-chat model file, with clear errors for bad files."""
    blob = read_weights(path, ChatModelError,
                        "train one with `companion train chat --export PATH`")
    if not isinstance(blob, dict) or blob.get("format") != FORMAT:
        raise ChatModelError(f"{path}: not a chit-chat model file (format {FORMAT})")
    return blob


class ChitChatModel:
    """A trained chit-chat model: ``reply(text, context) -> str`` (the ``ChitChat`` protocol).

    With a ``ranker`` (the default when loaded) the reply is the best-ranked of the beam's and
    the retrieved candidates, and the context's earlier lines resolve follow-ups ("she");
    without one, or when sampling, it is the plain decoded reply. Replies are decoded on
    ``threads`` torch threads (default 1), as the style transfer's are: one utterance's
    tensors are small, and on a busy two-core machine a second thread made each reply about a
    hundred times slower (1.8 s instead of 18 ms).
    """

    def __init__(self, net: Seq2Seq, vocab: Vocab, decode: ChatDecodeConfig, max_len: int,
                 meta: dict[str, Any] | None = None, config: dict[str, Any] | None = None,
                 threads: int | None = 1, ranker: ReplyRanker | None = None,
                 follow_up: ChatFollowUpConfig | None = None) -> None:
        self.net = net.eval()
        self.ranker = ranker
        self.follow_up = follow_up or load_chat_config().follow_up
        self.threads = threads
        self.vocab = vocab
        self.decode_cfg = decode
        self.max_len = max_len
        self.meta = meta or {}
        self.config = config or {}
        self._gen = torch.Generator().manual_seed(decode.seed) if decode.seed is not None \
            else None

    @classmethod
    def load(cls, path: str | Path, rank: ChatRankConfig | None = None,
             follow_up: ChatFollowUpConfig | None = None, papaya_dir: Path | None = None,
             **decode: Any) -> ChitChatModel:
        """Load a model file and the retrieval pool beside it; ``rank`` and ``follow_up``
        default to ``config/chat.yaml``'s, keyword arguments override the file's
        decoding settings. The pool's texts are read in place from ``papaya_dir`` (default:
        the Papaya folder of the data config stored in the model, from the repository root)
        and the chatterbot-corpus package. Without a pool the ranking keeps to the beam's
        candidates; pairs whose data is missing or changed are left out, with one warning."""
        blob = read_chat_file(path)
        try:
            vocab = Vocab(blob["vocab"])
            cfg = blob["config"]
            net = Seq2Seq(len(vocab), ChatModelConfig(**cfg["model"]))
            dec = ChatDecodeConfig(**{**cfg["decode"], **decode})
            max_len = int(cfg["data"]["max_len"])
            data_cfg = ChatDataConfig(**cfg["data"])
            net.load_state_dict(blob["state_dict"])
        except Exception as exc:
            raise ChatModelError(f"{path}: invalid or inconsistent model file ({exc})") from None
        if rank is None or follow_up is None:
            defaults = load_chat_config()
            rank, follow_up = rank or defaults.rank, follow_up or defaults.follow_up
        ranker = None
        if rank.enabled:
            folder = papaya_dir if papaya_dir is not None else data_cfg.resolved_papaya()
            ranker = ReplyRanker(net, vocab, _pool(pool_path(path), cfg["data"], folder), rank,
                                 dec)
        return cls(net, vocab, dec, max_len, blob.get("meta"), cfg, ranker=ranker,
                   follow_up=follow_up)

    def line_tokens(self, text: str) -> list[str]:
        """Utterance tokens as the model sees them (cut to ``max_len`` tokens)."""
        return tokenize(str(text)[:MAX_CHARS])[: self.max_len]

    def encode_text(self, text: str) -> list[int]:
        """Utterance ids as the model sees them."""
        return self.vocab.encode(self.line_tokens(text)) or [UNK_ID]

    def generate(self, src_ids: list[int]) -> list[int]:
        """Reply ids for one utterance with the configured decoding method."""
        if self.decode_cfg.method == "sample":
            return sample(self.net, src_ids, self.decode_cfg, self._gen)
        return beam_search(self.net, src_ids, self.decode_cfg)

    def decoded_reply(self, text: str) -> str:
        """The plain decoded reply to ``text``, without ranking or context (never empty)."""
        with torch_threads(self.threads), torch.inference_mode():
            ids = self.generate(self.encode_text(text))
        return detokenize(self.vocab.decode(ids, skip_unknown=True)) or FALLBACK

    def reply(self, text: str, context: object = None) -> str:
        """The model's reply to ``text`` after the person's earlier lines in ``context``
        (never empty)."""
        if self.ranker is None or self.decode_cfg.method == "sample":
            return self.decoded_reply(text)
        said = resolve(str(text)[:MAX_CHARS], context, self.follow_up)
        with torch_threads(self.threads), torch.inference_mode():
            ranked = self.ranker.candidates(self.line_tokens(said.line),
                                            tokenize(said.topic[:MAX_CHARS]))
        replies = [detokenize(c.tokens) for c in ranked]
        fresh = [r for r in replies if r not in said.robot_said]  # not the same reply again
        return (fresh or replies or [FALLBACK])[0]


def _pool(pool_file: Path, data_config: dict[str, Any], papaya_dir: Path | None) -> list[Pair]:
    """The retrieval pairs beside a model whose data is still as in training (one warning
    for those left out, or for a missing pool)."""
    if not pool_file.is_file():
        log.warning("%s: no retrieval pool; replies come from the beam alone", pool_file)
        return []
    pool = read_pool(pool_file, data_config, papaya_dir)
    if pool.left_out:
        log.warning("%s: %d of %d retrieval pairs left out, their data is missing or changed "
                    "(Papaya folder %s, chatterbot-corpus package); %d remain", pool_file,
                    pool.left_out, pool.total, papaya_dir, len(pool.pairs))
    return pool.pairs
