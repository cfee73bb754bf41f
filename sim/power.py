"""The robot's battery and motor temperature, advanced by :meth:`sim.robot.Robot.step`
from how fast its base and joints move (docs/robot.md has the models)."""

from __future__ import annotations

import math

from sim.robot_config import BatteryConfig, ThermalConfig


class Battery:
    """State of charge in [0, 1]: idle drain, extra drain with motion, charging
    (:class:`robot.body.Battery`)."""

    def __init__(self, cfg: BatteryConfig) -> None:
        self.cfg = cfg
        self.level = cfg.initial
        self.charging = False

    def set_level(self, level: float) -> None:
        """Set the state of charge (a household run keeps it equal to 1 - energy drive)."""
        if not 0.0 <= level <= 1.0:
            raise ValueError(f"battery level must lie in [0, 1], got {level}")
        self.level = float(level)

    def start_charging(self) -> None:
        """Plug the charger in (the world decides when the robot is docked)."""
        self.charging = True

    def stop_charging(self) -> None:
        """Unplug the charger."""
        self.charging = False

    def power_w(self, base_speed: float, turn_speed: float, joint_speed: float) -> float:
        """Net power drawn (W, negative while charging) at these speeds (m/s, rad/s)."""
        c = self.cfg
        draw = (c.idle_power_w + c.base_power_w_per_mps * base_speed
                + c.turn_power_w_per_radps * turn_speed + c.joint_power_w_per_radps * joint_speed)
        return draw - (c.charge_power_w if self.charging else 0.0)

    def update(self, dt: float, base_speed: float, turn_speed: float, joint_speed: float) -> None:
        """Drain (or charge) for ``dt`` seconds."""
        used_wh = self.power_w(base_speed, turn_speed, joint_speed) * dt / 3600.0
        self.level = min(1.0, max(0.0, self.level - used_wh / self.cfg.capacity_wh))


class MotorHeat:
    """One lumped motor temperature with a hysteretic overheat flag
    (:class:`robot.body.Thermal`)."""

    def __init__(self, cfg: ThermalConfig) -> None:
        self.cfg = cfg
        self.temperature = cfg.initial_c
        self.overheated = cfg.initial_c >= cfg.overheat_c

    def update(self, dt: float, base_speed: float, turn_speed: float, joint_speed: float,
               resting: bool) -> None:
        """Heat by the travel of ``dt`` seconds and relax towards ambient (exactly, any dt)."""
        c = self.cfg
        heating = (c.joint_heating_c_per_rad * joint_speed + c.base_heating_c_per_m * base_speed
                   + c.turn_heating_c_per_rad * turn_speed)
        tau = c.rest_cooling_tau_s if resting else c.cooling_tau_s
        excess = (self.temperature - c.ambient_c) * math.exp(-dt / tau)
        self.temperature = c.ambient_c + excess + heating * dt
        if self.temperature >= c.overheat_c:
            self.overheated = True
        elif self.temperature <= c.overheat_clear_c:
            self.overheated = False
