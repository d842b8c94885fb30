"""Section IV: move a footprint to another node, inclination or deorbit point, mirror a half footprint, and
shift it for the earth's rotation.

The report converts each point to down-range and cross-range (eqs. 8-11), changes the initial point's
longitude (re-node), its heading (re-incline) or adds down-range (step around the orbit), and iterates
back to latitude and longitude (eqs. 12-15). Every such move keeps a point's place relative to the initial
great circle, so it is one rotation of the sphere: R = F_to . S(step) . F_from^T with F the frame
(p0, d0, n) of a reference and S a turn about the pole n by the step. Applied to unit vectors it is exact
and vectorized; the report's iteration is kept only as a cross-check in the tests.
"""

from dataclasses import dataclass

import numpy as np

from footprint.core.constants import OMEGA_EARTH_DEG_S
from footprint.core.errors import InputError
from footprint.core.ranges import MEAN_RADIUS_NMI, great_circle_frame, unit_vectors


@dataclass(frozen=True)
class Reference:
    """The initial point and heading that define the initial great circle (the report's L and sigma_0)."""

    latitude_deg: float
    longitude_deg: float
    heading_deg: float


def frame(ref: Reference) -> np.ndarray:
    """Columns p0, d0, n: the initial point, the initial direction, the left pole."""
    return np.column_stack(great_circle_frame(ref.latitude_deg, ref.longitude_deg, ref.heading_deg))


def rotation(src: Reference, dst: Reference, step_downrange_nmi=0.0, radius_nmi=MEAN_RADIUS_NMI) -> np.ndarray:
    """The 3x3 rotation that carries a footprint about src to the same place about dst, moved on by the step."""
    a = step_downrange_nmi / radius_nmi
    step = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    return frame(dst) @ step @ frame(src).T


def move(latitude_deg, longitude_deg, src: Reference, dst: Reference, step_downrange_nmi=0.0,
         radius_nmi=MEAN_RADIUS_NMI):
    """Re-node, re-incline and step around the orbit in one: (lat, lon) in degrees, arrays of any shape."""
    u = unit_vectors(np.asarray(latitude_deg, float), np.asarray(longitude_deg, float))
    v = u @ rotation(src, dst, step_downrange_nmi, radius_nmi).T
    return latlon_of(v)


def latlon_of(v):
    """(lat, lon) in degrees of unit vectors (last axis xyz); longitude in (-180, 180]."""
    lat = np.degrees(np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1])))
    return lat, np.degrees(np.arctan2(v[..., 1], v[..., 0]))


def mirror(latitude_deg, longitude_deg, ref: Reference):
    """The other half of a symmetric footprint: each point reflected in the plane of the initial great circle."""
    n = frame(ref)[:, 2]
    u = unit_vectors(np.asarray(latitude_deg, float), np.asarray(longitude_deg, float))
    return latlon_of(u - 2.0 * (u @ n)[..., None] * n)


def rotation_shift(longitude_deg, flight_time_s, omega_deg_s=OMEGA_EARTH_DEG_S):
    """Section IV.3, the first-order earth-rotation shift: theta_rot = theta - omega_p t (latitude unchanged)."""
    lon = np.asarray(longitude_deg, float) - omega_deg_s * np.asarray(flight_time_s, float)
    return wrap_longitude(lon)


def wrap_longitude(lon):
    return (np.asarray(lon, float) + 180.0) % 360.0 - 180.0


def heading_for_inclination(latitude_deg, inclination_deg, ascending=True):
    """Heading (azimuth from north) of a circular orbit of the given inclination where it crosses a latitude.

    Spherical trigonometry of the orbit plane: cos i = sin(heading) cos(latitude); ascending passes head
    north (|heading| < 90 deg), descending ones south. At the node heading = 90 - i.
    """
    lat, inc = np.radians(latitude_deg), np.radians(inclination_deg)
    s = np.cos(inc) / np.cos(lat)
    if np.any(np.abs(s) > 1.0 + 1e-12):
        raise InputError("inclination_deg", f"an orbit of inclination {inclination_deg} deg never reaches "
                                            f"latitude {latitude_deg} deg (it reaches +-{min(inclination_deg, 180 - inclination_deg)} deg)")
    az = np.degrees(np.arcsin(np.clip(s, -1.0, 1.0)))
    return az if ascending else 180.0 - az


def inclination_for_heading(latitude_deg, heading_deg):
    """Inverse of heading_for_inclination: cos i = sin(heading) cos(latitude)."""
    return np.degrees(np.arccos(np.sin(np.radians(heading_deg)) * np.cos(np.radians(latitude_deg))))
