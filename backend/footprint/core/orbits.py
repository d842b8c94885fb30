"""A circular orbit: where the deorbit point is and which way the footprint's initial great circle heads.

AFWAL-TR-82-3036 Section IV places a footprint by "the longitude, latitude of the deorbit point plus the
heading angle of the orbit at that point". This module gives those for a circular orbit at any revolution
and argument of latitude u (the angle in the orbit plane from the ascending node, in the direction of
motion), vectorized over both.

Model (a sphere for the ground track, a point mass for the period, one secular J2 effect):

- period T = 2 pi sqrt(a^3 / mu), a = R_e + altitude (Kepler's third law);
- u = 360 deg (t / T - (revolution - 1)): revolution 1 leaves the ascending node at t = 0;
- the node's earth-fixed longitude drifts by (dOmega/dt - omega_earth) per second: west by omega_earth T
  each revolution, plus the J2 nodal regression (a flag, on by default)
  dOmega/dt = -(3/2) J2 n (R_e / a)^2 cos i  (e = 0; Vallado, Fundamentals of Astrodynamics and
  Applications, 4th ed., sec. 9.6, the first-order secular rate of the node; Kozai 1959);
- the other J2 secular rates (argument of latitude, hence the nodal period) are left out: about 0.2 % of
  T in low orbit, 10 s a revolution;
- positions are geocentric latitude and longitude of the point under the satellite on a sphere;
- the heading is the azimuth of the inertial velocity, atan2(cos i, sin i cos u): the trace of the
  orbit plane on the ground at that instant, which is the footprint's initial great circle. It is not
  the heading of the earth-relative velocity (that one differs by up to ~3.5 deg in low orbit).
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.constants import J_ZONAL, MU_EARTH_FT3_S2, OMEGA_EARTH_DEG_S, RADIUS_EQUATORIAL_FT
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, latlon_of, wrap_longitude

J2 = J_ZONAL / 1.5  # App. A gives J = 1.5 J2 (1623.41e-6), so J2 = 1082.27e-6
SECONDS_PER_DAY = 86_400.0


@dataclass(frozen=True)
class CircularOrbit:
    """A circular orbit about a rotating planet.

    `node_longitude_deg` is the earth-fixed longitude of the ascending node when revolution 1 crosses it,
    at t = 0 (the epoch). With a right ascension of the node and the Greenwich sidereal angle at the same
    epoch, use `CircularOrbit.from_right_ascension`.
    """

    inclination_deg: float
    altitude_ft: float
    node_longitude_deg: float = 0.0
    mu_ft3_s2: float = MU_EARTH_FT3_S2
    radius_ft: float = RADIUS_EQUATORIAL_FT  # R_e: the altitude's datum and the J2 reference radius
    rotation_rate_deg_s: float = OMEGA_EARTH_DEG_S
    j2: float = J2
    nodal_regression: bool = True

    @classmethod
    def from_right_ascension(
        cls,
        inclination_deg: float,
        altitude_ft: float,
        right_ascension_deg: float,
        greenwich_sidereal_deg: float,
        **kwargs: Any,
    ) -> "CircularOrbit":
        """The node's earth-fixed longitude is its right ascension less the Greenwich sidereal angle."""
        return cls(
            inclination_deg=inclination_deg,
            altitude_ft=altitude_ft,
            node_longitude_deg=float(wrap_longitude(right_ascension_deg - greenwich_sidereal_deg)),
            **kwargs,
        )

    @property
    def semi_major_axis_ft(self) -> float:
        return self.radius_ft + self.altitude_ft

    @property
    def period_s(self) -> float:
        """Kepler's third law, T = 2 pi sqrt(a^3 / mu)."""
        return 2.0 * math.pi * math.sqrt(self.semi_major_axis_ft**3 / self.mu_ft3_s2)

    @property
    def mean_motion_deg_s(self) -> float:
        return 360.0 / self.period_s

    @property
    def node_rate_deg_s(self) -> float:
        """Inertial secular rate of the node: -(3/2) J2 n (R_e/a)^2 cos i (Vallado sec. 9.6, e = 0); 0 when off."""
        if not self.nodal_regression:
            return 0.0
        ratio = self.radius_ft / self.semi_major_axis_ft
        return -1.5 * self.j2 * self.mean_motion_deg_s * ratio**2 * math.cos(math.radians(self.inclination_deg))

    @property
    def node_drift_deg_s(self) -> float:
        """Rate of the node's earth-fixed longitude: the regression less the earth's rotation."""
        return self.node_rate_deg_s - self.rotation_rate_deg_s

    @property
    def node_step_deg(self) -> float:
        """Change of the node's earth-fixed longitude from one revolution to the next (negative: west)."""
        return self.node_drift_deg_s * self.period_s

    def revolutions_in(self, hours: float) -> NDArray[np.int_]:
        """The revolutions (1, 2, ...) that start within `hours` of the epoch."""
        return np.arange(1, math.ceil(hours * 3600.0 / self.period_s - 1e-12) + 1)


def time_s(orbit: CircularOrbit, revolution: ArrayLike, u_deg: ArrayLike) -> NDArray[np.float64]:
    """Seconds since the epoch at argument of latitude u of a revolution (revolution 1 starts at t = 0)."""
    return ((np.asarray(revolution, float) - 1.0) + np.asarray(u_deg, float) / 360.0) * orbit.period_s


def node_longitude_deg(orbit: CircularOrbit, t_s: ArrayLike) -> NDArray[np.float64]:
    """Earth-fixed longitude of the ascending node at time t, in [-180, 180)."""
    return wrap_longitude(orbit.node_longitude_deg + orbit.node_drift_deg_s * np.asarray(t_s, float))


def revolution_node_longitude_deg(orbit: CircularOrbit, revolution: ArrayLike) -> NDArray[np.float64]:
    """Earth-fixed longitude of the ascending node where each revolution crosses it."""
    return node_longitude_deg(orbit, time_s(orbit, revolution, 0.0))


def _plane_vectors(
    orbit: CircularOrbit, revolution: ArrayLike, u_deg: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Earth-fixed unit vectors (..., 3): position p, direction of motion d and orbit normal n = p x d.

    In the node frame (x to the node, z to the pole) p = (cos u, cos i sin u, sin i sin u),
    d = (-sin u, cos i cos u, sin i cos u), n = (0, -sin i, cos i); the node frame is turned about the
    polar axis by the node's earth-fixed longitude at that instant.
    """
    rev, u = np.broadcast_arrays(np.asarray(revolution, float), np.asarray(u_deg, float))
    lam = np.radians(node_longitude_deg(orbit, time_s(orbit, rev, u)))
    ur, inc = np.radians(u), math.radians(orbit.inclination_deg)
    ci, si = math.cos(inc), math.sin(inc)
    cu, su = np.cos(ur), np.sin(ur)
    cl, sl = np.cos(lam), np.sin(lam)

    def turn(x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.stack([cl * x - sl * y, sl * x + cl * y, np.broadcast_to(z, cl.shape)], axis=-1)

    p = turn(cu, ci * su, si * su)
    d = turn(-su, ci * cu, si * cu)
    n = turn(np.zeros_like(cu), -si * np.ones_like(cu), ci * np.ones_like(cu))
    return p, d, n


def position(
    orbit: CircularOrbit, revolution: ArrayLike, u_deg: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Geocentric latitude and earth-fixed longitude (deg) under the satellite; arrays broadcast together."""
    p, _, _ = _plane_vectors(orbit, revolution, u_deg)
    return latlon_of(p)


def inertial_heading_deg(orbit: CircularOrbit, u_deg: ArrayLike) -> NDArray[np.float64]:
    """Azimuth from north of the inertial velocity: atan2(cos i, sin i cos u) (90 - i at the ascending node)."""
    inc = math.radians(orbit.inclination_deg)
    return np.degrees(np.arctan2(math.cos(inc), math.sin(inc) * np.cos(np.radians(u_deg))))


def frames(
    orbit: CircularOrbit,
    revolution: ArrayLike,
    u_deg: ArrayLike,
    entry_offset_nmi: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The footprint frames (p0, d0, n), each (..., 3) earth-fixed, of placements at deorbit (revolution, u).

    The entry point is `entry_offset_nmi` further along the orbit (an arc of the orbit plane, delta u =
    offset / R'), where and when the orbit reaches it. Returns (p0, d0, n, entry_time_s).
    """
    du = math.degrees(entry_offset_nmi / radius_nmi)
    u_entry = np.asarray(u_deg, float) + du
    p0, d0, n = _plane_vectors(orbit, revolution, u_entry)
    return p0, d0, n, time_s(orbit, revolution, u_entry)


def deorbit_reference(
    orbit: CircularOrbit,
    revolution: int,
    u_deg: float,
    entry_offset_nmi: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> Reference:
    """The initial point and heading of the footprint's initial great circle, placed at a deorbit point.

    The point is under the satellite at (revolution, u), or `entry_offset_nmi` further along the orbit
    (delta u = offset / R', reached that much later); the heading is the inertial azimuth there.
    """
    du = math.degrees(entry_offset_nmi / radius_nmi)
    lat, lon = position(orbit, revolution, u_deg + du)
    return Reference(
        latitude_deg=float(lat), longitude_deg=float(lon), heading_deg=float(inertial_heading_deg(orbit, u_deg + du))
    )
