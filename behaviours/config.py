"""Schema of ``config/behaviour.yaml``: the behaviour tree's timing and skill parameters."""

from __future__ import annotations

from pathlib import Path
from typing import Self

from pydantic import (
    Field,
    NonNegativeFloat,
    NonNegativeInt,
    PositiveFloat,
    PositiveInt,
    model_validator,
)

from core.config_files import StrictModel, load_model
from core.paths import REPO_ROOT
from robot.obstacle_tracks import TracksConfig


class PidGains(StrictModel):
    """Gains of one simple-pid controller."""

    kp: float
    ki: float = 0.0
    kd: float = 0.0


class PerceptionConfig(StrictModel):
    """Camera rates, which person boxes count, how far away their person is (the depth
    image) and how detections become the human-present stimulus."""

    tracking_rate: float = Field(gt=0, le=30)
    centring_rate: float = Field(gt=0, le=30)
    idle_rate: float = Field(gt=0, le=30)
    idle_after_s: float = Field(ge=0)
    min_conf: float = Field(gt=0, lt=1)
    depth_window: tuple[float, tuple[float, float]]
    depth_percentile: float = Field(ge=0, le=100)
    person_max_height_m: PositiveFloat
    present_max_distance_m: PositiveFloat
    present_hold_s: float = Field(ge=0)


class PidConfig(StrictModel):
    """Navigation controllers: heading and distance to a goal (robot/navigation.py)."""

    heading: PidGains
    distance: PidGains
    slowdown_heading_deg: float = Field(gt=0, le=180)
    lookahead_m: PositiveFloat


class DepthPointsConfig(StrictModel):
    """Which pixels of a depth frame become obstacle points for the charge skill's planner."""

    stride: PositiveInt
    min_height_m: float = Field(ge=0.0)
    max_height_m: PositiveFloat
    max_range_m: PositiveFloat


class ChargeConfig(StrictModel):
    """Charge skill: speech, path planning and docking tolerances."""

    ask: str
    done: str
    dock_blocked: str
    robot_radius: PositiveFloat
    body_radius: PositiveFloat
    grid_resolution: PositiveFloat
    waypoint_tolerance: PositiveFloat
    predock_distance: PositiveFloat
    replan_blocked_s: PositiveFloat
    obstacle_memory_s: NonNegativeFloat
    static_margin_m: NonNegativeFloat
    sensed_clearance_m: NonNegativeFloat
    replan_sensed_s: PositiveFloat
    security_distance_m: NonNegativeFloat
    slow_distance_m: PositiveFloat
    security_time_s: NonNegativeFloat
    depth_points: DepthPointsConfig
    tracks: TracksConfig
    dock_position_tolerance: PositiveFloat
    dock_yaw_tolerance_deg: PositiveFloat
    timeout_s: PositiveFloat

    @model_validator(mode="after")
    def _distances(self) -> Self:
        if self.slow_distance_m <= self.security_distance_m:
            raise ValueError("need slow_distance_m > security_distance_m")
        if self.body_radius > self.robot_radius:
            raise ValueError("need body_radius <= robot_radius")
        return self


class RestConfig(StrictModel):
    """Rest skill: the sentence, the rest posture and how fast to move into it and back."""

    say: str
    posture: str
    speed: float = Field(gt=0, le=1)
    posture_timeout_s: PositiveFloat


class HeadConfig(StrictModel):
    """Where find people points the head: up while searching, level at a seated person."""

    pitch: float = Field(ge=-0.7, le=0.6)
    seated_pitch: float = Field(ge=-0.7, le=0.6)
    seated_distance_m: PositiveFloat
    seated_box_top: float = Field(ge=0, le=1)


class FollowConfig(StrictModel):
    """Which person box find people follows, and the heading loop that centres it."""

    heading_pid: PidGains
    bottom_margin_px: NonNegativeInt
    keep_conf: float = Field(gt=0, lt=1)
    keep_gap_deg: PositiveFloat
    confirm_frames: PositiveInt
    centre_tolerance: float = Field(gt=0, lt=1)
    max_person_width_m: PositiveFloat


class SearchConfig(StrictModel):
    """The search phase: turning in place, then walking on (behaviours/skills/search.py)."""

    turn_speed: PositiveFloat
    lost_after_s: PositiveFloat
    look_around_turns: PositiveFloat
    sighting_memory_s: PositiveFloat
    sightings_kept: PositiveInt
    revisit_min_m: PositiveFloat


class ApproachConfig(StrictModel):
    """The approach phase: the distance loop and where it stops."""

    pid: PidGains
    max_speed: PositiveFloat
    max_offset: float = Field(gt=0, le=1)
    target_distance_m: PositiveFloat
    distance_tolerance_m: PositiveFloat
    backoff_s: PositiveFloat


class EscapeConfig(StrictModel):
    """Backing up and stepping aside when the base is blocked on the way."""

    speed: PositiveFloat
    back_s: PositiveFloat
    side_s: PositiveFloat


class FaceConfig(StrictModel):
    """The wait for the face: which face boxes count, and for how long."""

    region: float = Field(gt=0, le=1)
    min_conf: float = Field(gt=0, lt=1)
    cut_region: float = Field(ge=0, le=1)
    frames: PositiveInt
    wait_s: PositiveFloat


class FrontConfig(StrictModel):
    """Reading which way the person faces, and when to go round to their front."""

    min_confidence: float = Field(ge=0, le=1)
    frames: PositiveInt
    max_distance_m: PositiveFloat
    away_deg: float = Field(gt=0, le=180)
    tolerance_deg: float = Field(gt=0, le=180)


class DetourConfig(StrictModel):
    """Detours on the floor map: round furniture, or to the person's front."""

    distance_m: PositiveFloat
    candidates: PositiveInt
    arc_weight: NonNegativeFloat
    max_detours: NonNegativeInt
    greet_max_m: PositiveFloat


class OrbitConfig(StrictModel):
    """Circling the person when their face does not show."""

    speed: PositiveFloat
    leg_s: PositiveFloat


class GiveUpConfig(StrictModel):
    """Giving up on a person (or a box that is none) and ignoring where they stand."""

    ignore_s: PositiveFloat
    ignore_width_deg: PositiveFloat
    vanish_strikes: PositiveInt


class FindPeopleConfig(StrictModel):
    """Find-people skill: two PID loops on the detector's person box, its settings grouped
    by the approach's phases (docs/find_people.md)."""

    greet: str
    timeout_s: PositiveFloat
    head: HeadConfig
    follow: FollowConfig
    search: SearchConfig
    approach: ApproachConfig
    escape: EscapeConfig
    face: FaceConfig
    front: FrontConfig
    detour: DetourConfig
    orbit: OrbitConfig
    give_up: GiveUpConfig


class SingDanceConfig(StrictModel):
    """Sing/dance skill: where the routines live and how fast gestures move."""

    routines: Path
    speed: float = Field(gt=0, le=1)
    posture_timeout_s: PositiveFloat

    def resolved_routines(self) -> Path:
        """The routines file; a relative path is taken from the repository root."""
        return self.routines if self.routines.is_absolute() else REPO_ROOT / self.routines


class AskQuestionConfig(StrictModel):
    """Ask-question skill."""

    samples: PositiveInt


class ChatConfig(StrictModel):
    """Chat skill."""

    opener: str
    max_heard_age_s: PositiveFloat


class GazeConfig(StrictModel):
    """The camera's cue for whom a line is for (behaviours/speaker_gaze.py)."""

    bearing_tolerance_deg: float = Field(gt=0, le=90)
    min_confidence: float = Field(ge=0, le=1)
    away_deg: float = Field(gt=0, lt=180)
    within_s: float = Field(ge=0)
    max_distance_m: float = Field(gt=0)


class UnmadeConfig(StrictModel):
    """A voice heard of which no words were made out (behaviours/sense.py and listening.py):
    how far over the noise it must stand to be responded to, and what the robot says."""

    min_snr_db: float
    coming_over: str
    say_again: str


class ListeningConfig(StrictModel):
    """Answering people (behaviours/listening.py, the chat skill): turning to a voice and
    the promise made while a safety action must finish."""

    head_speed: float = Field(gt=0, le=1)
    turn_speed: PositiveFloat
    turn_gain: PositiveFloat
    facing_tolerance_deg: float = Field(gt=0, le=90)
    answer_tolerance_deg: float = Field(gt=0, le=90)
    answer_wait_s: float = Field(ge=0)
    promise: str
    promise_action: str
    activities: dict[str, str]
    closer_below_snr_db: float
    come_closer: str
    unmade: UnmadeConfig
    gaze: GazeConfig


class StandByConfig(StrictModel):
    """Stand-by skill: idle posture with a slow look around."""

    head_yaw_amplitude: float = Field(ge=0, le=2)
    period_s: PositiveFloat
    posture_timeout_s: PositiveFloat


class BehaviourConfig(StrictModel):
    """Schema of ``config/behaviour.yaml``."""

    homeostasis_step_s: PositiveFloat
    encouragement_s: float = Field(ge=0)
    emotion_hold_s: float = Field(ge=0)
    preempt_energy: float = Field(gt=0, le=1)
    perception: PerceptionConfig
    pid: PidConfig
    charge: ChargeConfig
    rest: RestConfig
    find_people: FindPeopleConfig
    sing_dance: SingDanceConfig
    ask_question: AskQuestionConfig
    chat: ChatConfig
    listening: ListeningConfig
    stand_by: StandByConfig


def load_behaviour_config(path: str | Path | None = None) -> BehaviourConfig:
    """The packaged behaviour.yaml, with the user file at ``path`` merged over it."""
    return load_model(BehaviourConfig, "behaviour.yaml", path)
