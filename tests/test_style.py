"""Style transfer: the data pipeline and each network's shapes and masking."""

import pytest
import torch
from style_helpers import one_thread, tiny_config, write_corpus

from core.config_files import ConfigError
from dialogue.style.config import load_style_config
from dialogue.style.model import FAKE, StyleCode, StyleTransferModel
from dialogue.style.text import detokenize, tokenize
from dialogue.style.training.data import load_splits
from dialogue.style.training.losses import discriminator_loss, pretrain_losses, transfer_losses
from textnets.batch import BatchSampler, make_batch
from textnets.generator import Generator
from textnets.textcnn import TextCNN
from textnets.vocab import BOS_ID, EOS_ID, PAD_ID, SPECIALS, UNK_ID, Vocab


@pytest.fixture(scope="module", autouse=True)
def _one_thread():
    with one_thread():
        yield


@pytest.fixture(scope="module")
def data_dir(tmp_path_factory):
    return write_corpus(tmp_path_factory.mktemp("yelp"))


# --- data -----------------------------------------------------------------------------

def test_tokenize_matches_the_yelp_format():
    assert tokenize("The food wasn't cold, it's 5 stars!") == [
        "the", "food", "was", "n't", "cold", ",", "it", "'s", "_num_", "stars", "!"]
    assert detokenize(["it", "'s", "good", "!"]) == "it's good!"


def test_split_is_seeded_per_class_and_disjoint(tmp_path, data_dir):
    cfg = load_style_config(tiny_config(tmp_path, data_dir)).data
    a, b = load_splits(cfg), load_splits(cfg)
    assert a["train"].sentences == b["train"].sentences
    assert [len(a[k].of_class(0)) for k in ("train", "valid", "test")] == [200, 25, 25]
    other = load_splits(cfg.model_copy(update={"seed": cfg.seed + 1}))
    assert other["train"].sentences != a["train"].sentences
    deduped = load_splits(cfg.model_copy(update={"dedupe": True}))
    seen = {" ".join(s) for s in deduped["train"].sentences}
    assert not seen & {" ".join(s) for s in deduped["test"].sentences}


def test_vocab_has_specials_and_min_count():
    v = Vocab.build([["a", "b", "a"], ["a", "c"]], min_count=2)
    assert v.itos[:4] == list(SPECIALS) and v.itos[4:] == ["a"]
    assert v.encode(["a", "zzz"]) == [4, UNK_ID]
    assert v.decode([BOS_ID, 4, EOS_ID, 4]) == ["a"]


def test_batch_pads_and_masks():
    b = make_batch([[5, 6, 7], [8]], [0, 1])
    assert b.inputs.tolist() == [[BOS_ID, 5, 6, 7], [BOS_ID, 8, PAD_ID, PAD_ID]]
    assert b.targets.tolist() == [[5, 6, 7, EOS_ID], [8, EOS_ID, PAD_ID, PAD_ID]]
    assert b.mask.tolist() == [[1, 1, 1, 1], [1, 1, 0, 0]] and b.lengths.tolist() == [4, 2]


def test_sampler_resumes_where_it_stopped():
    seqs = [[4] * (i % 7 + 1) for i in range(50)]
    a = BatchSampler(seqs, 0, 8, seed=3, bucket=2)
    for _ in range(9):  # past one epoch
        a.next()
    b = BatchSampler(seqs, 0, 8, seed=3, bucket=2)
    b.load_state_dict(a.state_dict())
    for _ in range(5):
        assert torch.equal(a.next().inputs, b.next().inputs)


def test_unknown_config_key_is_an_error(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("train: {bogus: 1}\n")
    with pytest.raises(ConfigError, match=r"train\.bogus: unknown key"):
        load_style_config(path)


# --- components -------------------------------------------------------------------------

@pytest.fixture
def model(tmp_path, data_dir):
    torch.manual_seed(0)
    return StyleTransferModel(30, load_style_config(tiny_config(tmp_path, data_dir)).model)


def test_style_code_and_its_ablation():
    torch.manual_seed(0)
    labels = torch.tensor([0, 1, 1])
    ae, plain = StyleCode(200, 16, True), StyleCode(200, 16, False)
    assert ae(labels).shape == plain(labels).shape == (3, 200)
    assert ae.loss(labels) > 0 and plain.loss(labels) == 0


def test_encoder_ignores_padding(model):
    alone = make_batch([[5, 6]], [0])
    padded = make_batch([[5, 6], [7, 8, 9, 10, 11]], [0, 1])
    za, _ = model.encode(alone.inputs, alone.lengths, alone.labels)
    zp, _ = model.encode(padded.inputs, padded.lengths, padded.labels)
    assert za.shape == (1, 24) and torch.allclose(za[0], zp[0], atol=1e-6)


def test_masked_style_markers_are_hidden_from_the_encoder(model):
    a, b, c = (make_batch([[5, w, 7]], [0]) for w in (6, 8, 9))

    def z(batch):
        return model.encode(batch.inputs, batch.lengths, batch.labels)[0]

    assert not torch.allclose(z(a), z(b))
    model.set_masked([6, 8])
    assert torch.allclose(z(a), z(b)) and not torch.allclose(z(a), z(c))
    soft = torch.softmax(torch.randn(2, 3, 30), -1)
    hidden = model.mask_soft(soft)
    assert torch.allclose(hidden.sum(-1), torch.ones(2, 3)) and hidden[..., [6, 8]].eq(0).all()


def test_generator_shapes_and_step_matches_teacher_forcing(model):
    b = make_batch([[5, 6, 7], [8]], [0, 1])
    z, y = torch.randn(2, 24), torch.randn(2, 8)
    emb = model.embedding(b.inputs)
    hidden, logits = model.generator.teacher_force(emb, z, y, model.embedding.weight)
    assert hidden.shape == (2, 4, 32) and logits.shape == (2, 4, 30)
    state = Generator.initial(z, y)
    for t in range(4):
        state = model.generator.step(emb[:, t], state)
        assert torch.allclose(state[0], hidden[:, t], atol=1e-5)
    h, words = model.generator.free_run(model.embedding, model.embedding.weight[BOS_ID], z, y,
                                        5, tau=0.5)
    assert h.shape == (2, 5, 32) and words.shape == (2, 5, 30)
    assert torch.allclose(words.sum(-1), torch.ones(2, 5), atol=1e-5)


def test_copy_attention_raises_the_source_words_and_ignores_padding(tmp_path, data_dir):
    torch.manual_seed(0)
    cfg = load_style_config(tiny_config(tmp_path, data_dir)).model
    model = StyleTransferModel(30, cfg.model_copy(update={"attention": True})).eval()
    alone = make_batch([[5, 6]], [0])
    padded = make_batch([[5, 6], [7, 8, 9, 10, 11]], [0, 1])
    za, ma = model.encode(alone.inputs, alone.lengths, alone.labels)
    zp, mp = model.encode(padded.inputs, padded.lengths, padded.labels)
    y = model.style(alone.labels)
    table = model.embedding.weight
    emb = model.embedding(alone.inputs)
    _, la = model.generator.teacher_force(emb, za, y, table, ma)
    _, lp = model.generator.teacher_force(emb, zp[:1], y, table, mp.select(torch.tensor([0])))
    assert torch.allclose(la, lp, atol=1e-5)  # padding is never attended
    _, plain = model.generator.teacher_force(emb, za, y, table)
    assert not torch.allclose(la, plain)
    with torch.no_grad():  # a strong copy path: the attended words win
        model.generator.copy.mix.weight.copy_(torch.eye(16) * 50)
        _, copied = model.generator.teacher_force(emb, za, y, table, ma)
    assert set(copied.argmax(-1)[0].tolist()) <= {BOS_ID, 5, 6}


def test_textcnn_masks_padding_and_short_sentences():
    torch.manual_seed(0)
    cnn = TextCNN(6, 4, [1, 2, 3, 4, 5], 3, 0.0).eval()
    x = torch.randn(2, 7, 6)
    mask = torch.tensor([[1.0] * 2 + [0.0] * 5, [1.0] * 7])
    noisy = x.clone()
    noisy[0, 2:] = 100.0  # garbage in the padding must not matter
    assert cnn(x, mask).shape == (2, 3)
    assert torch.allclose(cnn(x, mask), cnn(noisy, mask))
    assert torch.allclose(cnn(x[:1, :2], mask[:1, :2]), cnn(x, mask)[:1], atol=1e-6)


def test_losses_have_the_thesis_terms(model):
    b = make_batch([[5, 6, 7], [8, 9], [10]], [0, 1, 1])
    assert set(pretrain_losses(model, b)) == {"style", "lm_enc", "lm_gen"}
    cfg_w = load_style_config().train.weights
    total, losses, (h_real, h_fake) = transfer_losses(model, b, 0.5, cfg_w)
    assert set(losses) == {"style", "rec", "adv", "cycle"} and total.ndim == 0
    assert h_real.shape == h_fake.shape == (3, 4, 32)
    d_loss, acc = discriminator_loss(model, b, h_real, h_fake)
    assert d_loss > 0 and 0 <= acc <= 1
    assert model.discriminator(h_real, b.mask).shape == (3, FAKE + 1)


def test_per_word_weights_divide_the_sentence_losses_by_the_mean_length(model):
    b = make_batch([[5, 6, 7], [8, 9], [10]], [0, 1, 1])  # 4 + 3 + 2 targets with <eos>
    w = load_style_config().train.weights
    totals = {}
    for per_word in (False, True):
        torch.manual_seed(3)
        total, losses, _ = transfer_losses(model, b, 0.5, w.model_copy(
            update={"per_word": per_word}))
        totals[per_word] = total.item()
    words = 9 / 3
    expected = (losses["style"] + (losses["rec"] + 0.3 * losses["cycle"]) / words
                + losses["adv"]).item()
    assert abs(totals[True] - expected) < 1e-4 and totals[True] < totals[False]


def test_generator_steps_lower_the_adversarial_loss(model):
    torch.manual_seed(1)
    b = make_batch([[5, 6, 7, 8], [9, 10], [11, 12, 13]] * 4, [0, 1, 1] * 4)
    w = load_style_config().train.weights.model_copy(update={"rec": 0.0, "cycle": 0.0})
    opt = torch.optim.Adam(model.generator_parameters(), lr=0.01)
    model.discriminator.eval()  # a fixed judge

    def adv() -> float:
        torch.manual_seed(2)
        return transfer_losses(model, b, 0.5, w)[1]["adv"].item()

    before = adv()
    for _ in range(20):
        loss = transfer_losses(model, b, 0.5, w)[0]
        opt.zero_grad()
        loss.backward()
        opt.step()
    assert adv() < before
