"""Earth's shadow and the apparent Sun, as seen from the spacecraft (truth side).

Lit fraction: conical shadow with umbra and penumbra (Montenbruck & Gill,
"Satellite Orbits", 2000, sec. 3.4.2, pp. 80-81). Seen from the
spacecraft, the Sun and the Earth are disks of apparent radii
    a = asin(R_sun / |r_sun - r|),   b = asin(R_earth / |r|)
whose centres are c apart. The visible part of the solar disk is
    1                       if c >= a + b          (full Sun)
    0                       if c <= b - a          (umbra)
    1 - b^2 / a^2           if c <= a - b          (annular; never near the Earth)
    1 - A / (pi a^2)        otherwise (penumbra), A the overlap of the disks,
    A = a^2 acos(x/a) + b^2 acos((c - x)/b) - c y,
    x = (c^2 + a^2 - b^2) / (2 c),  y = sqrt(a^2 - x^2).
The disks are treated as plane circles (M&G do the same) and the Earth as a
sphere of equatorial radius without atmosphere: refraction and the 21 km
polar flattening move the shadow edges by a few seconds of eclipse.

Apparent Sun: stellar aberration to first order in v/c (Urban & Seidelmann,
"Explanatory Supplement to the Astronomical Almanac", 3rd ed., 2013, expr.
7.40, kept to first order; ERFA eraAb evaluates the full expression):
    u' = (u + beta - (u . beta) u) / |...|,   beta = v_obs / c,
with v_obs the observer's velocity relative to the solar-system barycentre
(the Earth's plus the spacecraft's geocentric velocity). Light time is left
out: the Sun moves ~13 m/s about the barycentre, 6.5 km in 500 s, 0.01 arcsec.
"""
import math

from numba import njit

from sim.constants import C_LIGHT_M_S, WGS84_A_M

R_EARTH_M = WGS84_A_M    # WGS84 equatorial radius
R_SUN_M = 6.96e8         # M&G sec. 3.4.2 (IAU 2015 nominal: 6.957e8)


@njit(cache=True)
def _disk_overlap_visible(a, b, c):
    """Visible fraction of a disk of radius a partly covered by a disk of
    radius b whose centre is c away (all in radians on the sky)."""
    if c >= a + b:
        return 1.0
    if c <= b - a:
        return 0.0
    if c <= a - b:
        return 1.0 - (b * b) / (a * a)
    x = (c * c + a * a - b * b) / (2.0 * c)
    y = math.sqrt(max(a * a - x * x, 0.0))
    ca = min(max(x / a, -1.0), 1.0)
    cb = min(max((c - x) / b, -1.0), 1.0)
    area = a * a * math.acos(ca) + b * b * math.acos(cb) - c * y
    return 1.0 - area / (math.pi * a * a)


@njit(cache=True)
def lit_fraction(r_sc_N_m, r_sun_N_m):
    """Fraction of the solar disk visible from the spacecraft, in [0, 1].
    Both positions geocentric, same axes, m."""
    rx, ry, rz = r_sc_N_m[0], r_sc_N_m[1], r_sc_N_m[2]
    dx, dy, dz = r_sun_N_m[0] - rx, r_sun_N_m[1] - ry, r_sun_N_m[2] - rz  # spacecraft -> Sun
    r = math.sqrt(rx * rx + ry * ry + rz * rz)
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    if r <= R_EARTH_M:
        return 0.0
    a = math.asin(R_SUN_M / d)
    b = math.asin(R_EARTH_M / r)
    # angle between the directions to the Earth's centre (-r) and to the Sun (d);
    # atan2 of |cross| and dot keeps full precision near 0 and pi, where acos does not
    cx, cy, cz = ry * dz - rz * dy, rz * dx - rx * dz, rx * dy - ry * dx
    c = math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), -(rx * dx + ry * dy + rz * dz))
    return _disk_overlap_visible(a, b, c)


@njit(cache=True)
def sun_vector_apparent_N(r_sc_N_m, v_sc_N_m_s, r_sun_N_m, v_earth_bary_N_m_s):
    """Unit vector from the spacecraft to the apparent Sun (aberration by the
    spacecraft's barycentric velocity, first order in v/c), GCI."""
    u = r_sun_N_m - r_sc_N_m
    u = u / math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    beta = (v_earth_bary_N_m_s + v_sc_N_m_s) / C_LIGHT_M_S
    p = u + beta - (u[0] * beta[0] + u[1] * beta[1] + u[2] * beta[2]) * u
    return p / math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
