"""``companion eval asr``: the recogniser on held-out lines said in a simulated room.

Each held-out line (the intent router's and the feedback model's held-out files, never in
the language model's corpus) is spoken by one of the people's voices and carried to the
robot's microphones by the room acoustics of a household run (sim/acoustics.py), from
1, 3 and 5 m, in a quiet room and with the TV on. The report gives the word error rate, the
share of lines the robot would act on (confidence at or above the threshold) and, for the
intent lines, the router's accuracy on the transcript against its accuracy on the text.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import jiwer
import numpy as np

from dialogue.intent import IntentClassifier
from dialogue.speech.config import SpeechConfig
from dialogue.speech.recognizer import SpeechRecognizer, Transcript
from dialogue.speech.training.corpus import HELD_OUT_FILES, tsv_lines
from dialogue.speech.training.rooms import NOISES, living_room, recording, speaker_at
from dialogue.speech.words import spoken_words
from robot.audio import RATE
from robot.voices import PEOPLE_VOICES, Voice, synthesise
from sim.robot_config import load_robot_config
from sim.soundscape import noise_loops

DISTANCES_M = (1.0, 3.0, 5.0)
VOICES = 4
# Voices none of the household's people has, which the acoustic model's adaptation never
# heard: how the recogniser does with a visitor.
VISITOR_VOICES = (Voice(name="en-us", variant="klatt6", pitch=45, speed=130),
                 Voice(name="en-us", variant="m3", pitch=50, speed=130),
                 Voice(name="en-us", variant="f3", pitch=65, speed=130),
                 Voice(name="en-us", variant="klatt5", pitch=55, speed=130))
# Voices of two synthesizer families (CMU Flite, Festival) that no model and no setting of
# the project was trained, adapted or chosen on: how it does with voices it has never met.
HELD_OUT_VOICES = (Voice(engine="flite", name="slt", speed=135),
                   Voice(engine="festival", name="kal_diphone", speed=135),
                   Voice(engine="flite", name="rms", speed=135),
                   Voice(engine="festival", name="cmu_us_slt_arctic_hts", speed=135),
                   Voice(engine="flite", name="awb", speed=135))
VOICE_SETS = {"household": PEOPLE_VOICES[:VOICES], "visitors": VISITOR_VOICES,
              "held-out": HELD_OUT_VOICES}
ROOM_M = (8.0, 7.0)                   # the living room's width and depth


@dataclass
class Condition:
    """The lines of one distance and noise: references, transcripts, routing."""

    distance: float
    noise: str
    family: str           # the synthesizer of the voices
    refs: list[str]
    hyps: list[str]
    understood: list[bool]
    routed: list[bool]
    routed_text: list[bool]

    def row(self) -> dict[str, object]:
        """The condition's figures."""
        n_routed = len(self.routed)
        return {"distance_m": self.distance, "noise": self.noise, "voices": self.family,
                "lines": len(self.refs),
                "wer": round(jiwer.wer(self.refs, self.hyps), 4),
                "understood": round(float(np.mean(self.understood)), 4),
                "routing": round(sum(self.routed) / n_routed, 4) if n_routed else None,
                "routing_text": round(sum(self.routed_text) / n_routed, 4) if n_routed
                else None}


@dataclass(frozen=True)
class Said:
    """One line said at one distance in one noise, as the recogniser heard it."""

    noise: str
    distance: float
    index: int            # of the line in the list given
    voice: Voice
    heard: Transcript
    decode_s: float
    audio_s: float


def said_in_rooms(texts: list[str], speakers: Sequence[Voice], recogniser: SpeechRecognizer,
                  seed: int = 0, array: bool = False) -> Iterator[Said]:
    """Each of ``texts``, said by ``speakers`` in turn, in the evaluation's living room (quiet
    and with the TV on) from each of :data:`DISTANCES_M`, and transcribed (``array``: as
    each of the head's microphones records it, :meth:`Acoustics.parts_at_array`)."""
    rng = np.random.default_rng(seed)
    loops = noise_loops(seed)
    who = [speakers[i % len(speakers)] for i in range(len(texts))]
    voices = [synthesise(text, voice) for text, voice in zip(texts, who, strict=True)]
    for noise in NOISES:
        acoustics, robot = living_room(*ROOM_M, noise)
        for distance in DISTANCES_M:
            for i, (samples, rate) in enumerate(voices):
                speaker = speaker_at(robot, distance, rng)
                audio = recording(acoustics, samples, rate, speaker, robot, loops, rng, array)
                t0 = time.perf_counter()
                heard = recogniser.transcribe(audio, RATE)
                yield Said(noise, distance, i, who[i], heard, time.perf_counter() - t0,
                           audio.shape[-1] / RATE)


def heads_microphones(choice: str | None = None) -> bool:
    """Whether recordings take each of the head's microphones, for a ``--microphones
    one|array`` choice; None: as robot.yaml's ``microphones.array`` says."""
    return load_robot_config().microphones.array if choice is None else choice == "array"


def evaluate_asr(limit: int | None = None, seed: int = 0,
                 progress: Callable[[str], None] | None = None,
                 cfg: SpeechConfig | None = None, voices: str = "household",
                 array: bool | None = None) -> dict[str, object]:
    """The table of :class:`Condition` rows (one per voice family, noise and distance) over
    the held-out lines (the first ``limit`` of each file when given), with the recogniser's
    speed; ``cfg`` chooses the models, and ``voices`` who says the lines (a key of
    :data:`VOICE_SETS`: the people's, visitors' or the held-out families');
    ``array`` records all the head's microphones (:func:`said_in_rooms`; default: as the
    robot's ``microphones.array`` says)."""
    if array is None:
        array = heads_microphones()
    speakers = VOICE_SETS[voices]
    lines = [(label if name.startswith("intent") else None, text)
             for name in HELD_OUT_FILES for label, text in tsv_lines(name)[:limit]]
    recogniser, router = SpeechRecognizer(cfg), IntentClassifier.default()
    conditions: dict[tuple[str, str, float], Condition] = {}
    decode_s = audio_s = 0.0
    for said in said_in_rooms([text for _, text in lines], speakers, recogniser, seed, array):
        key = (said.voice.engine, said.noise, said.distance)
        c = conditions.setdefault(key, Condition(said.distance, said.noise, said.voice.engine,
                                                 [], [], [], [], []))
        label, text = lines[said.index]
        decode_s, audio_s = decode_s + said.decode_s, audio_s + said.audio_s
        c.refs.append(" ".join(spoken_words(text)))
        c.hyps.append(said.heard.text)
        c.understood.append(recogniser.understood(said.heard))
        if label is not None:
            c.routed.append(router.classify(said.heard.text).label == label)
            c.routed_text.append(router.classify(text).label == label)
        if said.index == len(lines) - 1 and progress is not None:
            progress(f"{said.noise} {said.distance:g} m: {c.row()}")
    return {"rows": [conditions[k].row() for k in sorted(conditions)], "array": array,
            "voices": [v.label for v in speakers], "recogniser": recogniser.cfg.model.engine,
            "lines": len(lines), "real_time_factor": round(decode_s / audio_s, 4)}
