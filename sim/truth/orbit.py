"""Orbit of the spacecraft's centre of mass in the truth model: classical
elements <-> state, the orbit derivative, and a fixed-step RK4.

* elements -> state: Vallado, "Fundamentals of Astrodynamics and
  Applications", 4th ed., Algorithm 10 (COE2RV): perifocal position and
  velocity, rotated by R3(-raan) R1(-i) R3(-argp); checked on Example 2-6.
* state -> elements: Vallado Algorithm 9 (RV2COE), angles taken with atan2
  instead of acos so that they keep full precision near 0 and pi; checked on
  Example 2-5.
* derivative: d[r, v]/dt = [v, a_grav(r, t) + a_extra], a_grav from
  sim/truth/gravity.py, a_extra (thrust / mass, SRP) supplied by the caller.
  Allocation-free, so the truth integrator can embed it in its own RK4.

State vectors are 6-arrays [r_N_m, v_N_m_s] in GCI (GCRS axes), SI units.
"""
import math
from datetime import datetime

import numpy as np
from numba import njit
from pydantic import BaseModel, ConfigDict, Field, model_validator

from sim.truth.eclipse import R_EARTH_M
from sim.truth.ephemeris import ERA_RATE_RAD_S, earth_rotation_angle
from sim.truth.gravity import MU_EARTH_M3_S2, gravity_accel3


def elements_to_rv(a_m, e, i_rad, raan_rad, argp_rad, nu_rad, mu=MU_EARTH_M3_S2):
    """Classical elements -> (r_N_m, v_N_m_s)."""
    p = a_m * (1.0 - e * e)
    cn, sn = math.cos(nu_rad), math.sin(nu_rad)
    r_pqw = p / (1.0 + e * cn) * np.array([cn, sn, 0.0])
    v_pqw = math.sqrt(mu / p) * np.array([-sn, e + cn, 0.0])
    cO, sO = math.cos(raan_rad), math.sin(raan_rad)
    ci, si = math.cos(i_rad), math.sin(i_rad)
    cw, sw = math.cos(argp_rad), math.sin(argp_rad)
    # columns: the perifocal P and Q axes in N (R3(-raan) R1(-i) R3(-argp))
    rot = np.array([[cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci],
                    [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci],
                    [sw * si, cw * si]])
    return rot @ r_pqw[:2], rot @ v_pqw[:2]


def _angle(a, b, h_hat):
    """Angle from a to b, measured positive about h_hat, in [0, 2 pi)."""
    return math.atan2(float(np.dot(np.cross(a, b), h_hat)), float(np.dot(a, b))) % (2.0 * math.pi)


def rv_to_elements(r_N_m, v_N_m_s, mu=MU_EARTH_M3_S2, tiny=1e-11):
    """(r, v) -> (a_m, e, i_rad, raan_rad, argp_rad, nu_rad) of an ellipse.
    Circular (e < tiny): argp = 0 and nu is the argument of latitude.
    Equatorial (i < tiny or > pi - tiny): raan = 0, argp measured from +X."""
    r = np.asarray(r_N_m, float)
    v = np.asarray(v_N_m_s, float)
    rn = np.linalg.norm(r)
    h = np.cross(r, v)
    h_hat = h / np.linalg.norm(h)
    e_vec = ((v @ v - mu / rn) * r - (r @ v) * v) / mu
    e = float(np.linalg.norm(e_vec))
    a = 1.0 / (2.0 / rn - (v @ v) / mu)          # vis-viva
    i = math.acos(max(-1.0, min(1.0, h_hat[2])))
    node = np.array([-h[1], h[0], 0.0])           # K x h
    equatorial = np.linalg.norm(node) < tiny * np.linalg.norm(h)
    if equatorial:
        node = np.array([1.0, 0.0, 0.0])
    raan = 0.0 if equatorial else math.atan2(node[1], node[0]) % (2.0 * math.pi)
    if e < tiny:
        return a, e, i, raan, 0.0, _angle(node, r, h_hat)
    return a, e, i, raan, _angle(node, e_vec, h_hat), _angle(e_vec, r, h_hat)


class OrbitElements(BaseModel):
    """Osculating classical elements at the scenario epoch, GCI (GCRS axes)."""
    model_config = ConfigDict(extra="forbid", frozen=True)

    a_km: float = Field(gt=0.0)
    e: float = Field(ge=0.0, lt=1.0)
    i_deg: float = Field(ge=0.0, le=180.0)
    raan_deg: float = Field(ge=-360.0, le=360.0)
    argp_deg: float = Field(ge=-360.0, le=360.0)
    true_anomaly_deg: float = Field(ge=-360.0, le=360.0)

    @model_validator(mode="after")
    def _perigee_above_ground(self):
        perigee_km = self.a_km * (1.0 - self.e)
        if perigee_km <= R_EARTH_M / 1e3:
            raise ValueError(f"a_km * (1 - e) = {perigee_km:.1f} km: the perigee must be above the Earth's "
                             f"equatorial radius {R_EARTH_M / 1e3:.3f} km (raise a_km or lower e)")
        return self

    def to_rv(self, mu=MU_EARTH_M3_S2):
        """(r_N_m, v_N_m_s)."""
        d = math.radians
        return elements_to_rv(self.a_km * 1e3, self.e, d(self.i_deg), d(self.raan_deg), d(self.argp_deg),
                              d(self.true_anomaly_deg), mu)


# Geosynchronous radius: mean motion equal to the Earth's rotation rate,
# a = (mu / omega_E^2)^(1/3) = 42164.17 km (Kepler's third law; omega_E from IERS 2010 eq. 5.15).
GEOSYNC_A_KM = (MU_EARTH_M3_S2 / ERA_RATE_RAD_S ** 2) ** (1.0 / 3.0) / 1e3
SDO_LONGITUDE_DEG = -102.0   # assumption: public mission description, figure 8 centred near 102 deg W
SDO_INCLINATION_DEG = 28.5   # assumption: public mission description (inclined geosynchronous)
# RAAN 180 deg: the ascending node points to -X (the Sun at the March equinox
# is at +X, at the September equinox at -X), so the orbit plane contains the
# equinox line and the Earth's shadow (anti-Sun direction) lies in the plane at
# both equinoxes: eclipse seasons centre on them. With the node on -X the orbit
# normal is tilted 28.5 deg toward +Y from the pole while the ecliptic pole
# is tilted 23.4 deg toward -Y, so the two planes are 52 deg apart and the
# solstice Sun is 52 deg out of the orbit plane: no eclipses there. (RAAN 0 would
# put the orbit plane 5 deg from the ecliptic: eclipses most of the year.)
SDO_RAAN_DEG = 180.0


def sdo_orbit(epoch_utc: datetime) -> OrbitElements:
    """SDO's elements at ``epoch_utc``: circular (assumption) geosynchronous,
    argp = 0 so that the true anomaly is the argument of latitude u.

    The waist of the figure 8 is where the track crosses the equator, at the
    nodes (u = 0 or 180 deg), where the right ascension is exactly raan + u and
    the longitude raan + u - ERA. On a synchronous orbit u and ERA advance at
    the same rate, so raan + u - ERA stays at its initial value: choosing
    u0 = longitude + ERA(epoch) - raan centres the figure 8 on SDO_LONGITUDE_DEG
    (to the 0.15 deg by which the J2000 axes differ from the true pole of 2026)."""
    era_rad, _ = earth_rotation_angle(epoch_utc)
    u_deg = (SDO_LONGITUDE_DEG + math.degrees(era_rad) - SDO_RAAN_DEG) % 360.0
    return OrbitElements(a_km=GEOSYNC_A_KM, e=0.0, i_deg=SDO_INCLINATION_DEG, raan_deg=SDO_RAAN_DEG,
                         argp_deg=0.0, true_anomaly_deg=u_deg)


_SDO_EPOCH_UTC = datetime.fromisoformat("2026-03-20T12:00:00+00:00")  # = sim.scenario.DEFAULT_EPOCH
SDO_ORBIT = sdo_orbit(_SDO_EPOCH_UTC)

# Hubble: ~540 km altitude (public HST orbit, 2020s), 28.5 deg inclination (public,
# launch from KSC); near-circular e = 0.0003, raan, argp and anomaly: assumptions.
HST_ORBIT = OrbitElements(a_km=R_EARTH_M / 1e3 + 540.0, e=0.0003, i_deg=28.5, raan_deg=0.0,
                          argp_deg=0.0, true_anomaly_deg=0.0)


@njit(cache=True)
def orbit_derivative(r_N_m, v_N_m_s, t_s, g, ephem, accel_extra_N, out6):
    """d/dt [r, v] = [v, gravity + accel_extra_N] written into out6."""
    ax, ay, az = gravity_accel3(r_N_m[0], r_N_m[1], r_N_m[2], t_s, g, ephem)
    out6[0] = v_N_m_s[0]
    out6[1] = v_N_m_s[1]
    out6[2] = v_N_m_s[2]
    out6[3] = ax + accel_extra_N[0]
    out6[4] = ay + accel_extra_N[1]
    out6[5] = az + accel_extra_N[2]


@njit(cache=True)
def rk4_orbit_step(x6, t_s, dt_s, g, ephem, accel_extra_N, work):
    """One RK4 step of the orbit state x6 = [r, v] in place, accel_extra_N held
    over the step. work: (5, 6) scratch, so that the step allocates nothing."""
    k1, k2, k3, k4, xt = work[0], work[1], work[2], work[3], work[4]
    orbit_derivative(x6[0:3], x6[3:6], t_s, g, ephem, accel_extra_N, k1)
    for i in range(6):
        xt[i] = x6[i] + 0.5 * dt_s * k1[i]
    orbit_derivative(xt[0:3], xt[3:6], t_s + 0.5 * dt_s, g, ephem, accel_extra_N, k2)
    for i in range(6):
        xt[i] = x6[i] + 0.5 * dt_s * k2[i]
    orbit_derivative(xt[0:3], xt[3:6], t_s + 0.5 * dt_s, g, ephem, accel_extra_N, k3)
    for i in range(6):
        xt[i] = x6[i] + dt_s * k3[i]
    orbit_derivative(xt[0:3], xt[3:6], t_s + dt_s, g, ephem, accel_extra_N, k4)
    for i in range(6):
        x6[i] += (dt_s / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True)
def propagate_orbit(x0_6, t0_s, dt_s, n_steps, g, ephem, accel_extra_N):
    """States at t0_s + k dt_s, k = 0..n_steps, as an (n_steps + 1, 6) array
    (for standalone use and tests; the truth integrator embeds the derivative)."""
    out = np.empty((n_steps + 1, 6))
    x = x0_6.copy()
    work = np.empty((5, 6))
    out[0] = x
    for k in range(n_steps):
        rk4_orbit_step(x, t0_s + k * dt_s, dt_s, g, ephem, accel_extra_N, work)
        out[k + 1] = x
    return out
