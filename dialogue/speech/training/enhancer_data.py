"""The enhancer's training sounds: the project's own lines said by the household's voices,
recorded at the robot's microphones with a TV-like programme of other voices in the room.

Each example keeps its two parts apart (what the voice alone and the background alone
would have recorded, :meth:`Acoustics.parts_at_microphones`), which is what the network
learns to tell apart. The programmes are made here, never the one the household runs and
``companion eval asr`` play (:mod:`sim.soundscape`): other voices (no household
voice, and not the presenter's voice or the visitors' of ``eval asr --voices visitors``),
saying lines of the chatterbot corpus, over noise.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch

from dialogue.chat.sources import chatterbot_conversations
from dialogue.chat.training.data import chatterbot_dir
from dialogue.speech.config import EnhancerTrainConfig
from dialogue.speech.enhancer import log_power, spectrum
from dialogue.speech.training.rooms import ROBOT_HEADING, living_room, speaker_within
from robot.audio import RATE, resampled
from robot.voices import PEOPLE_VOICES, Voice, synthesise
from sim.soundscape import LOOP_S, pink_noise, unit


@dataclass
class Examples:
    """Training sounds as log-power spectra (``(frames, bins)``, fp16): of the recording
    (``mixed``) and of the voice alone (``voice``)."""

    mixed: list[torch.Tensor]
    voice: list[torch.Tensor]


def programme_sentences() -> list[str]:
    """The chatterbot corpus's English lines of at least four words."""
    lines = [line for path in sorted(chatterbot_dir().glob("*.yml"))
             for conv in chatterbot_conversations(path) for line in conv]
    return sorted({line for line in lines if len(line.split()) >= 4})


def programme(cfg: EnhancerTrainConfig, sentences: list[str], rng: np.random.Generator
              ) -> np.ndarray:
    """A loop of :data:`LOOP_S` seconds at unit RMS: drawn sentences, each in a drawn
    other voice, over pink noise at a drawn share."""
    parts: list[np.ndarray] = []
    while sum(len(p) for p in parts) < LOOP_S * RATE:
        voice = Voice(name=str(rng.choice(cfg.other_accents)),
                      variant=str(rng.choice(cfg.other_variants)),
                      pitch=int(rng.integers(*cfg.other_pitch)),
                      speed=int(rng.integers(*cfg.other_speed)))
        samples, rate = synthesise(str(rng.choice(sentences)), voice)
        parts += [resampled(samples, rate), np.zeros(int(rng.uniform(*cfg.pause_s) * RATE))]
    talk = unit(np.concatenate(parts)[: int(LOOP_S * RATE)])
    bed = pink_noise(LOOP_S, int(rng.integers(1 << 30)))
    return unit(talk + rng.uniform(*cfg.bed_share) * bed)


def make_examples(lines: list[list[str]], cfg: EnhancerTrainConfig,
                  progress: Callable[[str], None] | None = None) -> Examples:
    """``cfg.examples`` sounds: drawn lines in drawn household voices, rooms, distances and
    programme levels (none in ``1 - cfg.tv_share`` of them)."""
    rng = np.random.default_rng(cfg.seed)
    sentences = programme_sentences()
    loops = [programme(cfg, sentences, rng) for _ in range(cfg.programmes)]
    steady = pink_noise(LOOP_S, cfg.seed)
    out = Examples([], [])
    for k in range(cfg.examples):
        words = lines[int(rng.integers(len(lines)))]
        voice = PEOPLE_VOICES[int(rng.integers(len(PEOPLE_VOICES)))]
        width, depth = rng.uniform(*cfg.room_width_m), rng.uniform(*cfg.room_depth_m)
        tv = rng.random() < cfg.tv_share
        acoustics, robot = living_room(width, depth, "tv" if tv else "quiet",
                                       float(rng.uniform(*cfg.tv_db)))
        speaker = speaker_within(robot, depth, cfg.distance_m, rng)
        samples, rate = synthesise(" ".join(words), voice)
        noises = {"steady": steady, "programme": loops[int(rng.integers(len(loops)))]}
        if cfg.array:
            said, background = (part[0] for part in acoustics.parts_at_array(
                samples, rate, speaker, robot, ROBOT_HEADING, noises, rng))
        else:
            said, background = acoustics.parts_at_microphones(samples, rate, speaker, robot,
                                                              noises, rng)
        both = torch.as_tensor(np.stack([said + background, said]), dtype=torch.float32)
        mixed, alone = log_power(spectrum(both)).half()
        out.mixed.append(mixed)
        out.voice.append(alone)
        if progress is not None and (k + 1) % 500 == 0:
            progress(f"{k + 1} of {cfg.examples} training sounds")
    return out
