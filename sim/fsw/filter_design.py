"""Torque-command filter design, at parameter-build time (plain Python, scipy).

Seed 001 "Attitude control modes": torques "may be filtered with up to a
fourth-order discrete filter, with a different design possible in each mode and
for each axis"; "Inertial mode": a second-order elliptic filter; "Science
mode": second-order elliptic on X, second-order low-pass on Y, third-order
elliptic on Z. The run-time kernel is sim/fsw/torque_filter.py.

Design, for one axis:

1. Prewarp the discrete edge frequencies to the analog axis,
   w_a = (2 / T) tan(w_d T / 2), so that after the bilinear map the digital
   filter has its edges exactly at w_d (Franklin, Powell & Workman, "Digital
   Control of Dynamic Systems", 3rd ed., ch. 6 "Discrete Equivalents": Tustin's
   method with prewarping; scipy.signal.iirfilter prewarps the same way).
2. Analog prototype: scipy.signal.ellip / scipy.signal.butter(..., analog=True,
   output="zpk") (scipy docs: "ellip: Elliptic (Cauer) digital and analog filter
   design"; Wn is the passband edge, rp the ripple, rs the attenuation).
3. Bilinear (Tustin) transform: scipy.signal.bilinear_zpk(z, p, k, fs).
4. Second-order sections, scipy.signal.zpk2sos, each scaled to unity DC gain
   (an even-order elliptic has DC gain 10^(-rp/20); the flight software must
   pass a constant torque, e.g. the integral torque, unchanged).

Checked at design time: the elliptic's order must reach the stopband spec
(scipy.signal.ellipord on the prewarped edges), and every edge lies below the
Nyquist frequency. Errors name the spec field.
"""
from __future__ import annotations

import numpy as np
from scipy import signal

from sim.fsw.torque_filter import BANKS, MAX_SECTIONS, TorqueFilterParams, identity_sos
from sim.spacecraft.filter_models import AxisFilters, ButterworthSpec, EllipticSpec, TorqueFilters

AXES = "xyz"


def prewarp(f_Hz: float, dt: float) -> float:
    """Analog frequency (rad/s) that the bilinear map at step dt sends to f_Hz."""
    return 2.0 / dt * np.tan(np.pi * f_Hz * dt)


def _check_below_nyquist(spec, dt: float, where: str) -> None:
    nyquist = 0.5 / dt
    for field in ("pass_Hz", "stop_Hz", "cutoff_Hz"):
        f = getattr(spec, field, None)
        if f is not None and f >= nyquist:
            raise ValueError(f"{where}.{field} = {f:g} Hz must be below the Nyquist frequency "
                             f"{nyquist:g} Hz of the {dt:g} s control cycle")


def analog_prototype(spec, dt: float):
    """(z, p, k) of the analog prototype, edges prewarped for step dt."""
    if isinstance(spec, EllipticSpec):
        return signal.ellip(spec.order, spec.ripple_dB, spec.stop_atten_dB, prewarp(spec.pass_Hz, dt),
                            btype="low", analog=True, output="zpk")
    if isinstance(spec, ButterworthSpec):
        return signal.butter(spec.order, prewarp(spec.cutoff_Hz, dt), btype="low", analog=True, output="zpk")
    raise TypeError(f"unknown filter spec {type(spec).__name__}")


def check_spec(spec, dt: float, where: str = "filter") -> None:
    """Raise ValueError, naming the field, if the spec cannot be met at step dt."""
    _check_below_nyquist(spec, dt, where)
    if isinstance(spec, EllipticSpec):
        needed, _ = signal.ellipord(prewarp(spec.pass_Hz, dt), prewarp(spec.stop_Hz, dt), spec.ripple_dB,
                                    spec.stop_atten_dB, analog=True)
        if needed > spec.order:
            raise ValueError(
                f"{where}: an order-{spec.order} elliptic with ripple_dB = {spec.ripple_dB:g} cannot reach "
                f"stop_atten_dB = {spec.stop_atten_dB:g} by stop_Hz = {spec.stop_Hz:g} (needs order {needed}); "
                f"raise order, ripple_dB or stop_Hz, or lower stop_atten_dB")


def unity_dc_sections(sos: np.ndarray) -> np.ndarray:
    """Scale each section's numerator so that its gain at z = 1 is exactly 1."""
    out = np.array(sos, float)
    for s in out:
        dc_num, dc_den = s[:3].sum(), s[3:].sum()
        if abs(dc_num) < 1e-12 * np.abs(s[:3]).sum():
            raise ValueError("a section has a zero at DC (not a low-pass): cannot normalise its DC gain")
        s[:3] *= dc_den / dc_num
    return out


def design_sos(spec, dt: float, where: str = "filter") -> np.ndarray:
    """The discrete filter as (n_sections, 6) second-order sections
    [b0, b1, b2, 1, a1, a2], unity DC gain, for a control step dt (s)."""
    check_spec(spec, dt, where)
    z, p, k = analog_prototype(spec, dt)
    zd, pd, kd = signal.bilinear_zpk(z, p, k, fs=1.0 / dt)
    sos = signal.zpk2sos(zd, pd, kd)
    if np.any(np.abs(pd) >= 1.0):
        raise ValueError(f"{where}: discrete filter unstable (pole radius {np.abs(pd).max():.6f})")
    return unity_dc_sections(sos)


def axis_bank(filters: AxisFilters, dt: float, where: str = "filters") -> np.ndarray:
    """(3, MAX_SECTIONS, 6): each axis's sections, padded with pass-through
    sections [1, 0, 0, 1, 0, 0]; an unfiltered axis is all pass-through."""
    bank = np.empty((3, MAX_SECTIONS, 6))
    for i, spec in enumerate(filters.per_axis()):
        bank[i] = identity_sos(MAX_SECTIONS)
        if spec is not None:
            sos = design_sos(spec, dt, f"{where}.{AXES[i]}")
            bank[i, :len(sos)] = sos
    return bank


def make_torque_filter_params(filters: TorqueFilters, dt: float) -> TorqueFilterParams:
    """All banks, in the order of torque_filter.BANKS (index = bank number)."""
    return TorqueFilterParams(np.stack([axis_bank(getattr(filters, name), dt, f"torque_filters.{name}")
                                        for name in BANKS]))
