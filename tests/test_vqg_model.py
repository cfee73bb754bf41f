"""Visual question generation: the networks, a tiny seeded training run, resume, model files.

The tests need neither the rendered data set nor a shipped model: a tiny synthetic data set
(coloured boxes standing for objects, template questions) is written into a temporary folder
in the data set's folder format.
"""

import argparse
import csv
import itertools
import json
import os
import signal

import cv2
import numpy as np
import pytest
import torch
from test_training_resume import ctrl_c, refuses_changes_and_bad_checkpoints

from core.checkpoint import read_checkpoint
from core.errors import UserError
from perception.vqg.config import load_vqg_config
from perception.vqg.generator import VqgModelError, VqgQuestionGenerator
from perception.vqg.model import Latent, MatchDiscriminator, VqgModel
from perception.vqg.questions import frame_key, parse_question
from perception.vqg.scene import PALETTE, Node, SceneGraph, load_scene
from perception.vqg.training import cli as vqg_cli
from perception.vqg.training import train as vqg_train
from perception.vqg.training.dataset import read_image
from perception.vqg.training.facts import facts
from perception.vqg.verify import FactVerifier
from textnets.batch import make_batch
from textnets.vocab import PAD_ID

KINDS = ["mug", "ball", "book", "duck"]
COLOURS = ["red", "green", "blue", "yellow"]
TINY = """
data: {{dir: {dir}, image_width: 32, image_height: 24, min_count: 1}}
model: {{blocks: [[4], [8]], pool_grid: [2, 2], feature_dim: 24, embed_dim: 16,
         latent_vars: 4, latent_classes: 4, d1_filters: 8, d2_channels: 8}}
train: {{image_batch: 8, image_steps: 20, image_lr: 0.01, batch_size: 16, vae_steps: 40,
         adversarial_steps: {adv}, lr: 0.01, adv_lr: 0.003, disc_lr: 0.003,
         kl_warmup_steps: 20, generator_steps_per_disc: 2, log_every: 10,
         checkpoint_every: 10, eval_every: 20, select_images: 3, select_samples: 8}}
decode: {{max_words: 8, min_logprob: -1.0e9, fact_check: false}}  # no confidence check
eval: {{latency_runs: 2}}
"""


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(before)


def write_tiny_dataset(root, counts=None):
    """Coloured boxes on a grey floor, their scene graphs and template questions."""
    rng = np.random.default_rng(0)
    for split, count in (counts or {"train": 16, "val": 4, "test": 3}).items():
        for sub in ("images", "scenes"):
            (root / sub / split).mkdir(parents=True, exist_ok=True)
        (root / "questions").mkdir(exist_ok=True)
        lines = []
        for i in range(count):
            img = np.full((240, 320, 3), 128, np.uint8)
            nodes, questions = [], ["what room is this ?"]
            for k, kind in enumerate(rng.choice(KINDS, 2, replace=False)):
                colour = str(rng.choice(COLOURS))
                x0, size = 30 + 150 * k, 30 + 20 * KINDS.index(kind)
                img[100:100 + size, x0:x0 + size] = np.array(PALETTE[colour]) * 255
                nodes.append(Node(id=f"{kind}_{k}", kind=str(kind), colour=colour, x=1.5,
                                  y=0.5 - k, support="floor", side=("left", "right")[k]))
                questions += [f"what color is the {kind} ?", f"is there a {colour} {kind} ?",
                              f"how many {kind}s are there ?", f"where is the {kind} ?"]
            name = f"{i:06d}"
            cv2.imwrite(str(root / "images" / split / f"{name}.png"), img[..., ::-1])
            (root / "scenes" / split / f"{name}.json").write_text(
                SceneGraph("living_room", "playtime", nodes).to_json())
            lines.append(json.dumps({"id": name, "questions": questions}))
        (root / "questions" / f"{split}.jsonl").write_text("\n".join(lines) + "\n")
    return root


def tiny_config(tmp, data, adv=20):
    path = tmp / "tiny.yaml"
    path.write_text(TINY.format(dir=data, adv=adv))
    return path


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory):
    return write_tiny_dataset(tmp_path_factory.mktemp("vqg-data"))


@pytest.fixture(scope="module")
def trained(tmp_path_factory, data_dir):
    """A tiny model trained through the CLI handler and exported."""
    root = tmp_path_factory.mktemp("run")
    args = argparse.Namespace(config=tiny_config(root, data_dir), data=None, out=root / "out",
                              resume=False, export=root / "vqg.pt", no_progress=True,
                              ablation=None, image_from=None)
    assert vqg_cli.run_train(args) == 0
    return root


def read_log(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


# --- the networks -------------------------------------------------------------------------

def test_component_shapes():
    cfg = load_vqg_config().model
    model = VqgModel(50, cfg)
    images = torch.randint(0, 256, (2, 3, 96, 128), dtype=torch.uint8)
    f = model.image(model.image.features(images))
    assert f.shape == (2, 512) and f.abs().max() < 1
    assert model.generator.hidden == 640 and cfg.latent_dim == 128
    batch = make_batch([[5, 6, 7], [8]], [0, 1])
    z, kl = model.encoder(model.embedding(batch.targets), batch.lengths, f, 1.0)
    assert z.shape == (2, 128) and kl.shape == (2, 16) and bool((kl >= -1e-5).all())
    hidden, logits = model.generator.teacher_force(model.embedding(batch.inputs), z, f,
                                                   model.embedding.weight)
    assert hidden.shape == (2, 4, 640) and logits.shape == (2, 4, 50)
    assert model.d1(hidden, batch.mask).shape == (2, 1)
    assert model.d2(model.embedding(batch.targets), batch.mask, f).shape == (2,)
    ids, logp = model.decode(f, model.encoder.latent.prior(2), max_words=6)
    assert ids.shape[0] == 2 and ids.shape[1] <= 7 and logp.shape == (2,)


def test_padding_changes_neither_encoder_nor_d2():
    cfg = load_vqg_config().model
    model = VqgModel(30, cfg).eval()
    f = torch.rand(1, 512) - 0.5
    short, padded = make_batch([[5, 6]], [0]), make_batch([[5, 6]], [0])
    padded_targets = torch.cat([padded.targets, torch.full((1, 3), 9)], 1)
    mask = torch.cat([padded.mask, torch.zeros(1, 3)], 1)
    torch.manual_seed(0)
    z1, _ = model.encoder(model.embedding(short.targets), short.lengths, f, 0.5)
    torch.manual_seed(0)
    z2, _ = model.encoder(model.embedding(padded_targets), padded.lengths, f, 0.5)
    assert torch.allclose(z1, z2)
    d2 = model.d2
    assert torch.allclose(d2(model.embedding(short.targets), short.mask, f),
                          d2(model.embedding(padded_targets), mask, f), atol=1e-5)


def test_gumbel_latent_is_one_hot_at_low_temperature_and_kl_to_uniform():
    cfg = load_vqg_config().model
    latent = Latent(8, cfg)
    h = torch.randn(64, 8) * 3
    z, kl = latent(h, 0.05)
    groups = z.view(64, 16, 8)
    assert torch.allclose(groups.sum(-1), torch.ones(64, 16), atol=1e-5)
    assert groups.max(-1).values.median() > 0.99
    with torch.no_grad():
        latent.head.weight.zero_()
        latent.head.bias.zero_()
    assert latent(h, 1.0)[1].abs().max() < 1e-5  # uniform posterior: no KL
    prior = latent.prior(10).view(10, 16, 8)
    assert bool(((prior == 0) | (prior == 1)).all()) and bool((prior.sum(-1) == 1).all())
    gauss = Latent(8, cfg.model_copy(update={"latent": "gaussian"}))
    z, kl = gauss(h, 1.0)
    assert z.shape == (64, 128) and kl.shape == (64, 128) and bool((kl >= 0).all())


def test_match_discriminator_reads_the_last_real_word():
    d2 = MatchDiscriminator(4, 3, 2, 5)
    emb, f = torch.randn(2, 6, 4), torch.randn(2, 5)
    mask = torch.tensor([[1, 1, 1, 0, 0, 0], [1, 1, 1, 1, 1, 1]]).float()
    out = d2(emb, mask, f)
    changed = emb.clone()
    changed[0, 3:] = 7.0  # padding of the first question
    assert torch.allclose(out, d2(changed, mask, f))


# --- training, resume, model files --------------------------------------------------------

def test_tiny_training_lowers_the_losses(trained):
    out = trained / "out"
    for phase, field in (("image", "bce"), ("vae", "rec"), ("adversarial", "rec")):
        rows = read_log(out / f"log_{phase}.csv")
        assert float(rows[-1][field]) < float(rows[0][field]), phase
    adv = read_log(out / "log_adversarial.csv")
    assert all(r["g1"] and r["g2"] for r in adv) and any(r["d1"] for r in adv)
    valid = read_log(out / "valid_log.csv")
    assert [(r["phase"], r["step"]) for r in valid] == [("vae", "20"), ("vae", "40"),
                                                        ("adversarial", "20")]
    summary = json.loads((out / "summary.json").read_text())
    best = max(valid, key=lambda r: float(r["score"]))
    assert summary["selected"]["step"] == int(best["step"]) and best["best"] == "1"
    assert (trained / "vqg.pt").read_bytes() == (out / "vqg.pt").read_bytes()


def test_pretraining_targets_are_question_words_and_grounded_facts(data_dir, tmp_path):
    cfg = load_vqg_config(tiny_config(tmp_path, data_dir))
    cfg = cfg.model_copy(update={"train": cfg.train.model_copy(
        update={"image_targets": ("words", "facts"), "image_fact_min_images": 2})})
    data = vqg_train.prepare_data(cfg, tmp_path / "run")
    targets, names = data.image_targets["train"], data.target_names
    assert targets.shape == (16, len(names))
    assert names[:len(data.vocab)] == [f"word:{w}" for w in data.vocab.itos]
    fact_names = {n for n in names if n.startswith("fact:")}
    assert fact_names
    for i, name in enumerate(data.train.ids):
        marked = {names[j] for j in targets[i].nonzero().flatten().tolist()}
        words = {f"word:{w}" for q in data.train.questions[i] for w in q}
        scene = load_scene(data_dir / "scenes" / "train" / f"{name}.json")
        true = {f"fact:{frame_key(f)!r}" for f in facts(scene)}
        assert marked == (words & set(names)) | (true & fact_names)
    column = targets[:, len(data.vocab):]   # each kept fact is true in some images only
    assert (column.sum(0) >= 2).all() and (column.sum(0) <= 14).all()


def test_existing_run_needs_resume(trained):
    args = argparse.Namespace(config=trained / "tiny.yaml", data=None, out=trained / "out",
                              resume=False, export=None, no_progress=True, ablation=None,
                              image_from=None)
    with pytest.raises(FileExistsError):
        vqg_cli.run_train(args)


def test_an_ablation_reuses_the_pretrained_image_encoder(trained, tmp_path):
    args = argparse.Namespace(config=trained / "tiny.yaml", data=None, out=tmp_path / "gauss",
                              resume=False, export=None, no_progress=True, ablation="gaussian",
                              image_from=trained / "out" / "image_encoder.pt")
    assert vqg_cli.run_train(args) == 0
    assert not (tmp_path / "gauss" / "log_image.csv").exists()
    a = torch.load(trained / "out" / "image_encoder.pt", weights_only=True)["state_dict"]
    b = VqgQuestionGenerator.load(tmp_path / "gauss" / "vqg.pt").model
    assert b.cfg.latent == "gaussian"
    assert torch.allclose(a["trunk.0.weight"], b.image.trunk[0].weight, atol=1e-3)


def test_interrupted_training_resumes_to_the_same_model(tmp_path, data_dir, monkeypatch):
    cfg = load_vqg_config(tiny_config(tmp_path, data_dir, adv=6))
    cfg = cfg.model_copy(update={"train": cfg.train.model_copy(
        update={"vae_steps": 15, "image_steps": 5, "eval_every": 100})})
    vqg_train.train(cfg, tmp_path / "whole", progress=False)
    real, calls = vqg_train.vae_losses, itertools.count()

    def interrupt(*a, **k):
        if next(calls) == 12:  # SIGINT in the 13th VAE step
            os.kill(os.getpid(), signal.SIGINT)
        return real(*a, **k)

    monkeypatch.setattr(vqg_train, "vae_losses", interrupt)
    with ctrl_c(), pytest.raises(KeyboardInterrupt):
        vqg_train.train(cfg, tmp_path / "cut", progress=False)
    assert read_checkpoint(tmp_path / "cut" / "checkpoint.pt")["step"] == 13  # it finished
    monkeypatch.setattr(vqg_train, "vae_losses", real)
    vqg_train.train(cfg, tmp_path / "cut", resume=True, progress=False)
    a = torch.load(tmp_path / "whole" / "vqg.pt", weights_only=True)["state_dict"]
    b = torch.load(tmp_path / "cut" / "vqg.pt", weights_only=True)["state_dict"]
    assert all(torch.equal(a[k], b[k]) for k in a)
    assert [r["step"] for r in read_log(tmp_path / "cut" / "log_vae.csv")] == ["10", "15"]


def test_a_resume_keeps_the_run_config_and_refuses_an_unreadable_checkpoint(trained, tmp_path,
                                                                           capsys):
    refuses_changes_and_bad_checkpoints(
        ["train", "vqg", "--no-progress"], trained / "out", tmp_path, ["--ablation", "gaussian"],
        "model.latent: run has gumbel, --ablation gives gaussian", capsys, b"")


def test_shipped_format_asks_distinct_questions(trained, data_dir):
    decode = load_vqg_config(trained / "tiny.yaml").decode
    gen = VqgQuestionGenerator.load(trained / "vqg.pt", decode=decode)
    frame = cv2.imread(str(data_dir / "images" / "test" / "000000.png"))[..., ::-1].copy()
    questions = gen.ask(frame, 5)
    assert 1 <= len(questions) <= 5 and len(set(questions)) == len(questions)
    assert all(questions)
    strict = decode.model_copy(update={"min_logprob": 0.0})  # nothing is that certain
    assert VqgQuestionGenerator.load(trained / "vqg.pt", decode=strict).ask(frame, 5) == []
    assert gen.ask(frame, 0) == []
    assert (trained / "vqg.pt").stat().st_size < 25e6


def test_missing_and_corrupt_model_files_are_user_errors(tmp_path):
    with pytest.raises(VqgModelError, match="not found"):
        VqgQuestionGenerator.load(tmp_path / "none.pt")
    (tmp_path / "bad.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(VqgModelError, match=r"bad\.pt: not a readable model file"):
        VqgQuestionGenerator.load(tmp_path / "bad.pt")
    torch.save({"format": "other"}, tmp_path / "other.pt")
    with pytest.raises(VqgModelError, match="not a VQG model file"):
        VqgQuestionGenerator.load(tmp_path / "other.pt")
    assert issubclass(VqgModelError, UserError)


def test_eval_and_ask_commands(trained, data_dir, capsys):
    args = argparse.Namespace(config=trained / "tiny.yaml", data=None, model=trained / "vqg.pt",
                              images=3, samples=10, json=True, out=trained / "eval",
                              ablations=None, no_progress=True, image_from=None, split="test",
                              household=None)
    assert vqg_cli.run_eval(args) == 0
    result = json.loads(capsys.readouterr().out)
    for key in ("distinct_per_image", "dm", "ri", "rs", "grounded5_share", "bleu", "latency_ms"):
        assert key in result
    assert 1 <= result["distinct_per_image"] <= 10 and 0 <= result["ri"] <= 1
    assert result["split"] == "test"
    assert vqg_cli.run_eval(argparse.Namespace(**{**vars(args), "split": "val"})) == 0
    assert json.loads(capsys.readouterr().out)["split"] == "val"
    ask = argparse.Namespace(image=data_dir / "images" / "val" / "000001.png", n=3,
                             model=trained / "vqg.pt", seed=0, config=trained / "tiny.yaml")
    assert vqg_cli.run_ask(ask) == 0
    lines = capsys.readouterr().out.splitlines()
    assert 1 <= len(lines) <= 3


def test_prediction_ignores_padding_after_eos(trained):
    gen = VqgQuestionGenerator.load(trained / "vqg.pt")
    f = torch.zeros(3, gen.model.cfg.feature_dim)
    ids, _ = gen.model.decode(f, gen.model.encoder.latent.prior(3), 8)
    for row in ids.tolist():
        if 2 in row:  # <eos>
            assert all(i == PAD_ID for i in row[row.index(2) + 1:])


def test_shipped_model_asks_grounded_questions_about_a_rendered_scene():
    from perception.vqg.questions import is_grounded, parse_question
    from perception.vqg.training.data import render_scene

    # frame 1000 of the test split's seed stream: beyond the 300 frames of the data set
    rgb, graph = render_scene(np.random.SeedSequence([0, 2, 1000]))
    gen = VqgQuestionGenerator.load()
    assert gen.verifier is not None   # the shipped fact check is on by default
    questions = gen.ask(rgb, 10)
    grounded = {q for q in questions
                if (f := parse_question(q)) is not None and is_grounded(f, graph)}
    assert len(grounded) >= 5, questions


# --- the fact verifier --------------------------------------------------------------------
def test_the_fact_check_drops_questions_the_verifier_finds_unlikely(trained, data_dir):
    cfg = load_vqg_config(trained / "tiny.yaml")
    greedy = cfg.decode.model_copy(update={"greedy": True})  # the same questions each call
    gen = VqgQuestionGenerator.load(trained / "vqg.pt", decode=greedy)
    image = read_image(data_dir / "images" / "test" / "000000.png", 32, 24)
    asked = gen.questions(image, 40)
    keys = {q: repr(frame_key(f)) for q in asked if (f := parse_question(q)) is not None}
    assert len(set(keys.values())) >= 2, asked
    unlikely, likely = sorted(set(keys.values()))[:2]
    verifier = FactVerifier(cfg.model, [unlikely, likely], (32, 24))
    with torch.no_grad():
        verifier.head.weight.zero_()
        verifier.head.bias.copy_(torch.tensor([-4.0, 4.0]))   # p = 0.018 and 0.982
    probs = verifier.plausibility(image, [*asked, "not a question at all"])
    assert probs[-1] is None
    assert {q: p for q, p in zip(asked, probs, strict=False) if p is not None} == pytest.approx(
        {q: 0.018 if k == unlikely else 0.982 for q, k in keys.items() if k in (unlikely, likely)},
        abs=1e-3)
    gen.verifier = verifier
    checked = gen.questions(image, 40)
    assert checked == [q for q in asked if keys.get(q) != unlikely]


def test_a_facts_run_writes_a_verifier_of_its_fact_columns(data_dir, tmp_path):
    cfg = load_vqg_config(tiny_config(tmp_path, data_dir, adv=0))
    cfg = cfg.model_copy(update={"train": cfg.train.model_copy(
        update={"image_targets": ("words", "facts"), "image_fact_min_images": 2,
                "vae_steps": 5, "eval_every": 100})})
    vqg_train.train(cfg, tmp_path / "run", progress=False)
    verifier = FactVerifier.load(tmp_path / "run" / vqg_train.VERIFIER_FILE, VqgModelError)
    names = vqg_train.prepare_data(cfg, tmp_path / "run").target_names
    assert verifier.keys == [n[len("fact:"):] for n in names if n.startswith("fact:")]
    encoder = torch.load(tmp_path / "run" / vqg_train.IMAGE_FILE, weights_only=True)
    assert torch.allclose(verifier.image.trunk[0].weight,
                          encoder["state_dict"]["trunk.0.weight"], atol=1e-3)
    (tmp_path / "bad.pt").write_bytes(b"broken")
    with pytest.raises(VqgModelError, match=r"bad\.pt"):
        FactVerifier.load(tmp_path / "bad.pt", VqgModelError)
    with pytest.raises(VqgModelError, match="not a VQG fact-verifier file"):
        FactVerifier.load(tmp_path / "run" / vqg_train.IMAGE_FILE, VqgModelError)
