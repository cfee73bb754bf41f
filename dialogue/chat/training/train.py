"""Training the chit-chat bot: one readable loop in the CleanRL manner.

Every hyper-parameter comes from ``config/chat.yaml`` (or a ``--config`` file over it).
The loop writes as it goes: ``train_log.csv`` (flushed every ``log_every`` batches),
``eval_log.csv`` (one row per epoch), an atomic resumable ``checkpoint.pt`` every
``checkpoint_every`` epochs and, on SIGINT or SIGTERM, before the next batch
(:mod:`core.interrupts`), and ``chat.pt``, the weights with the best validation
perplexity so far (the model file to export). A resumed run keeps the log rows up to its
checkpoint and goes on exactly as an uninterrupted one.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from core.checkpoint import TrainingFolder
from core.interrupts import stop_point, stop_requests
from dialogue.chat.batch import batches
from dialogue.chat.config import ChatConfig
from dialogue.chat.model import save_chat_model
from dialogue.chat.pool import pool_path, write_pool
from dialogue.chat.seq2seq import Seq2Seq
from dialogue.chat.training.data import ChatDataError, load_chat_data
from dialogue.chat.training.evaluate import perplexity
from textnets.vocab import Vocab

TRAIN_FIELDS = ["epoch", "step", "loss", "perplexity", "lr", "wall_s"]
EVAL_FIELDS = ["epoch", "step", "train_perplexity", "valid_perplexity", "best", "lr", "wall_s"]
MODEL_FILE = "chat.pt"


def count_parameters(net: torch.nn.Module) -> int:
    """Number of trainable parameters (the tied embedding counted once)."""
    return sum(p.numel() for p in net.parameters() if p.requires_grad)


def train(cfg: ChatConfig, out_dir: Path, resume: bool = False, progress: bool = True) -> dict:
    """Train into ``out_dir``; returns a summary with the best validation perplexity."""
    tc = cfg.train
    model_path, eval_path = out_dir / MODEL_FILE, out_dir / "eval_log.csv"
    folder = TrainingFolder(out_dir, resume)
    folder.use_config(cfg)
    torch.set_num_threads(tc.threads)
    torch.manual_seed(tc.seed)
    data = load_chat_data(cfg.data)
    train_pairs, valid_pairs = data.splits["train"], data.splits["valid"]
    vocab = Vocab.build([side for pair in train_pairs for side in pair], cfg.data.min_count)
    net = Seq2Seq(len(vocab), cfg.model)
    optimizer = torch.optim.Adam(net.parameters(), lr=tc.learning_rate,
                                 weight_decay=tc.weight_decay)
    scheduler = torch.optim.lr_scheduler.ReduceLROnPlateau(
        optimizer, mode="min", factor=tc.lr_decay, patience=tc.lr_patience)
    epoch = step = position = bad_epochs = 0
    best = math.inf
    sums = [0.0, 0, 0.0, 0]  # nll and tokens since the last log row, then in this epoch
    plain_cfg = cfg.model_dump(mode="json")

    if folder.state is not None:
        state = folder.state
        if state["vocab"] != vocab.itos:
            raise ChatDataError(f"{folder.ckpt_path}: its vocabulary differs from the data now; "
                                "the data or data config changed since it was written")
        folder.restore(net=net, optimizer=optimizer, scheduler=scheduler)
        torch.set_rng_state(state["torch_rng"])
        epoch, step, position, bad_epochs = state["counters"]
        best, sums = state["best"], list(state["sums"])
    else:
        (out_dir / "data_counts.json").write_text(json.dumps(data.counts, indent=2))
        write_pool(pool_path(model_path), train_pairs, data.refs["train"], plain_cfg["data"])
    # on resume, the logs keep their rows up to the checkpoint
    folder.open_log(eval_path.name, EVAL_FIELDS, keep=lambda r: int(r[0]) <= epoch).close()
    log_file = folder.open_log("train_log.csv", TRAIN_FIELDS, keep=lambda r: int(r[1]) <= step)
    log = csv.writer(log_file)

    rng_at_position = torch.get_rng_state()  # the RNG as it was when `position` was reached
    wall = folder.wall

    def save_checkpoint() -> None:
        folder.save({"net": net.state_dict(), "optimizer": optimizer.state_dict(),
                     "scheduler": scheduler.state_dict(), "vocab": vocab.itos,
                     "torch_rng": rng_at_position, "sums": sums,
                     "counters": (epoch, step, position, bad_epochs), "best": best})

    per_epoch = math.ceil(len(train_pairs) / tc.batch_size)
    bar = tqdm(total=tc.epochs * per_epoch, initial=epoch * per_epoch + position,
               disable=not progress, desc="train chat", unit="batch")
    with stop_requests(), log_file, bar:
        while epoch < tc.epochs and (tc.early_stop is None or bad_epochs < tc.early_stop):
            net.train()
            rng = np.random.default_rng(tc.seed * 100_003 + epoch)  # same order on resume
            for i, batch in enumerate(batches(train_pairs, vocab, tc.batch_size, rng)):
                if i < position:
                    continue
                stop_point(save_checkpoint)
                nll, n = net.token_nll(batch)
                optimizer.zero_grad()
                (nll / n).backward()
                if tc.max_grad_norm is not None:
                    torch.nn.utils.clip_grad_norm_(net.parameters(), tc.max_grad_norm)
                optimizer.step()
                step, position = step + 1, i + 1
                rng_at_position = torch.get_rng_state()
                value = nll.item()
                sums = [sums[0] + value, sums[1] + n, sums[2] + value, sums[3] + n]
                bar.update(1)
                if step % tc.log_every == 0:
                    loss = sums[0] / sums[1]
                    log.writerow([epoch + 1, step, f"{loss:.4f}", f"{math.exp(loss):.2f}",
                                  f"{optimizer.param_groups[0]['lr']:.2e}", f"{wall():.1f}"])
                    log_file.flush()
                    bar.set_postfix(loss=f"{loss:.3f}", best=f"{best:.1f}")
                    sums[:2] = [0.0, 0]
            valid_ppl = perplexity(net, valid_pairs, vocab, tc.batch_size)
            scheduler.step(valid_ppl)
            improved = valid_ppl < best
            epoch, position = epoch + 1, 0
            bad_epochs = 0 if improved else bad_epochs + 1
            if improved:
                best = valid_ppl
                save_chat_model(model_path, net, vocab, plain_cfg, {
                    "epoch": epoch, "step": step, "valid_perplexity": valid_ppl,
                    "seed": tc.seed, "parameters": count_parameters(net),
                    "pairs": data.counts["split"]})
            train_ppl = math.exp(sums[2] / sums[3]) if sums[3] else math.nan
            sums[2:] = [0.0, 0]
            with eval_path.open("a", newline="") as fh:
                csv.writer(fh).writerow([epoch, step, f"{train_ppl:.2f}", f"{valid_ppl:.2f}",
                                         int(improved),
                                         f"{optimizer.param_groups[0]['lr']:.2e}",
                                         f"{wall():.1f}"])
            if epoch % tc.checkpoint_every == 0:
                save_checkpoint()
        save_checkpoint()
    return {"model": str(model_path), "best_valid_perplexity": best, "epochs": epoch,
            "steps": step, "vocab": len(vocab), "parameters": count_parameters(net),
            "pairs": data.counts["split"], "wall_s": round(wall(), 1)}
