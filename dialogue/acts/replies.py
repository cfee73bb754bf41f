"""The robot's own replies to what people share (``acts`` and ``care`` in
``config/acts.yaml``): acknowledge the feeling in the person's terms, offer what the robot
can do where it helps, and ask a follow-up that invites them to go on; then, while they do,
stay on that topic for up to ``thread.max_turns`` replies, never saying a reply twice in a
conversation. A care signal gets a calm reply that brings in whoever looks after the person.
"""

from __future__ import annotations

import re
import zlib
from dataclasses import dataclass, field

from dialogue.acts.config import QUESTION, ActsConfig, load_acts_config
from dialogue.acts.model import ActModel, Reading
from dialogue.acts.topics import PRONOUNS, Topic, TopicFinder
from dialogue.conversation import load_conversation_config
from dialogue.qa.wordnet import WordNet
from mind.preferences.memory import Fact

CHITCHAT_ACTS = frozenset({QUESTION, "smalltalk", "about_robot"})   # the seq2seq's and QA's
NOT_GOING_ON = frozenset({QUESTION, "greeting", "goodbye", "thanks", "company"})
GREETING = re.compile(r"\bgood (morning|afternoon|evening)\b", re.I)
LIKE = re.compile(r"\bi (?:really )?(?:love|like|enjoy|adore) ([a-z][a-z' ]{2,30}?)"
                  r"(?:[,.!?]|$| very| so| best)", re.I)
FORGET = re.compile(r"\bforget (?:that|it|what i (?:said|told you))\b|\bdon't remember that\b",
                    re.I)
PERSON_KINDS = ("female", "male", "people")
STORY = re.compile(r"\b(?:story|stories|tale|tales)\b", re.I)
JOKE = re.compile(r"\b(?:joke|jokes|something funny|make me laugh)\b", re.I)
NIGHT = re.compile(r"\b(?:bed|night|goodnight|nighty night|sleep|nap|turning in|lie down"
                   r"|kip)\b", re.I)
ASKS = re.compile(r"\?|^\W*(?:(?:robot|pip|love|dear|well|so|oh|and)\W+)?"
                  r"(?:what|who|where|when|why|which|is it|are you|can you|could you"
                  r"|will you|would you|do you|tell me|show me"
                  r"|how (?:do|does|did|is|are|can|many|much|old|long|far))\b", re.I)


def pick_kind(by_kind: dict[str, list[str]], topic: Topic) -> list[str]:
    """The replies for a job the line names; else those that say the line back, when it
    can be; else those for the topic's kind; else those that name a thing, when the line
    names something; else those for any topic."""
    if topic.kind == "job" and by_kind.get("job"):
        return by_kind["job"]
    if topic.echo and by_kind.get("echo"):
        return by_kind["echo"]
    named = by_kind.get("thing") if topic.kind != "any" else None
    return by_kind.get(topic.kind) or named or by_kind["any"]


@dataclass
class Thread:
    """The topic a conversation is on: the act that opened it, its topic, replies so far."""

    act: str
    topic: Topic
    turns: int = 1


@dataclass
class TalkState:
    """What one conversation remembers: its thread and every reply said in it."""

    thread: Thread | None = None
    said: set[str] = field(default_factory=set)


@dataclass(frozen=True)
class TalkReply:
    """An authored reply: its text, the act it answers, the topic, the line's emotion, the
    care signal raised (None for none) and the parts it was built of."""

    text: str
    act: str
    topic: Topic
    emotion: str | None
    care: str | None
    parts: tuple[str, ...]


class CompanionTalk:
    """Reads a line with the act model and, for what people share, composes the reply."""

    def __init__(self, cfg: ActsConfig, model: ActModel, finder: TopicFinder,
                 staff: bool = False) -> None:
        self.cfg, self.model, self.finder = cfg, model, finder
        self.helper = cfg.care.staff_helper if staff else cfg.care.family_helper

    @classmethod
    def load(cls, staff: bool = False, cfg: ActsConfig | None = None) -> CompanionTalk:
        """The shipped act model with ``cfg`` (default the packaged ``config/acts.yaml``) and
        the installed WordNet; ``staff``: the household has care staff to call."""
        cfg = cfg or load_acts_config()
        model = ActModel.default() if cfg == load_acts_config() else ActModel.load(cfg)
        wordnet = WordNet.load(load_conversation_config().knowledge.wordnet_dir)
        return cls(cfg, model, TopicFinder(cfg.topics, wordnet), staff)

    def read(self, text: str) -> Reading:
        """The act model's reading of ``text``."""
        return self.model.read(text)

    def emotion(self, reading: Reading) -> str | None:
        """The feeling the line shares: the feeling whose acts hold at least
        ``emotion.min_share`` of the probability, else None."""
        return next((e for e in ("negative", "positive")
                     if self.cfg.share(reading.acts, e) >= self.cfg.emotion.min_share), None)

    def mood_allowed(self, reading: Reading, mood: str) -> bool:
        """Whether a reply to the line may be styled in ``mood``: the contrary feeling holds
        less than ``emotion.doubt_share`` (no cheer for what may be sad news)."""
        contrary = "negative" if mood == "positive" else "positive"
        return self.cfg.share(reading.acts, contrary) < self.cfg.emotion.doubt_share

    def relevant(self, line: str, reply: str) -> bool:
        """Whether ``reply`` relates to ``line``: the cosine of their embeddings is at least
        ``relevance.min_cosine`` (a non sequitur is not said)."""
        return self.model.encoder.cosine(line, reply) >= self.cfg.relevance.min_cosine

    def follow_up(self, text: str, reply: str, state: TalkState) -> str:
        """``reply`` (the chit-chat's, to small talk) with the robot's own question about the
        line's topic after it, when it neither names the topic nor asks anything."""
        topic = self.finder.find(text)
        if topic.kind == "any" or "?" in reply or topic.word in reply.lower():
            return reply
        asks = self.cfg.acts["smalltalk"].ask
        options = asks.get(topic.kind) or asks.get("thing") or []
        return f"{reply} {self._pick(text, options, topic.slots(), state)}" if options else reply

    def small_talk(self, text: str, state: TalkState, name: str | None = None,
                   reading_act: str = "smalltalk") -> TalkReply:
        """The robot's own small-talk reply to ``text`` (when the chit-chat's did not
        relate), about the robot when the line was read so; a question gets an answer."""
        topic = self.finder.find(text)
        slots = self._slots(text, topic, name)
        act = "about_robot" if reading_act == "about_robot" else "smalltalk"
        asked = self.cfg.acts[act].asked
        if ASKS.search(text) and asked:
            said = self._pick(text, pick_kind(asked, topic), slots, state)
            return TalkReply(said, act, topic, None, None, ("asked",))
        parts = [self._pick(text, self._variants(act, part, topic), slots, state)
                 for part in ("ack", "ask")]
        return TalkReply(" ".join(parts), act, topic, None, None, ("ack", "ask"))

    def reply(self, text: str, reading: Reading, state: TalkState,
              name: str | None = None) -> TalkReply | None:
        """The authored reply to ``text`` (read as ``reading``), or None for a line the
        seq2seq or the QA bot answers. ``state`` is updated with the thread and the reply."""
        topic = self.finder.find(text)
        care = self.model.alert(reading)
        sure = reading.act_confidence >= self.cfg.classifier.min_confidence
        act = reading.act if sure else None
        slots = self._slots(text, topic, name)
        if care is not None:
            act = act if act is not None and act not in CHITCHAT_ACTS else "unwell"
            by_act = self.cfg.care.worry_replies if act == "worry" else {}
            acks = self.cfg.care.acks.get(care)
            ack = self._pick(text, pick_kind(acks, topic) if acks else
                             self._variants(act, "ack", topic), slots, state)
            said = self._pick(text, by_act.get(care) or self.cfg.care.replies[care], slots,
                              state)
            return self._said(state, Thread(act, topic), f"{ack} {said}", act, topic,
                              reading, care, ("ack", "care"))
        thread = state.thread
        if thread is not None and self._goes_on(thread, text, reading, act, topic):
            thread.turns += 1
            said = self._pick(text, self._variants(thread.act, "go_on", thread.topic),
                              {**slots, **thread.topic.slots()}, state)
            return self._said(state, thread, said, thread.act, thread.topic, reading, None,
                              ("go_on",))
        if act is None or act in CHITCHAT_ACTS:
            state.thread = None
            return None
        if act == "company" and (told := self._entertain(text, slots, state)) is not None:
            return self._said(state, Thread(act, topic), told, act, topic, reading, None,
                              ("tell",))
        felt = self.cfg.emotion_of(act)
        unsure = felt is not None and self.emotion(reading) != felt
        replies = self.cfg.unsure if unsure else self.cfg.acts[act]
        parts = [("ack", self._pick(text, pick_kind(replies.ack, topic), slots, state))]
        if replies.offer:
            parts.append(("offer", self._pick(text, replies.offer, slots, state)))
        ask = pick_kind(replies.ask, topic)
        if ask:
            parts.append(("ask", self._pick(text, ask, slots, state)))
        return self._said(state, Thread(act, topic), " ".join(p for _, p in parts), act,
                          topic, reading, None, tuple(k for k, _ in parts))

    def facts(self, text: str, told: TalkReply | None) -> list[Fact]:
        """What the line tells about its speaker, to remember: a visit coming (a person and a
        day), a sore body part, a worry, their old job, their pet, a relative named, what
        they love."""
        out = []
        topic = told.topic if told is not None else self.finder.find(text)
        act = told.act if told is not None else None
        when = topic.when.strip()
        if act == "plan" and topic.kind in PERSON_KINDS and when:
            out.append(Fact(kind="visit", said=topic.said, when=when))
        elif act == "unwell" and topic.kind == "body":
            out.append(Fact(kind="ailment", said=topic.said))
        elif act == "worry" and topic.kind != "any":
            out.append(Fact(kind="worry", said=topic.said))
        if topic.kind == "job":
            out.append(Fact(kind="job", said=topic.said))
        elif topic.kind == "pet" and topic.said.startswith("your"):
            out.append(Fact(kind="pet", said=topic.said))
        elif topic.kind in ("female", "male") and len(topic.said.split()) > 2:
            out.append(Fact(kind="family", said=topic.said))   # "your daughter Susan"
        if like := LIKE.search(text):
            out.append(Fact(kind="like", said=like.group(1).strip()))
        return out

    def recall(self, fact: Fact) -> str:
        """The robot's question about ``fact``, asked the next time it talks with them."""
        options = getattr(self.cfg.recall, fact.kind)
        slots = {"said": fact.said, "when": f" {fact.when}" if fact.when else ""}
        return options[zlib.crc32(fact.said.encode()) % len(options)].format_map(slots)

    def _entertain(self, text: str, slots: dict[str, str], state: TalkState) -> str | None:
        """A story or a joke when the line asks for one (one not yet told), else None."""
        fun = self.cfg.entertain
        if STORY.search(text):
            tale, ask = (self._pick(text, part, slots, state)
                         for part in (fun.stories, fun.story_ask))
            return f"Of course, here's a story. {tale} {ask}"
        if JOKE.search(text):
            joke, ask = (self._pick(text, part, slots, state)
                         for part in (fun.jokes, fun.joke_ask))
            return f"Here's a joke for you. {joke} {ask}"
        return None

    def _said(self, state: TalkState, thread: Thread, text: str, act: str, topic: Topic,
              reading: Reading, care: str | None, parts: tuple[str, ...]) -> TalkReply:
        state.thread = thread if act not in NOT_GOING_ON else None
        return TalkReply(text, act, topic, self.emotion(reading), care, parts)

    def _goes_on(self, thread: Thread, text: str, reading: Reading, act: str | None,
                 topic: Topic) -> bool:
        """Whether the line answers the thread's last follow-up: no question, greeting or
        farewell, and about the thread's topic: it names none of its own, names the same,
        or calls it by its pronoun ("she was lovely"); a line that opens another act on a
        new topic starts a thread of its own."""
        if thread.turns >= self.cfg.thread.max_turns or ASKS.search(text):
            return False
        person = thread.topic.pronoun in ("female", "male", "people")
        refers = person and bool(re.search(
            rf"\b(?:{'|'.join(PRONOUNS[thread.topic.pronoun])})\b", text, re.I))
        if refers:
            return True
        if reading.act in NOT_GOING_ON or reading.act == "about_robot":
            return False
        return topic.kind == "any" or topic.word == thread.topic.word

    def _variants(self, act: str, part: str, topic: Topic) -> list[str]:
        """The act's replies of ``part`` for ``topic`` (:func:`pick_kind`)."""
        return pick_kind(getattr(self.cfg.acts[act], part), topic)

    def _slots(self, text: str, topic: Topic, name: str | None) -> dict[str, str]:
        greeting = GREETING.search(text)
        night = NIGHT.search(text)
        return {**topic.slots(), "helper": self.helper, "name": f", {name}" if name else "",
                "Greeting": f"Good {greeting.group(1).lower()}" if greeting else "Hello",
                "Farewell": "Sleep well" if night else "See you later"}

    @staticmethod
    def _pick(text: str, options: list[str], slots: dict[str, str], state: TalkState) -> str:
        """A variant chosen by the line (so different lines hear different ones), the next
        one when it was already said in this conversation."""
        start = zlib.crc32(text.lower().encode()) % len(options)
        filled = [options[(start + k) % len(options)].format_map(slots)
                  for k in range(len(options))]
        said = next((f for f in filled if f not in state.said), filled[0])
        state.said.add(said)
        return said
