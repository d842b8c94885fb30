"""Every physical constant of the core, named once with its unit and source.

Units inside the core are the report's: feet, slugs, seconds, pounds; angles in radians inside kernels,
degrees at the edges.
"""

import math
from dataclasses import dataclass

# --- Earth, AFWAL-TR-82-3036 Appendix A (eq. A10 constants) -------------------------------------
MU_EARTH_FT3_S2 = 1.407698e16  # App. A, universal gravity constant times earth mass
RADIUS_EQUATORIAL_FT = 20_925_631.0  # App. A, R_e
J_ZONAL = 1623.41e-6  # App. A, J (= 1.5 J2)
H_ZONAL = 6.04e-6  # App. A, H (= 2.5 J3 in the report's sign convention)
K_ZONAL = 6.37e-6  # App. A, K (= -3.75 J4)
# App. A prints R_p = 20,885,965 ft, a flattening of 1/527 that no earth model has. One digit read 8 for 5
# gives 20,855,965 ft (f = 1/300.4), which we use; the printed value stays available as a planet override.
RADIUS_POLAR_FT = 20_855_965.0
RADIUS_POLAR_AS_PRINTED_FT = 20_885_965.0
OMEGA_EARTH_DEG_S = 0.004178  # Section IV.3, omega_p
OMEGA_EARTH_RAD_S = math.radians(OMEGA_EARTH_DEG_S)

# --- The earths orbits are propagated in ------------------------------------------------------------------------


@dataclass(frozen=True)
class Earth:
    """An earth an orbit belongs to, named for its source: its gravity (the point mass and the zonal harmonics J2-J4,
    unnormalized, of U = mu/r [1 - sum J_n (R/r)^n P_n(sin phi)]) and its rotation."""

    name: str
    mu_km3_s2: float
    radius_km: float  # equatorial: the harmonics' reference radius
    j2: float
    j3: float
    j4: float
    rotation_rad_s: float

    @property
    def mu_ft3_s2(self) -> float:
        return self.mu_km3_s2 * (1000.0 * FT_PER_M) ** 3

    @property
    def radius_ft(self) -> float:
        return self.radius_km * 1000.0 * FT_PER_M


# SGP4's earth, the constants its mean elements are fitted with: WGS-72 as `sgp4` has it (earth_gravity.wgs72,
# getgravconst('wgs72'): AIAA 2006-6753 sec. IV-A); its rotation the rate sgp4's deep-space code uses (rptim,
# 4.37526908801129966e-3 rad/min)
WGS72 = Earth("WGS-72", 398_600.8, 6_378.135, 0.001082616, -0.00000253881, -0.00000165597, 7.29211514668855e-5)
# A given state vector's earth: WGS-84 (NIMA TR8350.2, 3rd ed., table 3.1: GM, a, omega) with EGM96's zonal harmonics
# (its coefficient file's normalized C20, C30, C40: -0.484165371736e-3, 0.957254173792e-6, 0.539873863789e-6;
# J_n = -sqrt(2n + 1) C_n0)
WGS84 = Earth("WGS-84", 398_600.4418, 6_378.137, 1.0826266835531513e-3, -2.5326564853e-6, -1.6196215914e-6, 7.292115e-5)
MOON_DISTANCE_KM = 384_400.0  # the Moon's mean distance, its orbit's semi-major axis (NASA's Moon fact sheet)

# --- Sea level and unit conversions --------------------------------------------------------------
G0_FT_S2 = 32.174048556430446  # 9.80665 m/s^2 standard gravity (defines the geopotential foot)
FT_PER_M = 1.0 / 0.3048  # international foot
FT_PER_NMI = 1852.0 / 0.3048  # 6076.115 ft
# R' of eqs. (8)-(11), "the average radius of the earth": the report gives no value. We use the
# IUGG mean radius 6,371,008.8 m = 20,902,259 ft (3,440.07 nmi); it is a parameter of ranges.
MEAN_RADIUS_FT = 6_371_008.8 * FT_PER_M

# --- Air ------------------------------------------------------------------------------------------
GAMMA_AIR = 1.4
R_AIR_FT2_S2_R = 287.0429 * FT_PER_M**2 / 1.8  # 287.0429 J/(kg K) (ardc1959.md: p0/(rho0 T0)) = 1716.50 ft^2/(s^2 degR)
