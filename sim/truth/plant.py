"""The truth model assembled: body, wheels and sensors, built from a Spacecraft.

`sense` samples every sensor into a SensorRecord; `propagate` integrates the
plant over one control cycle with the actuator command held. Both are compiled
and called from the runner's cycle loop (sim/loop.py).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.spacecraft.definition import Spacecraft
from sim.truth.rigid_body import IH, IQ, IW, BodyParams, initial_state, make_body_params, rk4_step  # noqa: F401 (initial_state: re-exported for the runner)
from sim.truth.sensors import iru, star_tracker

ARCSEC = np.pi / 180.0 / 3600.0


class TruthParams(NamedTuple):
    body: BodyParams
    iru: iru.IruParams
    st: star_tracker.StarTrackerParams
    truth_dt: float
    substeps: int


def noise_per_cycle(n_star_trackers: int) -> int:
    return iru.N_NOISE + star_tracker.N_NOISE * n_star_trackers


def make_truth_params(sc: Spacecraft) -> TruthParams:
    w = sc.wheels
    body = make_body_params(sc.inertia_B_kgm2, w.axes_B, w.spin_inertia_kgm2, w.torque_max_Nm, w.h_max_Nms,
                            w.viscous_Nm_per_rad_s, w.coulomb_Nm, w.coulomb_smoothing_rad_s)
    dt = sc.timing.control_dt_s
    iru_p = iru.IruParams(sc.iru.lsb_arcsec * ARCSEC,
                          np.radians(sc.iru.arw_deg_per_sqrt_h) / 60.0,
                          np.radians(sc.iru.rrw_deg_h_per_sqrt_h) / 3600.0 / 60.0, dt)
    st_p = star_tracker.StarTrackerParams(
        np.array([t.q_BS for t in sc.star_trackers], float),
        np.array([[t.noise_transverse_arcsec_3sigma, t.noise_transverse_arcsec_3sigma,
                   t.noise_boresight_arcsec_3sigma] for t in sc.star_trackers]) / 3.0 * ARCSEC)
    substeps = int(round(dt / sc.timing.truth_dt_s))
    return TruthParams(body, iru_p, st_p, sc.timing.truth_dt_s, substeps)


def initial_iru_state(sc: Spacecraft, p: TruthParams, x: np.ndarray) -> np.ndarray:
    n = len(sc.wheels.axes_B)
    bias = np.radians(np.array(sc.iru.bias_deg_h)) / 3600.0
    return iru.iru_initial_state(bias, x[IH + n:IH + n + 3], x[IW:IW + 3], p.iru)


@njit(cache=True)
def sense(x, iru_state, p, noise, rec):
    n = p.body.axes_B.shape[0]
    iru.iru_sample(iru_state, p.iru, x[IH + n:IH + n + 3], noise[:iru.N_NOISE], rec.iru_rate_B_rad_s)
    star_tracker.star_tracker_sample(x[IQ:IQ + 4], p.st, noise[iru.N_NOISE:], rec.st_q_SN, rec.st_valid)


@njit(cache=True)
def propagate(x, p, wheel_cmd_Nm, torque_ext_B):
    work = np.empty((5, x.shape[0]))
    for _ in range(p.substeps):
        rk4_step(x, p.body, wheel_cmd_Nm, torque_ext_B, p.truth_dt, work)
