"""Adapting pocketsphinx's en-US acoustic model to the household's voices and rooms.

The acoustic model in pocketsphinx's wheel was trained on recorded human speech; the people
of the household speak with espeak-ng's formant voices, through rooms that reverberate and
may have the TV on. A home robot would adapt its recogniser to the people it lives with, as
a dictation program adapts to its user. Here that is maximum a posteriori (MAP) adaptation
(Gauvain and Lee, 1994) with SphinxTrain's tools:

1. the project's own training lines (never an evaluation line) are said by the people's
   voices in living rooms of drawn sizes, from drawn distances, quiet or with the TV on,
   and recorded at the robot's microphones (:mod:`sim.acoustics`);
2. ``sphinx_fe`` turns the recordings into the model's cepstral features;
3. ``bw`` aligns them with their words and gathers each Gaussian's statistics;
4. ``map_adapt`` moves the means, variances, mixture weights and transitions towards them,
   as far as their counts warrant; steps 3-4 repeat ``iterations`` times;
5. ``mk_s2sendump`` packs the mixture weights back into pocketsphinx's compact form.

The tools come from Debian's ``sphinxtrain``, ``sphinxbase-utils`` and ``pocketsphinx``
packages (``make setup`` installs them); they are needed to adapt, never to recognise.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
import wave
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from core.checkpoint import atomic_write_bytes
from core.errors import UserError
from dialogue.speech.beamformer import beamform
from dialogue.speech.config import SpeechAdaptConfig, SpeechConfig
from dialogue.speech.engines import ACOUSTIC_FILES, wheel_model_dir
from dialogue.speech.enhancer import VoiceEnhancer
from dialogue.speech.training.corpus import TRAIN_FILES, tsv_lines
from dialogue.speech.training.rooms import living_room, recording, speaker_within
from dialogue.speech.training.sphinx_files import read_sendump, write_s3_array
from dialogue.speech.training.train import full_dictionary
from dialogue.speech.words import spoken_words
from robot.audio import RATE
from robot.voices import PEOPLE_VOICES, synthesise
from sim.soundscape import noise_loops

Beam = Callable[[np.ndarray], np.ndarray]   # the head's microphones (M, n) -> one channel
PARAMETERS = ("means", "variances", "mixture_weights", "transition_matrices")
DECODER_ONLY = ("-cmn", "-varnorm", "-agc", "-model", "-feat", "-svspec")


class AdaptationToolsError(UserError):
    """SphinxTrain's or sphinxbase's tools are not installed."""


def _tool(cfg: SpeechAdaptConfig, name: str) -> str:
    """The path of a tool: SphinxTrain's folder first, then the ``PATH``."""
    found = cfg.sphinxtrain_dir / name
    if found.is_file():
        return str(found)
    if (on_path := shutil.which(name)) is not None:
        return on_path
    raise AdaptationToolsError(f"{name}: not found in {cfg.sphinxtrain_dir} or on the PATH "
                                 "(make setup installs sphinxtrain, sphinxbase-utils and "
                                 "pocketsphinx with apt-get)")


def _run(args: list[str], log: Path) -> None:
    """Run a tool, its output to ``log``; a failure names the log."""
    with log.open("ab") as out:
        done = subprocess.run(args, stdout=out, stderr=subprocess.STDOUT, check=False)
    if done.returncode != 0:
        raise UserError(f"{Path(args[0]).name} failed (exit {done.returncode}); see {log}")


def adaptation_lines(excluded: set[tuple[str, ...]], dictionary: set[str]) -> list[list[str]]:
    """The spoken words of the project's training lines, each once, that are not
    ``excluded`` (the evaluation lines) and whose words are all in ``dictionary``."""
    seen: set[tuple[str, ...]] = set()
    lines = []
    for name in TRAIN_FILES:
        for _, text in tsv_lines(name):
            words = tuple(spoken_words(text))
            if words and words not in seen and words not in excluded \
                    and all(w in dictionary for w in words):
                seen.add(words)
                lines.append(list(words))
    return lines


def adaptation_enhancer(cfg: SpeechConfig) -> VoiceEnhancer | None:
    """The enhancer the acoustic model's recordings pass through: the recogniser's, at its
    mask power, when ``adapt.enhanced`` asks for it and the recogniser has one."""
    m = cfg.model
    if not cfg.adapt.enhanced or m.enhancer is None:
        return None
    return VoiceEnhancer(m.path(m.enhancer), m.mask_power)


def adaptation_beam(cfg: SpeechConfig) -> Beam | None:
    """The beam the acoustic model's recordings of the head's microphones are taken
    through: the recogniser's (its dereverberation included), when ``adapt.array`` records
    them all and ``model.beamformer`` decodes the beam (else the first microphone is
    taken)."""
    m = cfg.model
    if not _through_beam(cfg):
        return None
    return partial(beamform, enhancer=VoiceEnhancer(m.path(m.enhancer)),
                   loading=m.beamformer_loading, dereverberation=m.dereverberation)


def _through_beam(cfg: SpeechConfig) -> bool:
    return bool(cfg.adapt.array and cfg.model.beamformer and cfg.model.enhancer is not None)


def adaptation_front_end(cfg: SpeechConfig) -> dict[str, object]:
    """What the recordings pass through before the statistics, as ``adaptation.json``
    records it: the beam (with its dereverberation and the enhancer steering it) or not."""
    m = cfg.model
    enhancer = None if m.enhancer is None else str(m.enhancer)
    if not _through_beam(cfg):
        return {"beam": False, "enhancer": enhancer if cfg.adapt.enhanced else None}
    dereverberation = None if m.dereverberation is None else m.dereverberation.model_dump()
    return {"beam": True, "enhancer": enhancer, "beamformer_loading": m.beamformer_loading,
            "dereverberation": dereverberation}


def record(lines: list[list[str]], cfg: SpeechAdaptConfig, folder: Path,
           enhancer: VoiceEnhancer | None = None, beam: Beam | None = None,
           ) -> tuple[list[str], list[str]]:
    """Say every line ``copies`` times, each time in a drawn voice, room, distance and
    noise, and write the microphones' recordings (with ``adapt.array`` all the head's,
    through ``beam`` or the first; then through ``enhancer`` when given) as 16 kHz WAV
    files in ``folder``; the file ids and their SphinxTrain transcription lines."""
    rng = np.random.default_rng(cfg.seed)
    loops = noise_loops(cfg.seed)
    ids, transcripts = [], []
    for copy in range(cfg.copies):
        for k, words in enumerate(lines):
            voice = PEOPLE_VOICES[int(rng.integers(len(PEOPLE_VOICES)))]
            width, depth = rng.uniform(*cfg.room_width_m), rng.uniform(*cfg.room_depth_m)
            noise = "tv" if rng.random() < cfg.tv_share else "quiet"
            acoustics, robot = living_room(width, depth, noise)
            speaker = speaker_within(robot, depth, cfg.distance_m, rng)
            samples, rate = synthesise(" ".join(words), voice)
            audio = recording(acoustics, samples, rate, speaker, robot, loops, rng, cfg.array)
            if cfg.array:
                audio = audio[0] if beam is None else beam(audio)
            if enhancer is not None:
                audio = enhancer.enhance(audio)
            fid = f"c{copy}_{k:05d}"
            with wave.open(str(folder / f"{fid}.wav"), "wb") as out:
                out.setnchannels(1)
                out.setsampwidth(2)
                out.setframerate(RATE)
                out.writeframes(np.clip(np.round(audio), -32768, 32767).astype("<i2").tobytes())
            ids.append(fid)
            transcripts.append(f"<s> {' '.join(words)} </s> ({fid})")
    return ids, transcripts


def _base_model(cfg: SpeechAdaptConfig, source: Path, folder: Path, log: Path) -> None:
    """The wheel's model in ``folder`` as SphinxTrain reads it: a text model definition
    and float mixture weights beside the other files."""
    for name in ACOUSTIC_FILES:
        if name != "sendump":
            shutil.copy(source / name, folder / name)
    _run([_tool(cfg, "pocketsphinx_mdef_convert"), "-text", str(source / "mdef"),
          str(folder / "mdef.txt")], log)
    write_s3_array(folder / "mixture_weights", read_sendump(source / "sendump"))


def _features(cfg: SpeechAdaptConfig, model: Path, work: Path, ids: list[str],
              log: Path) -> None:
    """Cepstral features of the recordings, with the model's front-end settings."""
    params = [line for line in (model / "feat.params").read_text().splitlines()
              if line.strip() and not line.startswith(DECODER_ONLY)]
    (work / "fe.params").write_text("\n".join(params) + "\n")
    (work / "adapt.fileids").write_text("\n".join(ids) + "\n")
    _run([_tool(cfg, "sphinx_fe"), "-argfile", str(work / "fe.params"), "-samprate",
          str(RATE), "-c", str(work / "adapt.fileids"), "-di", str(work / "wav"), "-do",
          str(work / "mfc"), "-ei", "wav", "-eo", "mfc", "-mswav", "yes"], log)


def _iteration(cfg: SpeechAdaptConfig, base: Path, prior: Path, out: Path, work: Path,
               dictionary: Path, log: Path) -> int:
    """One round of statistics (``bw``) and MAP re-estimation from ``prior`` into ``out``;
    how many recordings could not be aligned with their words."""
    accum = out / "accum"
    accum.mkdir(parents=True)
    before = log.read_text(errors="replace").count(" ignored") if log.exists() else 0
    _run([_tool(cfg, "bw"), "-hmmdir", str(prior), "-moddeffn", str(base / "mdef.txt"),
          "-ts2cbfn", ".ptm.", "-feat", "1s_c_d_dd", "-svspec", "0-12/13-25/26-38",
          "-cmn", "batch", "-agc", "none", "-dictfn", str(dictionary),
          "-fdictfn", str(base / "noisedict"), "-ctlfn", str(work / "adapt.fileids"),
          "-lsnfn", str(work / "adapt.transcription"), "-accumdir", str(accum),
          "-cepdir", str(work / "mfc"), "-cepext", "mfc", "-timing", "no"], log)
    _run([_tool(cfg, "map_adapt"), "-moddeffn", str(base / "mdef.txt"), "-ts2cbfn", ".ptm.",
          *[a for name, flag in zip(PARAMETERS, ("-meanfn", "-varfn", "-mixwfn", "-tmatfn"),
                                    strict=True) for a in (flag, str(prior / name))],
          *[a for name, flag in zip(PARAMETERS, ("-mapmeanfn", "-mapvarfn", "-mapmixwfn",
                                                 "-maptmatfn"), strict=True)
            for a in (flag, str(out / name))],
          "-accumdir", str(accum)], log)
    for name in ("feat.params", "noisedict"):
        shutil.copy(base / name, out / name)
    return log.read_text(errors="replace").count(" ignored") - before


def adapt_acoustic_model(cfg: SpeechAdaptConfig, excluded: set[tuple[str, ...]],
                         out_dir: Path, enhancer: VoiceEnhancer | None = None,
                         progress: Callable[[str], None] | None = None,
                         beam: Beam | None = None,
                         front_end: dict[str, object] | None = None) -> dict[str, object]:
    """Adapt the wheel's en-US model to recordings (taken through ``beam`` and
    ``enhancer`` when given, as the recogniser will take what it hears) and write what the
    recogniser loads to ``out_dir`` (with ``adaptation.json``, the figures for the model
    card, and ``front_end``, what the recordings passed through)."""
    say = progress or (lambda _: None)
    source = wheel_model_dir() / "en-us"
    dictionary = wheel_model_dir() / "cmudict-en-us.dict"
    lines = adaptation_lines(excluded, set(full_dictionary()))[:cfg.max_lines]
    with tempfile.TemporaryDirectory(prefix="adapt-") as tmp:
        work = Path(tmp)
        log = work / "tools.log"
        for folder in ("wav", "mfc", "base"):
            (work / folder).mkdir()
        _base_model(cfg, source, work / "base", log)
        ids, transcripts = record(lines, cfg, work / "wav", enhancer, beam)
        (work / "adapt.transcription").write_text("\n".join(transcripts) + "\n")
        say(f"{len(ids)} recordings of {len(lines)} lines")
        _features(cfg, source, work, ids, log)
        prior, ignored = work / "base", []
        for it in range(1, cfg.iterations + 1):
            out = work / f"iteration{it}"
            ignored.append(_iteration(cfg, work / "base", prior, out, work, dictionary, log))
            say(f"iteration {it}: {ignored[-1]} recordings not aligned")
            prior = out
        _run([_tool(cfg, "mk_s2sendump"), "-pocketsphinx", "yes", "-moddeffn",
              str(work / "base" / "mdef.txt"), "-mixwfn", str(prior / "mixture_weights"),
              "-sendumpfn", str(prior / "sendump")], log)
        shutil.copy(source / "mdef", prior / "mdef")
        out_dir.mkdir(parents=True, exist_ok=True)
        for name in ACOUSTIC_FILES:
            atomic_write_bytes(out_dir / name, (prior / name).read_bytes())
    figures = {"lines": len(lines), "recordings": len(ids), "not_aligned": ignored,
               **cfg.model_dump(mode="json", exclude={"sphinxtrain_dir"}),
               "front_end": front_end}
    atomic_write_bytes(out_dir / "adaptation.json",
                       (json.dumps(figures, indent=2) + "\n").encode())
    return figures
