"""People's own voices: the recogniser on human recordings with reference texts that Debian
packages install (``companion eval asr --recordings``; docs/speech.md, *Human recordings*).

Every other evaluation of the recogniser hears synthesised voices. These sets are read in
place, from where their packages put them (nothing is copied into the project):

- ``librivox``, ``cards``, ``goforward``: the test recordings of ``pocketsphinx-testdata``
  (``make setup`` installs it; BSD-2, Carnegie Mellon University; the LibriVox reading
  itself is in the public domain), 16 kHz, with the package's transcriptions (for
  goforward.raw, the sentence of its grammar ``goforward.gram``);
- ``asterisk-prompts``, ``asterisk-words``: Allison Smith's recorded telephone prompts of
  ``asterisk-core-sounds-en-wav``, 8 kHz, with the prompt texts of
  ``asterisk-core-sounds-en`` (CC BY-SA 3.0): the sentences, and the single words (digits,
  letters, the spelling alphabet). Evaluated only when installed (``make setup`` does not
  install them).

Each recording is heard two ways: straight in, as the microphone's one channel, and said
in the evaluation's quiet living room 1 and 3 m from the robot, recorded through the head's
microphones by the household acoustics (:mod:`dialogue.speech.training.rooms`). No setting
of the recogniser is chosen on these figures.
"""

from __future__ import annotations

import gzip
import re
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import jiwer
import numpy as np

from core.errors import UserError
from dialogue.speech.config import SpeechConfig
from dialogue.speech.recognizer import SpeechRecognizer
from dialogue.speech.training.evaluate import ROOM_M, heads_microphones
from dialogue.speech.training.rooms import living_room, recording, speaker_at
from dialogue.speech.wav import read_wav
from dialogue.speech.words import spoken_words
from robot.audio import RATE, resampled
from sim.acoustics import Acoustics, Point
from sim.soundscape import noise_loops

TESTDATA = Path("/usr/share/pocketsphinx/test/data")
ASTERISK_SOUNDS = Path("/usr/share/asterisk/sounds/en_US_f_Allison")
ASTERISK_TEXTS = Path("/usr/share/doc/asterisk-core-sounds-en/core-sounds-en.txt.gz")
RAW_RATE = 16_000                     # goforward.raw: headerless 16-bit mono at 16 kHz
ASTERISK_WORDS = ("digits", "letters", "phonetic")   # folders of single-word prompts
ASTERISK_SENTENCES = ("", "dictate", "followme")     # "": the sounds' own folder
DISTANCES_M = (1.0, 3.0)
DIRECT = "direct"
TRANSCRIPT_LINE = re.compile(r"^\s*(?:<s>)?\s*(.*?)\s*(?:</s>)?\s*\((\S+)\)\s*$")
NOT_SAID = re.compile(r"\[[^\]]*\]|\([^)]*\)|<[^>]*>")   # [tones], (notes), <beeps>
KEYS = {"*": " star ", "#": " pound "}                    # keys a prompt names by symbol


class RecordingsError(UserError):
    """A set of recordings is not installed, or its files do not pair up."""


@dataclass(frozen=True)
class Recording:
    """One human recording: its ``set``, ``id``, file and reference ``text`` (as written in
    its package, before normalising)."""

    set: str
    id: str
    path: Path
    text: str

    @property
    def reference(self) -> str:
        """The reference as the recogniser's words (:func:`spoken_words`)."""
        return " ".join(spoken_words(self.text))

    def audio(self) -> np.ndarray:
        """The recording at the microphones' rate (floats on the 16-bit scale)."""
        if self.path.suffix == ".raw":
            return np.fromfile(self.path, dtype="<i2").astype(np.float64)
        samples, rate = read_wav(self.path)
        return resampled(samples, rate)


@dataclass(frozen=True)
class RecordingSet:
    """A set of recordings: the Debian ``packages`` it needs, files that show they are
    installed (``markers``), and its loader."""

    name: str
    packages: tuple[str, ...]
    licence: str
    markers: tuple[Path, ...]
    load: Callable[[], list[Recording]]

    def installed(self) -> bool:
        """Whether the packages' files are there."""
        return all(m.exists() for m in self.markers)

    def missing(self) -> RecordingsError:
        """The error for a set whose packages are not installed."""
        lost = next((m for m in self.markers if not m.exists()), self.markers[0])
        return RecordingsError(f"{lost}: the {self.name} recordings are not installed "
                               f"(Debian's {', '.join(self.packages)}; make setup installs "
                               "them)")


def sphinx_transcription(path: Path) -> dict[str, str]:
    """``id -> words`` of a SphinxTrain transcription file (``<s> words </s> (id)``)."""
    texts = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        m = TRANSCRIPT_LINE.match(line)
        if m:
            texts[m.group(2)] = m.group(1)
    return texts


def _paired(name: str, folder: Path, fileids: str, transcription: str) -> list[Recording]:
    """The WAV files a fileids list names in ``folder``, each with its transcription."""
    texts = sphinx_transcription(folder / transcription)
    ids = (folder / fileids).read_text(encoding="utf-8").split()
    lost = [i for i in ids if i not in texts or not (folder / f"{i}.wav").is_file()]
    if lost:
        raise RecordingsError(f"{folder}: no transcription or no WAV file for {lost}")
    return [Recording(name, i, folder / f"{i}.wav", texts[i]) for i in ids]


def librivox() -> list[Recording]:
    """Five sentences of a LibriVox reading of *Sense and Sensibility*, chapter 1."""
    return _paired("librivox", TESTDATA / "librivox", "fileids", "transcription")


def cards() -> list[Recording]:
    """Five spoken card names ("eight of spades four of clubs seven of hearts")."""
    return _paired("cards", TESTDATA / "cards", "cards.fileids", "cards.transcription")


def goforward() -> list[Recording]:
    """goforward.raw, with the sentence of its grammar (``public <move> = ...;``)."""
    grammar = (TESTDATA / "goforward.gram").read_text(encoding="utf-8")
    m = re.search(r"public\s+<move>\s*=\s*([^;<\[|]+);", grammar)
    if m is None:
        raise RecordingsError(f"{TESTDATA / 'goforward.gram'}: no <move> sentence")
    return [Recording("goforward", "goforward", TESTDATA / "goforward.raw", m.group(1).strip())]


def asterisk_texts() -> dict[str, str]:
    """``prompt -> text`` of the prompts' text file, with what is not said taken out
    (tones in brackets, notes in parentheses) and keys named as said (``*``: "star")."""
    texts = {}
    for line in gzip.decompress(ASTERISK_TEXTS.read_bytes()).decode("utf-8").splitlines():
        name, sep, text = line.partition(":")
        if not sep or line.startswith(";"):
            continue
        said = NOT_SAID.sub(" ", text)
        for key, word in KEYS.items():
            said = said.replace(key, word)
        texts[name.strip()] = " ".join(said.split())
    return texts


def asterisk(name: str, folders: tuple[str, ...]) -> list[Recording]:
    """The prompts in ``folders`` of the sounds that have a text with words in it."""
    texts = asterisk_texts()
    found = []
    for prompt, text in sorted(texts.items()):
        folder = prompt.rpartition("/")[0]
        path = ASTERISK_SOUNDS / f"{prompt}.wav"
        if folder in folders and spoken_words(text) and path.is_file():
            found.append(Recording(name, prompt, path, text))
    return found


SPHINX_TESTDATA = ("pocketsphinx-testdata",)
ASTERISK = ("asterisk-core-sounds-en-wav", "asterisk-core-sounds-en")
ASTERISK_MARKERS = (ASTERISK_TEXTS, ASTERISK_SOUNDS / "digits" / "0.wav")
ASTERISK_LICENCE = "CC BY-SA 3.0 (Allison Smith)"
SETS = (
    RecordingSet("librivox", SPHINX_TESTDATA, "BSD-2 (CMU); the reading public domain",
                 (TESTDATA / "librivox" / "fileids",), librivox),
    RecordingSet("cards", SPHINX_TESTDATA, "BSD-2 (CMU)",
                 (TESTDATA / "cards" / "cards.fileids",), cards),
    RecordingSet("goforward", SPHINX_TESTDATA, "BSD-2 (CMU)",
                 (TESTDATA / "goforward.raw",), goforward),
    RecordingSet("asterisk-prompts", ASTERISK, ASTERISK_LICENCE, ASTERISK_MARKERS,
                 lambda: asterisk("asterisk-prompts", ASTERISK_SENTENCES)),
    RecordingSet("asterisk-words", ASTERISK, ASTERISK_LICENCE, ASTERISK_MARKERS,
                 lambda: asterisk("asterisk-words", ASTERISK_WORDS)),
)


def available_sets() -> list[RecordingSet]:
    """The sets, each checked to be installed (a missing one is a :class:`RecordingsError`)."""
    for s in SETS:
        if not s.installed():
            raise s.missing()
    return list(SETS)


@dataclass
class Tally:
    """What the recogniser made of one set in one condition."""

    set: str
    condition: str
    refs: list[str] = field(default_factory=list)
    hyps: list[str] = field(default_factory=list)
    seconds: float = 0.0          # of the recordings themselves
    heard_s: float = 0.0          # of what was decoded (a room's recording is longer)
    decode_s: float = 0.0

    def row(self) -> dict[str, object]:
        """The condition's figures."""
        return {"set": self.set, "condition": self.condition, "utterances": len(self.refs),
                "seconds": round(self.seconds, 1), "wer": round(jiwer.wer(self.refs, self.hyps), 4),
                "real_time_factor": round(self.decode_s / self.heard_s, 4)}


@dataclass(frozen=True)
class Heard:
    """One recording heard in one condition."""

    condition: str
    text: str
    heard_s: float
    decode_s: float


@cache
def quiet_room() -> tuple[Acoustics, Point]:
    """The evaluation's living room (``eval asr``'s size), quiet, and where the robot is."""
    return living_room(*ROOM_M, "quiet")


def heard(x: np.ndarray, recogniser: SpeechRecognizer, array: bool,
          rng: np.random.Generator, seed: int = 0) -> Iterator[Heard]:
    """A recording ``x`` (16 kHz) transcribed straight in (one channel), then said in the
    quiet living room from each of :data:`DISTANCES_M` (recorded by each of the head's
    microphones when ``array``, else by one)."""
    yield _transcribed(DIRECT, x, recogniser)
    acoustics, robot = quiet_room()
    for distance in DISTANCES_M:
        speaker = speaker_at(robot, distance, rng)
        audio = recording(acoustics, x, RATE, speaker, robot, noise_loops(seed), rng, array)
        yield _transcribed(f"quiet {distance:g} m", audio, recogniser)


def _transcribed(condition: str, audio: np.ndarray, recogniser: SpeechRecognizer) -> Heard:
    t0 = time.perf_counter()
    text = recogniser.transcribe(audio, RATE).text
    return Heard(condition, text, audio.shape[-1] / RATE, time.perf_counter() - t0)


def evaluate_recordings(limit: int | None = None, seed: int = 0,
                        cfg: SpeechConfig | None = None, array: bool | None = None,
                        progress: Callable[[str], None] | None = None) -> dict[str, object]:
    """Word error rate and speed of the recogniser (``cfg``) on every installed set (the
    first ``limit`` recordings of each), straight in and at 1 and 3 m of a quiet living
    room (``array``: the head's four microphones; default as robot.yaml says), with each
    transcript."""
    array = heads_microphones() if array is None else array
    sets = available_sets()
    recogniser = SpeechRecognizer(cfg)
    tallies: dict[tuple[str, str], Tally] = {}
    said = []
    for k, s in enumerate(sets):
        rng = np.random.default_rng([seed, k])
        for rec in s.load()[:limit]:
            x = rec.audio()
            for h in heard(x, recogniser, array, rng, seed):
                t = tallies.setdefault((s.name, h.condition), Tally(s.name, h.condition))
                t.refs.append(rec.reference)
                t.hyps.append(h.text)
                t.seconds += len(x) / RATE
                t.heard_s += h.heard_s
                t.decode_s += h.decode_s
                said.append({"set": s.name, "id": rec.id, "condition": h.condition,
                             "reference": rec.reference, "heard": h.text})
        if progress is not None:
            progress(f"{s.name}: {[t.row() for (n, _), t in tallies.items() if n == s.name]}")
    return {"recogniser": recogniser.cfg.model.engine, "array": array, "seed": seed,
            "limit": limit, "rows": [t.row() for t in tallies.values()],
            "sets": {s.name: {"packages": list(s.packages), "licence": s.licence}
                     for s in sets},
            "transcripts": said}


def report(result: dict[str, object]) -> list[str]:
    """The lines of the table :func:`evaluate_recordings` gives, for the terminal."""
    mics = "the head's four microphones" if result["array"] else "one microphone"
    lines = [f"human recordings, recogniser {result['recogniser']}; the rooms recorded "
             f"through {mics}",
             f"{'set':<17} {'condition':<10} {'utterances':>10} {'seconds':>8} {'WER':>6} "
             f"{'RTF':>6}"]
    for r in result["rows"]:
        lines.append(f"{r['set']:<17} {r['condition']:<10} {r['utterances']:>10} "
                     f"{r['seconds']:>8.1f} {r['wer']:>6.3f} {r['real_time_factor']:>6.3f}")
    return lines
