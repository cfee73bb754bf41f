"""``VqgQuestionGenerator``: questions about a camera frame from the trained VQG model.

``ask(frame, n)`` downscales the RGB frame to the model's input size, encodes it once (E_I),
draws ``n * decode.oversample`` latent codes from the prior (uniform categories, or N(0, I)
for the Gaussian ablation), decodes one question per code (greedy words by default), drops
those the generator itself finds unlikely (mean log-probability per word below
``decode.min_logprob``) and, with ``decode.fact_check``, those whose meaning the fact
verifier (perception/vqg/verify.py) finds unlikely in the frame (below
``decode.min_fact_prob``), and returns up to ``n`` distinct questions, best first: most
often decoded first, ties broken by the mean log-probability.

A model file (``assets/models/vqg.pt``) stores the vocabulary, the model config, the input
size and the weights in fp16; it loads with ``weights_only=True``. Decoding settings are
not part of it: they come from the ``decode`` section of the config.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import torch

from core.checkpoint import atomic_torch_save, fp16_state, fp32_state, read_weights
from core.errors import UserError
from core.torch_threads import torch_threads
from perception.vqg.config import (
    REPO_ROOT,
    DecodeConfig,
    ModelConfig,
    VqgConfig,
    load_vqg_config,
)
from perception.vqg.frames import prepare_frame
from perception.vqg.model import VqgModel
from perception.vqg.verify import FactVerifier
from textnets.vocab import Vocab

FORMAT = "companion-vqg-1"
DEFAULT_VQG_MODEL = REPO_ROOT / "assets" / "models" / "vqg.pt"


class VqgModelError(UserError):
    """A VQG model file is missing, unreadable or inconsistent."""


@dataclass(frozen=True)
class Screening:
    """The questions that passed the checks, best first, and what became of the others:
    ``decoded`` latent codes, of which ``empty`` gave no words and ``unsure`` failed the
    confidence check; the rest were ``distinct`` different questions, which the fact check
    (when there is one) then screened."""

    questions: list[str]
    decoded: int
    empty: int
    unsure: int
    distinct: int


def save_vqg(path: Path, model: VqgModel, vocab: Vocab, cfg: VqgConfig,
             meta: dict[str, Any]) -> None:
    """Write a model file atomically; floating-point weights are stored as fp16."""
    state = fp16_state(model)
    atomic_torch_save({"format": FORMAT, "vocab": list(vocab.itos),
                       "model": cfg.model.model_dump(mode="json"),
                       "input": [cfg.data.image_width, cfg.data.image_height],
                       "state_dict": state, "meta": meta}, path)


class VqgQuestionGenerator:
    """The :class:`behaviours.context.QuestionGenerator` of the trained VQG model.

    Decoding runs with one torch thread; ``seed`` fixes the stream of latent codes.
    """

    def __init__(self, model: VqgModel, vocab: Vocab, size: tuple[int, int],
                 decode: DecodeConfig, meta: dict | None = None, seed: int = 0,
                 verifier: FactVerifier | None = None) -> None:
        self.model, self.vocab, self.size, self.decode = model, vocab, size, decode
        self.meta = meta or {}
        self.verifier = verifier
        self.gen = torch.Generator().manual_seed(seed)

    @classmethod
    def load(cls, path: str | Path = DEFAULT_VQG_MODEL, seed: int = 0,
             decode: DecodeConfig | None = None) -> VqgQuestionGenerator:
        """Load a model file; a missing or broken one raises :class:`VqgModelError`.

        Decoding follows ``decode``, by default ``decode`` of ``config/vqg.yaml``;
        with its ``fact_check`` the fact verifier is loaded too."""
        path = Path(path)
        blob = read_weights(path, VqgModelError, "train one with `companion train vqg`")
        if not isinstance(blob, dict) or blob.get("format") != FORMAT:
            raise VqgModelError(f"{path}: not a VQG model file")
        try:
            vocab = Vocab(blob["vocab"])
            model = VqgModel(len(vocab), ModelConfig(**blob["model"]))
            width, height = (int(v) for v in blob["input"])
            model.load_state_dict(fp32_state(blob["state_dict"]))
        except Exception as exc:
            raise VqgModelError(f"{path}: invalid VQG model file ({exc})") from None
        decode = decode or load_vqg_config().decode
        checker = decode.verifier_path()
        verifier = None if checker is None else FactVerifier.load(checker, VqgModelError)
        return cls(model.eval(), vocab, (width, height), decode, blob.get("meta"), seed,
                   verifier)

    def image_input(self, frame: np.ndarray) -> torch.Tensor:
        """An RGB frame as the model's uint8 input ``(3, H, W)``."""
        return prepare_frame(frame, *self.size)

    def sample(self, image: torch.Tensor, k: int) -> list[tuple[str, float]]:
        """``k`` questions (with their mean log-probability per word), one per latent code
        drawn from the prior, for one uint8 image ``(3, H, W)``."""
        was_training = self.model.training
        self.model.eval()
        with torch.no_grad(), torch_threads(1):
            f = self.model.image(self.model.image.features(image[None])).expand(k, -1)
            z = self.model.encoder.latent.prior(k, self.gen)
            ids, logp = self.model.decode(f, z, self.decode.max_words, self.decode.greedy,
                                          self.decode.temperature, self.gen)
        self.model.train(was_training)
        return [(" ".join(self.vocab.decode(row)), float(lp))
                for row, lp in zip(ids.tolist(), logp, strict=True)]

    def screen(self, image: torch.Tensor, k: int) -> Screening:
        """The distinct questions decoded from ``k`` latent codes, best first (most often
        decoded, then most probable), with the count each check dropped. The confidence check
        drops questions whose mean log-probability per word is below ``decode.min_logprob``,
        the fact check (when a verifier is loaded) those whose meaning is a fact it rates
        below ``decode.min_fact_prob`` in this image."""
        sampled = self.sample(image, k)
        drawn = [(q, lp) for q, lp in sampled if q and lp >= self.decode.min_logprob]
        empty = sum(not q for q, _ in sampled)
        counts = Counter(q for q, _ in drawn)
        best: dict[str, float] = {}
        for q, lp in drawn:
            best[q] = max(lp, best.get(q, -np.inf))
        ranked = sorted(counts, key=lambda q: (-counts[q], -best[q]))
        kept = ranked
        if self.verifier is not None:
            with torch_threads(1):
                probs = self.verifier.plausibility(image, ranked)
            kept = [q for q, p in zip(ranked, probs, strict=True)
                    if p is None or p >= self.decode.min_fact_prob]
        return Screening(kept, k, empty, len(sampled) - empty - len(drawn), len(ranked))

    def questions(self, image: torch.Tensor, k: int) -> list[str]:
        """The questions of :meth:`screen`, best first."""
        return self.screen(image, k).questions

    def ask_screened(self, frame: np.ndarray, n: int) -> Screening:
        """:meth:`screen` of the RGB frame (``n * decode.oversample`` codes), cut to ``n``."""
        screening = self.screen(self.image_input(frame), n * self.decode.oversample)
        return replace(screening, questions=screening.questions[:n])

    def ask(self, frame: np.ndarray, n: int) -> list[str]:
        """Up to ``n`` distinct questions about the RGB frame, best first."""
        return self.ask_screened(frame, n).questions if n > 0 else []
