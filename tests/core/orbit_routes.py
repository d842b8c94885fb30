"""Independent routes for orbits and coasts (issue 52 item 1), written apart from the package: the constants typed from
their published sources, the point mass and zonal harmonics written out from their potential, a TEME (inertial)
propagation by scipy's DOP853 at rtol 1e-12, the interface found on the report's ellipsoid by a geodetic altitude of
its own, the earth's turning from skyfield's GMST and SGP4's states from `sgp4` itself. tests/core/test_orbit_earths.py
checks the acceleration against the potential."""

import math
from datetime import datetime

import numpy as np
from scipy.integrate import solve_ivp

FT_PER_KM = 1000.0 / 0.3048  # the international foot
# WGS-72 as SGP4 has it: Vallado et al., AIAA 2006-6753 sec. IV-A, `sgp4`'s getgravconst('wgs72')
WGS72 = {"mu_km3_s2": 398_600.8, "radius_km": 6_378.135, "j2": 0.001082616, "j3": -0.00000253881, "j4": -0.00000165597}
# WGS-84 (NIMA TR8350.2 table 3.1) with EGM96's zonals: J_n = -sqrt(2n+1) C_n0, C20 -0.484165371736e-3, C30
# 0.957254173792e-6, C40 0.539873863789e-6 (the EGM96 coefficient file)
WGS84 = {
    "mu_km3_s2": 398_600.4418,
    "radius_km": 6_378.137,
    "j2": math.sqrt(5) * 0.484165371736e-3,
    "j3": -math.sqrt(7) * 0.957254173792e-6,
    "j4": -3.0 * 0.539873863789e-6,
}
# the report's ellipsoid (AFWAL-TR-82-3036 App. A: R_e; R_p as printed, 20,885,965 ft, has one digit read 8 for 5)
RE_REPORT_FT, RP_REPORT_FT = 20_925_631.0, 20_855_965.0
INTERFACE_FT = 400_000.0


def zonal_acceleration(mu_km3_s2, radius_km, j2, j3=0.0, j4=0.0):
    """The acceleration (ft/s^2) of U = mu/r [1 - sum J_n (R/r)^n P_n(sin phi)], n = 2..4, each term's gradient written
    out (test_orbit_earths checks it against the potential by finite differences)."""
    mu, re = mu_km3_s2 * FT_PER_KM**3, radius_km * FT_PER_KM

    def f(_t, s):
        x, y, z = s[:3]
        r = math.sqrt(x * x + y * y + z * z)
        w = z * z / (r * r)
        c2, c3, c4 = -1.5 * j2 * mu * re**2 / r**5, -2.5 * j3 * mu * re**3 / r**7, 1.875 * j4 * mu * re**4 / r**7
        across = -mu / r**3 + c2 * (1 - 5 * w) + c3 * z * (3 - 7 * w) + c4 * (1 - 14 * w + 21 * w * w)
        along_z = (-mu / r**3 + c2 * (3 - 5 * w) + c4 * (5 - 70 / 3 * w + 21 * w * w)) * z
        along_z += c3 * r * r * (6 * w - 7 * w * w - 0.6)
        return [s[3], s[4], s[5], across * x, across * y, along_z]

    return f


def potential(mu_km3_s2, radius_km, j2, j3=0.0, j4=0.0):
    mu, re = mu_km3_s2 * FT_PER_KM**3, radius_km * FT_PER_KM

    def u(p):
        r = float(np.linalg.norm(p))
        s, q = p[2] / r, re / r
        legendre = ((3 * s * s - 1) / 2, (5 * s**3 - 3 * s) / 2, (35 * s**4 - 30 * s * s + 3) / 8)
        return mu / r * (1 - sum(j * q**n * pn for n, j, pn in zip((2, 3, 4), (j2, j3, j4), legendre)))

    return u


def geodetic_ft(x, y, z, re=RE_REPORT_FT, rp=RP_REPORT_FT):
    """Geodetic latitude (deg) and altitude (ft) on an ellipsoid: tan(lat) = z / (p (1 - e^2 N / (N + h))) iterated."""
    e2, p = 1.0 - (rp / re) ** 2, math.hypot(x, y)
    lat = math.atan2(z, p * (1.0 - e2))
    for _ in range(8):
        n = re / math.sqrt(1.0 - e2 * math.sin(lat) ** 2)
        h = p / math.cos(lat) - n
        lat = math.atan2(z, p * (1.0 - e2 * n / (n + h)))
    n = re / math.sqrt(1.0 - e2 * math.sin(lat) ** 2)
    return math.degrees(lat), p * math.cos(lat) + z * math.sin(lat) - re * re / n


def gmst_rad(utc: datetime, after_s: float = 0.0) -> float:
    """skyfield's GMST (UT1 from its bundled tables) `after_s` SI seconds after a UTC time (added in TAI)."""
    from skyfield.api import load

    ts = load.timescale(builtin=True)
    t = ts.from_datetime(utc)
    return math.radians(ts.tai_jd(t.whole, t.tai_fraction + after_s / 86_400.0).gmst * 15.0)


def sgp4_teme_km(tle_lines, utc: datetime):
    """SGP4's TEME position (km) and velocity (km/s) at a UTC time, by `sgp4` itself."""
    from sgp4.api import Satrec, jday

    sat = Satrec.twoline2rv(*tle_lines)
    err, r, v = sat.sgp4(*jday(utc.year, utc.month, utc.day, utc.hour, utc.minute, utc.second + utc.microsecond / 1e6))
    assert err == 0
    return np.array(r), np.array(v)


def interface_state(r_km, v_km_s, delta_v_fps, earth):
    """The burn (Δv against the inertial velocity) and the coast to 400,000 ft above the report's ellipsoid in TEME
    axes: (the coast's seconds, the TEME position (ft) and inertial velocity (ft/s) there)."""
    r, v = np.asarray(r_km) * FT_PER_KM, np.asarray(v_km_s) * FT_PER_KM
    return coast_to_interface(r, v * (1.0 - delta_v_fps / np.linalg.norm(v)), earth)


def coast_to_interface(r_ft, v_ft_s, earth):
    """The coast from a TEME state after its burn (ft, ft/s) to 400,000 ft above the report's ellipsoid: (the coast's
    seconds, the TEME position (ft) and inertial velocity (ft/s) there)."""
    r, v = np.asarray(r_ft, float), np.asarray(v_ft_s, float)

    def interface(_t, s):  # the altitude does not depend on the earth's turning: p and z do not
        return geodetic_ft(*s[:3])[1] - INTERFACE_FT

    interface.terminal, interface.direction = True, -1
    sol = solve_ivp(zonal_acceleration(**earth), (0.0, 20_000.0), np.concatenate([r, v]), method="DOP853",
                    rtol=1e-12, atol=1e-6, events=interface)  # fmt: skip
    return float(sol.t_events[0][0]), sol.y_events[0][0][:3], sol.y_events[0][0][3:]


def independent_entry(r_km, v_km_s, delta_v_fps, earth, burn_utc):
    """The burn and the coast to the interface (interface_state): (the coast's seconds, the entry's geodetic latitude
    and longitude, deg)."""
    t, (x, y, z), _ = interface_state(r_km, v_km_s, delta_v_fps, earth)
    theta = gmst_rad(burn_utc, t)  # TEME to earth-fixed: turned by -GMST about the pole (AIAA 2006-6753 sec. IV-C)
    xe, ye = math.cos(theta) * x + math.sin(theta) * y, -math.sin(theta) * x + math.cos(theta) * y
    return t, geodetic_ft(xe, ye, z)[0], math.degrees(math.atan2(ye, xe))
