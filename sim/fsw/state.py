"""The flight software's parameter and state records, shared by the compiled
cycle (cycle.py and the per-mode laws) and its Python side
(flight_software.py). Parameters are fixed for a run; the state arrays are
updated in place, so ground commands act by writing them between cycles.
"""
from typing import NamedTuple

import numpy as np

from sim.fsw.css_sun import CssSunParams
from sim.fsw.ekf import EkfParams, EkfState
from sim.fsw.ephemeris_task import EphemerisTaskParams, EphemerisTaskState
from sim.fsw.fdc import FdcParams, FdcState
from sim.fsw.pid import PidParams
from sim.fsw.sunacq import SunLawParams
from sim.fsw.thruster_modes import ThrusterModeParams, ThrusterModeState
from sim.fsw.torque_filter import TorqueFilterParams, TorqueFilterState
from sim.fsw.wheel_bias import WheelBiasParams

# Event codes the cycle returns for the Python side (mode machine, command lifecycle).
EVENT_NONE = 0
EVENT_SLEW_SETTLED = 1
EVENT_SCIENCE_ACQUIRED = 2   # Inertial: the CGT is in its acquisition range and autonomy is on
EVENT_CGT_LOST = 3           # Science: the CGT is invalid or out of its fine range
EVENT_BURN_DONE = 4          # DeltaV: the burn time is reached (thruster_modes.py)
EVENT_DELTAH_DONE = 5        # DeltaH: system momentum within the exit band of the target
EVENT_FDC = 6                # an FDC check fired: FdcState.last says which (fdc.py)
EVENT_ACE_TAKEOVER = 10      # the ACE took the wheels in Safehold (safehold.py)

# flags[] slots
F_WATCH_SLEW = 0   # 1: a slew is watched until inside the integral torque box
F_CGT_OK = 1       # 1: the CGT was valid and in its fine range last cycle
N_FLAGS = 2


class ScienceParams(NamedTuple):
    dcm_BG: np.ndarray        # (n_gt, 3, 3) the guide telescopes' nominal mountings
    gt_bias_G: np.ndarray     # (n_gt, 2) rad, added to [S_y, S_z] so the sum is zero at the SRB
    acq_range_rad: float      # CGT error per axis inside which Inertial hands over to Science


class FswParams(NamedTuple):
    pid: PidParams
    dist: np.ndarray          # (N, 3) wheel distribution matrix
    torque_limit: float       # software wheel torque limit, N m
    iru_ch_axes_B: np.ndarray  # (6, 3) the flight software's IRU channel axes
    dt: float
    ekf: EkfParams
    eph: EphemerisTaskParams
    eph_every: int            # control cycles per ephemeris sample
    pole_N: np.ndarray        # (3,) solar north pole, GCI
    tf: TorqueFilterParams
    sci: ScienceParams
    wb: WheelBiasParams
    sun: SunLawParams         # SunAcq, eq. (6)
    css: CssSunParams
    css_set: int
    thr: ThrusterModeParams   # DeltaV, DeltaH
    fdc: FdcParams


class FswState(NamedTuple):
    mode: np.ndarray                 # (1,) int64, sim.modes.Mode
    cycle: np.ndarray                # (1,) int64, control cycles run
    q_est_BN: np.ndarray             # (4,) the attitude estimate (the same array as ekf.q_est_BN)
    q_RN: np.ndarray                 # (4,) the target in use
    target: np.ndarray               # (1,) int64, snr.TARGET_*
    dq_RS: np.ndarray                # (4,) ground-commanded delta quaternion (TARGET_SNR_DELTA)
    q_RN_cmd: np.ndarray             # (4,) ground-commanded GCI target (TARGET_GCI)
    q_SN: np.ndarray                 # (4,) on-board SNR frame
    sun_N: np.ndarray                # (3,) on-board apparent Sun unit vector, GCI
    att_option: np.ndarray           # (1,) int64, ekf.OPTION_*
    st_select: np.ndarray            # (1,) int64, tracker flown by OPTION_STAR_TRACKER
    cgt: np.ndarray                  # (1,) int64, controlling guide telescope (0-based)
    autonomy: np.ndarray             # (1,) bool: autonomous Inertial -> Science allowed
    cgt_err_B: np.ndarray            # (2,) rad, eq. (4) pitch and yaw errors from the CGT (+ bias)
    integral: np.ndarray             # (3,) integral of theta_e, rad s
    theta_e: np.ndarray              # (3,) rad, body axes
    omega_e: np.ndarray              # (3,) rad/s
    torque_pid_B: np.ndarray         # (3,) N m, the control law's torque before the filter
    torque_cmd_B: np.ndarray         # (3,) N m, filtered: what the distribution is asked for
    torque_undelivered_B: np.ndarray  # (3,) N m withheld by the scaling
    flags: np.ndarray                # (N_FLAGS,) float
    rate_B: np.ndarray               # (3,) body rate from the IRU channels in use, rad/s
    int_active: np.ndarray           # (3,) bool: the integral torque acts on this axis
    torque_int_B: np.ndarray         # (3,) N m, the integral torque in torque_pid_B
    iru_ch_use: np.ndarray           # (6,) bool: channels rate selection may use (FDC clears failed ones)
    wheel_bias_Nm: np.ndarray        # (N,) the zero-speed-avoidance part of the wheel command
    ekf: EkfState
    eph: EphemerisTaskState
    tf: TorqueFilterState
    mode_info: np.ndarray            # (2,) int64: previous mode, cause of the last transition (CAUSE_CODES)
    sun_B: np.ndarray                # (3,) CSS Sun vector, body
    sun_ok: np.ndarray               # (1,) bool: the CSS saw the Sun this cycle
    proc_up: np.ndarray              # (1,) bool: the main processor runs (a processor fault clears it)
    thr: ThrusterModeState
    fdc: FdcState
