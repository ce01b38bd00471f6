"""The truth environment: Sun/Moon ephemeris table, Earth rotation angle,
Earth's shadow, aberration of the Sun, SRP. Every expectation comes from
outside the code: ERFA called directly, published constants, closed-form
geometry, the SDO mission's eclipse figures."""
import math
from datetime import UTC, datetime, timedelta

import erfa
import numpy as np
import pytest

from sim.truth import eclipse, ephemeris, gravity, orbit

EPOCH = datetime(2026, 3, 20, 12, 0, 0, tzinfo=UTC)   # = sim.scenario.DEFAULT_EPOCH
ARCSEC = math.pi / 180.0 / 3600.0


@pytest.fixture(scope="module")
def table():
    return ephemeris.build_table(EPOCH, 0.0, 3 * 86400.0, step_s=600.0)


def _erfa_direct(t_s):
    """Sun, Moon, Earth barycentric velocity straight from ERFA at t_s after EPOCH."""
    tt1, tt2 = ephemeris.tt_jd(EPOCH)
    pvh, pvb = erfa.epv00(tt1, tt2 + t_s / 86400.0)
    moon = erfa.moon98(tt1, tt2 + t_s / 86400.0)
    au, au_d = erfa.DAU, erfa.DAU / 86400.0
    return -pvh["p"] * au, moon["p"] * au, pvb["v"] * au_d


def test_table_interpolation_matches_erfa_off_node(table):
    # Off-node times (mid-step and odd fractions), 600 s step. Measured:
    # Sun < 0.01 m, Moon < 0.2 m (moon98's velocity omits a < 3 mm/s
    # precession coupling, ERFA note 7), Earth velocity < 1e-4 m/s.
    rng = np.random.default_rng(1)
    times = np.concatenate([[300.0, 86400.0 + 299.0], rng.uniform(0.0, 3 * 86400.0, 40)])
    err_sun = err_moon = err_v = 0.0
    for t in times:
        sun, moon, v_bary = _erfa_direct(t)
        err_sun = max(err_sun, np.linalg.norm(ephemeris.sun_position_N(table, t) - sun))
        err_moon = max(err_moon, np.linalg.norm(ephemeris.moon_position_N(table, t) - moon))
        err_v = max(err_v, np.linalg.norm(ephemeris.earth_velocity_bary_N(table, t) - v_bary))
    assert err_sun < 1.0      # brief: < 1 m for the Sun at a 600 s step
    assert err_moon < 1.0     # brief: < 1 m for the Moon
    assert err_v < 1e-3       # 1e-3 m/s is 3e-12 rad of aberration


def test_table_raises_outside_its_span(table):
    last = table.t0_s + (table.sun_N_m.shape[0] - 1) * table.step_s
    ephemeris.sun_position_N(table, last)          # the end node itself is inside
    for t in (table.t0_s - 1.0, last + 1.0, float("nan")):
        with pytest.raises(ValueError):
            ephemeris.sun_position_N(table, t)
    with pytest.raises(ValueError):
        ephemeris.build_table(EPOCH, 10.0, 0.0)


def test_sun_distance_over_a_year_spans_perihelion_to_aphelion():
    # NASA Earth fact sheet: perihelion 147.095e6 km, aphelion 152.100e6 km.
    year = ephemeris.build_table(datetime(2026, 1, 1, tzinfo=UTC), 0.0, 366 * 86400.0, step_s=86400.0)
    d = np.linalg.norm(year.sun_N_m, axis=1)
    assert 1.4700e11 < d.min() < 1.4720e11
    assert 1.5200e11 < d.max() < 1.5220e11
    # the Moon stays between perigee and apogee: 356 400 .. 406 700 km (NASA Moon fact sheet, extremes)
    m = np.linalg.norm(year.moon_N_m, axis=1)
    assert 3.56e8 < m.min() and m.max() < 4.07e8


def test_earth_rotation_angle_matches_iers_formula():
    # IERS Conventions (2010) eq. 5.15, Tu = JD(UT1) - 2451545.0, with UT1 = UTC.
    t_s = 5000.0
    era, rate = ephemeris.earth_rotation_angle(EPOCH, t_s)
    jd = 2451545.0 + (EPOCH + timedelta(seconds=t_s) - datetime(2000, 1, 1, 12, tzinfo=UTC)).total_seconds() / 86400.0
    tu = jd - 2451545.0
    expected = (2.0 * math.pi * (0.7790572732640 + 1.00273781191135448 * tu)) % (2.0 * math.pi)
    assert abs((era - expected + math.pi) % (2 * math.pi) - math.pi) < 1e-9   # 0.2 mas
    assert rate == pytest.approx(7.2921150e-5, rel=1e-7)   # IERS: omega = 7.292115e-5 rad/s


# ---- Earth's shadow -------------------------------------------------------

def _cone_radii(d_sun_m, x_m):
    """Radii of the umbra and penumbra cones at x_m behind the Earth's centre,
    by similar triangles on the common tangents of the Sun and Earth spheres."""
    rs, re = eclipse.R_SUN_M, eclipse.R_EARTH_M
    l_u = d_sun_m * re / (rs - re)          # umbra vertex, behind the Earth
    l_p = d_sun_m * re / (rs + re)          # penumbra vertex, toward the Sun
    rho_u = (l_u - x_m) * math.tan(math.asin(re / l_u))
    rho_p = (l_p + x_m) * math.tan(math.asin(re / l_p))
    return rho_u, rho_p


def test_lit_fraction_against_shadow_cones(table):
    sun = ephemeris.sun_position_N(table, 0.0)
    s_hat = sun / np.linalg.norm(sun)
    perp = np.cross(s_hat, [0.0, 0.0, 1.0])
    perp /= np.linalg.norm(perp)
    assert eclipse.lit_fraction(42164e3 * s_hat, sun) == 1.0                     # day side
    for x in (7000e3, 42164e3, 400000e3):
        rho_u, rho_p = _cone_radii(np.linalg.norm(sun), x)
        def at(rho, x=x):
            return eclipse.lit_fraction(-x * s_hat + rho * perp, sun)
        assert at(0.0) == 0.0                      # on the shadow axis: umbra
        assert at(rho_u - 10.0) == 0.0             # 10 m inside the umbra cone
        assert 0.0 < at(rho_u + 10.0) < 1e-3       # 10 m outside it: a sliver of Sun
        assert 0.999 < at(rho_p - 10.0) < 1.0      # 10 m inside the penumbra cone
        assert at(rho_p + 10.0) == 1.0             # 10 m outside: full Sun
        assert 0.0 < at(0.5 * (rho_u + rho_p)) < 1.0


def test_lit_fraction_against_numerical_disk_overlap(table):
    # Independent area: count a 600 x 600 grid over the solar disk (tangent-plane
    # angles seen from the spacecraft) that lies outside the Earth's disk.
    sun = ephemeris.sun_position_N(table, 0.0)
    s_hat = sun / np.linalg.norm(sun)
    e1 = np.cross(s_hat, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    x = 42164e3
    rho_u, rho_p = _cone_radii(np.linalg.norm(sun), x)
    g = np.linspace(-1.0, 1.0, 600)
    gx, gy = np.meshgrid(g, g)
    inside_sun = gx ** 2 + gy ** 2 <= 1.0
    for f in (0.1, 0.3, 0.5, 0.7, 0.9):
        r_sc = -x * s_hat + (rho_u + f * (rho_p - rho_u)) * e1
        d = sun - r_sc
        a = math.asin(eclipse.R_SUN_M / np.linalg.norm(d))
        b = math.asin(eclipse.R_EARTH_M / np.linalg.norm(r_sc))
        c = math.acos(np.dot(-r_sc, d) / np.linalg.norm(r_sc) / np.linalg.norm(d))
        covered = (gx * a - c) ** 2 + (gy * a) ** 2 <= b * b   # Earth's centre at (c, 0)
        expected = (inside_sun & ~covered).sum() / inside_sun.sum()
        assert eclipse.lit_fraction(r_sc, sun) == pytest.approx(expected, abs=1e-3)   # measured 1.4e-4


def _daily_eclipse_minutes(start, days, dt_s=30.0):
    """Propagate SDO (full truth gravity, RK4) and return minutes per UTC day
    with any part of the Sun hidden (lit fraction < 1)."""
    tab = ephemeris.build_table(start, 0.0, days * 86400.0, step_s=1800.0)  # Moon still < 0.5 m
    g = gravity.make_gravity_params(start)
    r, v = orbit.sdo_orbit(start).to_rv()
    n = round(days * 86400.0 / dt_s)
    xs = orbit.propagate_orbit(np.concatenate([r, v]), 0.0, dt_s, n, g, tab, np.zeros(3))
    t = np.arange(n + 1) * dt_s
    # Coarse hourly Sun straight from ERFA, only to pick the steps near the shadow
    # (epv00 costs ~60 us a call); the lit fraction itself uses the table's Sun.
    tt1, tt2 = ephemeris.tt_jd(start)
    t_hour = np.arange(0.0, t[-1] + 3600.0, 3600.0)
    sun_h = -erfa.epv00(tt1, tt2 + t_hour / 86400.0)[0]["p"]
    s_hat = np.stack([np.interp(t, t_hour, sun_h[:, j]) for j in range(3)], axis=1)
    s_hat /= np.linalg.norm(s_hat, axis=1)[:, None]
    along = np.einsum("ij,ij->i", xs[:, :3], s_hat)
    off_axis = np.linalg.norm(xs[:, :3] - along[:, None] * s_hat, axis=1)
    lit = np.ones(n + 1)
    for k in np.nonzero((along < 0.0) & (off_axis < 8.0e6))[0]:      # the shadow is < 6.6e6 m wide
        lit[k] = eclipse.lit_fraction(xs[k, :3], ephemeris.sun_position_N(tab, t[k]))
    per_day = round(86400.0 / dt_s)
    return np.array([(lit[d * per_day:(d + 1) * per_day] < 1.0).sum() * dt_s / 60.0 for d in range(days)])


def test_sdo_eclipse_season_at_equinox_and_none_at_solstice():
    start = datetime(2026, 3, 1, tzinfo=UTC)
    minutes = _daily_eclipse_minutes(start, 113)          # to 2026-06-22
    # Issue: "SDO sees eclipse seasons of up to about 72 min a day around the
    # equinoxes". Closed form for a circular orbit crossing the shadow axis:
    # 2 (asin(R_e / a) + R_sun / 1 AU) / (2 pi) * sidereal day = 71.6 min.
    peak_day = int(np.argmax(minutes))
    assert 70.0 <= minutes.max() <= 74.0
    assert abs((start + timedelta(days=peak_day)).date() - datetime(2026, 3, 20).date()) <= timedelta(days=2)
    # Season length: the Sun leaves the orbit plane at sin(i + obliquity) * 0.9856 deg/day
    # = 0.78 deg/day and eclipses stop beyond asin(R_e / a) + R_sun / 1 AU = 8.97 deg:
    # 2 * 8.97 / 0.78 = 23 days.
    season = np.nonzero(minutes > 0.0)[0]
    assert 20 <= len(season) <= 25 and season.max() - season.min() + 1 == len(season)
    # June solstice (2026-06-21): no eclipse at all, nor anywhere from May on.
    solstice_day = (datetime(2026, 6, 21, tzinfo=UTC) - start).days
    assert minutes[solstice_day] == 0.0
    assert minutes[61:].max() == 0.0


# ---- aberration and SRP -----------------------------------------------------

def test_apparent_sun_shows_annual_aberration(table):
    # IAU (1976) constant of aberration: 20.49552 arcsec; the actual angle varies by
    # +-0.35 arcsec with the Earth's orbital speed (e = 0.0167).
    t = 7200.0
    sun = ephemeris.sun_position_N(table, t)
    v_bary = ephemeris.earth_velocity_bary_N(table, t)
    r_sc = np.array([42164e3, 0.0, 0.0])
    app = eclipse.sun_vector_apparent_N(r_sc, np.zeros(3), sun, v_bary)
    geo = (sun - r_sc) / np.linalg.norm(sun - r_sc)
    angle = math.atan2(np.linalg.norm(np.cross(geo, app)), np.dot(geo, app)) / ARCSEC
    assert 20.1 < angle < 20.9
    # and ERFA's full (relativistic) aberration, eraAb, agrees to 1 mas
    beta = v_bary / erfa.CMPS
    full = erfa.ab(geo, beta, np.linalg.norm(sun - r_sc) / erfa.DAU, math.sqrt(1.0 - beta @ beta))
    assert np.linalg.norm(np.cross(full, app)) / ARCSEC < 1e-3    # measured 0.02 mas
    # the apparent Sun leans toward the direction of motion
    assert np.dot(app - geo, v_bary) > 0.0


def test_srp_cannonball(table):
    # P = Phi / c with the total solar irradiance 1361 W/m^2 (Kopp & Lean 2011):
    # 4.54e-6 N/m^2; M&G's 4.56e-6 uses 1367 W/m^2.
    assert gravity.P_SUN_1AU_N_M2 == pytest.approx(1361.0 / 299792458.0, rel=0.006)
    sun = ephemeris.sun_position_N(table, 0.0)
    r = np.array([0.0, 42164e3, 0.0])
    a = gravity.srp_accel_cannonball_N(r, sun, 1.0, 20.0, 3000.0, 1.3)
    d = r - sun
    dist = np.linalg.norm(d)
    # magnitude by hand: P (1 AU / d)^2 C_r A / m, pushed away from the Sun
    assert np.linalg.norm(a) == pytest.approx(4.56e-6 * (erfa.DAU / dist) ** 2 * 1.3 * 20.0 / 3000.0, rel=1e-12)
    assert np.dot(a, d) / np.linalg.norm(a) / dist == pytest.approx(1.0, abs=1e-12)
    half = gravity.srp_accel_cannonball_N(r, sun, 0.5, 20.0, 3000.0, 1.3)
    assert np.allclose(half, 0.5 * a, rtol=0, atol=1e-20)
