"""The VQG data set: grounding on hand-written cases, paraphrases, garbage, the visibility
rule on a seeded render, and resumable writing."""

from __future__ import annotations

import json

import numpy as np
import pytest

from core.config_files import ConfigError
from perception.vqg.questions import frame_key, is_grounded, is_on_topic, parse_question, tokenize
from perception.vqg.scene import Node, SceneGraph
from perception.vqg.training.data import make_renderer, questions_for, write_vqg_dataset
from perception.vqg.training.data_config import load_vqg_data_config
from perception.vqg.training.facts import Style, wordings
from perception.vqg.training.layout import sample_plan

CFG = load_vqg_data_config()


def _party() -> SceneGraph:
    """A hand-made birthday party: cake with three lit candles and two mugs on the table, a
    ball on the floor, a dancer on the left and a sitter on the sofa."""
    nodes = [Node("table_0", "table", "brown", 2.0, 0.0, size=(1.1, 0.8, 0.75), side="middle"),
             Node("sofa_0", "sofa", "blue", 3.5, 1.0, size=(0.9, 2.0, 0.85), side="left"),
             Node("cake_0", "cake", "white", 2.0, 0.0, support="table_0", candles=3, lit=True,
                  side="middle"),
             *[Node(f"candle_{i}", "candle", ("blue", "yellow")[i % 2], 2.0, 0.0,
                    support="cake_0", lit=True, side="middle") for i in range(3)],
             Node("mug_0", "mug", "red", 2.1, 0.2, support="table_0", side="middle"),
             Node("mug_1", "mug", "blue", 2.1, -0.2, support="table_0", side="middle"),
             Node("ball_0", "ball", "green", 2.5, -1.0, support="floor", side="right"),
             Node("person_0", "person", "red", 3.0, 1.2, pose="arms_raised",
                  activity="dancing", trousers="black", side="left", near=["sofa_0"]),
             Node("person_1", "person", "yellow", 3.6, 1.0, pose="sitting", activity="sitting",
                  trousers="blue", support="sofa_0", side="left")]
    return SceneGraph("living_room", "birthday_party", nodes)


GROUNDED = ["how many candles are on the cake ?", "what colour is the mug on the table ?",
            "is there a ball on the floor ?", "what are the people doing ?",
            "why is everyone so happy ?", "is anyone dancing ?", "is the mug red ?",
            "who is sitting on the sofa ?", "are the candles lit ?", "is this a birthday party ?",
            "what colour is the shirt of the person on the left ?", "are there two mugs ?",
            "how many red mugs are on the table ?", "what is on the table ?",
            "is the person on the sofa wearing blue trousers ?", "is this a party ?"]
NOT_GROUNDED = ["is there a dog ?", "is the ball on the table ?", "is anyone reading ?",
                "is this a kitchen ?", "how many green mugs are there ?", "is this a dance party ?",
                "are there three mugs ?", "is the mug purple ?", "what is on the bed ?",
                "is the person on the right dancing ?", "what are the people eating ?"]


@pytest.mark.parametrize("text", GROUNDED)
def test_true_questions_are_grounded(text):
    frame = parse_question(text)
    assert frame is not None, text
    assert is_grounded(frame, _party()) and is_on_topic(frame, _party())


@pytest.mark.parametrize("text", NOT_GROUNDED)
def test_false_questions_are_not_grounded(text):
    frame = parse_question(text)
    assert frame is not None, text
    assert not is_grounded(frame, _party())


def test_topic_covers_absent_but_fitting_things():
    party = _party()
    assert is_on_topic(parse_question("is there a present ?"), party)  # birthday, not there
    assert is_on_topic(parse_question("is this a kitchen ?"), party)   # about the room
    assert not is_on_topic(parse_question("is there a bed ?"), party)
    assert not is_on_topic(parse_question("is anyone reading ?"), party)


PARAPHRASES = [
    ["how many people are there ?", "how many people are here ?",
     "How many people are in the room?", "how many guests can you see ?"],
    ["what colour is the mug ?", "what color is the cup ?", "what is the colour of the mug ?"],
    ["is there a ball on the floor ?", "are there any balls on the ground ?",
     "do you see a ball on the floor ?"],
    ["what are the people doing ?", "what is everyone doing ?", "what are they up to ?"],
    ["why is everyone so happy ?", "why are the people so happy ?", "why is everyone smiling ?"],
]


def test_paraphrases_share_a_frame_and_meanings_differ():
    keys = []
    for group in PARAPHRASES:
        frames = {frame_key(parse_question(t)) for t in group}
        assert len(frames) == 1, group
        keys.append(frames.pop())
    assert len(set(keys)) == len(keys)
    assert frame_key(parse_question("how many mugs are there ?")) != keys[0]


@pytest.mark.parametrize("text", ["", "?", "mug mug mug ?", "how many many mugs are there ?",
                                  "how many mugs are there", "the mug is red .", "what what what ?",
                                  "is there a ? ?", "how many zorbs are there ?",
                                  "is there a a mug ?", "colour mug table ?"])
def test_garbage_is_not_a_question(text):
    assert parse_question(text) is None


@pytest.mark.parametrize("text", ["how many people are sitting on the sofa ?",
                                  "what is the person in the red shirt doing ?",
                                  "how many chairs are around the table ?",
                                  "what colour is the person's shirt?", "is it a birthday ?",
                                  "what is the girl eating ?", "is there a dog on the sofa ?",
                                  "how many mugs are there on the table in the room ?"])
def test_free_form_questions_parse(text):
    assert parse_question(text) is not None


def test_tokenize():
    assert tokenize("Is it someone's birthday?") == ["is", "it", "someone", "'s", "birthday", "?"]
    assert tokenize("What colour is the mug,  please ?!") == [
        "what", "colour", "is", "the", "mug", "please", "?"]


@pytest.fixture(scope="module")
def renders():
    r = make_renderer(CFG)
    out = []
    for i in range(3):
        seed = np.random.SeedSequence([CFG.seed, 0, i])
        plan = sample_plan(seed, CFG.scene, r.hfov)
        rgb, graph = r.render_plan(plan)
        out.append((seed, plan, rgb, graph, r.last_mask))
    r.close()
    return out


def test_graph_holds_what_the_mask_shows(renders):
    px = CFG.visibility.min_pixels
    for _, plan, rgb, graph, (bodies, links, ids) in renders:
        assert rgb.shape == (CFG.scene.height, CFG.scene.width, 3)
        kept = {n.id for n in graph.nodes}
        for n in plan.graph.nodes:
            mask = bodies == ids[n.id]
            if n.kind == "cake":
                mask &= links < 0
            shown = int(mask.sum()) >= getattr(px, n.category)
            assert (n.id in kept) == shown, n.id
        for c in graph.of_kind("candle"):
            assert c.support in kept and c.pixels >= px.candle
        for n in graph.nodes:
            assert n.support in kept | {"", "floor"} and set(n.near) <= kept


def test_generated_questions_parse_back_and_are_grounded(renders):
    for seed, _, _, graph, _ in renders:
        again = SceneGraph.from_dict(json.loads(graph.to_json()))
        assert again == graph
        questions = questions_for(graph, seed, CFG)
        assert 30 <= len(questions) <= CFG.questions.max_questions
        assert len(set(questions)) == len(questions)
        frames = [parse_question(q) for q in questions]
        assert all(f is not None and is_grounded(f, graph) and is_on_topic(f, graph)
                   for f in frames), questions
        assert len({frame_key(f) for f in frames}) >= 20
        assert all(q == " ".join(tokenize(q)) for q in questions)


def test_each_question_of_an_image_has_its_own_meaning(renders):
    for seed, _, _, graph, _ in renders:
        keys = [frame_key(parse_question(q)) for q in questions_for(graph, seed, CFG)]
        assert len(set(keys)) == len(keys)


def test_fixed_wording_depends_on_the_meaning_alone():
    frame = parse_question("how many people are there ?")
    fixed = {tuple(wordings(frame, Style(), np.random.default_rng(s), 1, fixed=True))
             for s in range(10)}
    drawn = {tuple(wordings(frame, Style(), np.random.default_rng(s), 1, fixed=False))
             for s in range(10)}
    assert len(fixed) == 1 < len(drawn)
    assert parse_question(fixed.pop()[0]) == frame
    # the meanings of one kind still spread over its templates
    counts = [wordings(parse_question(f"how many {n} are there ?"), Style(),
                       np.random.default_rng(0), 1, fixed=True)[0]
              for n in ("chairs", "mugs", "balls", "people", "toys", "books")]
    assert len({" ".join(t.split()[:2]) for t in counts}) >= 2


def test_cake_with_many_lit_candles_loads():
    r = make_renderer(CFG)
    try:
        body = r._object(Node("cake_0", "cake", "pink", 2.0, 0.0, 0.75, candles=8, lit=True))
        assert body >= 0
    finally:
        r.close()


def test_write_is_atomic_and_resumable(tmp_path):
    out = tmp_path / "vqg"
    cfg = CFG.model_copy(update={"examples": 2})
    splits = {"train": 2, "val": 1}
    assert write_vqg_dataset(out, cfg, splits, progress=False) == {"train": 2, "val": 1}
    (out / "images" / "train" / "000001.png").unlink()
    assert write_vqg_dataset(out, cfg, splits, progress=False) == {"train": 1, "val": 0}
    lines = (out / "questions" / "train.jsonl").read_text().splitlines()
    assert [json.loads(line)["id"] for line in lines] == ["000000", "000001"]
    assert all(json.loads(line)["questions"] for line in lines)
    assert len(list((out / "scenes" / "val").glob("*.json"))) == 1
    meta = json.loads((out / "meta.json").read_text())
    assert meta["counts"] == splits and meta["seed"] == CFG.seed
    assert len(list((out / "examples").glob("*.png"))) == 2
    assert "?" in (out / "examples" / "examples.txt").read_text()
    assert not list(out.rglob(".*.tmp"))


def test_config_rejects_unknown_keys(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("scene: {colour_of_sky: blue}\n")
    with pytest.raises(ConfigError, match=r"scene\.colour_of_sky: unknown key"):
        load_vqg_data_config(bad)
