"""Schema of ``config/acts.yaml``: the conversation acts, the words that name a line's topic,
the care signals and the robot's authored replies."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from core.paths import from_root

ACTS = ("loss", "lonely", "unwell", "worry", "good_news", "memory", "plan", "need", "company",
        "thanks", "greeting", "goodbye", "about_robot", "smalltalk")
QUESTION = "question"         # a line for the QA bot (the intent router decides which)
SHARING = ("loss", "lonely", "unwell", "worry", "good_news", "memory", "plan", "need")
# the acts that share something of the person (the others are social formulae and chat)
CARE = ("none", "pain", "dizzy", "fall", "medicine", "not_eating", "confused")
KINDS = ("echo", "female", "male", "people", "pet", "body", "time", "job", "thing", "any")
Variants = dict[str, list[str]]
SLOTS = ("topic", "Topic", "word", "they", "them", "their", "They", "Their", "when", "echo",
         "helper", "name", "Greeting", "Farewell")   # what a reply may fill in


def check_slots(templates: list[str], where: str, slots: tuple[str, ...] = SLOTS) -> None:
    """Raise ``ValueError`` for a template with a slot not in ``slots`` (or bad braces)."""
    known = dict.fromkeys(slots, "")
    for t in templates:
        try:
            t.format_map(known)
        except (KeyError, ValueError, IndexError) as exc:
            raise ValueError(f"{where}: {t!r}: unknown slot or stray brace ({exc}); "
                             f"slots: {', '.join(slots)}") from None


class ClassifierConfig(StrictModel):
    """How sure the act and care models must be."""

    min_confidence: float = Field(ge=0, le=1)
    care_min_confidence: float = Field(ge=0, le=1)


class TrainingConfig(StrictModel):
    """``companion train acts``: the lines and the heads' logistic regression."""

    training_file: Path
    c_act: float = Field(gt=0)
    c_care: float = Field(gt=0)
    max_iter: int = Field(ge=1)


class RelevanceConfig(StrictModel):
    """When a chit-chat reply is a non sequitur."""

    min_cosine: float = Field(ge=-1, le=1)


class ThreadConfig(StrictModel):
    """How long follow-ups stay on one topic."""

    max_turns: int = Field(ge=1)


class TopicWords(StrictModel):
    """The words that name what a line is about, by kind."""

    female: list[str]
    male: list[str]
    people: list[str]
    pet: list[str]
    body: list[str]
    time: list[str]


class EntertainConfig(StrictModel):
    """The robot's own stories and jokes, and what it asks after one."""

    stories: list[str] = Field(min_length=1)
    jokes: list[str] = Field(min_length=1)
    story_ask: list[str] = Field(min_length=1)
    joke_ask: list[str] = Field(min_length=1)


class RecallConfig(StrictModel):
    """The robot's questions about what someone told it before ({said}, {when})."""

    visit: list[str] = Field(min_length=1)
    ailment: list[str] = Field(min_length=1)
    worry: list[str] = Field(min_length=1)
    forgot: str = Field(min_length=1)       # said when asked to forget
    nothing: str = Field(min_length=1)      # said when there was nothing to forget

    @model_validator(mode="after")
    def _slots(self) -> RecallConfig:
        check_slots([*self.visit, *self.ailment, *self.worry], "recall", ("said", "when"))
        return self


class EmotionConfig(StrictModel):
    """The feeling of a line of each act, and how sure of it the robot must be."""

    negative: list[str]
    positive: list[str]
    min_share: float = Field(ge=0, le=1)     # a feeling is the line's at this probability
    doubt_share: float = Field(ge=0, le=1)   # a mood styles no reply this likely contrary


class CareConfig(StrictModel):
    """The care signals: who helps, which raise an alert, and what the robot says."""

    staff_helper: str = Field(min_length=1)
    family_helper: str = Field(min_length=1)
    alert: list[str]
    replies: dict[str, list[str]]
    worry_replies: dict[str, list[str]]   # when the line is a worry ("I'm scared of falling")
    acks: dict[str, Variants]             # instead of the act's acknowledgement

    @model_validator(mode="after")
    def _known(self) -> CareConfig:
        unknown = {*self.alert, *self.replies, *self.worry_replies, *self.acks} - set(CARE)
        if unknown:
            raise ValueError(f"unknown care signals {sorted(unknown)}; known: {CARE}")
        if missing := [k for k in self.alert if not self.replies.get(k)]:
            raise ValueError(f"care signals without replies: {missing}")
        return self


class ActReplies(StrictModel):
    """An act's replies: an acknowledgement, a follow-up question, an offer and what it says
    as the conversation goes on, each by the kind of topic (``any`` for every other)."""

    ack: Variants
    ask: Variants
    offer: list[str]
    go_on: Variants
    asked: Variants = Field(default_factory=dict)   # small talk: the answer to a question

    @model_validator(mode="after")
    def _kinds(self) -> ActReplies:
        for part in (self.ack, self.ask, self.go_on):
            if unknown := {*part, *self.asked} - set(KINDS):
                raise ValueError(f"unknown topic kinds {sorted(unknown)}; known: {KINDS}")
            if "any" not in part:
                raise ValueError("each part needs replies for 'any' topic")
        if not self.ack["any"]:
            raise ValueError("an act needs at least one acknowledgement for 'any' topic")
        return self


class ActsConfig(StrictModel):
    """The whole file."""

    model_dir: Path
    classifier: ClassifierConfig
    training: TrainingConfig
    relevance: RelevanceConfig
    thread: ThreadConfig
    topics: TopicWords
    emotion: EmotionConfig
    entertain: EntertainConfig
    recall: RecallConfig
    care: CareConfig
    acts: dict[str, ActReplies]
    unsure: ActReplies                       # for a feeling the robot is not sure of

    @model_validator(mode="after")
    def _every_act(self) -> ActsConfig:
        for name, replies in [*self.acts.items(), ("unsure", self.unsure)]:
            for part in ("ack", "ask", "go_on", "asked"):
                for kind, texts in getattr(replies, part).items():
                    check_slots(texts, f"acts.{name}.{part}.{kind}")
            check_slots(replies.offer, f"acts.{name}.offer")
        for group in (self.care.replies, self.care.worry_replies):
            for kind, texts in group.items():
                check_slots(texts, f"care.{kind}")
        for kind, by_kind in self.care.acks.items():
            for texts in by_kind.values():
                check_slots(texts, f"care.acks.{kind}")
        fun = self.entertain
        check_slots([*fun.stories, *fun.jokes, *fun.story_ask, *fun.joke_ask], "entertain")
        if missing := set(ACTS) - set(self.acts):
            raise ValueError(f"acts without replies: {sorted(missing)}")
        if unknown := {*self.acts, *self.emotion.negative, *self.emotion.positive} - set(ACTS):
            raise ValueError(f"unknown acts {sorted(unknown)}; known: {ACTS}")
        return self

    def resolved_model_dir(self) -> Path:
        """Where the encoder and the heads are."""
        return from_root(self.model_dir)

    def share(self, acts: dict[str, float], emotion: str) -> float:
        """The probability, under ``acts``, of the acts that share ``emotion``."""
        return sum(acts.get(a, 0.0) for a in getattr(self.emotion, emotion))

    def emotion_of(self, act: str) -> str | None:
        """"negative", "positive" or None: the feeling a line of ``act`` shares."""
        if act in self.emotion.negative:
            return "negative"
        return "positive" if act in self.emotion.positive else None


@cache
def load_acts_config(path: str | Path | None = None) -> ActsConfig:
    """The packaged defaults, merged with a user's file at ``path``."""
    return load_model(ActsConfig, "acts.yaml", path)
