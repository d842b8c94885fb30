"""Where the sun is for a landing site: its elevation and the local apparent solar time (issue 28 item 3, the
daylight rule).

The sun's apparent right ascension and declination by the Astronomical Almanac's low-precision formulas ("The Sun",
Astronomical Almanac section C; Meeus, Astronomical Algorithms 2nd ed., ch. 25 for their derivation): good to 0.01 deg
from 1950 to 2050. The hour angle from Greenwich mean sidereal time (footprint.core.elements.gmst_deg, UT1 from
skyfield's bundled data); the elevation is geometric, from the geodetic latitude (no refraction: 0.57 deg at the
horizon, 0.02 deg at 40 deg; no parallax: 0.0024 deg). Local apparent solar time is 12 h plus the sun's hour angle.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime, timedelta

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.elements import J2000_JD, gmst_deg

UNIX_EPOCH_JD = 2440587.5
DAYLIGHT_ELEVATION_DEG = -0.833  # sunrise and sunset: the upper limb on the horizon, 34' of refraction (Almanac)
CIVIL_TWILIGHT_DEG = -6.0


def _days_from_j2000(utc: Sequence[datetime]) -> NDArray[np.float64]:
    return np.array([u.astimezone(UTC).timestamp() / 86_400.0 + UNIX_EPOCH_JD - J2000_JD for u in utc])


def right_ascension_declination_deg(utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The sun's apparent right ascension in [0, 360) and declination (deg) at each UTC time (Almanac, sec. C)."""
    n = _days_from_j2000(utc)  # UT for TT: 69 s moves the sun by 0.0008 deg
    mean_longitude = np.radians(280.460 + 0.9856474 * n)
    g = np.radians(357.528 + 0.9856003 * n)  # mean anomaly
    ecliptic_longitude = mean_longitude + np.radians(1.915 * np.sin(g) + 0.020 * np.sin(2.0 * g))
    obliquity = np.radians(23.439 - 0.0000004 * n)
    ra = np.arctan2(np.cos(obliquity) * np.sin(ecliptic_longitude), np.cos(ecliptic_longitude))
    dec = np.arcsin(np.sin(obliquity) * np.sin(ecliptic_longitude))
    return np.degrees(ra) % 360.0, np.degrees(dec)


def hour_angle_deg(utc: Sequence[datetime], longitude_deg: ArrayLike) -> NDArray[np.float64]:
    """The sun's local hour angle in [-180, 180) (deg, positive west of the meridian: afternoon)."""
    ra, _ = right_ascension_declination_deg(utc)
    h: NDArray[np.float64] = (gmst_deg(utc) + np.asarray(longitude_deg, float) - ra + 180.0) % 360.0 - 180.0
    return h


def elevation_deg(utc: Sequence[datetime], latitude_deg: ArrayLike, longitude_deg: ArrayLike) -> NDArray[np.float64]:
    """The sun's geometric elevation above the horizon (deg) at each time and geodetic site (arrays broadcast)."""
    _, dec = np.radians(right_ascension_declination_deg(utc))
    h = np.radians(hour_angle_deg(utc, longitude_deg))
    lat = np.radians(np.asarray(latitude_deg, float))
    sin_elevation = np.sin(lat) * np.sin(dec) + np.cos(lat) * np.cos(dec) * np.cos(h)
    elevation: NDArray[np.float64] = np.degrees(np.arcsin(np.clip(sin_elevation, -1.0, 1.0)))  # round-off passes 1
    return elevation


def local_solar_time_h(utc: Sequence[datetime], longitude_deg: ArrayLike) -> NDArray[np.float64]:
    """Local apparent solar time (hours in [0, 24)): 12 h when the sun crosses the site's meridian."""
    return (12.0 + hour_angle_deg(utc, longitude_deg) / 15.0) % 24.0


def equation_of_time_min(utc: Sequence[datetime]) -> NDArray[np.float64]:
    """Apparent minus mean solar time (minutes): the mean sun's right ascension less the true sun's."""
    n = _days_from_j2000(utc)
    ra, _ = right_ascension_declination_deg(utc)
    return ((280.460 + 0.9856474 * n - ra + 180.0) % 360.0 - 180.0) * 4.0


def night_intervals(
    start: datetime, end: datetime, latitude_deg: float, longitude_deg: float, step_s: float = 60.0
) -> list[tuple[datetime, datetime]]:
    """The spans of [start, end] when the sun is below DAYLIGHT_ELEVATION_DEG at the site, to `step_s`."""
    count = int((end - start).total_seconds() // step_s) + 1
    times = [start + timedelta(seconds=k * step_s) for k in range(count)]
    dark = elevation_deg(times, latitude_deg, longitude_deg) < DAYLIGHT_ELEVATION_DEG
    edges = np.flatnonzero(np.diff(np.concatenate([[0], dark.astype(np.int8), [0]])))
    return [(times[a], times[b - 1]) for a, b in zip(edges[::2], edges[1::2])]
