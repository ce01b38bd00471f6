"""Environmental disturbance torques on the truth side.

Solar radiation pressure on a faceted model (flat plates), Montenbruck & Gill,
"Satellite Orbits" (2000), eq. 3.75 and Wertz (ed.), "Spacecraft Attitude
Determination and Control" (1978), sec. 17.2: for a plate of area A, unit
normal n and Sun unit vector s (spacecraft to Sun) with cos(theta) = n.s > 0,

    F = -P A cos(theta) [ (1 - rho_s) s + 2 (rho_s cos(theta) + rho_d / 3) n ]

with P the solar pressure at the spacecraft; the torque about the centre of
mass is the sum of (r_facet - r_cm) x F. Facets do not shadow one another
(an assumption). Zero in umbra, scaled by the lit fraction in penumbra.

Gravity gradient, Wertz eq. 17-38 / Markley & Crassidis eq. 3.155:
    tau = 3 mu / |r|^5 (r_B x J r_B)
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.linalg import cross, matvec

SOLAR_PRESSURE_1AU_N_m2 = 4.56e-6  # Montenbruck & Gill (2000) eq. 3.69: 1367 W/m^2 / c
AU_m = 1.495978707e11              # IAU 2012 Resolution B2


class SrpParams(NamedTuple):
    area_m2: np.ndarray        # (n,)
    normal_B: np.ndarray       # (n, 3) outward unit normals
    centroid_B: np.ndarray     # (n, 3) in the structure frame, m
    rho_specular: np.ndarray   # (n,)
    rho_diffuse: np.ndarray    # (n,)


@njit(cache=True)
def srp_force_torque_B(sun_B, sun_distance_m, lit_fraction, cm_B, p):
    """(force_B N, torque_B N m about the centre of mass)."""
    force = np.zeros(3)
    torque = np.zeros(3)
    if lit_fraction <= 0.0:
        return force, torque
    pressure = SOLAR_PRESSURE_1AU_N_m2 * (AU_m / sun_distance_m) ** 2 * lit_fraction
    for k in range(p.area_m2.shape[0]):
        n = p.normal_B[k]
        c = n[0] * sun_B[0] + n[1] * sun_B[1] + n[2] * sun_B[2]
        if c <= 0.0:
            continue
        a = -pressure * p.area_m2[k] * c
        ks = a * (1.0 - p.rho_specular[k])
        kn = a * 2.0 * (p.rho_specular[k] * c + p.rho_diffuse[k] / 3.0)
        # scalar accumulation: this runs per facet per RK4 step
        f0, f1, f2 = ks * sun_B[0] + kn * n[0], ks * sun_B[1] + kn * n[1], ks * sun_B[2] + kn * n[2]
        r0, r1, r2 = p.centroid_B[k, 0] - cm_B[0], p.centroid_B[k, 1] - cm_B[1], p.centroid_B[k, 2] - cm_B[2]
        force[0] += f0
        force[1] += f1
        force[2] += f2
        torque[0] += r1 * f2 - r2 * f1
        torque[1] += r2 * f0 - r0 * f2
        torque[2] += r0 * f1 - r1 * f0
    return force, torque


@njit(cache=True)
def gravity_gradient_torque_B(r_B_m, inertia_B, mu_m3_s2):
    r2 = r_B_m[0] * r_B_m[0] + r_B_m[1] * r_B_m[1] + r_B_m[2] * r_B_m[2]
    k = 3.0 * mu_m3_s2 / (r2 * r2 * np.sqrt(r2))
    return k * cross(r_B_m, matvec(inertia_B, r_B_m))
