"""Published constants that both the truth model and the flight software use.
Each side keeps its own models (the wall: sim/fsw never imports sim/truth);
a number taken from a standard is written once, here.
"""
import math

ARCSEC_RAD = math.pi / (180.0 * 3600.0)   # rad per arcsec
C_LIGHT_M_S = 299792458.0                 # exact (SI)
AU_M = 149597870700.0                     # IAU 2012 Resolution B2
G0_M_S2 = 9.80665                         # standard gravity (3rd CGPM, 1901): defines Isp in seconds
LBF_N = 4.4482216152605                   # pound-force in newtons (NIST SP 811, Appendix B.8)

# WGS84 (NIMA TR8350.2, 3rd ed., Table 3.1 / 3.3): GM including the atmosphere,
# the ellipsoid's equatorial radius and flattening.
MU_EARTH_M3_S2 = 3.986004418e14
WGS84_A_M = 6378137.0
WGS84_INV_F = 298.257223563

# EGM2008 (Pavlis et al. 2012, JGR 117, B04406) reference radius and fully
# normalised, tide-free coefficients (NGA EGM2008 coefficient file). They are
# scaled to GM = 3.986004415e14; using WGS84's GM instead rescales them by
# 7.5e-10, which is negligible.
R_EQ_EGM2008_M = 6378136.3
_C20N, _C30N, _C40N = -0.484165143790815e-3, 0.957161207093473e-6, 0.539965866638991e-6
_C22N, _S22N = 0.243938357328313e-5, -0.140027370385934e-5
# Unnormalised: C_nm = N_nm Cbar_nm, N_nm = sqrt((2 - delta_0m)(2n + 1)(n - m)!/(n + m)!)
# (Montenbruck & Gill, "Satellite Orbits", 2000, sec. 3.2); J_n = -C_n0.
J2 = -_C20N * math.sqrt(5.0)          # 1.0826262e-3
J3 = -_C30N * math.sqrt(7.0)          # -2.5324105e-6
J4 = -_C40N * 3.0                     # -1.6198976e-6
C22 = _C22N * math.sqrt(10.0 / 24.0)  # 1.5746153e-6
S22 = _S22N * math.sqrt(10.0 / 24.0)  # -9.0387279e-7

# IERS Conventions (2010), Table 1.1: GM_sun (TDB-compatible) and the Moon/Earth mass ratio.
MU_SUN_M3_S2 = 1.32712442099e20
MU_MOON_M3_S2 = 0.0123000371 * MU_EARTH_M3_S2   # 4.90280e12
P_SUN_1AU_N_M2 = 4.56e-6  # M&G eq. 3.69: P = Phi/c, Phi ~ 1367 W/m^2 at 1 AU
