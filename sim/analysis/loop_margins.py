"""Linear stability margins of the SDO single-axis attitude loop.

The loop, per body axis, broken at the torque command (seed 001 eq. (3), the
torque filter, the one-cycle actuator delay, a rigid body):

    u_k = F(z) z^-d [ I (k_p + k_i T z/(z-1)) theta_k + I k_d omega_k ]

* Plant: 1/(I s^2) under a zero-order hold at T (Franklin, Powell & Workman,
  "Digital Control of Dynamic Systems", 3rd ed., the satellite attitude
  example, ZOH equivalent): theta(z)/u(z) = T^2 (z + 1) / (2 I (z - 1)^2),
  omega(z)/u(z) = T / (I (z - 1)); computed with scipy.signal.cont2discrete.
* Rate sensor: the IRU is rate-integrating and the rate is the difference of
  successive angle counts over T (sim/truth/sensors/iru.py), omega_k =
  (theta_k - theta_{k-1}) / T; "instantaneous" samples the true rate instead.
* PID as sim/fsw/pid.py: integral_k = integral_{k-1} + theta_k T, used in the
  same cycle; the derivative term acts on the measured rate.
* F(z): the axis's torque filter (sim/fsw/filter_design.py); z^-d the actuator
  delay (seed 000 "Option one": the one-cycle delay; sdo.yaml
  timing.actuator_delay_cycles).
* gain: torque scaling k_t (seed 000 eq. (1)), or I_fsw / I_true when the flight
  software's inertia is not the truth's.

The inertia cancels (the gains are k * I), so an axis differs from another only
by its filter and by any inertia mismatch.

The loop is conditionally stable (type 3: the integrator and the double
integrator give -270 deg at low frequency), so the closed loop with gain k L is
stable on an interval k_low < k < k_high: k_high is the usual gain margin,
k_low the gain-reduction margin of seed 000 "Background" (the output torque
must be at least k_low of the desired torque). Both come from the phase
crossovers of the frequency response (scipy.signal.dfreqresp), and are checked
against the closed-loop poles (root locus, as in seed 000).

Seed 000 "Background": "Project requirements state that there must be at least
6 dB of gain margin on the system."
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import optimize, signal

from sim.fsw.filter_design import design_sos
from sim.spacecraft import load_spacecraft
from sim.spacecraft.filter_models import load_torque_filters

N_GRID = 4000      # log-spaced grid from W_MIN to Nyquist; crossings refined by brentq
W_MIN = 1e-4       # rad/s, well below the integrator corner k_i / k_p ~ 0.07 rad/s


class Margins(NamedTuple):
    k_low: float          # closed loop stable for k_low < k < k_high (0 if stable down to k -> 0)
    k_high: float         # inf if no upper crossover
    gm_low_dB: float      # -20 log10 k_low: how far the loop gain may drop
    gm_high_dB: float     # 20 log10 k_high: how far the loop gain may rise
    w_low: float          # rad/s, phase crossover giving k_low
    w_high: float         # rad/s, phase crossover giving k_high
    pm_deg: float         # phase margin at the gain crossover (smallest if several)
    w_c: float            # rad/s, that gain crossover


def rigid_body_zoh(inertia: float, dt: float):
    """ZOH equivalent of 1/(I s^2): (num_theta, num_omega, den) in z
    (descending powers) and the discrete poles (eigenvalues of A_d, exactly 1, 1)."""
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    B = np.array([[0.0], [1.0 / inertia]])
    C = np.eye(2)
    D = np.zeros((2, 1))
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((A, B, C, D), dt, method="zoh")
    num, den = signal.ss2tf(Ad, Bd, Cd, Dd)
    return _trim(num[0]), _trim(num[1]), _trim(den), np.linalg.eigvals(Ad).real


def _trim(p) -> np.ndarray:
    """Drop leading coefficients that are zero to rounding."""
    p = np.asarray(p, float)
    scale = np.abs(p).max()
    i = 0
    while i < len(p) - 1 and abs(p[i]) <= 1e-13 * scale:
        i += 1
    return p[i:]


def _padd(a, b):
    n = max(len(a), len(b))
    return np.pad(a, (n - len(a), 0)) + np.pad(b, (n - len(b), 0))


def open_loop(kp: float, kd: float, ki: float, dt: float, sos=None, delay_cycles: int = 1,
              rate_sensor: str = "differenced", inertia: float = 1.0, gain: float = 1.0) -> signal.dlti:
    """L(z) of the loop broken at the torque command, with the closed loop's
    characteristic equation 1 + L(z) = 0. sos: the axis filter (None: none).

    Returned in zero-pole-gain form with the poles placed exactly (the triple
    pole at z = 1 of the integrator and the double integrator would lose
    precision near DC as an expanded polynomial)."""
    n_th, n_om, _, plant_poles = rigid_body_zoh(inertia, dt)   # both over den = (z - 1)^2
    if rate_sensor == "differenced":      # (theta_k - theta_k-1) / T = theta (z - 1) / (z T)
        n_r, d_r_poles = np.polymul(n_th, [1.0, -1.0]) / dt, [0.0]
    elif rate_sensor == "instantaneous":
        n_r, d_r_poles = n_om, []
    else:
        raise ValueError(f"rate_sensor must be 'differenced' or 'instantaneous', not {rate_sensor!r}")
    d_r = np.poly(d_r_poles)
    # PID on theta: (kp (z - 1) + ki T z) / (z - 1); rate path kd I n_r / (den d_r). Over the
    # common denominator den (z - 1) d_r (no factor shared with the numerator):
    c_num = np.array([kp + ki * dt, -kp]) * inertia
    num = _trim(_padd(np.polymul(np.polymul(c_num, n_th), d_r), np.polymul(kd * inertia * n_r, [1.0, -1.0])))
    zeros, poles, k = np.roots(num), np.r_[plant_poles, 1.0, d_r_poles], num[0] * gain
    if sos is not None:
        fz, fp, fk = signal.sos2zpk(np.asarray(sos, float))
        zeros, poles, k = np.r_[zeros, fz], np.r_[poles, fp], k * fk
    poles = np.r_[poles, np.zeros(delay_cycles)]
    return signal.dlti(zeros, poles, k, dt=dt)


def _response(L: signal.dlti, w) -> np.ndarray:
    _, h = signal.dfreqresp(L, w=np.atleast_1d(w) * L.dt)
    return h


def closed_loop_radius(L: signal.dlti, k: float) -> float:
    """Largest closed-loop pole radius for loop gain k: roots of den + k num."""
    num, den = L.gain * np.poly(L.zeros).real, np.poly(L.poles).real
    return float(np.abs(np.roots(_padd(den, k * num))).max())


def is_stable(L: signal.dlti, k: float = 1.0) -> bool:
    return closed_loop_radius(L, k) < 1.0


def margins(L: signal.dlti) -> Margins:
    """Gain margins both ways and the phase margin, from the frequency response."""
    if not is_stable(L):
        raise ValueError("the nominal closed loop is unstable: margins are undefined")
    w_nyq = np.pi / L.dt
    w = np.geomspace(W_MIN, w_nyq * (1 - 1e-9), N_GRID)
    h = _response(L, w)
    k_low, w_low, k_high, w_high = 0.0, np.nan, np.inf, np.nan
    im = lambda x: _response(L, x)[0].imag
    for i in np.nonzero(np.sign(h.imag[:-1]) != np.sign(h.imag[1:]))[0]:
        wx = optimize.brentq(im, w[i], w[i + 1], xtol=1e-12)
        hx = _response(L, wx)[0]
        if hx.real >= 0.0:
            continue                      # a crossing of the positive real axis: k < 0
        k = 1.0 / abs(hx)
        if k < 1.0 and k > k_low:
            k_low, w_low = k, wx
        elif k > 1.0 and k < k_high:
            k_high, w_high = k, wx
    pm, w_c = np.inf, np.nan
    mag = lambda x: abs(_response(L, x)[0]) - 1.0
    for i in np.nonzero(np.sign(np.abs(h[:-1]) - 1.0) != np.sign(np.abs(h[1:]) - 1.0))[0]:
        wx = optimize.brentq(mag, w[i], w[i + 1], xtol=1e-12)
        p = 180.0 + np.degrees(np.angle(_response(L, wx)[0]))
        p = (p + 180.0) % 360.0 - 180.0
        if abs(p) < abs(pm):
            pm, w_c = p, wx
    gm_low = -20 * np.log10(k_low) if k_low > 0 else np.inf
    return Margins(k_low, k_high, gm_low, 20 * np.log10(k_high), w_low, w_high, pm, w_c)


def stable_gain_interval(L: signal.dlti, k_max: float = 1e3) -> tuple[float, float]:
    """(k_low, k_high) from the closed-loop poles alone (root locus): bisection
    on the largest pole radius, outward from the nominal k = 1. The cross-check
    of `margins`."""
    if not is_stable(L):
        raise ValueError("the nominal closed loop is unstable")
    f = lambda lk: closed_loop_radius(L, np.exp(lk)) - 1.0
    ks = np.exp(np.linspace(0.0, np.log(1e-3), 200))
    lo = next((k for k in ks if not is_stable(L, k)), None)
    k_low = 0.0 if lo is None else np.exp(optimize.brentq(f, np.log(lo), 0.0, xtol=1e-10))
    ks = np.exp(np.linspace(0.0, np.log(k_max), 200))
    hi = next((k for k in ks if not is_stable(L, k)), None)
    k_high = np.inf if hi is None else np.exp(optimize.brentq(f, 0.0, np.log(hi), xtol=1e-10))
    return k_low, k_high


def continuous_gain_reduction(kp: float, kd: float, ki: float) -> dict:
    """Seed 000's simplified loop: the PID and 1/(I s^2) in continuous time,
    no filter, delay, gyro or wheel dynamics. L(s) = (k_d s^2 + k_p s + k_i) / s^3.

    The loop gain k_t may drop to k_low before the closed loop
    s^3 + k_t (k_d s^2 + k_p s + k_i) is unstable. Returned both from the
    frequency response (scipy.signal.freqresp: the -180 deg crossover) and from
    the Routh criterion of seed 000 eq. (1), k_i < k_p k_d k_t."""
    L = signal.lti([kd, kp, ki], [1.0, 0.0, 0.0, 0.0])
    im = lambda w: signal.freqresp(L, w=[w])[1][0].imag
    w180 = optimize.brentq(im, 1e-4, 10.0, xtol=1e-14)  # phase -270 below, -90 above
    h = signal.freqresp(L, w=[w180])[1][0]
    return {"k_low_freqresp": 1.0 / abs(h), "w180_rad_s": w180, "k_low_routh": ki / (kp * kd),
            "k_low_6dB": 2.0 / abs(h)}


def sdo_margin_table(name: str = "sdo", inertia_truth_B=None) -> dict:
    """Margins per (mode, axis) for a spacecraft's gains, control step, delay
    and torque filters; inertia_truth_B (3,) adds an inertia mismatch."""
    sc = load_spacecraft(name)
    g, dt = sc.fsw.inertial, sc.timing.control_dt_s
    inertia_fsw = np.diag(np.array(sc.inertia_B_kgm2))
    ratio = np.ones(3) if inertia_truth_B is None else inertia_fsw / np.asarray(inertia_truth_B, float)
    table = {}
    filters = load_torque_filters(name)
    for mode in ("inertial", "science"):
        for i, spec in enumerate(getattr(filters, mode).per_axis()):
            sos = None if spec is None else design_sos(spec, dt)
            L = open_loop(g.kp_per_s2, g.kd_per_s, g.ki_per_s3, dt, sos, sc.timing.actuator_delay_cycles,
                          inertia=inertia_fsw[i], gain=ratio[i])
            table[(mode, "xyz"[i])] = margins(L)
    return table


def main() -> None:
    g = load_spacecraft("sdo").fsw.inertial
    c = continuous_gain_reduction(g.kp_per_s2, g.kd_per_s, g.ki_per_s3)
    print(f"continuous PID, no filter/delay: k_low = {c['k_low_freqresp']:.4f} (Routh {c['k_low_routh']:.4f}), "
          f"with 6 dB: {c['k_low_6dB']:.4f}; seed 000: 0.17 and 0.34")
    for label, truth in (("full tanks", None), ("FSW full / truth empty", [1750.0, 3460.0, 2810.0])):
        print(f"\n{label}:  mode     axis  GM up dB  GM down dB (k_low)   PM deg  w_c rad/s  w180 up")
        for (mode, axis), m in sdo_margin_table("sdo", truth).items():
            print(f"{'':{len(label)}}   {mode:9s} {axis}   {m.gm_high_dB:7.2f}   {m.gm_low_dB:7.2f} ({m.k_low:.4f})"
                  f"  {m.pm_deg:6.1f}   {m.w_c:.3f}     {m.w_high:.3f}")


if __name__ == "__main__":
    main()
