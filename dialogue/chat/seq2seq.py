"""The chit-chat network of the thesis (§3.3, §4.2): an LSTM encoder-decoder with Luong
attention, as a plain ``nn.Module``.

* Encoder: a ``layers``-deep bidirectional LSTM over the utterance (packed, so padding never
  reaches it); its final states, the two directions side by side, start the decoder.
* Decoder: a ``layers``-deep LSTM over ``<bos> + reply``. At every step Luong's "general"
  attention scores the encoder outputs, the context and the decoder output go through
  ``tanh(W_c [c; h])`` to the embedding size, and the output layer is the transposed word
  embedding (tied weights, one matrix for encoder, decoder and output).
* Loss: teacher-forced cross-entropy summed over real reply tokens (padding excluded).
"""

from __future__ import annotations

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn
from torch.nn.utils.rnn import pack_padded_sequence, pad_packed_sequence

from dialogue.chat.batch import Batch
from dialogue.chat.config import ChatModelConfig
from textnets.vocab import PAD_ID

State = tuple[torch.Tensor, torch.Tensor]


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

    def attend(self, tgt_in: torch.Tensor, state: State, enc_out: torch.Tensor,
               src_mask: torch.Tensor) -> tuple[torch.Tensor, State, torch.Tensor]:
        """Attentional vectors ``(B, T, E)``, the new state and attention weights
        ``(B, T, S)``; :meth:`logits` turns the vectors into word scores."""
        dec_out, state = self.decoder(self.drop(self.embed(tgt_in)), state)
        scores = torch.bmm(self.attn(dec_out), enc_out.transpose(1, 2))
        scores = scores.masked_fill(~src_mask[:, None, :], float("-inf"))
        weights = torch.softmax(scores, dim=-1)
        context = torch.bmm(weights, enc_out)
        att = self.drop(torch.tanh(self.combine(torch.cat([context, dec_out], dim=-1))))
        return att, state, weights

    def logits(self, att: torch.Tensor) -> torch.Tensor:
        """Word scores of attentional vectors (the tied output layer)."""
        return F.linear(att, self.embed.weight, self.out_bias)

    def decode(self, tgt_in: torch.Tensor, state: State, enc_out: torch.Tensor,
               src_mask: torch.Tensor) -> tuple[torch.Tensor, State, torch.Tensor]:
        """Logits ``(B, T, V)``, the new state and attention weights ``(B, T, S)``."""
        att, state, weights = self.attend(tgt_in, state, enc_out, src_mask)
        return self.logits(att), state, weights

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
        return self.logits(att), (torch.stack(hs), torch.stack(cs))

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
