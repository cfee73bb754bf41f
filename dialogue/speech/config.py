"""Schema of ``config/speech.yaml``: the recogniser's model files and thresholds, and
how the household language model is estimated."""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Self

from pydantic import Field, model_validator

from core.config_files import StrictModel, load_model
from core.errors import UserError
from core.paths import from_root


class SpeechModelError(UserError):
    """The recogniser's model files are missing or unreadable."""


class DereverberationConfig(StrictModel):
    """Weighted prediction error over the head's microphones (dialogue/speech/
    dereverberation.py): how many past frames predict the late reverberation, how many
    recent ones are left out of the prediction, and how many rounds re-estimate the voice's
    power."""

    taps: int = Field(ge=1, le=40)
    delay: int = Field(ge=1, le=10)
    iterations: int = Field(ge=1, le=10)


class WhisperConfig(StrictModel):
    """faster-whisper's settings (dialogue/speech/engines.py): how its weights are held,
    how wide its search is, how many cores it uses, and when its transcript is sure enough
    to act on."""

    compute_type: Literal["int8", "int8_float32", "float32"]
    beam_size: int = Field(ge=1, le=10)
    threads: int = Field(ge=1, le=16)
    min_confidence: float = Field(ge=0, le=1)


class SpeechModelConfig(StrictModel):
    """Which decoder the recogniser runs (``engine``), the model files pocketsphinx loads
    and its language weight, faster-whisper's settings, and the household front end
    (dereverberation, beam, enhancer) either decodes through."""

    engine: Literal["whisper", "pocketsphinx"]
    whisper: WhisperConfig
    language_model: Path
    dictionary: Path
    acoustic_model: Path | None   # None: the wheel's own en-US model, as it ships
    enhancer: Path | None         # None: the recordings are decoded as they are
    mask_power: float = Field(ge=1, le=16)
    mask_output: bool             # the enhancer's mask also cleans the channel decoded
    loud_room_db: float | None = Field(ge=0, le=100)   # None: the power everywhere
    language_weight: float = Field(gt=0, le=50)
    beamformer: bool              # decode the head's microphones through the MVDR beam
    beamformer_loading: float = Field(ge=0, le=10)
    dereverberation: DereverberationConfig | None   # None: the recordings as they are

    @model_validator(mode="after")
    def _beam_needs_mask(self) -> Self:
        if self.beamformer and self.enhancer is None:
            raise ValueError("beamformer: the beam is steered by the enhancer's mask; name "
                             "an enhancer or set beamformer: false")
        return self

    def path(self, name: Path) -> Path:
        """``name`` from the repository root unless absolute."""
        return from_root(name)


class SourceWeights(StrictModel):
    """How much each source of lines counts in the language model."""

    own: float = Field(gt=0)
    conversation: float = Field(gt=0)
    topics: float = Field(gt=0)
    vocatives: float = Field(gt=0)


class TopicsConfig(StrictModel):
    """Questions about WordNet's most common nouns and people (training/topics.py)."""

    nouns: int = Field(ge=0)
    people: int = Field(ge=0)
    noun_frames: list[str] = Field(min_length=1)
    people_frames: list[str] = Field(min_length=1)
    seed: int = Field(ge=0)

    @model_validator(mode="after")
    def _one_slot(self) -> Self:
        for frame in [*self.noun_frames, *self.people_frames]:
            if frame.count("{}") != 1:
                raise ValueError(f"frame {frame!r} must hold one {{}} for the topic")
        return self


class SpeechTrainConfig(StrictModel):
    """How the household language model is estimated (dialogue/speech/training/)."""

    order: int = Field(ge=1, le=5)
    discount: float = Field(gt=0, lt=1)
    min_city_population: int = Field(ge=0)
    city_variants: int = Field(ge=0, le=100)
    seed: int = Field(ge=0)
    papaya_dir: Path | None
    weights: SourceWeights
    min_count: float = Field(ge=0)
    topics: TopicsConfig

    def resolved(self, folder: Path | None) -> Path | None:
        """``folder`` from the repository root unless absolute (None stays None)."""
        return None if folder is None else from_root(folder)


def _check_ranges(cfg: SpeechAdaptConfig | EnhancerTrainConfig, names: tuple[str, ...],
                  zero: bool) -> None:
    """Refuse a ``(low, high)`` setting of ``cfg`` that is not ordered or starts below 0
    (at 0 too unless ``zero``), and rooms too shallow to talk across."""
    for name in names:
        low, high = getattr(cfg, name)
        if not (low >= 0 if zero else low > 0) or low > high:
            sign = "<=" if zero else "<"
            raise ValueError(f"{name}: need 0 {sign} low <= high, got {low}, {high}")
    if cfg.room_depth_m[0] < 2.5:
        raise ValueError("room_depth_m: rooms less than 2.5 m deep leave no room to talk")


class SpeechAdaptConfig(StrictModel):
    """How the acoustic model is adapted to the household (dialogue/speech/training/
    acoustic.py): how its training lines are said and recorded, and how often re-estimated."""

    max_lines: int | None = Field(ge=1)
    copies: int = Field(ge=1, le=20)
    distance_m: tuple[float, float]
    room_width_m: tuple[float, float]
    room_depth_m: tuple[float, float]
    tv_share: float = Field(ge=0, le=1)
    enhanced: bool
    array: bool         # record all the head's microphones (Acoustics.parts_at_array)
    iterations: int = Field(ge=1, le=5)
    seed: int = Field(ge=0)
    sphinxtrain_dir: Path

    @model_validator(mode="after")
    def _ranges(self) -> Self:
        _check_ranges(self, ("distance_m", "room_width_m", "room_depth_m"), zero=False)
        return self


class EnhancerTrainConfig(StrictModel):
    """How the voice enhancer is trained (dialogue/speech/training/enhancer.py): its
    sounds, its network's size and the optimiser's settings."""

    examples: int = Field(ge=10)
    programmes: int = Field(ge=1)
    other_accents: list[str] = Field(min_length=1)
    other_variants: list[str] = Field(min_length=1)
    other_pitch: tuple[int, int]
    other_speed: tuple[int, int]
    pause_s: tuple[float, float]
    bed_share: tuple[float, float]
    tv_share: float = Field(ge=0, le=1)
    tv_db: tuple[float, float]
    distance_m: tuple[float, float]
    room_width_m: tuple[float, float]
    room_depth_m: tuple[float, float]
    hidden: int = Field(ge=8, le=1024)
    layers: int = Field(ge=1, le=4)
    mask_floor: float = Field(ge=0, lt=1)
    compression: float = Field(gt=0, le=1)
    epochs: int = Field(ge=1)
    batch: int = Field(ge=1)
    crop_frames: int = Field(ge=16)
    learning_rate: float = Field(gt=0)
    max_grad_norm: float = Field(gt=0)
    validation_share: float = Field(gt=0, lt=1)
    threads: int = Field(ge=1)
    seed: int = Field(ge=0)
    array: bool                 # the first of the head's microphones, as parts_at_array records
    init: Path | None           # start from this enhancer's weights (None: random)

    @model_validator(mode="after")
    def _ranges(self) -> Self:
        _check_ranges(self, ("other_pitch", "other_speed", "pause_s", "bed_share", "tv_db",
                             "distance_m", "room_width_m", "room_depth_m"), zero=True)
        return self


class VadConfig(StrictModel):
    """Where an utterance starts and ends in a stream of sound (dialogue/speech/vad.py):
    Silero VAD's speech threshold, the silence that ends an utterance, the shortest speech
    that is one, the sound kept around it and the longest utterance."""

    threshold: float = Field(gt=0, lt=1)
    min_silence_ms: int = Field(ge=32, le=5000)
    min_speech_ms: int = Field(ge=0, le=5000)
    pre_roll_ms: int = Field(ge=0, le=2000)
    max_utterance_s: float = Field(ge=1, le=120)


class SpeechConfig(StrictModel):
    """``config/speech.yaml``."""

    model: SpeechModelConfig
    min_confidence: float = Field(ge=0, le=1)
    min_snr_db: float = Field(ge=-20, le=40)
    min_level_db: float = Field(ge=0, le=100)
    train: SpeechTrainConfig
    adapt: SpeechAdaptConfig
    enhance: EnhancerTrainConfig
    vad: VadConfig

    @property
    def acting_confidence(self) -> float:
        """The confidence a transcript needs to be acted on: the configured decoder's own
        threshold (``model.whisper.min_confidence`` or, for pocketsphinx,
        ``min_confidence``), as the two measure confidence differently."""
        m = self.model
        return m.whisper.min_confidence if m.engine == "whisper" else self.min_confidence


def load_speech_config(path: str | Path | None = None) -> SpeechConfig:
    """The packaged speech settings, with the file at ``path`` merged over them."""
    return load_model(SpeechConfig, "speech.yaml", path)
