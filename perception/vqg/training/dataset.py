"""The VQG data set as tensors: questions, the vocabulary, and images cached as uint8.

A data set folder (``companion data vqg``) holds ``images/{split}/NNNNNN.png`` (RGB
320x240), ``scenes/{split}/NNNNNN.json`` and ``questions/{split}.jsonl`` (one
``{"id", "questions"}`` object a line, questions already tokenised: lower case, single
spaces, "?" apart). Images are downscaled once to the model's input size (area
interpolation) and kept as one uint8 tensor file per split in the run folder, so training
never decodes a PNG twice. The vocabulary (:class:`dialogue.style.training.data.Vocab`) is built
from the training questions only.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import cv2
import torch

from core.checkpoint import atomic_torch_save
from core.errors import UserError
from core.files import DATA_LIMIT, FileReadError, read_text
from perception.vqg.frames import prepare_frame
from textnets.vocab import Vocab

SPLITS = ("train", "val", "test")


class VqgDataError(UserError):
    """The VQG data set folder is missing or malformed."""


@dataclass
class SplitData:
    """One split: image ids, each image's questions (token lists) and the images."""

    ids: list[str]
    questions: list[list[list[str]]]
    images: torch.Tensor  # uint8 (N, 3, H, W)

    def pairs(self, vocab: Vocab, max_words: int) -> tuple[list[list[int]], list[int]]:
        """Id sequences of the questions of at most ``max_words`` words, and their image's
        index."""
        seqs, owner = [], []
        for i, qs in enumerate(self.questions):
            for q in qs:
                if len(q) <= max_words:
                    seqs.append(vocab.encode(q))
                    owner.append(i)
        return seqs, owner


def read_questions(root: Path, split: str) -> tuple[list[str], list[list[list[str]]]]:
    """Image ids and their tokenised questions from ``questions/{split}.jsonl``."""
    path = root / "questions" / f"{split}.jsonl"
    try:
        lines = read_text(path, limit=DATA_LIMIT).splitlines()
    except FileReadError as exc:
        raise VqgDataError(f"{exc}; render a data set with `companion data vqg`") from None
    ids, questions = [], []
    for n, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
            ids.append(str(row["id"]))
            questions.append([str(q).split() for q in row["questions"]])
        except (ValueError, KeyError, TypeError) as exc:
            raise VqgDataError(f"{path}:{n}: not a question record ({exc})") from None
    return ids, questions


def read_image(path: Path, width: int, height: int) -> torch.Tensor:
    """One PNG as the model's uint8 input (see :func:`prepare_frame`)."""
    bgr = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if bgr is None:
        raise VqgDataError(f"{path}: cannot read the image")
    return prepare_frame(bgr[..., ::-1], width, height)


def load_images(root: Path, split: str, ids: list[str], width: int, height: int,
                cache_dir: Path | None) -> torch.Tensor:
    """The split's images ``(N, 3, height, width)``, read through a cache file when given."""
    cache = cache_dir / f"images_{split}_{width}x{height}.pt" if cache_dir else None
    if cache is not None and cache.exists():
        blob = torch.load(cache, map_location="cpu", weights_only=True)
        if blob["ids"] == ids and blob["root"] == str(root):
            return blob["images"]
    images = torch.stack([read_image(root / "images" / split / f"{i}.png", width, height)
                          for i in ids]) if ids else torch.zeros(0, 3, height, width,
                                                                dtype=torch.uint8)
    if cache is not None:
        atomic_torch_save({"ids": ids, "root": str(root), "images": images}, cache)
    return images


def load_split(root: Path, split: str, width: int, height: int,
               cache_dir: Path | None = None) -> SplitData:
    """Questions and images of one split."""
    ids, questions = read_questions(root, split)
    return SplitData(ids, questions, load_images(root, split, ids, width, height, cache_dir))


def build_vocab(train: SplitData, min_count: int) -> Vocab:
    """Words of the training questions seen at least ``min_count`` times."""
    return Vocab.build((q for qs in train.questions for q in qs), min_count)
