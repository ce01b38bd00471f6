"""Typed, validated flight-software section of a spacecraft file (`fsw:`):
attitude determination, the Inertial/Science PID with the integral torque
box, Science-mode guide-telescope use, and the torque filters."""
from __future__ import annotations

from typing import Literal

from pydantic import Field

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
    slew_allowance_s: Positive = Field(
        description="a slew is complete once inside the integral torque box on every axis; it fails if not by "
                    "its angle at the limited rate (k_p/k_d x attitude limit) plus this allowance")
