"""The sphere of radius R': points as unit vectors, down-range and cross-range about an initial great circle
(AFWAL-TR-82-3036 eqs. 8-11), moving a footprint to another node, inclination or deorbit point, mirroring a
half and shifting it for the earth's rotation (Section IV, eqs. 12-15), longitude wrapping and unwrapping,
and the initial great circle itself. Every module that needs the sphere's geometry takes it from here.

Ranges. Closed form with unit vectors instead of the report's spherical triangles: with p0 the initial
point, d0 the initial direction and n = p0 x d0 the left pole, a point P has cross-range R' asin(P.n)
(positive to the left, where a positive bank turns) and down-range R' atan2(P.d0, P.p0) measured along the
great circle, negative behind the initial point. Eq. (11) as printed has the opposite cross-range sign and
eq. (10) loses the sign of points behind; this form keeps both. Along a trajectory the down-range is
unwrapped so that it can exceed half the circumference (the report's footprints reach 14,500 nmi).

Moves. The report converts each point to down-range and cross-range (eqs. 8-11), changes the initial
point's longitude (re-node), its heading (re-incline) or adds down-range (step around the orbit), and
iterates back to latitude and longitude (eqs. 12-15). Every such move keeps a point's place relative to the
initial great circle, so it is one rotation of the sphere: R = F_to . S(step) . F_from^T with F the frame
(p0, d0, n) of a reference and S a turn about the pole n by the step. Applied to unit vectors it is exact
and vectorized; the report's iteration is kept only as a cross-check in the tests.

Longitudes. `wrap_longitude` puts a longitude in [-180, 180) (about a centre, optionally (-180, 180]);
`unwrap_longitude` makes a sequence continuous. The compiled integrator wraps its heading with its own
numba kernel, core.controls.wrap_deg ((-180, 180]), which must stay inside the compiled code.
"""

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core._jit import njit
from footprint.core.constants import FT_PER_NMI, MEAN_RADIUS_FT, OMEGA_EARTH_DEG_S
from footprint.core.errors import InputError

MEAN_RADIUS_NMI = MEAN_RADIUS_FT / FT_PER_NMI


# ------------------------------------------------------------------------------------------ longitudes
def wrap_longitude(
    longitude_deg: ArrayLike, center_deg: float = 0.0, *, closed_above: bool = False
) -> NDArray[np.float64]:
    """Longitudes (deg, any shape) moved by whole turns into the 360 deg about center_deg:
    [center - 180, center + 180) by default, so +180 becomes -180 (the transform's, the orbits' and the
    GeoJSON's convention); with closed_above=True (center - 180, center + 180], so -180 becomes +180 (the
    map's axis labels; core.controls.wrap_deg's convention for headings)."""
    lon = np.asarray(longitude_deg, float)
    wrapped = center_deg + (lon - center_deg + 180.0) % 360.0 - 180.0  # floor modulo: 0 <= x % 360 < 360
    if closed_above:
        wrapped = np.where(wrapped == center_deg - 180.0, center_deg + 180.0, wrapped)
    return wrapped


def unwrap_longitude(longitude_deg: ArrayLike, reference_deg: float | None = None) -> NDArray[np.float64]:
    """Longitudes (deg) of a path or ring made continuous: 360 deg added or taken wherever neighbours would
    differ by more than 180 deg. Without reference_deg the first longitude stays as given (numpy.unwrap with
    a period of 360 deg); with it the first is put within 180 deg of reference_deg and each next one a step
    of at most 180 deg from the one before (a ring that crosses +-180 deg never jumps by 360 deg)."""
    lon = np.asarray(longitude_deg, float)
    if reference_deg is None:
        return np.unwrap(lon, period=360.0)
    if lon.size == 0:
        return lon
    first = wrap_longitude(lon[0], reference_deg)
    return np.concatenate([[first], first + np.cumsum(wrap_longitude(np.diff(lon)))])


# -------------------------------------------------------------------------------------- unit vectors
def unit_vectors(latitude_deg: ArrayLike, longitude_deg: ArrayLike) -> NDArray[np.float64]:
    """Unit vectors (..., 3) of points given by latitude and longitude (deg; broadcast together): x towards
    latitude 0, longitude 0, z towards the north pole."""
    lat, lon = np.broadcast_arrays(
        np.radians(np.asarray(latitude_deg, float)), np.radians(np.asarray(longitude_deg, float))
    )
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)  # spherical to xyz


def latlon_of(v: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(lat, lon) in degrees of unit vectors (last axis xyz); longitude in [-180, 180] (atan2: +180 where
    y is +0 and x < 0, -180 where y is -0)."""
    lat = np.degrees(np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1])))  # xyz to spherical, exact near the poles
    return lat, np.degrees(np.arctan2(v[..., 1], v[..., 0]))


# ----------------------------------------------------------------------------- the initial great circle
def great_circle_frame(
    latitude0_deg: ArrayLike, longitude0_deg: ArrayLike, heading0_deg: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(p0, d0, n): initial point, initial direction, left pole; unit vectors (shape (..., 3) for arrays of the
    arguments)."""
    if np.ndim(latitude0_deg) == np.ndim(longitude0_deg) == np.ndim(heading0_deg) == 0:
        return _one_frame(float(latitude0_deg), float(longitude0_deg), float(heading0_deg))  # type: ignore[arg-type]
    lat, lon, hdg = np.radians(latitude0_deg), np.radians(longitude0_deg), np.radians(heading0_deg)
    p0 = unit_vectors(latitude0_deg, longitude0_deg)
    north = np.stack([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)], axis=-1)
    east = np.stack([-np.sin(lon), np.cos(lon), np.zeros_like(lon)], axis=-1)
    # the heading is the azimuth from north (the report's sigma_0)
    d0 = np.cos(hdg)[..., None] * north + np.sin(hdg)[..., None] * east
    return p0, d0, np.cross(p0, d0)


def _one_frame(
    latitude0_deg: float, longitude0_deg: float, heading0_deg: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """great_circle_frame of one point in plain floats (every flight's summary takes one: numpy's broadcasting cost
    more than the arithmetic)."""
    lat, lon, hdg = math.radians(latitude0_deg), math.radians(longitude0_deg), math.radians(heading0_deg)
    sl, cl, so, co, sh, ch = math.sin(lat), math.cos(lat), math.sin(lon), math.cos(lon), math.sin(hdg), math.cos(hdg)
    p = (cl * co, cl * so, sl)
    d = (-ch * sl * co - sh * so, -ch * sl * so + sh * co, ch * cl)  # cos(h) north + sin(h) east
    n = (p[1] * d[2] - p[2] * d[1], p[2] * d[0] - p[0] * d[2], p[0] * d[1] - p[1] * d[0])
    return np.array(p), np.array(d), np.array(n)


@dataclass(frozen=True)
class Reference:
    """The initial point and heading that define the initial great circle (the report's L and sigma_0)."""

    latitude_deg: float
    longitude_deg: float
    heading_deg: float


def great_circle(ref: Reference, downrange_deg: ArrayLike) -> NDArray[np.float64]:
    """Unit vectors (..., 3) on ref's initial great circle at the given down-range angles (deg) from the
    initial point: cos(a) p0 + sin(a) d0 (latlon_from_ranges at zero cross-range)."""
    p0, d0, _ = great_circle_frame(ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    a = np.radians(downrange_deg)[..., None]
    return np.cos(a) * p0 + np.sin(a) * d0


# ------------------------------------------------------------------------------- eqs. (8)-(15): ranges
def latlon_from_ranges(
    downrange_nmi: ArrayLike,
    crossrange_nmi: ArrayLike,
    latitude0_deg: float,
    longitude0_deg: float,
    heading0_deg: float,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Inverse of downrange_crossrange_nmi in closed form (the report iterates, eqs. 12-15):
    P = cos(c) (cos(d) p0 + sin(d) d0) + sin(c) n with d, c the ranges as angles. Returns (lat, lon) deg."""
    p0, d0, n = great_circle_frame(latitude0_deg, longitude0_deg, heading0_deg)
    a = np.asarray(downrange_nmi, float)[..., None] / radius_nmi
    b = np.asarray(crossrange_nmi, float)[..., None] / radius_nmi
    return latlon_of(np.cos(b) * (np.cos(a) * p0 + np.sin(a) * d0) + np.sin(b) * n)


def downrange_crossrange_nmi(
    latitude_deg: ArrayLike,
    longitude_deg: ArrayLike,
    latitude0_deg: float,
    longitude0_deg: float,
    heading0_deg: float,
    radius_nmi: float = MEAN_RADIUS_NMI,
    unwrap: bool = False,
    frame: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Down-range and cross-range (nmi) of points about the great circle through the initial point
    (eqs. 8-11 in closed form, see the module docstring), shaped like the points.

    `unwrap=True` treats the points as a path from the initial point and lets the down-range grow past
    half a circumference. `frame`: great_circle_frame of the initial point and heading, when the caller has it.
    """
    p0, d0, n = great_circle_frame(latitude0_deg, longitude0_deg, heading0_deg) if frame is None else frame
    lat, lon = np.broadcast_arrays(
        np.radians(np.asarray(latitude_deg, float)), np.radians(np.asarray(longitude_deg, float))
    )
    shape = np.atleast_1d(lat).shape if unwrap else lat.shape
    down, cross = ranges_rad(np.ravel(lat), np.ravel(lon), p0, d0, n, unwrap)
    return radius_nmi * down.reshape(shape), radius_nmi * cross.reshape(shape)


@njit
def ranges_rad(
    latitude_rad: NDArray[np.float64],
    longitude_rad: NDArray[np.float64],
    p0: NDArray[np.float64],
    d0: NDArray[np.float64],
    n: NDArray[np.float64],
    unwrap: bool,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Down-range and cross-range angles (rad) of points (rad): cross = atan2(P.n, |P in the plane|), exact near the
    poles too; down = atan2(P.d0, P.p0), unwrapped along the points as numpy.unwrap does (a step of pi or more
    corrected by whole turns) when `unwrap`. One compiled loop: every flight's track takes it."""
    m = latitude_rad.shape[0]
    down, cross = np.empty(m), np.empty(m)
    axes = frame_axes(p0, d0, n)
    correction, previous = 0.0, 0.0
    for i in range(m):
        cl = math.cos(latitude_rad[i])
        x, y, z = cl * math.cos(longitude_rad[i]), cl * math.sin(longitude_rad[i]), math.sin(latitude_rad[i])
        along_d0, along_p0, along_n = range_terms(x, y, z, axes)
        cross[i] = math.atan2(along_n, math.hypot(along_p0, along_d0))
        raw = math.atan2(along_d0, along_p0)
        if unwrap and i > 0:
            correction = unwrapped_correction(raw, previous, correction)
        previous = raw
        down[i] = raw + correction
    return down, cross


FrameAxes = tuple[float, float, float, float, float, float, float, float, float]  # p0, d0, n: x, y, z of each


@njit
def frame_axes(p0: NDArray[np.float64], d0: NDArray[np.float64], n: NDArray[np.float64]) -> FrameAxes:
    """great_circle_frame's three unit vectors as nine numbers (a compiled loop over points reads them from
    registers: it vectorizes)."""
    return p0[0], p0[1], p0[2], d0[0], d0[1], d0[2], n[0], n[1], n[2]


@njit
def range_terms(x: float, y: float, z: float, axes: FrameAxes) -> tuple[float, float, float]:
    """(a, b, c) of the unit vector (x, y, z) about the frame (frame_axes): its down-range angle (rad, within
    (-pi, pi]) is atan2(a, b), its cross-range angle atan2(c, |(a, b)|): eqs. (8)-(11) in closed form."""
    p0x, p0y, p0z, d0x, d0y, d0z, nx, ny, nz = axes
    return x * d0x + y * d0y + z * d0z, x * p0x + y * p0y + z * p0z, x * nx + y * ny + z * nz


@njit
def unwrapped_correction(raw: float, previous: float, correction: float) -> float:
    """numpy.unwrap's running correction (whole turns) after the step from `previous` to `raw` (rad): a step of pi
    or more is folded into [-pi, pi), +pi kept for a positive step."""
    step = raw - previous
    folded = (step + math.pi) % (2.0 * math.pi) - math.pi
    if folded == -math.pi and step > 0.0:
        folded = math.pi
    if abs(step) >= math.pi:
        correction += folded - step
    return correction


def close_half_along_axis(points: Iterable[tuple[Any, ...]]) -> list[tuple[Any, ...]]:
    """A half footprint (every cross-range >= 0, or every one <= 0) closed along the initial great circle:
    a point of cross-range 0 added at its first and at its last down-range; any other boundary as given.
    points: tuples (down-range, cross-range, ...); an added point copies the rest of its neighbour's."""
    pts = list(points)
    if all(p[1] >= 0.0 for p in pts) or all(p[1] <= 0.0 for p in pts):
        pts = [(pts[0][0], 0.0, *pts[0][2:])] + pts + [(pts[-1][0], 0.0, *pts[-1][2:])]
    return pts


# ---------------------------------------------------------------------------- Section IV: moving a footprint
def frame(ref: Reference) -> NDArray[np.float64]:
    """Columns p0, d0, n: the initial point, the initial direction, the left pole."""
    return np.column_stack(great_circle_frame(ref.latitude_deg, ref.longitude_deg, ref.heading_deg))


def rotation(
    src: Reference, dst: Reference, step_downrange_nmi: float = 0.0, radius_nmi: float = MEAN_RADIUS_NMI
) -> NDArray[np.float64]:
    """The 3x3 rotation that carries a footprint about src to the same place about dst, moved on by the step."""
    a = step_downrange_nmi / radius_nmi
    step: NDArray[np.float64] = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    return frame(dst) @ step @ frame(src).T  # R = F_to . S(step) . F_from^T


def move(
    latitude_deg: ArrayLike,
    longitude_deg: ArrayLike,
    src: Reference,
    dst: Reference,
    step_downrange_nmi: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Re-node, re-incline and step around the orbit in one: (lat, lon) in degrees, arrays of any shape."""
    u = unit_vectors(np.asarray(latitude_deg, float), np.asarray(longitude_deg, float))
    v = u @ rotation(src, dst, step_downrange_nmi, radius_nmi).T
    return latlon_of(v)


def mirror(
    latitude_deg: ArrayLike, longitude_deg: ArrayLike, ref: Reference
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The other half of a symmetric footprint: each point reflected in the plane of the initial great circle."""
    n = frame(ref)[:, 2]
    u = unit_vectors(np.asarray(latitude_deg, float), np.asarray(longitude_deg, float))
    return latlon_of(u - 2.0 * (u @ n)[..., None] * n)  # Householder reflection in the plane normal to n


def rotation_shift(
    longitude_deg: ArrayLike, flight_time_s: ArrayLike, omega_deg_s: float = OMEGA_EARTH_DEG_S
) -> NDArray[np.float64]:
    """Section IV.3, the first-order earth-rotation shift: theta_rot = theta - omega_p t (latitude unchanged);
    longitude in [-180, 180)."""
    lon = np.asarray(longitude_deg, float) - omega_deg_s * np.asarray(flight_time_s, float)
    return wrap_longitude(lon)


def heading_for_inclination(latitude_deg: float, inclination_deg: float, ascending: bool = True) -> float:
    """Heading (azimuth from north) of a circular orbit of the given inclination where it crosses a latitude.

    Spherical trigonometry of the orbit plane: cos i = sin(heading) cos(latitude); ascending passes head
    north (|heading| < 90 deg), descending ones south. At the node heading = 90 - i.
    """
    lat, inc = np.radians(latitude_deg), np.radians(inclination_deg)
    s = np.cos(inc) / np.cos(lat)
    if np.any(np.abs(s) > 1.0 + 1e-12):
        raise InputError(
            "inclination_deg",
            f"an orbit of inclination {inclination_deg} deg never reaches "
            f"latitude {latitude_deg} deg (it reaches +-{min(inclination_deg, 180 - inclination_deg)} deg)",
        )
    az: float = np.degrees(np.arcsin(np.clip(s, -1.0, 1.0)))
    return az if ascending else 180.0 - az


def inclination_for_heading(latitude_deg: float, heading_deg: float) -> float:
    """Inverse of heading_for_inclination: cos i = sin(heading) cos(latitude)."""
    inclination_deg: float = np.degrees(np.arccos(np.sin(np.radians(heading_deg)) * np.cos(np.radians(latitude_deg))))
    return inclination_deg
