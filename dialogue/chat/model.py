"""The chit-chat bot (thesis §3.3, §4.2): an LSTM encoder-decoder with Luong attention.

* Encoder: a ``layers``-deep bidirectional LSTM over the utterance (packed, so padding never
  reaches it); its final states, the two directions side by side, start the decoder.
* Decoder: a ``layers``-deep LSTM over ``<bos> + reply``. At every step Luong's "general"
  attention scores the encoder outputs, the context and the decoder output go through
  ``tanh(W_c [c; h])`` to the embedding size, and the output layer is the transposed word
  embedding (tied weights, one matrix for encoder, decoder and output).
* Loss: teacher-forced cross-entropy summed over real reply tokens (padding excluded).

:class:`ChitChatModel` wraps a trained file and implements the dialogue manager's
``ChitChat`` protocol.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn
from torch.nn.utils.rnn import pack_padded_sequence, pad_packed_sequence

from app.core.checkpoint import atomic_torch_save, read_weights
from app.core.errors import UserError
from dialogue.chat.config import ChatDecodeConfig, ChatModelConfig
from dialogue.chat.training.data import PAD_ID, UNK_ID, Batch, Vocab, detokenize, tokenize

FORMAT = "companion-chat-1"
FALLBACK = "I see. Tell me more."
MAX_CHARS = 2000  # longer input is cut before tokenising
State = tuple[torch.Tensor, torch.Tensor]


class ChatModelError(UserError):
    """A chit-chat model file is missing, unreadable or inconsistent."""


class Seq2Seq(nn.Module):
    """Encoder-decoder LSTM with Luong (general) attention and tied embeddings."""

    def __init__(self, vocab_size: int, cfg: ChatModelConfig) -> None:
        super().__init__()
        self.cfg = cfg
        e, h, n = cfg.embedding, cfg.hidden, cfg.layers
        inner = cfg.dropout if n > 1 else 0.0
        self.embed = nn.Embedding(vocab_size, e, padding_idx=PAD_ID)
        self.encoder = nn.LSTM(e, h // 2 if cfg.bidirectional else h, n, batch_first=True,
                               dropout=inner, bidirectional=cfg.bidirectional)
        self.decoder = nn.LSTM(e, h, n, batch_first=True, dropout=inner)
        self.attn = nn.Linear(h, h, bias=False)  # score(h_t, h_s) = h_t^T W_a h_s
        self.combine = nn.Linear(2 * h, e)  # attentional vector, embedding-sized for tying
        self.out_bias = nn.Parameter(torch.zeros(vocab_size))
        self.drop = nn.Dropout(cfg.dropout)
        nn.init.normal_(self.embed.weight, std=e ** -0.5)
        with torch.no_grad():
            self.embed.weight[PAD_ID].zero_()

    def encode(self, src: torch.Tensor, src_mask: torch.Tensor) -> tuple[torch.Tensor, State]:
        """Encoder outputs ``(B, S, H)`` and the decoder's initial state."""
        lengths = src_mask.sum(1).clamp(min=1).cpu()
        packed = pack_padded_sequence(self.drop(self.embed(src)), lengths, batch_first=True,
                                      enforce_sorted=False)
        out, (h, c) = self.encoder(packed)
        out, _ = pad_packed_sequence(out, batch_first=True, total_length=src.shape[1])
        if self.cfg.bidirectional:  # (2L, B, H/2) -> (L, B, H): directions side by side
            h, c = (torch.cat([x[0::2], x[1::2]], dim=-1) for x in (h, c))
        return out, (h.contiguous(), c.contiguous())

    def decode(self, tgt_in: torch.Tensor, state: State, enc_out: torch.Tensor,
               src_mask: torch.Tensor) -> tuple[torch.Tensor, State, torch.Tensor]:
        """Logits ``(B, T, V)``, the new state and attention weights ``(B, T, S)``."""
        dec_out, state = self.decoder(self.drop(self.embed(tgt_in)), state)
        scores = torch.bmm(self.attn(dec_out), enc_out.transpose(1, 2))
        scores = scores.masked_fill(~src_mask[:, None, :], float("-inf"))
        weights = torch.softmax(scores, dim=-1)
        context = torch.bmm(weights, enc_out)
        att = self.drop(torch.tanh(self.combine(torch.cat([context, dec_out], dim=-1))))
        logits = F.linear(att, self.embed.weight, self.out_bias)
        return logits, state, weights

    def step(self, tok: torch.Tensor, state: State, enc_out: torch.Tensor,
             src_mask: torch.Tensor) -> tuple[torch.Tensor, State]:
        """One decoding step for tokens ``(K,)``: logits ``(K, V)`` and the new state.

        The same computation as :meth:`decode` with ``T = 1`` in eval mode, written with
        plain matrix products: on a CPU this is about twice as fast as calling the LSTM.
        """
        inp, hs, cs = self.embed(tok), [], []
        for layer in range(self.cfg.layers):
            gates = F.linear(inp, getattr(self.decoder, f"weight_ih_l{layer}"),
                             getattr(self.decoder, f"bias_ih_l{layer}")) + F.linear(
                state[0][layer], getattr(self.decoder, f"weight_hh_l{layer}"),
                getattr(self.decoder, f"bias_hh_l{layer}"))
            i, f, g, o = gates.chunk(4, dim=-1)
            c = torch.sigmoid(f) * state[1][layer] + torch.sigmoid(i) * torch.tanh(g)
            inp = torch.sigmoid(o) * torch.tanh(c)
            hs.append(inp)
            cs.append(c)
        scores = torch.bmm(enc_out, self.attn(inp)[:, :, None])[:, :, 0]
        weights = torch.softmax(scores.masked_fill(~src_mask, float("-inf")), dim=-1)
        context = torch.bmm(weights[:, None, :], enc_out)[:, 0]
        att = torch.tanh(self.combine(torch.cat([context, inp], dim=-1)))
        return F.linear(att, self.embed.weight, self.out_bias), (torch.stack(hs),
                                                                 torch.stack(cs))

    def forward(self, batch: Batch) -> torch.Tensor:
        """Teacher-forced logits ``(B, T, V)`` for ``batch``."""
        enc_out, state = self.encode(batch.src, batch.src_mask)
        return self.decode(batch.tgt_in, state, enc_out, batch.src_mask)[0]

    def token_nll(self, batch: Batch) -> tuple[torch.Tensor, int]:
        """Summed negative log-likelihood of the real reply tokens, and their number."""
        logits = self(batch)
        nll = F.cross_entropy(logits.reshape(-1, logits.shape[-1]), batch.tgt_out.reshape(-1),
                              ignore_index=PAD_ID, reduction="sum")
        return nll, int(batch.tgt_mask.sum())


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

    The conversation context is not used: the model answers one utterance at a time, as the
    thesis's does.
    """

    def __init__(self, net: Seq2Seq, vocab: Vocab, decode: ChatDecodeConfig, max_len: int,
                 meta: dict[str, Any] | None = None, config: dict[str, Any] | None = None
                 ) -> None:
        self.net = net.eval()
        self.vocab = vocab
        self.decode_cfg = decode
        self.max_len = max_len
        self.meta = meta or {}
        self.config = config or {}
        self._gen = torch.Generator().manual_seed(decode.seed) if decode.seed is not None \
            else None

    @classmethod
    def load(cls, path: str | Path, **decode: Any) -> ChitChatModel:
        """Load a model file; keyword arguments override its decoding settings."""
        blob = read_chat_file(path)
        try:
            vocab = Vocab(blob["vocab"])
            cfg = blob["config"]
            net = Seq2Seq(len(vocab), ChatModelConfig(**cfg["model"]))
            dec = ChatDecodeConfig(**{**cfg["decode"], **decode})
            max_len = int(cfg["data"]["max_len"])
            net.load_state_dict(blob["state_dict"])
        except Exception as exc:
            raise ChatModelError(f"{path}: invalid or inconsistent model file ({exc})") from None
        return cls(net, vocab, dec, max_len, blob.get("meta"), cfg)

    def encode_text(self, text: str) -> list[int]:
        """Utterance ids as the model sees them (cut to ``max_len`` tokens)."""
        return self.vocab.encode(tokenize(str(text)[:MAX_CHARS])[: self.max_len]) or [UNK_ID]

    def generate(self, src_ids: list[int]) -> list[int]:
        """Reply ids for one utterance with the configured decoding method."""
        from dialogue.chat.decode import beam_search, sample

        if self.decode_cfg.method == "sample":
            return sample(self.net, src_ids, self.decode_cfg, self._gen)
        return beam_search(self.net, src_ids, self.decode_cfg)

    def reply(self, text: str, context: object = None) -> str:
        """The model's reply to ``text`` (never empty)."""
        with torch.inference_mode():
            ids = self.generate(self.encode_text(text))
        return detokenize(self.vocab.decode(ids)) or FALLBACK
