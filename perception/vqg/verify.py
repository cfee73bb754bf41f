"""``FactVerifier``: how likely the meaning of a question holds in an image, from the image.

An image encoder E_I (the VQG model's CNN, trained from scratch) with a multi-label head
that predicts which grounded facts of the data set's scene graphs are true in an image:
the ``fact:`` columns of E_I's pre-training when ``train.image_targets`` includes
``facts`` (perception/vqg/training/train.py). The question generator reads its own questions back to
their meaning (:func:`perception.vqg.questions.parse_question`) and drops those whose fact
the verifier finds unlikely in the frame: a generate-then-check step, with the check
learned from images like the generator (it never sees a scene graph at run time).

A verifier file stores the fact keys (``repr(frame_key(frame))``), the model config of
E_I, the input size and the fp16 weights; it loads with ``weights_only=True``.
"""

from __future__ import annotations

from pathlib import Path

import torch
import torch.nn.functional as F  # noqa: N812
from torch import nn

from core.checkpoint import atomic_torch_save, fp16_state, fp32_state, read_weights
from perception.vqg.config import DEFAULT_VERIFIER, ModelConfig
from perception.vqg.model import ImageEncoder
from perception.vqg.questions import frame_key, parse_question

FORMAT = "companion-vqg-verifier-1"
__all__ = ["DEFAULT_VERIFIER", "FactVerifier", "verifier_from_pretraining"]


class FactVerifier(nn.Module):
    """E_I and a linear head: one logit per fact key."""

    def __init__(self, cfg: ModelConfig, keys: list[str], size: tuple[int, int]) -> None:
        super().__init__()
        self.cfg, self.keys, self.size = cfg, list(keys), size
        self.index = {k: j for j, k in enumerate(self.keys)}
        self.image = ImageEncoder(cfg)
        self.head = nn.Linear(cfg.feature_dim, len(self.keys))

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        """Fact logits ``(B, facts)`` of uint8 images ``(B, 3, H, W)``."""
        return self.head(self.image(self.image.features(images)))

    def plausibility(self, image: torch.Tensor, questions: list[str]) -> list[float | None]:
        """Per question, the predicted probability that its meaning holds in the uint8
        image ``(3, H, W)`` (resized to the verifier's input if need be); None for a
        question that does not parse or whose meaning is not one of the verifier's facts."""
        keys = []
        for q in questions:
            frame = parse_question(q)
            keys.append(None if frame is None else self.index.get(repr(frame_key(frame))))
        if all(k is None for k in keys):
            return [None] * len(questions)
        batch = image[None]
        if tuple(batch.shape[-2:]) != (self.size[1], self.size[0]):
            batch = F.interpolate(batch.float(), size=(self.size[1], self.size[0]),
                                  mode="area").round().to(torch.uint8)
        with torch.no_grad():
            probs = torch.sigmoid(self(batch))[0]
        return [None if k is None else float(probs[k]) for k in keys]

    def save(self, path: Path, meta: dict) -> None:
        """Write the verifier file atomically (weights in fp16)."""
        state = fp16_state(self)
        atomic_torch_save({"format": FORMAT, "keys": self.keys,
                           "model": self.cfg.model_dump(mode="json"), "input": list(self.size),
                           "state_dict": state, "meta": meta}, path)

    @classmethod
    def load(cls, path: str | Path, error: type[Exception]) -> FactVerifier:
        """Load a verifier file; a missing or broken one raises ``error`` naming the path."""
        path = Path(path)
        blob = read_weights(path, error, "train one with `companion train vqg` and "
                            "`train.image_targets: [words, facts]`")
        if not isinstance(blob, dict) or blob.get("format") != FORMAT:
            raise error(f"{path}: not a VQG fact-verifier file")
        try:
            width, height = (int(v) for v in blob["input"])
            verifier = cls(ModelConfig(**blob["model"]), blob["keys"], (width, height))
            verifier.load_state_dict(fp32_state(blob["state_dict"]))
        except Exception as exc:
            raise error(f"{path}: invalid VQG fact-verifier file ({exc})") from None
        return verifier.eval()


def verifier_from_pretraining(encoder: ImageEncoder, head: nn.Linear, names: list[str],
                              cfg: ModelConfig, size: tuple[int, int]) -> FactVerifier:
    """The verifier made of a pre-trained E_I and the ``fact:`` rows of its head."""
    rows = [j for j, n in enumerate(names) if n.startswith("fact:")]
    verifier = FactVerifier(cfg, [names[j][len("fact:"):] for j in rows], size)
    verifier.image.load_state_dict(encoder.state_dict())
    with torch.no_grad():
        verifier.head.weight.copy_(head.weight[rows])
        verifier.head.bias.copy_(head.bias[rows])
    return verifier.eval()
