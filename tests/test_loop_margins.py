"""Linear stability of the SDO attitude loop (sim/analysis/loop_margins.py):
the 6 dB gain-margin requirement and the 17 % torque figure of seed 000
"Background", checked three ways: frequency response (scipy.signal), closed-loop
poles (root locus), and a time simulation through the flight software's
filter kernel."""
import numpy as np
import pytest
from scipy import signal

from sim.analysis.loop_margins import (continuous_gain_reduction, margins, open_loop, rigid_body_zoh,
                                       sdo_margin_table, stable_gain_interval)
from sim.fsw.filter_design import design_sos, make_torque_filter_params
from sim.fsw.torque_filter import BANKS, filter_torque, make_torque_filter_state
from sim.spacecraft import load_spacecraft
from sim.spacecraft.filter_models import load_torque_filters

SC = load_spacecraft("sdo")
G = SC.fsw.inertial
DT = SC.timing.control_dt_s                      # seed 001: 200 ms control cycle
DELAY = SC.timing.actuator_delay_cycles          # seed 000 "Option one": one-cycle delay
I_FULL = np.diag(np.array(SC.inertia_B_kgm2))    # seed 000: K_p / k_p, full tanks
I_EMPTY = np.diag(np.array(SC.mass.inertia_empty_B_kgm2))
FILTERS = load_torque_filters("sdo")
TABLE = sdo_margin_table("sdo")
# the flight software's inertia is the full-tank one; the truth's may be empty:
# the loop gain is then I_fsw / I_true (up to 1.26, 2.0 dB, on X)
TABLE_EMPTY = sdo_margin_table("sdo", I_EMPTY)
CASES = sorted(TABLE)
REQUIRED_GM_DB = 6.0   # seed 000 "Background": "at least 6 dB of gain margin on the system"


def _loop(mode, axis, **kw):
    spec = getattr(FILTERS, mode).per_axis()["xyz".index(axis)]
    sos = None if spec is None else design_sos(spec, DT)
    return open_loop(G.kp_per_s2, G.kd_per_s, G.ki_per_s3, DT, sos, DELAY, inertia=I_FULL["xyz".index(axis)], **kw)


def test_zoh_double_integrator_closed_form():
    # Franklin, Powell & Workman, satellite attitude example: 1/(I s^2) under a ZOH at T is
    # theta/u = T^2 (z + 1) / (2 I (z - 1)^2) and omega/u = T / (I (z - 1))
    I, T = 3963.0, DT
    n_th, n_om, den, poles = rigid_body_zoh(I, T)
    assert den == pytest.approx([1.0, -2.0, 1.0], abs=1e-15)
    assert poles == pytest.approx([1.0, 1.0], abs=0.0)
    assert n_th == pytest.approx([T**2 / (2 * I), T**2 / (2 * I)], rel=1e-12)
    assert n_om == pytest.approx([T / I, -T / I], rel=1e-12)


def test_open_loop_against_hand_written_loop():
    """L(z) at a few points of the unit circle against the formula of the
    module docstring, written out: filter, delay, differenced gyro, PID."""
    T, kp, kd, ki = DT, G.kp_per_s2, G.kd_per_s, G.ki_per_s3
    sos = design_sos(FILTERS.science.z, DT)
    L = open_loop(kp, kd, ki, T, sos, 1, inertia=2211.0)
    w = np.array([1e-3, 0.01, 0.1, 0.5, 2.0, 10.0])       # rad/s
    _, h = signal.dfreqresp(L, w=w * T)
    for w, h in zip(w, h):
        z = np.exp(1j * w * T)
        theta = T**2 * (z + 1) / (2 * (z - 1) ** 2)            # per unit torque / I
        omega_meas = theta * (1 - 1 / z) / T                    # (theta_k - theta_k-1) / T
        F = np.prod([(s[0] * z**2 + s[1] * z + s[2]) / (z**2 + s[4] * z + s[5]) for s in sos])
        expected = F / z * ((kp + ki * T * z / (z - 1)) * theta + kd * omega_meas)
        assert h == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("mode, axis", CASES)
def test_gain_margin_at_least_6dB(mode, axis):
    """Seed 000 "Background": at least 6 dB of gain margin. The loop is
    conditionally stable, so both ways: the gain may rise by 6 dB (filter,
    delay) and drop by 6 dB (torque scaling, seed 000: output torque >= 34 %)."""
    for m in (TABLE[mode, axis], TABLE_EMPTY[mode, axis]):
        assert m.gm_high_dB >= REQUIRED_GM_DB
        assert m.gm_low_dB >= REQUIRED_GM_DB


@pytest.mark.parametrize("mode, axis", CASES)
def test_phase_margin_design_target(mode, axis):
    # assumption: 30 deg design target (the seeds state no phase-margin requirement)
    assert TABLE[mode, axis].pm_deg >= 30.0
    assert TABLE_EMPTY[mode, axis].pm_deg >= 30.0


@pytest.mark.parametrize("mode, axis", CASES)
def test_margins_agree_with_root_locus(mode, axis):
    """The stable gain interval from the closed-loop poles alone (seed 000's
    root-locus method) equals the one from the frequency response."""
    L = _loop(mode, axis)
    m = margins(L)
    k_low, k_high = stable_gain_interval(L)
    assert k_low == pytest.approx(m.k_low, rel=1e-6)
    assert k_high == pytest.approx(m.k_high, rel=1e-6)


def _simulate(k, axis, bank, n=4000):
    """The closed loop, one axis excited: the PID of sim/fsw/pid.py written out
    (integral_k = integral_k-1 + theta_k T, used in the same cycle; no box, no
    limits: the linear loop), the flight software's filter_torque kernel, a
    torque gain k, the one-cycle delay, the exact ZOH rigid body and the
    differenced gyro of sim/truth/sensors/iru.py. Returns |theta| (n,)."""
    fp = make_torque_filter_params(FILTERS, DT)
    fs = make_torque_filter_state()
    I = I_FULL[axis]
    theta, omega, theta_prev, integral, u_applied = 1e-4, 0.0, 1e-4, 0.0, 0.0
    torque, out = np.zeros(3), np.zeros(3)
    hist = np.empty(n)
    for j in range(n):
        th_e, om_e = -theta, -(theta - theta_prev) / DT
        integral += th_e * DT
        torque[axis] = k * I * (G.kd_per_s * om_e + G.kp_per_s2 * th_e + G.ki_per_s3 * integral)
        filter_torque(torque, fp, fs, bank, out)
        theta_prev = theta
        theta += omega * DT + u_applied * DT**2 / (2 * I)      # exact under a held torque
        omega += u_applied * DT / I
        u_applied = out[axis]                                   # one-cycle delay
        hist[j] = abs(theta)
    return hist


@pytest.mark.parametrize("mode, axis", [("inertial", "x"), ("science", "z")])
def test_time_simulation_changes_stability_at_the_margins(mode, axis):
    """The frequency-domain margins hold in the time domain, with the filter run
    through the flight software's kernel: 2 % inside k_high (10 % inside k_low)
    the response decays, as far outside it grows."""
    m = TABLE[mode, axis]
    i, bank = "xyz".index(axis), BANKS.index(mode)
    peak = lambda h: h[-500:].max() / h[:500].max()
    assert peak(_simulate(1.0, i, bank)) < 1e-3
    assert peak(_simulate(0.98 * m.k_high, i, bank)) < 1e-3
    assert peak(_simulate(1.02 * m.k_high, i, bank)) > 1e3
    assert peak(_simulate(1.1 * m.k_low, i, bank)) < 0.5
    assert peak(_simulate(0.9 * m.k_low, i, bank)) > 2.0


def test_17_percent_of_desired_torque():
    """Seed 000 "Background": with the integral torque and no attitude
    saturation, the system stays stable "as long as the system output torque is
    at least 17% of the desired control torque"; 6 dB of margin makes it 34 %
    ("Torque Space Description"), so tau_d < 1.47 N m and < 0.74 N m for
    tau_sat = 0.25 N m.

    Reproduced on seed 000's own simplified loop (continuous PID and rigid body;
    no structural filter, delay, gyro or wheel dynamics): the loop gain may drop
    to k_i / (k_p k_d) = 0.1527, the exact Routh bound of seed 000 eq. (1). That
    is 1.7 points under the paper's root-locus figure (0.17); the 6 dB bound is
    0.305 against 0.34. Seed 000 says its gains changed between analyses
    ("Integral torque reset analysis"), which may account for it."""
    c = continuous_gain_reduction(G.kp_per_s2, G.kd_per_s, G.ki_per_s3)
    assert c["k_low_freqresp"] == pytest.approx(c["k_low_routh"], rel=1e-9)
    assert c["k_low_routh"] == pytest.approx(0.1527, abs=5e-5)
    assert abs(c["k_low_freqresp"] - 0.17) < 0.02                    # seed 000: 17 %
    assert c["k_low_6dB"] == pytest.approx(0.3054, abs=5e-4)
    assert abs(c["k_low_6dB"] - 0.34) < 0.04                         # seed 000: 34 %
    tau_sat = SC.wheels.torque_max_Nm                                # seed 000: 0.25 N m
    assert tau_sat / c["k_low_freqresp"] == pytest.approx(1.64, abs=0.01)   # seed 000: 1.47 N m
    assert tau_sat / c["k_low_6dB"] == pytest.approx(0.82, abs=0.01)        # seed 000: 0.74 N m
    # the -180 deg crossover of the continuous loop is sqrt(k_i / k_d)
    assert c["w180_rad_s"] == pytest.approx(np.sqrt(G.ki_per_s3 / G.kd_per_s), rel=1e-9)


def test_filter_and_delay_move_the_torque_fraction_toward_17_percent():
    """The discrete loop with the one-cycle delay and each filter needs
    16-18 % of the desired torque: the neglected dynamics (seed 000 eq. (1)
    text) cost phase at the 0.11 rad/s crossover and raise the 15.3 %."""
    bare = margins(open_loop(G.kp_per_s2, G.kd_per_s, G.ki_per_s3, DT, None, DELAY))
    assert 0.153 < bare.k_low < 0.16
    for mode, axis in CASES:
        assert 0.16 < TABLE[mode, axis].k_low < 0.18
        assert TABLE[mode, axis].k_low > bare.k_low


def test_margins_refuse_an_unstable_nominal_loop():
    with pytest.raises(ValueError, match="unstable"):
        margins(_loop("inertial", "x", gain=0.1))
