"""Room acoustics: what a line said somewhere in the household sounds like at the robot's
microphones (docs/acoustics.md has the formulas and where the constants come from).

Levels are in dB SPL. A voice of ``speech_db`` at 1 m reaches the robot along two kinds of
path, whose powers add:

- the straight line, losing ``20 log10 d`` to distance and ``wall_loss_db`` for every solid
  wall it goes through;
- through open doors: the shortest chain of door openings between the two rooms, losing
  ``20 log10`` of the chain's length and ``door_loss_db`` at each door it bends through.

In the speaker's own room the walls return the sound as a diffuse reverberant field. With
Sabine's reverberation time ``T = 0.161 V / (alpha S)`` and the critical distance
``r_c = 0.057 sqrt(V / T)``, where direct and reverberant sound are equally loud, the
reverberant energy is ``(d / r_c)^2`` times the direct. It is added as the voice convolved
with exponentially decaying noise of that time. ``directivity`` is the product of the
talker's directivity factor (about 2 for a voice facing the listener) and the microphone
array's (its beam towards the voice), which both lengthen ``r_c``. The robot's own room
adds its steady background (``noise.level_db``), every room's source (a TV at ``source_db``
at 1 m) carries to the robot like a voice, and the microphones add their own noise
(``self_noise_db``).
The robot's own voice is never a source: it does not listen while it speaks.

:meth:`Acoustics.parts_at_array` records the same sounds at each of the robot's head
microphones (sim/microphone_array.py) instead: the direct sound delayed from one
microphone to the next, the reverberation and the room's noise as diffuse fields, a
source's programme reverberated like a voice, and the levels with the talker's directivity
alone (``talker_directivity``): the array's beam is not assumed there, a beamformer earns it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from pydantic import Field
from scipy.signal import fftconvolve

from core.config_files import StrictModel
from robot.audio import RATE, REFERENCE_DB, resampled
from sim.layout import Room
from sim.microphone_array import MicrophoneArray

MIN_DISTANCE_M = 0.3      # nearer than this a mouth is no longer a point source
DOOR_HEIGHT_M = 2.05      # the household's door openings (sim/world.py)
Point = tuple[float, float]


class AcousticsConfig(StrictModel):
    """How sound carries through the household (robot.yaml ``acoustics``)."""

    speech_db: float = Field(ge=30, le=90)
    wall_loss_db: float = Field(ge=0, le=80)
    door_loss_db: float = Field(ge=0, le=40)
    absorption: float = Field(gt=0, le=1)
    directivity: float = Field(ge=1, le=20)
    self_noise_db: float = Field(ge=0, le=80)
    lead_s: float = Field(ge=0.1, le=2)
    trail_s: float = Field(ge=0.0, le=2)
    microphones: list[tuple[float, float]] = Field(min_length=1, max_length=16)
    talker_directivity: float = Field(ge=1, le=20)


@dataclass(frozen=True)
class Wall:
    """A solid piece of wall on the floor plan: an axis-aligned rectangle."""

    x0: float
    y0: float
    x1: float
    y1: float

    def crossed_by(self, a: Point, b: Point) -> bool:
        """Whether the segment ``a``-``b`` passes through the rectangle (slab test)."""
        lo, hi = 0.0, 1.0
        for start, delta, low, high in ((a[0], b[0] - a[0], self.x0, self.x1),
                                        (a[1], b[1] - a[1], self.y0, self.y1)):
            if abs(delta) < 1e-12:
                if not low <= start <= high:
                    return False
                continue
            t0, t1 = sorted(((low - start) / delta, (high - start) / delta))
            lo, hi = max(lo, t0), min(hi, t1)
            if lo > hi:
                return False
        return True


def door_centres(room: Room) -> list[tuple[Point, float]]:
    """The centre of each of the room's doors, on its wall line, with its width (m)."""
    out = []
    for d in room.doors:
        if d.wall in ("south", "north"):
            at = (room.x[0] + d.offset, room.y[0] if d.wall == "south" else room.y[1])
        else:
            at = (room.x[0] if d.wall == "west" else room.x[1], room.y[0] + d.offset)
        out.append((at, d.width))
    return out


def _volume_surface(room: Room) -> tuple[float, float]:
    w, h, z = room.x[1] - room.x[0], room.y[1] - room.y[0], room.wall_height
    return w * h * z, 2 * (w * h + w * z + h * z)


def reverberation(room: Room, absorption: float, directivity: float = 1.0
                  ) -> tuple[float, float]:
    """Sabine's reverberation time (s) of the room and its critical distance (m) for a
    source and receiver of the given combined ``directivity`` factor."""
    volume, surface = _volume_surface(room)
    t60 = 0.161 * volume / (absorption * surface)
    return t60, 0.057 * math.sqrt(directivity * volume / t60)


def room_constant(room: Room, absorption: float) -> float:
    """The room constant ``R = alpha S / (1 - alpha)`` (m^2)."""
    return absorption * _volume_surface(room)[1] / (1 - min(absorption, 0.99))


def _level(linear_power: float) -> float:
    return 10.0 * math.log10(max(linear_power, 1e-12))


@lru_cache(maxsize=32)
def _tail(t60: float, seed: int) -> np.ndarray:
    """A unit-energy impulse response of a diffuse field decaying 60 dB in ``t60``."""
    n = int(RATE * min(1.5 * t60, 2.0))
    t = np.arange(n) / RATE
    h = np.random.default_rng(seed).normal(size=n) * np.exp(-6.9 * t / t60)
    h[: int(0.005 * RATE)] = 0.0   # the first reflections come a few ms after the direct sound
    return h / np.sqrt((h ** 2).sum())


class Acoustics:
    """One household's acoustics: its rooms, its solid walls and its noise sources."""

    def __init__(self, cfg: AcousticsConfig, rooms: Sequence[Room], walls: Sequence[Wall],
                 sources: dict[str, Point]) -> None:
        self.cfg = cfg
        self.rooms = tuple(rooms)
        self.walls = tuple(walls)
        self.sources = sources          # a noise source's name -> where it plays from
        doors = [d for r in self.rooms for d in door_centres(r)]
        # a door joins every room whose edge it lies on, whichever room names it
        self.doors = {r.name: [d for d in doors if r.contains(*d[0])] for r in self.rooms}
        self.array = MicrophoneArray(cfg.microphones, RATE)

    def room_at(self, p: Point) -> Room | None:
        """The room holding ``p`` (None: in a wall or outside)."""
        return next((r for r in self.rooms if r.contains(*p)), None)

    def walls_between(self, a: Point, b: Point) -> int:
        """How many solid walls the straight line from ``a`` to ``b`` goes through."""
        return sum(w.crossed_by(a, b) for w in self.walls)

    def _door_path(self, a: Point, b: Point) -> tuple[float, list[float]] | None:
        """The shortest chain of doors from ``a``'s room to ``b``'s: its length and the
        widths of the doors it bends through (None: the rooms do not connect)."""
        start, goal = self.room_at(a), self.room_at(b)
        if start is None or goal is None or start.name == goal.name:
            return None
        done: set[Point] = set()
        frontier = [(math.dist(a, at), [w], at) for at, w in self.doors[start.name]]
        while frontier:
            frontier.sort(key=lambda f: f[0])
            length, widths, at = frontier.pop(0)
            if at in done:
                continue
            done.add(at)
            rooms = [r for r in self.rooms if r.contains(*at)]
            if any(r.name == goal.name for r in rooms):
                return length + math.dist(at, b), widths
            frontier += [(length + math.dist(at, d), [*widths, w], d) for r in rooms
                         for d, w in self.doors[r.name] if d not in done]
        return None

    def paths(self, a: Point, b: Point, directivity: float | None = None
              ) -> tuple[float, float, float]:
        """The direct level (dB re the level at 1 m), the reverberant level (same), and
        the length (m) of the loudest path from a source at ``a`` to a listener at ``b``
        (``directivity``: of source and listener together, default the configured one)."""
        cfg = self.cfg
        q = cfg.directivity if directivity is None else directivity
        d = max(math.dist(a, b), MIN_DISTANCE_M)
        walls = cfg.wall_loss_db * self.walls_between(a, b)
        direct, length = -20 * math.log10(d) - walls, d
        room, there = self.room_at(a), self.room_at(b)
        if room is None:
            return direct, -math.inf, length
        field = -20 * math.log10(reverberation(room, cfg.absorption, q)[1])
        if there is None or there.name == room.name:
            return direct, field, length
        reverberant = field - walls
        if (door := self._door_path(a, b)) is not None:
            through = (-20 * math.log10(max(door[0], MIN_DISTANCE_M))
                       - cfg.door_loss_db * len(door[1]))
            if through > direct:
                length = door[0]
            direct = _level(10 ** (direct / 10) + 10 ** (through / 10))
            # the diffuse field leaks through each opening of area S into a room of
            # constant R, losing 10 log10(R / S) (room-to-room transmission)
            leak = sum(10 * math.log10(room_constant(there, cfg.absorption) / (w * DOOR_HEIGHT_M))
                       for w in door[1])
            reverberant = _level(10 ** (reverberant / 10) + 10 ** ((field - leak) / 10))
        return direct, reverberant, length

    def noise_levels(self, at: Point) -> dict[str, float]:
        """The background at ``at`` (dB SPL) by kind: ``steady`` (the room's noise and the
        microphones' own) and ``programme`` (what the rooms' sources play, e.g. the TV)."""
        steady = 10 ** (self.cfg.self_noise_db / 10)
        room = self.room_at(at)
        if room is not None:
            steady += 10 ** (room.noise.level_db / 10)
        programme = 0.0
        for r in self.rooms:
            if r.noise.source is not None:
                direct, reverberant, _ = self.paths(self.sources[r.noise.source], at)
                programme += 10 ** ((r.noise.source_db + direct) / 10)
                programme += 10 ** ((r.noise.source_db + reverberant) / 10)
        return {"steady": _level(steady), "programme": _level(programme)}

    def background_db(self, at: Point) -> float:
        """The whole background at ``at`` (dB SPL): every kind of :meth:`noise_levels`."""
        return _level(sum(10 ** (v / 10) for v in self.noise_levels(at).values()))

    def speech_db(self, speaker: Point, listener: Point) -> float:
        """The level (dB SPL) a voice at ``speaker`` has at ``listener``, all paths."""
        direct, reverberant, _ = self.paths(speaker, listener)
        return self.cfg.speech_db + _level(10 ** (direct / 10) + 10 ** (reverberant / 10))

    def at_microphones(self, voice: np.ndarray, rate: int, speaker: Point, listener: Point,
                       noises: Mapping[str, np.ndarray], rng: np.random.Generator
                       ) -> np.ndarray:
        """What the microphones record (16 kHz floats, 1.0 = one 16-bit step) while
        ``voice`` (samples at ``rate``) is said at ``speaker``: the sum of the two parts of
        :meth:`parts_at_microphones`."""
        said, background = self.parts_at_microphones(voice, rate, speaker, listener, noises, rng)
        return said + background

    def at_array(self, voice: np.ndarray, rate: int, speaker: Point, listener: Point,
                 heading: float, noises: Mapping[str, np.ndarray], rng: np.random.Generator
                 ) -> np.ndarray:
        """What each of the head's microphones records (``(M, n)``): the sum of the two
        parts of :meth:`parts_at_array`."""
        said, background = self.parts_at_array(voice, rate, speaker, listener, heading, noises,
                                                rng)
        return said + background

    def parts_at_microphones(self, voice: np.ndarray, rate: int, speaker: Point,
                             listener: Point, noises: Mapping[str, np.ndarray],
                             rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """The two parts of what the microphones record while ``voice`` is said at
        ``speaker``, from ``lead_s`` before the voice to ``trail_s`` after it: the voice's
        direct and reverberant sound, and the background (``noises``: a loop of each kind
        of :meth:`noise_levels` at 16 kHz and unit RMS, entered at a random point)."""
        cfg = self.cfg
        x = resampled(voice, rate)
        x /= max(float(np.sqrt((x ** 2).mean())), 1e-9)     # unit RMS: the voice at 1 m
        direct, reverberant, _ = self.paths(speaker, listener)
        wet = fftconvolve(x, _tail(self._t60(speaker), int(rng.integers(8))))
        lead, trail = int(cfg.lead_s * RATE), int(cfg.trail_s * RATE)
        said = np.zeros(lead + len(wet) + trail)
        said[lead:lead + len(x)] += x * _rms(cfg.speech_db + direct)
        said[lead:lead + len(wet)] += wet * _rms(cfg.speech_db + reverberant)
        background = np.zeros_like(said)
        for kind, level in self.noise_levels(listener).items():
            background += _entered(noises[kind], len(said), rng) * _rms(level)
        return said, background

    def _t60(self, at: Point) -> float:
        """The reverberation time (s, to 10 ms) of the room holding ``at`` (0.3 outside)."""
        room = self.room_at(at)
        return 0.3 if room is None else round(reverberation(room, self.cfg.absorption)[0], 2)

    def _ringing(self, at: Point) -> int:
        """How many samples a sound keeps ringing in ``at``'s room (its tails' length)."""
        return len(_tail(self._t60(at), 0))

    def _tails(self, at: Point, rng: np.random.Generator) -> list[np.ndarray]:
        """An independent reverberation tail of ``at``'s room for each microphone."""
        seeds = rng.choice(16, size=self.array.count, replace=False)
        return [_tail(self._t60(at), int(seed)) for seed in seeds]

    def _loops(self, loop: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` samples of ``loop`` for each microphone, each entered at a random point."""
        return np.stack([_entered(loop, n, rng) for _ in range(self.array.count)])

    def _at_array(self, sound: np.ndarray, source: Point, listener: Point, heading: float,
                  level_db: float, rng: np.random.Generator) -> np.ndarray:
        """``sound`` (unit RMS) played at ``level_db`` one metre from ``source``, at each
        microphone (``(M, len(sound) - tail)``): its direct sound delayed to each, its
        reverberation diffuse; the first tail's length of ``sound`` only feeds the
        reverberation (the room was already ringing when the recording starts)."""
        array, q = self.array, self.cfg.talker_directivity
        direct, reverberant, _ = self.paths(source, listener, q)
        tails = self._tails(source, rng)
        pre = len(tails[0])
        out = array.delayed(sound, array.delays(source, listener, heading))[:, pre:]
        wet = np.stack([fftconvolve(sound, h)[pre:len(sound)] for h in tails])
        return (out * _rms(level_db + direct)
                + array.diffuse(wet) * _rms(level_db + reverberant))

    def parts_at_array(self, voice: np.ndarray, rate: int, speaker: Point, listener: Point,
                       heading: float, noises: Mapping[str, np.ndarray],
                       rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`parts_at_microphones` at each of the head's microphones (``(M, n)``
        each), the head at ``listener`` facing ``heading`` (rad): the voice, and the
        background (the room's steady noise diffuse, the microphones' own independent at
        each, every room's source as a voice is)."""
        cfg = self.cfg
        x = resampled(voice, rate)
        x /= max(float(np.sqrt((x ** 2).mean())), 1e-9)
        pre = self._ringing(speaker)
        lead, trail = int(cfg.lead_s * RATE), int(cfg.trail_s * RATE)
        padded = np.concatenate([np.zeros(pre + lead), x, np.zeros(pre + trail)])
        said = self._at_array(padded, speaker, listener, heading, cfg.speech_db, rng)
        n = said.shape[1]
        background = self._loops(noises["steady"], n, rng) * _rms(cfg.self_noise_db)
        room = self.room_at(listener)
        if room is not None:
            steady = self._loops(noises["steady"], n, rng)
            background += self.array.diffuse(steady) * _rms(room.noise.level_db)
        for r in self.rooms:
            if r.noise.source is not None:
                at = self.sources[r.noise.source]
                played = _entered(noises["programme"], n + self._ringing(at), rng)
                background += self._at_array(played, at, listener, heading, r.noise.source_db,
                                             rng)
        return said, background


def _entered(loop: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` samples of ``loop``, entered at a random point."""
    return np.resize(np.roll(loop, -int(rng.integers(len(loop)))), n)


def _rms(level_db: float) -> float:
    """The RMS (in 16-bit steps) of a sound of ``level_db`` dB SPL at the microphones."""
    return 32768.0 * 10 ** ((level_db - REFERENCE_DB) / 20)
