"""The Inertial PID against seed 000's numbers (Vess & Starin, integral torque box)."""
import numpy as np
import pytest

from sim.fsw.build import pid_params
from sim.fsw.pid import limit_attitude, pid_torque
from sim.spacecraft import load_spacecraft


@pytest.fixture(scope="module")
def pid():
    return pid_params(load_spacecraft("sdo"))


def _inertia_diag(pid):
    return np.diag(pid.inertia_B)


def test_gains_times_inertia_match_seed000(pid):
    I = _inertia_diag(pid)
    # seed 000 "Integral torque reset analysis": K_p = [159, 285, 235] N m/rad
    assert pid.kp * I == pytest.approx([159, 285, 235], abs=0.5)
    # same section: K_i = [11.3, 20.3, 16.8] N m/(rad s)
    assert pid.ki * I == pytest.approx([11.3, 20.3, 16.8], abs=0.05)


def test_integrator_time_constant_about_14_s(pid):
    # seed 000: "The time constant for the integrator is equal to K_p/K_i, which is approximately 14 sec"
    assert pid.kp / pid.ki == pytest.approx(14.0, abs=0.1)


def _box_torque(pid, theta_lim, omega_lim):
    """PD torque at the corner of the integral torque box, computed by the
    flight software's own control law (integral zero)."""
    theta = np.full(3, theta_lim)
    omega = np.full(3, omega_lim)
    torque, _ = pid_torque(theta, omega, np.zeros(3), np.zeros(3, dtype=bool), 1.0, pid._replace(ki=0.0))
    return torque


def test_tau_lim_original_box(pid):
    # seed 000 eq. (13) with the original limits theta = 6.98e-4 rad, omega = 2.62e-5 rad/s:
    # tau_lim = [0.138, 0.247, 0.204] N m
    assert _box_torque(pid, 6.98e-4, 2.62e-5) == pytest.approx([0.138, 0.247, 0.204], abs=0.0015)


def test_tau_lim_chosen_box(pid):
    # seed 000 eq. (13) and text, chosen limits 1.212e-3 rad and 4.0e-5 rad/s:
    # tau_lim = [0.234, 0.419, 0.346] N m, each under the 0.74 N m margin torque
    t = _box_torque(pid, pid.box_theta_lim, pid.box_omega_lim)
    assert t == pytest.approx([0.234, 0.419, 0.346], abs=0.0015)
    assert np.all(t < 0.74)


def test_eq9_saturated_integrator_against_box(pid):
    I = _inertia_diag(pid)
    # seed 000 eq. (9): on Y the saturated integrator gives 0.203 N m against K_p theta_lim = 0.199 N m
    assert pid.ki * I[1] * pid.integrator_limit == pytest.approx(0.203, abs=0.001)
    assert pid.kp * I[1] * 6.98e-4 == pytest.approx(0.199, abs=0.001)


def test_box_holds_integrator_outside_and_integrates_inside(pid):
    integral = np.array([1e-3, -2e-3, 5e-4])
    before = integral.copy()
    # outside the box on one axis only: seed 001 "Inertial mode", "for any axis": input zeroed, value held
    active = np.ones(3, dtype=bool)
    _, t_int = pid_torque(np.array([2e-3, 0.0, 0.0]), np.zeros(3), integral, active, 1.0, pid)
    assert not active.any() and np.array_equal(integral, before)
    # hold (flown): the held integral torque still acts, K_i times the integral
    assert t_int == pytest.approx(pid.ki * pid.inertia_B @ before, abs=1e-15)
    theta = np.array([1e-4, -1e-4, 2e-4])
    pid_torque(theta, np.zeros(3), integral, active, 1.0, pid)
    assert active.all()
    # rectangle-rule integration over one control cycle (0.2 s, seed 001 "DeltaV")
    assert integral == pytest.approx(before + theta * 0.2, abs=1e-15)


def test_integrator_limit_0p01_rad_s(pid):
    # seed 000 eq. (9) text: "The integrator saturation limit is 0.01 rad-sec"
    integral = np.array([0.00999, -0.00999, 0.0])
    pid_torque(np.array([1e-3, -1e-3, 0.0]), np.zeros(3), integral, np.ones(3, dtype=bool), 1.0, pid)
    assert integral[:2] == pytest.approx([0.01, -0.01], abs=1e-15)


def test_attitude_limiter_keeps_direction():
    theta = np.array([0.3, -0.4, 1.2])
    out = limit_attitude(theta, 7e-3)
    assert np.linalg.norm(out) == pytest.approx(7e-3, rel=1e-12)
    assert np.cross(out, theta) == pytest.approx(np.zeros(3), abs=1e-15)
    small = np.array([1e-4, 0, 0])
    assert np.array_equal(limit_attitude(small, 7e-3), small)


def test_rate_term_damps(pid):
    # seed 001 eq. (2)-(3): omega_e = -omega, so a positive body rate gets a negative torque
    torque, _ = pid_torque(np.zeros(3), -np.array([1e-3, 1e-3, 1e-3]), np.zeros(3), np.zeros(3, dtype=bool), 1.0,
                           pid)
    assert np.all(torque < 0)


# -- the other options of seed 000's trade study ----------------------------------
def _run(pid, theta, omega, integral, active, k_t=1.0):
    return pid_torque(np.asarray(theta, float), np.asarray(omega, float), integral, active, k_t, pid)


def test_option1_routh_threshold_on_torque_scaling(pid):
    """Seed 000 eq. (1): k_i < k_p k_d k_t. With the seed's gains the integral
    must go when the delivered fraction k_t drops below k_i / (k_p k_d) = 0.1527."""
    p = pid._replace(box_option=1)
    threshold = 0.005129 / (0.07192 * 0.467055)  # seed 000 "Option one" gains
    assert threshold == pytest.approx(0.1527, abs=1e-4)
    small = [1e-5, 0, 0]
    on = np.zeros(3, dtype=bool)
    _run(p, small, [0, 0, 0], np.zeros(3), on, k_t=threshold * 1.01)
    assert on.all()
    _run(p, small, [0, 0, 0], np.zeros(3), on, k_t=threshold * 0.99)
    assert not on.any()


def test_option2_pd_torque_against_saturation(pid):
    """Seed 000 "Option two": integral only while the PD torque is below
    tau_sat = 0.25 N m and the attitude is not limited."""
    p = pid._replace(box_option=2)
    on = np.zeros(3, dtype=bool)
    # Y: K_p,y theta = 285 N m/rad * 8e-4 rad = 0.228 N m < 0.25
    _run(p, [0, 8e-4, 0], [0, 0, 0], np.zeros(3), on)
    assert on.all()
    # 285 * 9e-4 = 0.257 N m > 0.25
    _run(p, [0, 9e-4, 0], [0, 0, 0], np.zeros(3), on)
    assert not on.any()


def test_zero_method_keeps_integrating_without_the_torque(pid):
    p = pid._replace(disable_method=1)
    integral = np.array([1e-3, 0, 0])
    on = np.ones(3, dtype=bool)
    theta = [2e-3, 0, 0]  # outside the 1.212e-3 rad box
    _, t_int = _run(p, theta, [0, 0, 0], integral, on)
    assert not on.any() and not t_int.any()
    assert integral[0] == pytest.approx(1e-3 + 2e-3 * 0.2, abs=1e-15)


def test_zero_reset_method_restarts_the_integrator_on_re_entry(pid):
    p = pid._replace(disable_method=2)
    integral = np.array([5e-3, -5e-3, 1e-3])
    on = np.ones(3, dtype=bool)
    _, t_int = _run(p, [2e-3, 0, 0], [0, 0, 0], integral, on)
    assert not t_int.any() and integral[0] == 5e-3  # zeroed torque, held value
    theta = np.array([1e-4, 0, 0])
    _, t_int = _run(p, theta, [0, 0, 0], integral, on)
    assert on.all()
    assert integral == pytest.approx(theta * 0.2, abs=1e-15)  # reset, then one cycle's worth
