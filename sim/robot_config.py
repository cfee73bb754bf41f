"""The robot's settings (``config/robot.yaml``, validated): its base, joints, battery,
motor heat, camera, postures, voice, microphones, laser scanners and the household's
acoustics; docs/robot.md describes them."""

from __future__ import annotations

from pathlib import Path
from typing import Self

from pydantic import Field, NonNegativeFloat, PositiveFloat, model_validator

from core.config_files import StrictModel, load_model
from robot.body import BaseConfig, CameraConfig
from robot.joints import JOINT_NAMES
from robot.lasers import LasersConfig
from robot.voices import Voice
from sim.acoustics import AcousticsConfig
from sim.hearing import MicrophonesConfig


class JointsConfig(StrictModel):
    """Joint motors and the reached tolerance."""

    position_tolerance: PositiveFloat
    position_gain_per_s: PositiveFloat
    force_scale: PositiveFloat


class BatteryConfig(StrictModel):
    """Battery capacity, consumption and charging."""

    capacity_wh: PositiveFloat
    initial: float = Field(ge=0.0, le=1.0)
    idle_power_w: NonNegativeFloat
    base_power_w_per_mps: NonNegativeFloat
    turn_power_w_per_radps: NonNegativeFloat
    joint_power_w_per_radps: NonNegativeFloat
    charge_power_w: NonNegativeFloat


class ThermalConfig(StrictModel):
    """Motor temperature model and overheat thresholds."""

    ambient_c: float
    initial_c: float
    joint_heating_c_per_rad: NonNegativeFloat
    base_heating_c_per_m: NonNegativeFloat
    turn_heating_c_per_rad: NonNegativeFloat
    cooling_tau_s: PositiveFloat
    rest_cooling_tau_s: PositiveFloat
    rest_posture: str
    overheat_c: float
    overheat_clear_c: float

    @model_validator(mode="after")
    def _hysteresis(self) -> Self:
        if not self.ambient_c <= self.overheat_clear_c < self.overheat_c:
            raise ValueError("need ambient_c <= overheat_clear_c < overheat_c")
        return self


class RobotConfig(StrictModel):
    """Schema of ``config/robot.yaml``."""

    base: BaseConfig
    joints: JointsConfig
    voice: Voice
    initial_posture: str
    posture_speed: float = Field(gt=0.0, le=1.0)
    postures: dict[str, dict[str, float]]
    battery: BatteryConfig
    thermal: ThermalConfig
    camera: CameraConfig
    microphones: MicrophonesConfig
    lasers: LasersConfig
    acoustics: AcousticsConfig

    @model_validator(mode="after")
    def _postures_known(self) -> Self:
        for name, angles in self.postures.items():
            unknown = sorted(set(angles) - set(JOINT_NAMES))
            if unknown:
                raise ValueError(f"posture {name!r} names unknown joints {unknown}")
        for used in (self.initial_posture, self.thermal.rest_posture):
            if used not in self.postures:
                raise ValueError(f"posture {used!r} is not defined in `postures`")
        return self


def load_robot_config(path: str | Path | None = None) -> RobotConfig:
    """The packaged robot.yaml, with the user file at ``path`` merged over it."""
    return load_model(RobotConfig, "robot.yaml", path)
