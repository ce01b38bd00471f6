"""Typed, validated flight-software section of a spacecraft file (`fsw:`):
attitude determination, the Inertial/Science PID with the integral torque
box, Science-mode guide-telescope use, and the torque filters."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from sim.spacecraft.filter_models import TorqueFilters
from sim.spacecraft.model import NonNegative, Positive, Strict


class InertialControl(Strict):
    """Seed 001 eq. (3) PID with the seed 000 integral torque box (option 3, hold)."""
    kp_per_s2: Positive = Field(description="k_p; K_p = k_p * I")
    kd_per_s: Positive = Field(description="k_d; K_d = k_d * I")
    ki_per_s3: NonNegative = Field(description="k_i; K_i = k_i * I")
    integrator_limit_rad_s: Positive = Field(description="per-axis limit of the integral of theta_e")
    box_theta_lim_rad: Positive = Field(description="integral torque box attitude limit, per axis")
    box_omega_lim_rad_s: Positive = Field(description="integral torque box rate limit, per axis")
    attitude_limit_rad: Positive = Field(description="magnitude limit of theta_e (overshoot suppression)")
    box_option: Literal[1, 2, 3] = Field(
        3, description="when the integral acts: 1 Routh criterion, 2 PD torque/attitude saturation, 3 the box")
    box_per_axis: bool = Field(False, description="option 3 per axis (else any axis outside disables all)")
    disable: Literal["hold", "zero", "zero_reset"] = Field(
        "hold", description="how: hold the integral torque, zero it, or zero it and reset on re-entry")
    torque_sat_Nm: Positive = Field(0.25, description="actuator saturation torque, option 2")


class EkfSetup(Strict):
    """The Kalman filter's start (it begins at the uplinked attitude)."""
    initial_sigma_attitude_arcsec: Positive = Field(description="1-sigma per axis of the initial attitude")
    initial_sigma_bias_deg_h: Positive = Field(description="1-sigma per axis of the initial gyro bias")
    sun_accuracy_arcsec_3sigma: Positive = Field(description="on-board Sun direction error, for the DSS update")


class ScienceControl(Strict):
    """Seed 001 "Science mode": pitch and yaw from the controlling guide telescope."""
    cgt: int = Field(1, ge=1, le=4, description="controlling guide telescope at start, 1..4")
    acquisition_range_arcsec: Positive = Field(
        description="CGT error (measurement + bias) per axis below which Inertial may hand over to Science")
    autonomy: bool = Field(True, description="autonomous Inertial -> Science allowed at start")


class WheelBias(Strict):
    """Null-space logic that keeps wheel speeds away from zero (seed 001)."""
    gain_per_s: NonNegative = Field(description="proportional gain on the null-space momentum shift")
    limit_Nm: NonNegative = Field(description="largest per-wheel torque the logic may add")
    h_min_Nms: NonNegative = Field(description="wheel momentum magnitude the logic keeps each wheel above")
    h_target_Nms: NonNegative = Field(description="level the shift aims at (above h_min: margin for drag)")


class OnboardEphemeris(Strict):
    """The on-board orbit model's solar radiation pressure (seed 001 "On-Board Ephemeris")."""
    srp_area_m2: NonNegative = Field(description="cannonball area facing the Sun")
    cr: float = Field(ge=0, le=2, description="radiation pressure coefficient, 1 (absorbing) to 2")
    sample_s: Positive = Field(1.0, description="ephemeris task sample time (seed 001: nominally 1 s)")


class SunAcquisition(Strict):
    """Seed 001 eq. (6): PD on the CSS Sun vector with IRU rates; rate-only in eclipse."""
    kp_per_s2: Positive = Field(description="k_p; K_p = k_p * I")
    kd_per_s: Positive = Field(description="k_d; K_d = k_d * I")
    sun_error_limit: Annotated[float, Field(gt=0, le=1)] = Field(
        description="limit of |s_d x s| (attitude limiting): the slew rate is k_p/k_d times it")
    css_set: Literal["primary", "backup", "both"] = Field("both", description="CSS eyes used")


class Safehold(Strict):
    """Seed 001 eq. (7), in the ACE: CSS Sun vector and CSS-derived Y/Z rates,
    the X rate from the wheel tachometers, IRU rates in eclipse."""
    kp_per_s2: Positive
    kd_per_s: Positive
    k_perp: Positive = Field(description="rate gain perpendicular to the Sun line")
    k_sunline: Positive = Field(description="rate gain along the Sun line")
    sun_error_limit: Annotated[float, Field(gt=0, le=1)]
    rate_filter_s: Positive = Field(description="time constant of the low-pass on the CSS-derived rate")
    h_sunline_ref_Nms: float = Field(
        0.0, description="system momentum along the Sun line the tachometer-derived X rate is measured against")
    heartbeat_cycles: int = Field(ge=1, description="missed main-processor cycles before the ACE takes over")
    css_set: Literal["primary", "backup", "both"] = Field("primary", description="CSS eyes read by this ACE")


class ThrusterControl(Strict):
    """DeltaV and DeltaH (seed 001): PD on the IRU-propagated attitude, gains
    k * I(propellant) from the decoupled (diagonal) inertia; thruster pulses."""
    deltav_kp_per_s2: Positive
    deltav_kd_per_s: Positive
    deltah_kp_per_s2: Positive
    deltah_kd_per_s: Positive
    tipoff_kp_factor: Positive = Field(0.1, description="DeltaH tip-off contingency: K_p times this")
    wheel_gain_per_s: Positive = Field(description="DeltaH wheel command: torque = J_s * gain * speed error")
    h_exit_Nms: Positive = Field(description="DeltaH exits when |H_wheels + H_body - H_target| is below this")
    settling_burn_s: NonNegative = Field(description="ACS-thruster burn before a main-engine burn")
    thruster_set: Literal["primary", "redundant"] = Field("primary", description="set in use at start")


ModeName = Literal["SUNACQ", "INERTIAL", "SCIENCE", "DELTAH", "DELTAV", "SAFEHOLD"]


class Fdc(Strict):
    """Failure detection and correction thresholds; each check can be
    disabled by command (set_fdc_check)."""
    attitude_limit_deg: dict[ModeName, Positive] = Field(
        description="per mode: attitude error beyond which the mode's FDC response fires")
    rate_limit_deg_s: dict[ModeName, Positive] = Field(description="per mode: body rate beyond which it fires")
    limit_response: dict[ModeName, Literal["INERTIAL", "SUNACQ", "SAFEHOLD"]] = Field(
        description="per mode: where the attitude/rate limit check takes the spacecraft")
    limit_persistence_s: Positive = Field(description="how long a limit must be exceeded")
    wheel_torque_threshold_Nm: Positive
    wheel_persistence_s: Positive
    iru_disagree_deg_s: Positive
    iru_persistence_s: Positive
    iru_window_s: Positive

    @model_validator(mode="after")
    def _every_limit_has_a_response(self) -> "Fdc":
        missing = sorted((set(self.attitude_limit_deg) | set(self.rate_limit_deg_s)) - set(self.limit_response))
        if missing:
            raise ValueError(f"limit_response: modes {', '.join(missing)} have limits but no response")
        return self


class Fsw(Strict):
    attitude_option: Literal["ekf", "star_tracker", "iru"] = Field(
        "ekf", description="attitude determination at start: the Kalman filter, a star tracker, IRU propagation")
    star_tracker: int = Field(0, ge=0, description="index of the star tracker flown by option star_tracker")
    ekf: EkfSetup
    ephemeris: OnboardEphemeris | None = Field(
        None, description="the on-board ephemeris task; absent: no SNR targeting, no Sun reference for a DSS")
    inertial: InertialControl
    science: ScienceControl
    wheel_bias: WheelBias | None = Field(None, description="absent: no zero-speed avoidance")
    torque_filters: TorqueFilters
    sun_acquisition: SunAcquisition | None = Field(None, description="absent: no SunAcq mode")
    safehold: Safehold | None = Field(None, description="absent: no ACE Safehold")
    thruster_control: ThrusterControl | None = Field(None, description="absent: no DeltaV/DeltaH")
    fdc: Fdc | None = Field(None, description="absent: no failure detection and correction")
    slew_allowance_s: Positive = Field(
        description="a slew is complete once inside the integral torque box on every axis; it fails if not by "
                    "its angle at the limited rate (k_p/k_d x attitude limit) plus this allowance")
