"""The spacecraft definition: every section of sim/spacecraft/*.yaml."""
from __future__ import annotations

from pydantic import Field, field_validator, model_validator

from sim.spacecraft.actuator_models import MainEngine, Thrusters
from sim.spacecraft.fsw_models import Fsw
from sim.spacecraft.model import Positive, StarTracker, Strict, Timing, Vec3, Wheels
from sim.spacecraft.sensor_models import SensorSuite
from sim.spacecraft.structure_models import MassProperties, Surface, check_inertia


class Spacecraft(Strict):
    name: str
    description: str = ""
    mass_kg: Positive
    inertia_B_kgm2: tuple[Vec3, Vec3, Vec3] = Field(
        description="inertia about the centre of mass with full tanks, B axes")
    mass: MassProperties
    surface: Surface
    timing: Timing
    wheels: Wheels
    sensors: SensorSuite
    star_trackers: list[StarTracker] = Field(min_length=1)
    thrusters: Thrusters
    main_engine: MainEngine
    fsw: Fsw

    _inertia = field_validator("inertia_B_kgm2")(check_inertia)

    @model_validator(mode="after")
    def _propellant_fits(self) -> "Spacecraft":
        if self.mass.propellant_kg >= self.mass_kg:
            raise ValueError(f"mass.propellant_kg ({self.mass.propellant_kg:g}) must be below mass_kg ({self.mass_kg:g})")
        return self

    @model_validator(mode="after")
    def _tracker_exists(self) -> "Spacecraft":
        if self.fsw.star_tracker >= len(self.star_trackers):
            raise ValueError(
                f"fsw.star_tracker = {self.fsw.star_tracker} but only {len(self.star_trackers)} star tracker(s) defined")
        return self

    @model_validator(mode="after")
    def _pulses_fit_the_cycle(self) -> "Spacecraft":
        t = self.thrusters
        if t.max_pulses_per_cycle * t.pulse_s > self.timing.control_dt_s + 1e-12:
            raise ValueError(f"thrusters.max_pulses_per_cycle = {t.max_pulses_per_cycle} pulses of {t.pulse_s:g} s "
                             f"do not fit in the {self.timing.control_dt_s:g} s control cycle (timing.control_dt_s)")
        return self

    @property
    def n_wheels(self) -> int:
        return len(self.wheels.axes_B)
