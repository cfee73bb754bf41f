"""The dialogue manager (thesis §3.3, Fig. 3.9): route each utterance to the QA bot or to
chit-chat, keep a short context, and return the reply with any side effect for the robot.

Chit-chat and the mood-driven style transfer plug in through two small protocols,
:class:`ChitChat` and :class:`StyleTransfer`; without a chit-chat model the manager says
so (route ``chitchat_unavailable``) instead of inventing an answer.
"""

from __future__ import annotations

import dataclasses
import logging
import re
import unicodedata
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol, runtime_checkable

from dialogue.acts.config import QUESTION, SHARING
from dialogue.acts.model import Reading
from dialogue.acts.replies import ASKS, FORGET, CompanionTalk, TalkReply, TalkState
from dialogue.input_check import InputCheck
from dialogue.intent import CHITCHAT, MODES, Intent, IntentClassifier
from dialogue.persona import Persona
from dialogue.qa import CATEGORIES
from dialogue.qa.base import Action, Answer, DialogueError
from dialogue.qa.bot import QABot
from dialogue.qa.places import TIME_WORDS, place_lost
from dialogue.qa.text import STOPWORDS, content_words, normalise
from mind.preferences.memory import Fact, Memory

log = logging.getLogger("companion.dialogue")

Mood = Literal["positive", "negative"]
MAX_CHARS = 500  # longer input is cut here
HISTORY = 10  # turns kept in the context
FOLLOWABLE = ("time", "weather", "news", "information", "related_topics", "map")
ABOUT_A_PLACE = ("time", "weather")  # routes whose answer depends on the place asked about
FOLLOW_UP = re.compile(r"^(?:and|what about|how about|and what about|and how about)\b", re.I)
MORE = re.compile(r"^(?:tell me |say )?(?:some )?more\b", re.I)  # after an answer about a topic
INTRO = re.compile(r"\b(?:my name is|my name's|call me|i am called|i'm called)\s+"
                   r"([A-Za-z][\w'-]*(?-i: [A-Z][\w'-]*)?)", re.I)
SHORT_INTRO = re.compile(r"^(?:(?:hi|hello|hey)\b[\s,!.]*)?(?:i'm|i am)\s+"
                         r"((?-i:[A-Z][a-z][\w'-]*))[\s.!]*$", re.I)  # "Hi, I'm Anna."
LATER = frozenset({"back", "again", "sometime", "soon", "anytime", "whenever"})  # "call me back"
ASK_NAME = re.compile(r"\b(?:what(?:'s| is) my name|do you (?:know|remember) my name)\b", re.I)
RECALLED = ("visit", "ailment", "worry")   # what the robot asks about when they meet again
UNAVAILABLE = ("I'm sorry, my chit-chat model isn't loaded, so I can't chat freely right now. "
               "I can tell you the time or the weather, read the news, look things up, show "
               "the map, sing a song or take a photo.")


@dataclass
class DialogueContext:
    """What the manager remembers about one conversation."""

    name: str | None = None
    last_topic: str | None = None
    last_route: str | None = None
    mode: str = "auto"  # "auto", "qa", "chitchat" or a QA category (the tablet buttons)
    history: deque[tuple[str, str]] = field(default_factory=lambda: deque(maxlen=HISTORY))
    talk: TalkState = field(default_factory=TalkState)  # the topic it is on, what it said


@runtime_checkable
class ChitChat(Protocol):
    """A chit-chat model: one reply to one utterance."""

    def reply(self, text: str, context: DialogueContext) -> str:
        """The model's reply to ``text``."""
        ...


@runtime_checkable
class StyleTransfer(Protocol):
    """Mood-driven style transfer of sentences to ``to`` = "positive" or "negative"."""

    def translate(self, sentences: list[str], to: str) -> list[str]:
        """The sentences rewritten in the style ``to``."""
        ...


SAY_AGAIN = "Sorry, could you say that again?"
NOT_UNDERSTOOD = "I'm sorry, I still can't make out what you said."


@dataclass(frozen=True)
class Reply:
    """What the robot says, through which route, any action, and what the tablet shows."""

    text: str
    route: str
    action: Action | None = None
    tablet: str | None = None
    mood: str | None = None
    unstyled: str | None = None   # the chit-chat reply before the style transfer changed it
    found: bool = True            # False when the robot could not answer ("I don't know")
    act: str | None = None        # what the line shared (dialogue/acts), when it was read
    emotion: str | None = None    # the line's feeling: "negative", "positive" or None
    care: str | None = None       # the care signal the line raised, if any
    remembered: tuple[str, ...] = ()   # the kinds of what it newly keeps about the speaker

    def to_dict(self) -> dict[str, Any]:
        """Plain data for logs and ``--json`` output."""
        return {"text": self.text, "route": self.route,
                "action": self.action.to_dict() if self.action else None,
                "tablet": self.tablet, "mood": self.mood, "unstyled": self.unstyled,
                "found": self.found, "act": self.act, "emotion": self.emotion,
                "care": self.care, "remembered": list(self.remembered)}


def clean_input(text: object, max_chars: int = MAX_CHARS) -> str:
    """``text`` as a single line: control characters removed, spaces collapsed, length cut."""
    s = text if isinstance(text, str) else "" if text is None else str(text)
    s = s[: max_chars * 4]
    s = "".join(" " if unicodedata.category(c) in ("Cc", "Zl", "Zp") else c for c in s
                if unicodedata.category(c) not in ("Cf", "Cs", "Co", "Cn"))
    return " ".join(s.split())[:max_chars].strip()


class DialogueManager:
    """Answers one utterance at a time; see :meth:`respond`."""

    def __init__(self, qa: QABot | None = None, *, classifier: IntentClassifier | None = None,
                 chitchat: ChitChat | None = None, style: StyleTransfer | None = None,
                 on_reply: Callable[[dict[str, Any]], None] | None = None,
                 max_chars: int = MAX_CHARS, input_check: InputCheck | None = None,
                 persona: Persona | None = None, min_confidence: float = 0.0,
                 talk: CompanionTalk | None = None) -> None:
        self.qa = qa if qa is not None else QABot.offline()
        self.min_confidence = min_confidence    # of a transcript, to act on it
        self.classifier = classifier or IntentClassifier.default()
        self.chitchat = chitchat
        self.style = style
        self.on_reply = on_reply
        self.max_chars = max_chars
        self.input_check = input_check or InputCheck.default()
        self.persona = persona or Persona.default()
        self.talk = talk
        self.memory: Memory | None = None   # what people told, kept between runs (when set)
        self._told: TalkReply | None = None  # the authored reply of the line being answered
        self.context = DialogueContext()
        self.contexts: dict[str, DialogueContext] = {}

    def context_of(self, person: str | None) -> DialogueContext:
        """The conversation with ``person`` (the manager's own for no one in particular)."""
        if person is None:
            return self.context
        return self.contexts.setdefault(person, DialogueContext())

    def respond(self, text: str, mood: Mood | bool = "positive",
                context: DialogueContext | None = None, confidence: float = 1.0,
                person: str | None = None) -> Reply:
        """Reply to ``text``. ``mood`` (or True for positive) styles chit-chat replies;
        ``context`` defaults to the manager's own. A transcript of speech whose
        ``confidence`` is under ``min_confidence`` is not acted on: the robot asks for it
        again (route ``say_again``), and says it cannot make it out when the line after
        that is unclear too (``not_understood``); so is a time or weather question whose
        place was lost (:func:`dialogue.qa.places.place_lost`). Never raises for any input
        text; a bad ``mood`` or ``context.mode`` is a :class:`DialogueError`. With a
        ``memory`` and the ``person`` speaking, what they tell about themselves is kept, the
        first reply of a conversation asks about what they told before, and "forget that"
        forgets the last thing kept."""
        mood = ("positive" if mood else "negative") if isinstance(mood, bool) else mood
        if mood not in ("positive", "negative"):
            raise DialogueError(f"mood must be 'positive' or 'negative', got {mood!r}")
        ctx = context if context is not None else self.context
        if ctx.mode not in MODES:
            raise DialogueError(f"unknown mode {ctx.mode!r}; choose from {', '.join(MODES)}")
        said = clean_input(text, self.max_chars)
        first = not ctx.history
        if first and self.memory is not None and person is not None and ctx.name is None:
            ctx.name = next((f.said for f in reversed(self.memory.facts.get(person, []))
                             if f.kind == "name"), None)    # greeted by the name they gave
        named = ctx.name
        try:
            reply = (self._unsure(mood, ctx) if confidence < self.min_confidence
                     else self._respond(said, mood, ctx))
            if self.memory is not None and person is not None and self.talk is not None:
                reply = self._remember(said, reply, person, first,
                                       ctx.name if ctx.name != named else None)
        except Exception:  # the robot must keep talking whatever goes wrong inside
            log.exception("dialogue failed on %r", said)
            reply = Reply("Sorry, something went wrong while I was thinking about that.",
                          "error", mood=mood, found=False)
        ctx.history.append((said, reply.text))
        record = {"input": said, **reply.to_dict(), "person": person}
        log.info("reply %s", record)
        if self.on_reply:
            self.on_reply(record)
        return reply

    @staticmethod
    def _unsure(mood: str, ctx: DialogueContext) -> Reply:
        """Ask for an unclear line again, once: after a second unclear line, say so."""
        if ctx.history and ctx.history[-1][1] == SAY_AGAIN:
            return Reply(NOT_UNDERSTOOD, "not_understood", mood=mood, found=False)
        return Reply(SAY_AGAIN, "say_again", mood=mood, found=False)

    def _respond(self, said: str, mood: str, ctx: DialogueContext) -> Reply:
        unclear = self._unclear(said, mood)
        if unclear is not None:
            return unclear
        if not normalise(said):
            return Reply("Sorry, I didn't catch that. Could you say it again?", "empty",
                         mood=mood, found=False)
        if ASK_NAME.search(said):
            text = (f"Your name is {ctx.name}." if ctx.name
                    else "You haven't told me your name yet. What is it?")
            return Reply(text, "context", mood=mood)
        about_me = self.persona.answer(said, ctx.name)
        if about_me is not None:
            return Reply(about_me, "persona", mood=mood)
        greeting = ""
        intro = self._intro(said) or self._short_intro(said)
        if intro:
            ctx.name = intro.group(1).strip().title()
            greeting = f"Nice to meet you, {ctx.name}!"
            said = (said[:intro.start()] + said[intro.end():]).strip(" ,.!;")
            if not content_words(said):
                return Reply(greeting, "introduction", mood=mood)
        intent = self.classifier.classify(said, ctx.mode)
        route = self._route(said, intent, ctx)
        reading = self.talk.read(said) if self.talk is not None else None
        shared = self._shared(said, reading, intent, route, ctx)
        if shared is not None:
            reply = self._authored(shared, mood)
        elif route in ABOUT_A_PLACE and place_lost(said):
            return self._unsure(mood, ctx)   # not the home's time for a city it missed
        elif route == CHITCHAT:
            reply = self._chitchat(said, mood, ctx, reading)
        else:
            answer: Answer = self.qa.answer(route, said, last_topic=ctx.last_topic,
                                            name=ctx.name)
            if answer.topic:
                ctx.last_topic = answer.topic
            reply = Reply(answer.text, route, answer.action, answer.tablet, mood,
                          found=answer.found)
        if reading is not None and reply.act is None:
            reply = dataclasses.replace(reply, act=reading.act,
                                        emotion=self.talk.emotion(reading) if self.talk else None)
        ctx.last_route = reply.route
        if greeting:
            reply = dataclasses.replace(reply, text=f"{greeting} {reply.text}")
        return reply

    @staticmethod
    def _intro(said: str) -> re.Match[str] | None:
        """ "My name is Anna", "call me Anna"; not "call me this week" or "call me back"
        (a transcript has no capitals to tell a name by)."""
        intro = INTRO.search(said)
        first = intro.group(1).split()[0].lower() if intro else ""
        return None if first in STOPWORDS or first in TIME_WORDS or first in LATER else intro

    def _short_intro(self, said: str) -> re.Match[str] | None:
        """ "I'm Anna" as a whole line; not "I'm Happy" (an adjective WordNet knows)."""
        intro = SHORT_INTRO.search(said)
        wordnet = self.input_check.wordnet
        if intro and wordnet is not None and wordnet.base_forms(intro.group(1).lower(), "a"):
            return None
        return intro

    def _unclear(self, said: str, mood: str) -> Reply | None:
        """A short honest reply to a line of symbols, far too long, not English or not
        understood (:mod:`dialogue.input_check`), instead of a guess."""
        unclear = self.input_check.check(said) if said else None
        if unclear is None:
            return None
        return Reply(unclear.text, unclear.route, mood=mood, found=False)

    def _route(self, said: str, intent: Intent, ctx: DialogueContext) -> str:
        if (intent.source == "model" and ctx.last_route in FOLLOWABLE
                and FOLLOW_UP.search(said) and not set(intent.cues) - {ctx.last_route}):
            return ctx.last_route  # "And in Paris?" after a time question: same category
        if (intent.source == "model" and ctx.last_route == "information" and not intent.cues
                and MORE.search(said)):
            return ctx.last_route  # "Tell me more" after "Who was Albert Einstein?"
        return intent.label

    def _remember(self, said: str, reply: Reply, person: str, first: bool,
                  name: str | None) -> Reply:
        """Keep what ``said`` tells about ``person`` (the ``name`` they just gave, too), or
        forget the last thing kept when asked; on a conversation's ``first`` reply, ask
        about something told before."""
        assert self.memory is not None and self.talk is not None
        recall = self.talk.cfg.recall
        if FORGET.search(said):
            gone = self.memory.forget_last(person)
            return Reply(recall.forgot if gone else recall.nothing, "forget", mood=reply.mood)
        asked = self.memory.to_ask(person, RECALLED) if first else None   # told before
        facts = self.talk.facts(said, self._told) if reply.route in ("companion",
                                                                        CHITCHAT) else []
        if name:
            facts.append(Fact(kind="name", said=name))
        kept = tuple(f.kind for f in facts if f.said and self.memory.remember(person, f))
        text = f"{reply.text} {self.talk.recall(asked)}" if asked else reply.text
        return dataclasses.replace(reply, text=text, remembered=kept)

    def _shared(self, said: str, reading: Reading | None, intent: Intent, route: str,
                ctx: DialogueContext) -> TalkReply | None:
        """The robot's authored reply to what ``said`` shares: always for a care signal;
        else unless the act model read a question, or the router's cue words send the line
        to a QA category and it asks something ("What's the weather like for Sunday?") or
        shares nothing ("Sing me a song, love"), or the tablet chose the mode. Asking the
        day or the time is answered, with no alert, however confused it sounds."""
        self._told = None
        if self.talk is None or reading is None or intent.source == "mode":
            return None
        if reading.care == "confused" and route == "time" and ASKS.search(said):
            return None                                   # "what day is it?": it is told
        asks = route != CHITCHAT and intent.cues and (
            ASKS.search(said) or reading.act not in SHARING)   # "sing me a song, love"
        if self.talk.model.alert(reading) is None and (reading.act == QUESTION or asks):
            ctx.talk.thread = None
            return None
        self._told = self.talk.reply(said, reading, ctx.talk, ctx.name)
        return self._told

    @staticmethod
    def _authored(shared: TalkReply, mood: str) -> Reply:
        """An authored reply, said as written: it answers the person's feeling, which the
        robot's mood must not contradict (docs/conversation.md)."""
        return Reply(shared.text, "companion", mood=mood, act=shared.act,
                     emotion=shared.emotion, care=shared.care)

    def _chitchat(self, said: str, mood: str, ctx: DialogueContext,
                  reading: Reading | None = None) -> Reply:
        if self.chitchat is None:
            return Reply(UNAVAILABLE, "chitchat_unavailable", mood=mood, found=False)
        try:
            text = self.chitchat.reply(said, ctx).strip()
        except Exception:
            log.exception("chit-chat model failed on %r", said)
            return Reply("Sorry, I lost my train of thought. Could you say that again?",
                         "chitchat_error", mood=mood, found=False)
        emotion = self.talk.emotion(reading) if self.talk and reading else None
        act = reading.act if reading else None
        if self.talk is not None and not self.talk.relevant(said, text):
            log.info("chit-chat reply %r does not relate to %r: not said", text, said)
            return self._authored(self.talk.small_talk(said, ctx.talk, ctx.name,
                                                       act or "smalltalk"), mood)
        plain = text
        allowed = self.talk is None or reading is None or self.talk.mood_allowed(reading, mood)
        if self.style is not None and text and allowed:
            try:
                styled = self.style.translate([text], mood)
                text = (styled[0].strip() or text) if styled else text
            except Exception:
                log.exception("style transfer failed on %r", text)
        if self.talk is not None and act == "smalltalk" and text:
            text = self.talk.follow_up(said, text, ctx.talk)
        return Reply(text or "Hmm.", CHITCHAT, mood=mood,
                     unstyled=plain if text != plain else None, act=act, emotion=emotion)


__all__ = ["CATEGORIES", "ChitChat", "DialogueContext", "DialogueManager", "Reply",
           "StyleTransfer", "clean_input"]
