"""Mass properties, disturbance torques and thrusters against hand
computations and textbook closed forms."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.truth import disturbances as dist
from sim.truth import mass, thrusters

# -- mass properties ----------------------------------------------------------
J_FULL = np.diag([2211.0, 3963.0, 3268.0])   # seed 000, full tanks
J_EMPTY = np.diag([1750.0, 3460.0, 2810.0])
MP = mass.make_mass_params(3000.0, 900.0, J_FULL, J_EMPTY, [0.0, 0.0, 0.0], [0.15, 0.0, 0.0])


def test_mass_properties_interpolate_between_full_and_empty():
    assert mass.total_mass_kg(900.0, MP) == 3000.0 and mass.total_mass_kg(0.0, MP) == 2100.0
    assert np.array_equal(mass.inertia_B(900.0, MP), J_FULL)
    assert np.array_equal(mass.inertia_B(0.0, MP), J_EMPTY)
    assert mass.inertia_B(450.0, MP) == pytest.approx((J_FULL + J_EMPTY) / 2, abs=1e-12)
    assert mass.centre_of_mass_B(300.0, MP) == pytest.approx([0.10, 0.0, 0.0], abs=1e-15)
    # dJ/dm times the whole propellant load is the full-minus-empty difference
    assert mass.inertia_rate_per_kg(MP) * 900.0 == pytest.approx(J_FULL - J_EMPTY, abs=1e-12)


def test_bad_propellant_load_is_refused():
    with pytest.raises(ValueError, match="propellant"):
        mass.make_mass_params(1000.0, 1200.0, J_FULL, J_EMPTY, [0, 0, 0], [0, 0, 0])


# -- solar radiation pressure ---------------------------------------------------
def _plate(area, normal, centroid, rs, rd):
    return dist.SrpParams(np.array([area]), np.array([normal], float), np.array([centroid], float),
                          np.array([rs]), np.array([rd]))


def test_srp_on_an_absorbing_plate_facing_the_sun():
    # hand computation: black plate, 10 m^2, Sun along its normal at 1 AU:
    # F = P A = 4.56e-6 * 10 = 4.56e-5 N away from the Sun; 2 m lever arm on Y -> torque on Z
    p = _plate(10.0, [1, 0, 0], [0.0, 2.0, 0.0], 0.0, 0.0)
    f, t = dist.srp_force_torque_B(np.array([1.0, 0, 0]), dist.AU_m, 1.0, np.zeros(3), p)
    assert f == pytest.approx([-4.56e-5, 0, 0], abs=1e-15)
    assert t == pytest.approx(np.cross([0, 2.0, 0], [-4.56e-5, 0, 0]), abs=1e-15)  # [0, 0, +9.12e-5]


def test_srp_specular_and_diffuse_plate_at_an_angle():
    # Wertz sec. 17.2 for theta = 60 deg, rho_s = 0.3, rho_d = 0.2, A = 2 m^2, 1 AU
    th = np.radians(60.0)
    s = np.array([np.cos(th), np.sin(th), 0.0])
    p = _plate(2.0, [1, 0, 0], [0, 0, 0], 0.3, 0.2)
    f, _ = dist.srp_force_torque_B(s, dist.AU_m, 1.0, np.zeros(3), p)
    P, c = 4.56e-6, 0.5
    expected = -P * 2.0 * c * ((1 - 0.3) * s + 2 * (0.3 * c + 0.2 / 3) * np.array([1.0, 0, 0]))
    assert f == pytest.approx(expected, abs=1e-18)


def test_srp_scales_with_distance_and_vanishes_in_umbra_and_behind():
    p = _plate(1.0, [1, 0, 0], [0, 1.0, 0], 0.0, 0.0)
    s = np.array([1.0, 0, 0])
    f1, _ = dist.srp_force_torque_B(s, dist.AU_m, 1.0, np.zeros(3), p)
    f2, _ = dist.srp_force_torque_B(s, 2 * dist.AU_m, 1.0, np.zeros(3), p)
    assert f2[0] == pytest.approx(f1[0] / 4, rel=1e-12)  # inverse square
    f3, t3 = dist.srp_force_torque_B(s, dist.AU_m, 0.0, np.zeros(3), p)
    assert not f3.any() and not t3.any()
    f4, _ = dist.srp_force_torque_B(-s, dist.AU_m, 1.0, np.zeros(3), p)
    assert not f4.any()  # the back of a plate is not lit


# -- gravity gradient -------------------------------------------------------------
MU = 3.986004418e14  # EGM2008


def test_gravity_gradient_closed_form_for_a_pitch_offset():
    """Markley & Crassidis eq. 3.155; for a body pitched by theta from the local
    vertical in its orbit plane, |tau_y| = 3 mu / (2 r^3) |I_zz - I_xx| sin(2 theta)."""
    r = 42164e3
    theta = np.radians(20.0)
    r_B = r * np.array([np.cos(theta), 0.0, np.sin(theta)])
    t = dist.gravity_gradient_torque_B(r_B, J_FULL, MU)
    expected = 3 * MU / (2 * r ** 3) * (3268.0 - 2211.0) * np.sin(2 * theta)
    assert abs(t[1]) == pytest.approx(expected, rel=1e-12)
    assert t[0] == pytest.approx(0.0, abs=1e-20) and t[2] == pytest.approx(0.0, abs=1e-20)


def test_gravity_gradient_vanishes_along_principal_axes_and_is_frame_covariant():
    for axis in np.eye(3):
        assert dist.gravity_gradient_torque_B(7000e3 * axis, J_FULL, MU) == pytest.approx(np.zeros(3), abs=1e-20)
    R = Rotation.from_rotvec([0.3, -0.7, 0.2]).as_matrix()
    r_B = np.array([4000e3, -2000e3, 5000e3])
    t1 = dist.gravity_gradient_torque_B(r_B, J_FULL, MU)
    t2 = dist.gravity_gradient_torque_B(R @ r_B, R @ J_FULL @ R.T, MU)
    assert R @ t1 == pytest.approx(t2, abs=1e-15)  # N m, double precision on ~1e-3 N m


# -- thrusters ---------------------------------------------------------------------
def _suite():
    c10, s10 = np.cos(np.radians(10)), np.sin(np.radians(10))
    pos = np.array([[-1.5, 1.0, 1.0], [-1.5, -1.0, 1.0]])
    dirs = np.array([[c10, -s10, 0.0], [c10, s10, 0.0]])
    tp = thrusters.ThrusterParams(pos, dirs, np.full(2, 5 * thrusters.LBF_N), np.full(2, 290.0), 0.05)
    ep = thrusters.EngineParams(np.array([-1.6, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), 110 * thrusters.LBF_N, 312.0)
    return tp, ep


def test_pulse_on_fractions_within_a_cycle():
    faults = np.zeros((3, thrusters.N_FAULT_SLOTS))
    out = np.zeros(3)
    pulses = np.array([0.0, 2.0, 4.0])
    # seed 001: up to four 50 ms pulses per 200 ms cycle; 50 ms RK4 steps
    seen = []
    for j in range(4):
        thrusters.on_fraction(pulses, j, 0.05, 0.05, faults, out)
        seen.append(out.copy())
    assert np.array(seen).sum(axis=0) == pytest.approx([0, 2, 4])
    # with 0.1 s steps a single 50 ms pulse fills half of the first step
    thrusters.on_fraction(np.array([1.0, 0, 0]), 0, 0.1, 0.05, faults, out)
    assert out[0] == pytest.approx(0.5)
    faults[0, thrusters.STUCK_ON] = 1.0
    faults[2, thrusters.FAIL_OFF] = 1.0
    thrusters.on_fraction(pulses, 3, 0.05, 0.05, faults, out)
    assert out.tolist() == [1.0, 0.0, 0.0]


def test_thruster_pair_gives_pitch_torque_and_flow():
    tp, ep = _suite()
    f, t, flow, te = thrusters.thrust_force_torque_B(np.array([1.0, 1.0]), 0.0, np.zeros(3), tp, ep)
    F = 5 * 4.4482216152605  # 5 lbf in N (NIST)
    # the canted Y components cancel; pitch torque = 2 z F cos10 (hand computation)
    assert f == pytest.approx([2 * F * np.cos(np.radians(10)), 0, 0], abs=1e-12)
    assert t[1] == pytest.approx(2 * 1.0 * F * np.cos(np.radians(10)), rel=1e-12)
    assert flow == pytest.approx(2 * F / (290 * 9.80665), rel=1e-12)
    assert not te.any()


def test_engine_through_cm_gives_no_torque_and_offset_gives_misalignment_torque():
    tp, ep = _suite()
    f, t, flow, te = thrusters.thrust_force_torque_B(np.zeros(2), 1.0, np.zeros(3), tp, ep)
    assert not t.any() and f[0] == pytest.approx(110 * 4.4482216152605)
    # a 1 cm lateral centre-of-mass offset: torque = r x F (hand computation)
    cm = np.array([0.0, 0.01, 0.0])
    _, t2, _, te2 = thrusters.thrust_force_torque_B(np.zeros(2), 1.0, cm, tp, ep)
    assert t2 == pytest.approx(np.cross(ep.position_B - cm, f), abs=1e-12)
    assert np.array_equal(t2, te2)
    # rocket flow: mdot = F / (Isp g0)
    assert flow == pytest.approx(110 * 4.4482216152605 / (312 * 9.80665), rel=1e-12)
