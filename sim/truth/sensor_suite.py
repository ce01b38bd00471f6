"""Every sensor of the spacecraft, sampled together once per control cycle.

This is the only place the truth state becomes sensor output: each model in
sim/truth/sensors/ sees the true attitude, rates, wheel speeds and the
environment (apparent Sun, lit fraction, Earth and Moon) and writes what the
flight software is allowed to read into the SensorRecord (sim/records.py).
Noise comes in one row of standard normals per cycle, laid out as below.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.truth.sensors import css, dss, guide_telescope, iru_units, star_tracker_exclusion, tachometer

R_MOON_M = 1737.4e3   # IAU 2015 mean radius


class SensorParams(NamedTuple):
    """A spacecraft without CSS or guide telescopes has zero of them (empty
    arrays: the kernels loop over none); the DSS and the tachometers are
    switched by `present`."""
    iru: iru_units.IruUnitsParams
    st: star_tracker_exclusion.StarTrackerExclusionParams
    css: css.CssParams
    dss: dss.DssParams
    gt: guide_telescope.GuideTelescopeParams
    tach: tachometer.TachometerParams
    present: np.ndarray  # (2,) [DSS, tachometers] 1.0 present


P_DSS, P_TACH = 0, 1
ABSENT_CSS = css.CssParams(np.zeros((0, 3)), 1.0, 1.0, 0.0, 1.0)
ABSENT_GT = guide_telescope.GuideTelescopeParams(np.zeros((0, 3, 3)), 0.0, 1.0, 0.0, 1.0)
ABSENT_DSS = dss.DssParams(np.eye(3), 0.0, 0.0, 0.0, 0.0, 1.0)


class SensorStates(NamedTuple):
    iru: np.ndarray   # (iru_units.STATE_SIZE,)
    tach: np.ndarray  # (tachometer.state_size(n_wheels),)


class SensorFaults(NamedTuple):
    """Fault inputs per unit; slot meanings are each sensor module's FAULT_* constants."""
    iru: np.ndarray   # (6, iru_units.N_FAULT_SLOTS)
    st: np.ndarray    # (n_st, star_tracker_exclusion.N_FAULT_SLOTS)
    css: np.ndarray   # (16, css.N_FAULT_SLOTS)
    dss: np.ndarray   # (1, dss.N_FAULT_SLOTS)
    gt: np.ndarray    # (4, guide_telescope.N_FAULT_SLOTS)
    tach: np.ndarray  # (n_wheels, tachometer.N_FAULT_SLOTS)


def counts(p: SensorParams) -> tuple[int, int, int]:
    """(star trackers, CSS eyes, guide telescopes) a spacecraft has."""
    return p.st.st.q_BS.shape[0], p.css.boresight_B.shape[0], p.gt.dcm_GB.shape[0]


def noise_per_cycle(p: SensorParams) -> int:
    n_st, n_css, n_gt = counts(p)
    return (iru_units.N_NOISE + star_tracker_exclusion.N_NOISE * n_st + n_css + dss.N_NOISE * int(p.present[P_DSS])
            + 2 * n_gt)


def make_faults(p: SensorParams, n_wheels: int) -> SensorFaults:
    n_st, n_css, n_gt = counts(p)
    return SensorFaults(np.zeros((iru_units.N_CHANNELS, iru_units.N_FAULT_SLOTS)),
                        np.zeros((n_st, star_tracker_exclusion.N_FAULT_SLOTS)),
                        np.zeros((n_css, css.N_FAULT_SLOTS)), np.zeros((1, dss.N_FAULT_SLOTS)),
                        np.zeros((n_gt, guide_telescope.N_FAULT_SLOTS)),
                        np.zeros((n_wheels, tachometer.N_FAULT_SLOTS)))


@njit(cache=True, inline="always")
def sample_all(q_BN, theta_int_B, wheel_speed_rad_s, sun_N, lit, r_N_m, moon_N_m, states, p, faults, noise, rec):
    """Sample every sensor into rec. sun_N: apparent unit Sun vector from the
    spacecraft; r_N_m, moon_N_m: geocentric positions of spacecraft and Moon."""
    k = 0
    iru_units.iru_units_sample(theta_int_B, states.iru, p.iru, noise[k:k + iru_units.N_NOISE], faults.iru,
                               rec.iru_rate_ch_rad_s, rec.iru_ch_valid)
    k += iru_units.N_NOISE
    r = np.sqrt(np.sum(r_N_m * r_N_m))
    to_moon = moon_N_m - r_N_m
    d_moon = np.sqrt(np.sum(to_moon * to_moon))
    n_st = faults.st.shape[0]
    star_tracker_exclusion.star_tracker_exclusion_sample(
        q_BN, sun_N, lit, -r_N_m / r, np.arcsin(min(6378137.0 / r, 1.0)), to_moon / d_moon,
        np.arcsin(min(R_MOON_M / d_moon, 1.0)), p.st, noise[k:k + star_tracker_exclusion.N_NOISE * n_st], faults.st,
        rec.st_q_SN, rec.st_valid)
    k += star_tracker_exclusion.N_NOISE * n_st
    n_css = p.css.boresight_B.shape[0]
    css.css_sample(q_BN, sun_N, lit, p.css, noise[k:k + n_css], faults.css, rec.css_current_A)
    k += n_css
    if p.present[P_DSS] > 0.0:
        dss.dss_sample(q_BN, sun_N, lit, p.dss, noise[k:k + dss.N_NOISE], faults.dss, rec.dss_angles_rad,
                       rec.dss_valid)
        k += dss.N_NOISE
    n_gt = p.gt.dcm_GB.shape[0]
    guide_telescope.guide_telescope_sample(q_BN, sun_N, lit, p.gt, noise[k:k + 2 * n_gt], faults.gt,
                                           rec.gt_offset_G_rad, rec.gt_valid, rec.gt_in_range)
    if p.present[P_TACH] > 0.0:
        tachometer.tachometer_sample(wheel_speed_rad_s, states.tach, p.tach, faults.tach, rec.tach_speed_rad_s,
                                     rec.tach_valid)
