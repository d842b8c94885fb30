"""Orbits from real elements (issue 28, step 1): a two-line element set checked and parsed, propagated by SGP4 (the
maintained `sgp4` package: Vallado, Crawford, Hujsak & Kelso, "Revisiting Spacetrack Report #3", AIAA 2006-6753),
its TEME position turned earth-fixed by Greenwich mean sidereal time, and the sub-satellite point.

Time scales from skyfield's bundled data (leap seconds, UT1 - UTC; `load.timescale(builtin=True)`: nothing is
fetched at run time). TEME to earth-fixed is the rotation by GMST about the pole (AIAA 2006-6753 sec. IV-C, polar
motion neglected: under 20 m); skyfield's GMST is IAU 2006's, within 1e-5 deg of the 1982 formula SGP4 assumes.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from footprint.core import constants as c
from footprint.core.errors import InputError
from footprint.core.frames import geodetic_from_ecef

FT_PER_KM = 1000.0 * c.FT_PER_M
LINE_CHARS = 69  # a TLE line, its checksum digit last
J2000_JD = 2451545.0


@functools.cache
def timescale() -> Any:
    """skyfield's time scale from the files it ships (no download)."""
    from skyfield.api import load

    return load.timescale(builtin=True)


def checksum(line: str) -> int:
    """A TLE line's check digit: its first 68 characters' digits summed, each minus sign counting 1, modulo 10."""
    return sum(int(ch) if ch.isdigit() else ch == "-" for ch in line[: LINE_CHARS - 1]) % 10


@dataclass(frozen=True)
class Elements:
    """A two-line element set: its lines as given and the mean elements they hold (epoch in UTC)."""

    name: str | None
    line1: str
    line2: str
    satellite_number: int | None
    epoch: datetime
    inclination_deg: float
    right_ascension_deg: float
    eccentricity: float
    argument_of_perigee_deg: float
    mean_anomaly_deg: float
    mean_motion_rev_day: float
    bstar: float

    @functools.cached_property
    def satrec(self) -> Any:
        from sgp4.api import Satrec

        return Satrec.twoline2rv(self.line1, self.line2)

    def teme_km(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """SGP4's TEME position (km, n x 3) and velocity (km/s) at each UTC time; an error of SGP4 (a decayed orbit)
        names the first time it happens."""
        from sgp4.api import SGP4_ERRORS, jday

        days = np.array([jday(t.year, t.month, t.day, t.hour, t.minute, t.second + t.microsecond * 1e-6) for t in utc])
        err, r, v = self.satrec.sgp4_array(np.ascontiguousarray(days[:, 0]), np.ascontiguousarray(days[:, 1]))
        bad = np.flatnonzero(err)
        if bad.size:
            raise InputError("tle", f"SGP4 fails at {utc[bad[0]].isoformat()}: {SGP4_ERRORS[int(err[bad[0]])]}")
        return r, v


class Orbit(Protocol):
    """What the landing opportunities read of an orbit: its epoch and a few of its elements, and its TEME state at
    any UTC time of a window (Elements by SGP4; deorbit.PropagatedState by our integrator)."""

    @property
    def name(self) -> str | None: ...
    @property
    def satellite_number(self) -> int | None: ...
    @property
    def epoch(self) -> datetime: ...
    @property
    def inclination_deg(self) -> float: ...
    @property
    def eccentricity(self) -> float: ...
    @property
    def mean_motion_rev_day(self) -> float: ...
    def teme_km(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...


def _check_line(line: str, number: int, field: str) -> None:
    if len(line) != LINE_CHARS or not line.startswith(f"{number} "):
        raise InputError(
            field, f"line {number} must be {LINE_CHARS} characters starting '{number} ' ({len(line)} given)"
        )
    digit = line[-1]
    if not digit.isdigit() or int(digit) != checksum(line):
        raise InputError(field, f"line {number}: its check digit is {digit!r}, its characters give {checksum(line)}")


def parse_tle(text: str, field: str = "tle") -> Elements:
    """A TLE (two lines, or three with a name first) checked (lengths, line numbers, check digits, one satellite
    number) and parsed; a mistake names `field` and says what is wrong."""
    lines = [ln.rstrip() for ln in text.strip().splitlines() if ln.strip()]
    if len(lines) not in (2, 3):
        raise InputError(field, f"a TLE has two lines (three with a name first); {len(lines)} given")
    name = lines[0].strip() if len(lines) == 3 else None
    line1, line2 = lines[-2], lines[-1]
    _check_line(line1, 1, field)
    _check_line(line2, 2, field)
    if line1[2:7] != line2[2:7]:
        raise InputError(field, f"line 1 is satellite {line1[2:7].strip()}, line 2 satellite {line2[2:7].strip()}")
    try:
        from sgp4.api import Satrec

        sat = Satrec.twoline2rv(line1, line2)
    except ValueError as exc:
        raise InputError(field, f"the elements cannot be read ({exc})") from exc
    epoch = datetime(1949, 12, 31, tzinfo=UTC) + timedelta(days=sat.jdsatepoch - 2433281.5 + sat.jdsatepochF)
    return Elements(
        name=name,
        line1=line1,
        line2=line2,
        satellite_number=int(sat.satnum),
        epoch=epoch,
        inclination_deg=math.degrees(sat.inclo),
        right_ascension_deg=math.degrees(sat.nodeo),
        eccentricity=float(sat.ecco),
        argument_of_perigee_deg=math.degrees(sat.argpo),
        mean_anomaly_deg=math.degrees(sat.mo),
        mean_motion_rev_day=sat.no_kozai * 1440.0 / (2.0 * math.pi),
        bstar=float(sat.bstar),
    )


def gmst_deg(utc: Sequence[datetime]) -> NDArray[np.float64]:
    """Greenwich mean sidereal time (deg) at each UTC time, from UT1 (skyfield's bundled IERS data)."""
    t = timescale().from_datetimes([u.astimezone(UTC) for u in utc])
    return np.asarray(t.gmst, float) * 15.0


def _turned(a: NDArray[np.float64], theta_rad: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rows of a turned by theta about the pole (each row its own angle)."""
    ct, st = np.cos(theta_rad), np.sin(theta_rad)
    out: NDArray[np.float64] = np.column_stack([ct * a[:, 0] - st * a[:, 1], st * a[:, 0] + ct * a[:, 1], a[:, 2]])
    return out


def teme_to_earth_fixed(
    r_km: NDArray[np.float64], v_km_s: NDArray[np.float64], utc: Sequence[datetime], omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """TEME states (km, km/s; n x 3) as earth-fixed position (ft) and earth-relative velocity (ft/s): turned by -GMST
    about the pole, the earth's turning omega x r taken away (AIAA 2006-6753 sec. IV-C, polar motion neglected)."""
    theta = -np.radians(gmst_deg(utc))
    r, v = _turned(r_km, theta) * FT_PER_KM, _turned(v_km_s, theta) * FT_PER_KM
    v[:, 0] += omega_rad_s * r[:, 1]
    v[:, 1] -= omega_rad_s * r[:, 0]
    return r, v


def earth_fixed_to_teme(
    r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64], utc: Sequence[datetime], omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The inverse of teme_to_earth_fixed: TEME position (km) and velocity (km/s)."""
    v = v_rel_fps.copy()
    v[:, 0] -= omega_rad_s * r_ft[:, 1]
    v[:, 1] += omega_rad_s * r_ft[:, 0]
    theta = np.radians(gmst_deg(utc))
    return _turned(r_ft, theta) / FT_PER_KM, _turned(v, theta) / FT_PER_KM


def earth_fixed_ft(orbit: Orbit, utc: Sequence[datetime]) -> NDArray[np.float64]:
    """The satellite's earth-fixed position (ft, n x 3)."""
    r, v = orbit.teme_km(utc)
    return teme_to_earth_fixed(r, v, utc, 0.0)[0]


def subsatellite_points(
    orbit: Orbit,
    utc: Sequence[datetime],
    re_ft: float = c.RADIUS_EQUATORIAL_FT,
    rp_ft: float = c.RADIUS_POLAR_FT,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Geodetic latitude and longitude (deg) of the point under the satellite, and its altitude (ft), on the
    report's oblate earth (App. A) unless other radii are given."""
    out = np.array([geodetic_from_ecef(x, y, z, re_ft, rp_ft, True, 3) for x, y, z in earth_fixed_ft(orbit, utc)])
    return np.degrees(out[:, 0]), np.degrees(out[:, 1]), out[:, 2]


MAX_EPOCH_AGE_DAYS = 14.0  # SGP4's mean elements go stale: a window farther than this from the epoch is refused


def check_window(orbit: Orbit, start: datetime, end: datetime, field: str = "window") -> None:
    """A UTC window the orbit can answer for: in order, within MAX_EPOCH_AGE_DAYS of the epoch at both ends, and
    the orbit not decayed before its end (its propagation says so); else one line naming `field`."""
    if end <= start:
        raise InputError(f"{field}.end", f"{end.isoformat()} is not after the start {start.isoformat()}")
    for name, t in (("start", start), ("end", end)):
        days = abs((t - orbit.epoch).total_seconds()) / 86400.0
        if days > MAX_EPOCH_AGE_DAYS:
            raise InputError(
                f"{field}.{name}",
                f"{t.isoformat()} is {days:,.1f} days from the elements' epoch {orbit.epoch.isoformat()} "
                f"(at most {MAX_EPOCH_AGE_DAYS:g}: take a newer element set)",
            )
    hours = max(1, math.ceil((end - start).total_seconds() / 3600.0))
    try:
        orbit.teme_km([start + (end - start) * k / hours for k in range(hours + 1)])
    except InputError as exc:
        raise InputError(field, f"the orbit does not last the window: {str(exc).split(': ', 1)[1]}") from exc
