"""The truth model through a main-engine burn, driven directly with
ActuatorCommands (no flight-software mode fires the engine yet): the rocket
equation, angular momentum while the inertia changes with the propellant, and
the mass properties' linear law (sim/truth/mass.py), each against closed forms
and hand computations from sim/spacecraft/sdo.yaml.
"""
import math

import numpy as np
import pytest

from sim.attitude import quat_rotate
from sim.records import empty_actuator_command
from sim.scenario import DEFAULT_EPOCH
from sim.spacecraft import load_spacecraft
from sim.truth import build, plant
from sim.truth import mass as massmod
from sim.truth.rigid_body import angular_momentum_B

CYCLE_S = 0.2                     # sdo.yaml timing.control_dt_s
TRUTH_DT_S = 0.05                 # sdo.yaml timing.truth_dt_s
LBF_N = 4.4482216152605           # NIST SP 811
G0 = 9.80665                      # standard gravity, defines Isp
ENGINE_F = 110.0 * LBF_N          # sdo.yaml main_engine.thrust_lbf -> 489.30 N
ENGINE_ISP = 290.0                # sdo.yaml main_engine.isp_s
FLOW = ENGINE_F / (ENGINE_ISP * G0)  # 0.172056 kg/s
M0 = 3000.0                       # sdo.yaml mass_kg (full tanks)
PROP_FULL = 900.0                 # sdo.yaml mass.propellant_kg
J_FULL = np.diag([2211.0, 3963.0, 3268.0])   # sdo.yaml inertia_B_kgm2
J_EMPTY = np.diag([1750.0, 3460.0, 2810.0])  # sdo.yaml mass.inertia_empty_B_kgm2
CM_FULL = np.array([0.0, 0.05, -0.06])       # sdo.yaml mass.cm_full_B_m
CM_EMPTY = np.array([0.15, 0.05, -0.06])     # sdo.yaml mass.cm_empty_B_m
# sdo.yaml wheels: spin inertia 0.1114 kg m^2 on axes [0.5, +-0.866 (Y or Z)]:
# sum Js g g^T = Js diag(4 * 0.25, 2 * 0.75, 2 * 0.75)
SPIN_INERTIA_B = 0.1114 * np.diag([1.0, 1.5, 1.5])

MU = 3.986004418e14               # m^3/s^2, Earth (IERS 2010 / EGM2008)
A_ORBIT = 42164.0e3               # m, a circular geosynchronous-radius orbit (test choice)


def _circular_orbit():
    """r along X_N, v along Y_N: the body's +X (identity attitude) is radial."""
    return [A_ORBIT, 0.0, 0.0], [0.0, math.sqrt(MU / A_ORBIT), 0.0]


def _fly(sc, world, duration_s, engine_on, omega=(0.0, 0.0, 0.0), h_wheels=(0.0,) * 4, each_cycle=None):
    p = build.make_truth_params(sc, world)
    assert p.substeps * p.truth_dt == pytest.approx(CYCLE_S)
    r, v = _circular_orbit()
    ts = build.make_truth_state(sc, p, [1.0, 0.0, 0.0, 0.0], list(omega), list(h_wheels), r, v,
                                sc.mass.propellant_kg)
    act = empty_actuator_command(sc.n_wheels, len(sc.thrusters.units))  # wheel motors idle
    act.engine_on[0] = 1.0 if engine_on else 0.0
    for k in range(round(duration_s / CYCLE_S)):
        plant.set_environment(ts, p, k * CYCLE_S)
        plant.propagate(ts, p, act)
        if each_cycle is not None:
            each_cycle(ts, p)
    return ts, p


def _h_N(ts, p):
    """Total angular momentum (body + rotors) about the centre of mass, inertial axes."""
    j_prime = massmod.inertia_B(ts.x[-1], p.dyn.mass) - p.dyn.wheels.spin_inertia_B
    return quat_rotate(ts.x[0:4], angular_momentum_B(ts.x, j_prime, p.dyn.wheels))


def _rv(ts):
    ir = 7 + 4 + 3   # q (4), omega (3), four wheels, theta_int (3): sim/truth/dynamics.py offsets
    return ts.x[ir:ir + 3].copy(), ts.x[ir + 3:ir + 6].copy()


BURN_S = 600.0


@pytest.fixture(scope="module")
def ten_minute_burn():
    """A 10-minute burn and a coast over the same time, point-mass gravity only,
    no SRP, no gravity-gradient or engine torque, and the engine overridden to
    fire along +X through the centre of mass (which moves along X only, y and z
    of full and empty being equal), so the thrust stays fixed in inertial space."""
    sc = load_spacecraft("sdo", {"main_engine": {"position_B_m": [-1.7, 0.05, -0.06], "direction_B": [1.0, 0.0, 0.0]}})
    world = build.World(DEFAULT_EPOCH, BURN_S + 100.0, srp=False, gravity_gradient=False, engine_torque=False,
                        zonal=False, tesseral=False, third_body=False)
    burn, p = _fly(sc, world, BURN_S, True)
    coast, _ = _fly(sc, world, BURN_S, False)
    return burn, coast, p


def test_rocket_equation_over_a_ten_minute_burn(ten_minute_burn):
    burn, coast, _ = ten_minute_burn
    # propellant: F t / (Isp g0) = 0.172056 kg/s * 600 s = 103.2314 kg (constant flow: RK4 exact)
    used = PROP_FULL - burn.x[-1]
    assert used == pytest.approx(FLOW * BURN_S, abs=1e-6)
    assert coast.x[-1] == PROP_FULL
    # the attitude stayed put, so the thrust direction is +X_N throughout
    assert np.abs(burn.x[0:4] - [1.0, 0.0, 0.0, 0.0]).max() < 1e-12
    assert np.abs(burn.x[4:7]).max() < 1e-12

    m1 = M0 - used
    dv_rocket = ENGINE_ISP * G0 * math.log(M0 / m1)   # Tsiolkovsky: 99.584 m/s
    dv = _rv(burn)[1] - _rv(coast)[1]
    # Tolerance: the two trajectories separate by |dr| <= a_max t^2 / 2 (29 km at the end), and
    # the difference in gravity between them is at most 2 mu / r^3 |dr| (largest eigenvalue of
    # the gravity-gradient tensor), so the gravity part of the difference is at most
    # n^2 a_max T^3 / 3 = 0.065 m/s; 10 % more for the terms of order |dr| / r ~ 1e-3 and
    # the frame's turn, plus the zero-order hold of 1/m over each 0.05 s step
    # (dv * flow * dt / (2 m) = 1.4e-4 m/s).
    n2 = MU / A_ORBIT ** 3
    a_max = ENGINE_F / m1
    tol = 1.1 * n2 * a_max * BURN_S ** 3 / 3.0 + dv_rocket * FLOW * TRUTH_DT_S / (2.0 * m1)
    assert np.linalg.norm(dv) == pytest.approx(dv_rocket, abs=tol)
    assert dv == pytest.approx([dv_rocket, 0.0, 0.0], abs=tol)
    # the test tells the rocket equation from constant-mass F t / m0 (97.86 m/s) and F t / m1 (101.3 m/s)
    assert abs(ENGINE_F * BURN_S / M0 - dv_rocket) > 10 * tol
    assert abs(ENGINE_F * BURN_S / m1 - dv_rocket) > 10 * tol


def test_mass_properties_follow_the_propellant(ten_minute_burn):
    burn, _, p = ten_minute_burn
    m_final = PROP_FULL - FLOW * BURN_S      # 796.7686 kg
    assert burn.x[-1] == pytest.approx(m_final, abs=1e-6)
    f = m_final / PROP_FULL                  # 0.885298
    # sim/truth/mass.py's linear law, by hand from sdo.yaml: J = J_empty + f (J_full - J_empty),
    # e.g. J_xx = 1750 + 0.885298 * 461 = 2158.12 kg m^2; cm_x = 0.15 - 0.885298 * 0.15 = 0.017205 m
    j_hand = J_EMPTY + f * (J_FULL - J_EMPTY)
    cm_hand = CM_EMPTY + f * (CM_FULL - CM_EMPTY)
    assert massmod.inertia_B(burn.x[-1], p.dyn.mass) == pytest.approx(j_hand, abs=1e-6)
    assert massmod.centre_of_mass_B(burn.x[-1], p.dyn.mass) == pytest.approx(cm_hand, abs=1e-9)
    assert massmod.total_mass_kg(burn.x[-1], p.dyn.mass) == pytest.approx(M0 - FLOW * BURN_S, abs=1e-6)
    # the dynamics used that law: the inertia held over the last RK4 step is the one at the
    # propellant load at the top of that step, m_final + flow * 0.05 s
    f_last = (m_final + FLOW * TRUTH_DT_S) / PROP_FULL
    j_last = J_EMPTY + f_last * (J_FULL - J_EMPTY)
    assert burn.held.j_prime + SPIN_INERTIA_B == pytest.approx(j_last, abs=1e-6)
    assert burn.held.scalars[1] == pytest.approx(FLOW, rel=1e-12)
    # how much moved: inertia down by [52.9, 57.7, 52.5] kg m^2, centre of mass forward by 17.2 mm
    assert np.diag(J_FULL - j_hand) == pytest.approx(np.diag(J_FULL - J_EMPTY) * FLOW * BURN_S / PROP_FULL,
                                                     abs=1e-6)
    assert cm_hand[0] - CM_FULL[0] == pytest.approx(0.0172, abs=1e-4)


def test_angular_momentum_conserved_through_a_burn_while_tumbling():
    """Thrust through a fixed centre of mass, no SRP or gravity gradient: no external
    torque, so H_N is constant although J changes (sim/truth/mass.py keeps dJ/dt in
    Euler's equation)."""
    sc = load_spacecraft("sdo", {"main_engine": {"position_B_m": CM_FULL.tolist(), "direction_B": [1.0, 0.0, 0.0]},
                                 "mass": {"cm_empty_B_m": CM_FULL.tolist()}})
    duration = 300.0
    world = build.World(DEFAULT_EPOCH, duration + 100.0, srp=False, gravity_gradient=False)
    history = []
    burn, p = _fly(sc, world, duration, True, omega=(0.01, -0.02, 0.015), h_wheels=(10.0, -5.0, 3.0, 8.0),
                   each_cycle=lambda ts, p: history.append((_h_N(ts, p), ts.x[4:7].copy())))
    h = np.array([x[0] for x in history])
    omega = np.array([x[1] for x in history])
    r, v = _circular_orbit()
    h0 = _h_N(build.make_truth_state(sc, p, [1.0, 0.0, 0.0, 0.0], [0.01, -0.02, 0.015], [10.0, -5.0, 3.0, 8.0],
                                     r, v, PROP_FULL), p)
    h0_norm = np.linalg.norm(h0)   # 108.7 N m s

    used = PROP_FULL - burn.x[-1]  # 51.6 kg
    assert used == pytest.approx(FLOW * duration, abs=1e-6)
    dj = massmod.inertia_B(PROP_FULL, p.dyn.mass) - massmod.inertia_B(burn.x[-1], p.dyn.mass)
    # inertia fell by [26.43, 28.84, 26.26] kg m^2 (hand: (J_full - J_empty) * 51.6 / 900)
    assert dj == pytest.approx((J_FULL - J_EMPTY) * FLOW * duration / PROP_FULL, abs=1e-6)

    # Tolerance 2e-6 of |H| (2.2e-4 N m s): the mass properties are held over each 0.05 s step,
    # an error of at most |dJ/dt| dt^2 / 2 |domega/dt| = 0.0962 * 1.25e-3 * 1.4e-4 = 1.7e-8 N m s
    # per step, 1.0e-4 N m s over 6000 steps; RK4's own error is ~1e-14. A model that left out
    # dJ/dt would drift by ~|dJ| |omega| ~ 0.6 N m s, 3000 times the tolerance.
    rel = 2e-6
    assert np.abs(np.diff(omega, axis=0)).max() / CYCLE_S < 1.4e-4 * 1.2   # the |domega/dt| used above
    assert np.linalg.norm(dj @ omega[-1]) > 1000 * rel * h0_norm
    assert np.abs(h - h0).max() < rel * h0_norm
    assert np.abs(np.linalg.norm(h, axis=1) - h0_norm).max() < rel * h0_norm
    # the body really tumbles: its rate changes as the inertia does and the wheels drag
    assert np.linalg.norm(omega[-1] - omega[0]) > 5e-3
