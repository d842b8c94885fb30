"""Down-range and cross-range about an initial great circle, AFWAL-TR-82-3036 eqs. (8)-(11).

Closed form with unit vectors on a sphere of radius R' instead of the report's spherical triangles:
with p0 the initial point, d0 the initial direction and n = p0 x d0 the left pole, a point P has
cross-range R' asin(P.n) (positive to the left, where a positive bank turns) and down-range
R' atan2(P.d0, P.p0) measured along the great circle, negative behind the initial point. Eq. (11) as
printed has the opposite cross-range sign and eq. (10) loses the sign of points behind; this form keeps
both. Along a trajectory the down-range is unwrapped so that it can exceed half the circumference
(the report's footprints reach 14,500 nmi).
"""

import numpy as np

from footprint.core.constants import FT_PER_NMI, MEAN_RADIUS_FT

MEAN_RADIUS_NMI = MEAN_RADIUS_FT / FT_PER_NMI


def unit_vectors(latitude_deg, longitude_deg):
    lat, lon = np.radians(latitude_deg), np.radians(longitude_deg)
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)


def great_circle_frame(latitude0_deg, longitude0_deg, heading0_deg):
    """(p0, d0, n): initial point, initial direction, left pole; unit vectors."""
    lat, lon, hdg = np.radians(latitude0_deg), np.radians(longitude0_deg), np.radians(heading0_deg)
    p0 = unit_vectors(latitude0_deg, longitude0_deg)
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    d0 = np.cos(hdg) * north + np.sin(hdg) * east
    return p0, d0, np.cross(p0, d0)


def latlon_from_ranges(downrange_nmi, crossrange_nmi, latitude0_deg, longitude0_deg, heading0_deg,
                       radius_nmi=MEAN_RADIUS_NMI):
    """Inverse of downrange_crossrange_nmi in closed form (the report iterates, eqs. 12-15):
    P = cos(c) (cos(d) p0 + sin(d) d0) + sin(c) n with d, c the ranges as angles. Returns (lat, lon) deg."""
    p0, d0, n = great_circle_frame(latitude0_deg, longitude0_deg, heading0_deg)
    a = np.asarray(downrange_nmi, float)[..., None] / radius_nmi
    b = np.asarray(crossrange_nmi, float)[..., None] / radius_nmi
    pts = np.cos(b) * (np.cos(a) * p0 + np.sin(a) * d0) + np.sin(b) * n
    lat = np.degrees(np.arctan2(pts[..., 2], np.hypot(pts[..., 0], pts[..., 1])))
    return lat, np.degrees(np.arctan2(pts[..., 1], pts[..., 0]))


def downrange_crossrange_nmi(latitude_deg, longitude_deg, latitude0_deg, longitude0_deg, heading0_deg,
                             radius_nmi=MEAN_RADIUS_NMI, unwrap=False):
    """Down-range and cross-range (nmi) of points about the great circle through the initial point.

    `unwrap=True` treats the points as a path from the initial point and lets the down-range grow past
    half a circumference.
    """
    p0, d0, n = great_circle_frame(latitude0_deg, longitude0_deg, heading0_deg)
    pts = unit_vectors(np.asarray(latitude_deg, float), np.asarray(longitude_deg, float))
    along_p0, along_d0 = pts @ p0, pts @ d0
    cross = np.arctan2(pts @ n, np.hypot(along_p0, along_d0))  # not asin: exact near the poles too
    down = np.arctan2(along_d0, along_p0)
    if unwrap:
        down = np.unwrap(np.atleast_1d(down))
    return radius_nmi * down, radius_nmi * cross
