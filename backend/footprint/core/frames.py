"""Earth-fixed cartesian state, the oblate earth, and the local geocentric horizon (App. A).

Frame: x toward longitude 0 on the equator, z toward the north pole, y completing a right-handed set
(eastward at longitude 90 E). The report's earth-referenced frame has Z toward the south pole and so
Y westward; the physics is the same. Latitude and altitude are geodetic on the ellipsoid of equatorial
radius R_e and polar radius R_p ("the polar radius used ... for latitude and altitude", App. A). The
flight-path angle and heading are measured in the local geocentric horizon, as in App. A.
Heading is the azimuth from north, clockwise.
"""

import math

from footprint.core._jit import njit


@njit
def geodetic_from_ecef(
    x_ft: float, y_ft: float, z_ft: float, re_ft: float, rp_ft: float, oblate: bool, iterations: int = 2
) -> tuple[float, float, float]:
    """(geodetic latitude rad, longitude rad, altitude ft). Spherical: geocentric latitude, r - R_e.

    One iteration is good to 1e-9 rad and 1e-8 ft up to 3,000,000 ft (enough for the equations of motion);
    two reach the round-off level.
    """
    lon = math.atan2(y_ft, x_ft)
    p = math.sqrt(x_ft * x_ft + y_ft * y_ft)
    if not oblate:
        r = math.sqrt(p * p + z_ft * z_ft)
        return math.atan2(z_ft, p), lon, r - re_ft
    # Bowring's method (Survey Review 23, 1976)
    e2 = 1.0 - (rp_ft * rp_ft) / (re_ft * re_ft)
    ep2 = (re_ft * re_ft) / (rp_ft * rp_ft) - 1.0
    beta = math.atan2(re_ft * z_ft, rp_ft * p)
    lat = 0.0
    for _ in range(iterations):
        sb, cb = math.sin(beta), math.cos(beta)
        lat = math.atan2(z_ft + ep2 * rp_ft * sb * sb * sb, p - e2 * re_ft * cb * cb * cb)
        beta = math.atan2(rp_ft * math.sin(lat), re_ft * math.cos(lat))
    sl, cl = math.sin(lat), math.cos(lat)
    n = re_ft / math.sqrt(1.0 - e2 * sl * sl)
    alt = p * cl + z_ft * sl - re_ft * re_ft / n  # regular at the poles, unlike p/cos(lat) - N
    return lat, lon, alt


@njit
def geodetic_latitude_terms(
    x_ft: float, y_ft: float, z_ft: float, re_ft: float, rp_ft: float, oblate: bool, iterations: int = 2
) -> tuple[float, float]:
    """(s, c): the geodetic latitude is atan2(s, c), s and c its sine and cosine times one positive factor, by
    geodetic_from_ecef's Bowring iterations with the reduced latitude's sine and cosine from normalized vectors (as
    altitude_ft) in place of atan2, sin and cos: the same latitude to round-off (1e-15 rad), for every row of a
    history (its atan2 taken over the whole column at once)."""
    p = math.sqrt(x_ft * x_ft + y_ft * y_ft)
    if not oblate:
        return z_ft, p
    e2 = 1.0 - (rp_ft * rp_ft) / (re_ft * re_ft)
    ep2 = (re_ft * re_ft) / (rp_ft * rp_ft) - 1.0
    bz, bp = re_ft * z_ft, rp_ft * p  # tan(beta) = Re z / (Rp p), beta the reduced latitude
    s, c = z_ft, p
    for _ in range(iterations):
        ib = 1.0 / math.sqrt(bz * bz + bp * bp)
        sb, cb = bz * ib, bp * ib
        # Bowring: tan(lat) = (z + e'^2 Rp sin^3 beta) / (p - e^2 Re cos^3 beta); then tan(beta) = Rp tan(lat) / Re
        s = z_ft + ep2 * rp_ft * sb * sb * sb
        c = p - e2 * re_ft * cb * cb * cb
        bz, bp = rp_ft * s, re_ft * c
    return s, c


@njit
def altitude_ft(x_ft: float, y_ft: float, z_ft: float, re_ft: float, rp_ft: float, oblate: bool) -> float:
    """Geodetic altitude only: one Bowring step written with normalized vectors instead of trigonometry.

    Same accuracy as geodetic_from_ecef with one iteration (1e-8 ft to 3,000,000 ft), a quarter of the cost;
    the equations of motion need nothing else.
    """
    p = math.sqrt(x_ft * x_ft + y_ft * y_ft)
    if not oblate:
        return math.sqrt(p * p + z_ft * z_ft) - re_ft
    e2 = 1.0 - (rp_ft * rp_ft) / (re_ft * re_ft)
    ep2 = (re_ft * re_ft) / (rp_ft * rp_ft) - 1.0
    # reduced latitude beta: tan(beta) = Re z / (Rp p)
    bz, bp = re_ft * z_ft, rp_ft * p
    ib = 1.0 / math.sqrt(bz * bz + bp * bp)
    sb, cb = bz * ib, bp * ib
    # Bowring: tan(lat) = (z + e'^2 Rp sin^3 beta) / (p - e^2 Re cos^3 beta)
    num = z_ft + ep2 * rp_ft * sb * sb * sb
    den = p - e2 * re_ft * cb * cb * cb
    il = 1.0 / math.sqrt(num * num + den * den)
    sl, cl = num * il, den * il
    return p * cl + z_ft * sl - re_ft * math.sqrt(1.0 - e2 * sl * sl)


@njit
def ecef_from_geodetic(
    lat_rad: float, lon_rad: float, altitude_ft: float, re_ft: float, rp_ft: float, oblate: bool
) -> tuple[float, float, float]:
    """Inverse of geodetic_from_ecef (closed form)."""
    sl, cl = math.sin(lat_rad), math.cos(lat_rad)
    if not oblate:
        r = re_ft + altitude_ft
        return r * cl * math.cos(lon_rad), r * cl * math.sin(lon_rad), r * sl
    e2 = 1.0 - (rp_ft * rp_ft) / (re_ft * re_ft)
    n = re_ft / math.sqrt(1.0 - e2 * sl * sl)
    return (
        (n + altitude_ft) * cl * math.cos(lon_rad),
        (n + altitude_ft) * cl * math.sin(lon_rad),
        (n * (1.0 - e2) + altitude_ft) * sl,
    )


@njit
def horizon_basis(
    x_ft: float, y_ft: float, z_ft: float
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """Unit vectors up, north, east of the local geocentric horizon (App. A, X_g north, Z_g down)."""
    r = math.sqrt(x_ft * x_ft + y_ft * y_ft + z_ft * z_ft)
    ux, uy, uz = x_ft / r, y_ft / r, z_ft / r
    p = math.sqrt(ux * ux + uy * uy)
    if p < 1e-12:  # at a pole: take longitude 0 to define north
        ex, ey, ez = 0.0, 1.0, 0.0
    else:
        ex, ey, ez = -uy / p, ux / p, 0.0
    # north = up x east
    nx = uy * ez - uz * ey
    ny = uz * ex - ux * ez
    nz = ux * ey - uy * ex
    return ux, uy, uz, nx, ny, nz, ex, ey, ez


@njit
def flight_angles(x_ft: float, y_ft: float, z_ft: float, vx: float, vy: float, vz: float) -> tuple[float, float, float]:
    """(speed ft/s, flight-path angle rad, heading rad in [0, 2 pi)) of an earth-fixed velocity."""
    ux, uy, uz, nx, ny, nz, ex, ey, ez = horizon_basis(x_ft, y_ft, z_ft)
    v = math.sqrt(vx * vx + vy * vy + vz * vz)
    vu = vx * ux + vy * uy + vz * uz
    vn = vx * nx + vy * ny + vz * nz
    ve = vx * ex + vy * ey + vz * ez
    gamma = math.atan2(vu, math.sqrt(vn * vn + ve * ve))
    heading = math.atan2(ve, vn)
    if heading < 0.0:
        heading += 2.0 * math.pi
    return v, gamma, heading


@njit
def heading_terms(x_ft: float, y_ft: float, z_ft: float, vx: float, vy: float, vz: float) -> tuple[float, float]:
    """(e, n): flight_angles' heading is atan2(e, n) (then taken into [0, 2 pi)), e and n the velocity's east and
    north components in horizon_basis times one positive factor (r times the distance from the axis), without its
    divisions: for every row of a history."""
    p2 = x_ft * x_ft + y_ft * y_ft
    r = math.sqrt(p2 + z_ft * z_ft)
    if math.sqrt(p2) < 1e-12 * r:  # at a pole, as horizon_basis: east along +y, north = up x east
        return vy, -(z_ft / r) * vx
    return (x_ft * vy - y_ft * vx) * r, p2 * vz - z_ft * (x_ft * vx + y_ft * vy)


@njit
def velocity_from_angles(
    x_ft: float, y_ft: float, z_ft: float, speed_fps: float, gamma_rad: float, heading_rad: float
) -> tuple[float, float, float]:
    """Earth-fixed velocity from speed, flight-path angle and heading in the geocentric horizon."""
    ux, uy, uz, nx, ny, nz, ex, ey, ez = horizon_basis(x_ft, y_ft, z_ft)
    vu = speed_fps * math.sin(gamma_rad)
    vh = speed_fps * math.cos(gamma_rad)
    vn = vh * math.cos(heading_rad)
    ve = vh * math.sin(heading_rad)
    return (vu * ux + vn * nx + ve * ex, vu * uy + vn * ny + ve * ey, vu * uz + vn * nz + ve * ez)
