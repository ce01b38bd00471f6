"""Wheel torque distribution (seed 001 "Attitude control modes"): geometry,
algorithm, and the status that reports undelivered torque."""
import numpy as np
import pytest
from scipy.optimize import linprog

from sim.fsw.distribution import distribute, distribution_matrix
from sim.spacecraft import load_spacecraft

SC = load_spacecraft("sdo")
G = np.array(SC.wheels.axes_B).T  # 3 x 4, columns are spin axes
LIMIT = SC.wheels.torque_limit_sw_Nm  # seed 001: 0.2 N m software limit


def test_unsaturated_torque_is_delivered_exactly():
    D = distribution_matrix(SC.wheels.axes_B)
    u = np.zeros(4)
    torque = np.array([0.05, -0.1, 0.02])
    undelivered = distribute(torque, D, LIMIT, u)
    # physics: motor torque u on the rotors puts -G u on the body
    assert -G @ u == pytest.approx(torque, abs=1e-15)
    assert undelivered == pytest.approx(np.zeros(3), abs=1e-15)
    # minimum norm: u has no component in G's null space
    null = np.linalg.svd(G)[2][-1]
    assert abs(u @ null) < 1e-15


def test_saturated_torque_keeps_direction_and_reports_the_rest():
    D = distribution_matrix(SC.wheels.axes_B)
    u = np.zeros(4)
    torque = np.array([1.0, 2.0, -0.5])
    undelivered = distribute(torque, D, LIMIT, u)
    delivered = -G @ u
    assert np.max(np.abs(u)) == pytest.approx(LIMIT, rel=1e-12)
    # seed 001: "the direction of the torque vector remains constant"
    assert np.cross(delivered, torque) == pytest.approx(np.zeros(3), abs=1e-12)
    assert delivered @ torque > 0
    assert delivered + undelivered == pytest.approx(torque, abs=1e-12)


def test_y_axis_capability_against_linear_program():
    """The largest Y torque the pyramid can give within the limit, by linprog
    (maximise t subject to -G u = t e_y, |u_i| <= 0.2): the scaled min-norm
    answer must reach it, since Y lies in the plane of wheels 1 and 3."""
    res = linprog(c=[0, 0, 0, 0, -1], A_eq=np.hstack([-G, -np.array([[0], [1], [0]])]), b_eq=np.zeros(3),
                  bounds=[(-LIMIT, LIMIT)] * 4 + [(0, None)])
    D = distribution_matrix(SC.wheels.axes_B)
    u = np.zeros(4)
    distribute(np.array([0, 10.0, 0]), D, LIMIT, u)
    # 2 * cos(30 deg) * 0.2 N m = 0.346 N m from wheels 1 and 3 (seed 001 pyramid geometry)
    assert res.x[-1] == pytest.approx(2 * np.cos(np.radians(30)) * LIMIT, abs=1e-9)
    assert (-G @ u)[1] == pytest.approx(res.x[-1], abs=1e-9)
