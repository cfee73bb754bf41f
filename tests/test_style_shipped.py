"""The shipped style-transfer model (assets/models/style/) against its judge and its bars."""

import pytest

from dialogue.style.config import CLASSIFIER_FILE
from dialogue.style.files import load_classifier
from dialogue.style.text import tokenize
from dialogue.style.training.evaluate import evaluate
from dialogue.style.training.metrics import classify
from dialogue.style.transfer import DEFAULT_STYLE_MODEL, StyleTransfer

# the first 200 test sentences of each class; the whole test split measures 87.4 % (bar 85 %)
ACCURACY_BAR = 0.8
NEGATIVE = ["the food was cold and the service was slow .",
            "the waiter was rude to us all night .",
            "the pizza was bland and overpriced .",
            "i will never come back to this hotel ."]
POSITIVE = ["the staff were friendly and the pasta was delicious .",
            "we had a great time at the bar .",
            "the coffee here is always fresh and tasty .",
            "i love this little bakery ."]


@pytest.fixture(scope="module")
def shipped():
    transfer = StyleTransfer.load(DEFAULT_STYLE_MODEL)
    judge, vocab, _ = load_classifier(DEFAULT_STYLE_MODEL.parent / CLASSIFIER_FILE)
    return transfer, judge, vocab


@pytest.mark.parametrize(("sources", "to"), [(NEGATIVE, "positive"), (POSITIVE, "negative")])
def test_shipped_model_flips_the_judge_and_keeps_a_content_word(shipped, sources, to):
    transfer, judge, vocab = shipped
    target = ("negative", "positive").index(to)
    assert classify(judge, vocab, [tokenize(s) for s in sources]) == [1 - target] * len(sources)
    results = transfer.translate_detailed(sources, to)
    flipped = 0
    for source, result in zip(sources, results, strict=True):
        out = result.transferred.split()
        kept = transfer.content_words(tokenize(source)) & set(out)
        flipped += bool(kept) and classify(judge, vocab, [out]) == [target]
    assert flipped >= 3, [r.transferred for r in results]


def test_shipped_model_meets_the_bars_on_held_out_sentences():
    result = evaluate(DEFAULT_STYLE_MODEL.parent, limit=400)  # the first 200 per class
    assert result["accuracy"] >= ACCURACY_BAR and result["self_bleu"] >= 40
    assert result["classifier_accuracy"] >= 0.9
