"""On-board time scales: UTC from the spacecraft clock, TT and UT1 from UTC.

The flight software knows UTC as seconds of sim time ``t_s`` since an epoch
given as a Julian Date (UTC). It never calls ERFA; the two offsets it needs
are uploaded parameters:

* TT = TAI + 32.184 s (IAU 1991 Resolution A4; IERS Conventions 2010, sec.
  10.1), TAI = UTC + (TAI - UTC), the leap-second count (37 s since
  2017-01-01, IERS Bulletin C). A leap second inside a run leaves the count
  off by 1 s: the Sun then moves 0.04 arcsec, the Moon 0.5 arcsec.
* UT1 = UTC + DUT1, |DUT1| < 0.9 s by the definition of UTC; 0 is "UT1 ~ UTC"
  (the truth model makes the same choice, sim/truth/ephemeris.py).

Dates are kept as days since J2000.0 (JD 2451545.0) rather than as full
Julian Dates: a double then resolves 2e-12 day (0.2 us) instead of 40 us.
TDB - TT (periodic, < 2 ms; ERFA eraDtdb) is neglected: the solar series are
evaluated at TT.
"""
from typing import NamedTuple

from numba import njit

DAY_S = 86400.0
JD_J2000 = 2451545.0
TT_MINUS_TAI_S = 32.184
DAYS_PER_JULIAN_CENTURY = 36525.0


class OnboardClock(NamedTuple):
    epoch_utc_days_j2000: float   # UTC (quasi-)JD of t_s = 0, minus 2451545.0
    tai_minus_utc_s: float        # uploaded leap-second count, s
    ut1_minus_utc_s: float        # uploaded DUT1, s (0: UT1 ~ UTC)


def make_clock(epoch_jd_utc: float, tai_minus_utc_s: float, ut1_minus_utc_s: float = 0.0,
               epoch_jd_utc_2: float = 0.0) -> OnboardClock:
    """The clock record from an epoch JD (UTC), optionally in two parts
    (``epoch_jd_utc + epoch_jd_utc_2``, ERFA's convention) for full resolution."""
    if not abs(ut1_minus_utc_s) < 0.9:
        raise ValueError(f"ut1_minus_utc_s = {ut1_minus_utc_s}: |UT1 - UTC| is below 0.9 s by definition of UTC")
    if not 0.0 <= tai_minus_utc_s <= 100.0:
        raise ValueError(f"tai_minus_utc_s = {tai_minus_utc_s}: the leap-second count is 10..37 s since 1972")
    return OnboardClock(float((epoch_jd_utc - JD_J2000) + epoch_jd_utc_2), float(tai_minus_utc_s),
                        float(ut1_minus_utc_s))


@njit(cache=True)
def tt_days_j2000(clock, t_s):
    """TT days since J2000.0 at sim time t_s."""
    return clock.epoch_utc_days_j2000 + (t_s + clock.tai_minus_utc_s + TT_MINUS_TAI_S) / DAY_S


@njit(cache=True)
def tt_centuries_j2000(clock, t_s):
    """TT Julian centuries since J2000.0 (the T of Meeus and of the AA)."""
    return tt_days_j2000(clock, t_s) / DAYS_PER_JULIAN_CENTURY


@njit(cache=True)
def ut1_days_j2000(clock, t_s):
    """UT1 days since J2000.0 (the Tu of IERS Conventions 2010, eq. 5.15)."""
    return clock.epoch_utc_days_j2000 + (t_s + clock.ut1_minus_utc_s) / DAY_S
