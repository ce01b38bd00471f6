"""Build the truth model's parameters and initial state from a Spacecraft and
a scenario's world (epoch, duration, orbit, which disturbances act)."""
from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

import numpy as np

from sim.constants import ARCSEC_RAD as ARCSEC
from sim.spacecraft.definition import Spacecraft
from sim.truth import dynamics, plant, sensor_suite
from sim.truth.disturbances import SrpParams
from sim.truth.ephemeris import build_table
from sim.truth.gravity import make_gravity_params
from sim.truth.mass import make_mass_params
from sim.truth.orbit import OrbitElements, sdo_orbit
from sim.truth.rigid_body import make_wheel_params
from sim.truth.sensor_suite import SensorParams, SensorStates
from sim.truth.sensors import (
    css,
    dss,
    guide_telescope,
    iru_units,
    star_tracker,
    star_tracker_exclusion,
    tachometer,
)
from sim.truth.thrusters import LBF_N, EngineParams, ThrusterParams

EPHEMERIS_STEP_S = 600.0  # cubic Hermite on 600 s nodes: < 1 m for Sun and Moon (tests/test_environment.py)


@dataclass(frozen=True)
class World:
    """The scenario's side of the truth model."""
    epoch_utc: datetime
    duration_s: float
    srp: bool = True
    gravity_gradient: bool = True
    engine_torque: bool = True
    zonal: bool = True
    tesseral: bool = True
    third_body: bool = True


def default_orbit(spacecraft: str, epoch_utc: datetime) -> OrbitElements:
    """The orbit a spacecraft flies when a scenario names none."""
    named = {"sdo": sdo_orbit}
    if spacecraft not in named:
        raise KeyError(f"no default orbit for spacecraft {spacecraft!r}; give the scenario an orbit")
    return named[spacecraft](epoch_utc)


def make_dynamics_params(sc: Spacecraft, world: World) -> dynamics.DynamicsParams:
    w = sc.wheels
    wheels = make_wheel_params(w.axes_B, w.spin_inertia_kgm2, w.torque_max_Nm, w.h_max_Nms,
                               w.viscous_Nm_per_rad_s, w.coulomb_Nm, w.coulomb_smoothing_rad_s)
    m = sc.mass
    mass = make_mass_params(sc.mass_kg, m.propellant_kg, sc.inertia_B_kgm2, m.inertia_empty_B_kgm2,
                            m.cm_full_B_m, m.cm_empty_B_m)
    f = sc.surface.facets
    srp = SrpParams(np.array([x.area_m2 for x in f]), np.array([x.normal_B for x in f], float),
                    np.array([x.centroid_B_m for x in f], float), np.array([x.rho_specular for x in f]),
                    np.array([x.rho_diffuse for x in f]))
    t = sc.thrusters
    thr = ThrusterParams(np.array([u.position_B_m for u in t.units], float),
                         np.array([u.direction_B for u in t.units], float),
                         np.array([u.thrust_lbf * LBF_N for u in t.units]), np.array([u.isp_s for u in t.units]),
                         t.pulse_s)
    e = sc.main_engine
    eng = EngineParams(np.array(e.position_B_m, float), np.array(e.direction_B, float), e.thrust_lbf * LBF_N,
                       e.isp_s)
    grav = make_gravity_params(world.epoch_utc, world.zonal, world.tesseral, world.third_body)
    ephem = build_table(world.epoch_utc, 0.0, world.duration_s, EPHEMERIS_STEP_S)
    switches = np.zeros(dynamics.N_SWITCHES)
    switches[dynamics.SW_SRP] = world.srp
    switches[dynamics.SW_GRAVITY_GRADIENT] = world.gravity_gradient
    switches[dynamics.SW_ENGINE_TORQUE] = world.engine_torque
    return dynamics.DynamicsParams(wheels, mass, srp, thr, eng, grav, ephem, switches)


def make_free_body_params(inertia_B, wheels, epoch_utc: datetime, duration_s: float = 3600.0,
                          zonal: bool = False) -> dynamics.DynamicsParams:
    """A body in orbit with wheels and nothing else: constant mass, no surface,
    no thrusters, point-mass gravity (plus J2-J4 if `zonal`), no disturbance
    torque. For physics checks of the integrator against closed forms."""
    mass = make_mass_params(1000.0, 0.0, inertia_B, inertia_B, np.zeros(3), np.zeros(3))
    srp = SrpParams(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0))
    thr = ThrusterParams(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0), 0.05)
    eng = EngineParams(np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.0, 300.0)
    grav = make_gravity_params(epoch_utc, zonal, False, False)
    ephem = build_table(epoch_utc, 0.0, duration_s, EPHEMERIS_STEP_S)
    return dynamics.DynamicsParams(wheels, mass, srp, thr, eng, grav, ephem, np.zeros(dynamics.N_SWITCHES))


def make_sensor_params(sc: Spacecraft) -> SensorParams:
    dt = sc.timing.control_dt_s
    ss = sc.sensors
    st = star_tracker.StarTrackerParams(
        np.array([t.q_BS for t in sc.star_trackers], float),
        np.array([[t.noise_transverse_arcsec_3sigma, t.noise_transverse_arcsec_3sigma,
                   t.noise_boresight_arcsec_3sigma] for t in sc.star_trackers]) / 3.0 * ARCSEC)
    tach_pulses = ss.tachometers.pulses_per_rev if ss.tachometers else 1
    return SensorParams(
        iru_units.make_iru_units_params(**ss.iru_units.model_dump(exclude={"bias_deg_h"}), dt=dt),
        star_tracker_exclusion.make_star_tracker_exclusion_params(st, **ss.star_tracker_exclusion.model_dump()),
        css.make_css_params(**ss.css.model_dump()) if ss.css else sensor_suite.ABSENT_CSS,
        dss.make_dss_params(**ss.dss.model_dump()) if ss.dss else sensor_suite.ABSENT_DSS,
        (guide_telescope.make_guide_telescope_params(**ss.guide_telescopes.model_dump()) if ss.guide_telescopes
         else sensor_suite.ABSENT_GT),
        tachometer.make_tachometer_params(tach_pulses, dt=dt),
        np.array([float(ss.dss is not None), float(ss.tachometers is not None)]))


def make_truth_params(sc: Spacecraft, world: World) -> plant.TruthParams:
    substeps = int(round(sc.timing.control_dt_s / sc.timing.truth_dt_s))
    return plant.TruthParams(make_dynamics_params(sc, world), make_sensor_params(sc), sc.timing.truth_dt_s, substeps)


def make_truth_state(sc: Spacecraft, p: plant.TruthParams, q_BN, omega_BN_B, h_wheels, r_N_m, v_N_m_s,
                     propellant_kg) -> plant.TruthState:
    x = dynamics.initial_state(q_BN, omega_BN_B, h_wheels, r_N_m, v_N_m_s, propellant_kg)
    w = p.dyn.wheels
    bias = np.radians(np.array(sc.sensors.iru_units.bias_deg_h)) / 3600.0
    omega = np.asarray(omega_BN_B, float)
    speeds = np.asarray(h_wheels, float) / w.spin_inertia - w.axes_B @ omega
    sensors = SensorStates(iru_units.iru_units_initial_state(bias, np.zeros(3), omega, p.sensors.iru),
                           tachometer.tachometer_initial_state(speeds))
    return plant.make_truth_state(x, sensors, p.sensors, sc.n_wheels, len(sc.thrusters.units))
