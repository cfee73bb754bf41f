"""Shared pieces of the style-transfer tests: a synthetic review corpus and a tiny config.

The tests need neither the Yelp files nor a shipped model: a small corpus of templated
reviews is written into a temporary folder.
"""

import random
from contextlib import contextmanager

import torch

GOOD = ["great", "delicious", "friendly", "amazing", "excellent", "perfect", "tasty", "fresh"]
BAD = ["terrible", "cold", "rude", "awful", "bland", "horrible", "stale", "dirty"]
NOUNS = ["food", "service", "staff", "pizza", "place", "waiter", "coffee", "burger", "pasta",
         "salad", "bar", "menu"]
TEMPLATES = ["the {n} was {a} .", "{a} {n} and {b} {m} .", "i thought the {n} was {a} !",
             "their {n} is always {a} .", "the {n} here is so {a} ."]


def corpus(words: list[str], n: int, rng: random.Random) -> list[str]:
    out = []
    for _ in range(n):
        t = rng.choice(TEMPLATES)
        out.append(t.format(n=rng.choice(NOUNS), m=rng.choice(NOUNS), a=rng.choice(words),
                            b=rng.choice(words)))
    return out


TINY = """
data: {{dir: {dir}, negative: [reviews.0], positive: [reviews.1], min_count: 1,
        dedupe: false}}
model: {{embed_dim: 16, style_dim: 8, content_dim: 24, style_hidden: 8, disc_filters: 8,
         mask_ratio: 3.0, mask_min_count: 2, attention: true}}
classifier: {{embed_dim: 16, filters: 8, epochs: 2, batch_size: 32, lr: 0.01}}
lm: {{embed_dim: 16, hidden: 24, epochs: 2, batch_size: 32, lr: 0.01}}
train: {{threads: 1, batch_size: 32, pretrain_lr: 0.01, lr: 0.003, disc_lr: 0.01, lm_steps: 40,
         rec_steps: 40, adversarial_steps: {adv}, log_every: 10, checkpoint_every: 10,
         eval_every: 10, eval_sentences: 40}}
decode: {{style_min_count: 2}}
"""


def write_corpus(d):
    """Write 250 negative and 250 positive templated reviews into the folder ``d``."""
    rng = random.Random(0)
    (d / "reviews.0").write_text("\n".join(corpus(BAD, 250, rng)) + "\n")
    (d / "reviews.1").write_text("\n".join(corpus(GOOD, 250, rng)) + "\n")
    return d


@contextmanager
def one_thread():
    """Tiny tensors: threads only add overhead (and stall badly on a busy machine)."""
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        yield
    finally:
        torch.set_num_threads(before)


def tiny_config(tmp_path, data_dir, adv=60, name="tiny.yaml"):
    """Write the tiny training config into ``tmp_path``; return its path."""
    path = tmp_path / name
    path.write_text(TINY.format(dir=data_dir, adv=adv))
    return path
