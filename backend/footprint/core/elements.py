"""Orbits from real elements (issue 28, step 1): a two-line element set checked and parsed, propagated by SGP4 (the
maintained `sgp4` package: Vallado, Crawford, Hujsak & Kelso, "Revisiting Spacetrack Report #3", AIAA 2006-6753),
its TEME position turned earth-fixed by Greenwich mean sidereal time, and the sub-satellite point.

Time scales from skyfield's bundled data (core.utc: leap seconds, UT1 - UTC; nothing is fetched at run time). TEME
to earth-fixed is the rotation by GMST about the pole (AIAA 2006-6753 sec. IV-C, polar motion neglected: under
20 m); skyfield's GMST is IAU 2006's, within 1e-5 deg of the 1982 formula SGP4 assumes.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from footprint.core import constants as c
from footprint.core.errors import InputError
from footprint.core.frames import geodetic_from_ecef
from footprint.core.utc import iso, times

FT_PER_KM = 1000.0 * c.FT_PER_M
LINE_CHARS = 69  # a TLE line, its checksum digit last
J2000_JD = 2451545.0


def checksum(line: str) -> int:
    """A TLE line's check digit: its first 68 characters' digits summed, each minus sign counting 1, modulo 10."""
    return sum(int(ch) if ch in "0123456789" else ch == "-" for ch in line[: LINE_CHARS - 1]) % 10


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
    revolution_number: int | None = None  # at epoch (line 2 columns 64-68)

    @property
    def earth(self) -> c.Earth:
        """SGP4's earth: the elements are fitted with WGS-72's constants, and its states belong with them."""
        return c.WGS72

    @functools.cached_property
    def satrec(self) -> Any:
        from sgp4.api import Satrec

        return Satrec.twoline2rv(self.line1, self.line2)

    def teme_km(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """SGP4's TEME position (km, n x 3) and velocity (km/s) at each UTC time; an error of SGP4 (a decayed orbit)
        names the first time it happens. SGP4 counts time from its epoch in UTC's Julian dates (AIAA 2006-6753), so
        a leap second's 23:59:60 is its 23:59:59."""
        from sgp4.api import SGP4_ERRORS, jday

        days = np.array([jday(t.year, t.month, t.day, t.hour, t.minute, t.second + t.microsecond * 1e-6) for t in utc])
        err, r, v = self.satrec.sgp4_array(np.ascontiguousarray(days[:, 0]), np.ascontiguousarray(days[:, 1]))
        bad = np.flatnonzero(err)
        if bad.size:
            raise InputError("tle", f"SGP4 fails at {iso(utc[bad[0]])}: {SGP4_ERRORS[int(err[bad[0]])]}")
        return r, v


class Orbit(Protocol):
    """What the landing opportunities read of an orbit: its epoch and a few of its elements, its TEME state at any UTC
    time of a window (Elements by SGP4; deorbit.PropagatedState by our integrator), and the earth it belongs to (its
    coast is flown in that earth's gravity)."""

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
    @property
    def revolution_number(self) -> int | None: ...
    @property
    def earth(self) -> c.Earth: ...
    def teme_km(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...


@dataclass(frozen=True)
class TleField:
    """A field of the element lines: its line, first and last column (from 1, as the format numbers them), its
    characters (a regular expression of the whole field, and in words) and its range if bounded."""

    line: int
    first: int
    last: int
    name: str
    pattern: str
    allowed: str
    low: float | None = None
    high: float | None = None
    unit: str = ""

    def text(self, line: str) -> str:
        return line[self.first - 1 : self.last]

    @property
    def where(self) -> str:
        columns = f"column {self.first}" if self.first == self.last else f"columns {self.first}-{self.last}"
        return f"line {self.line} {columns} ({self.name})"


# The column layout: T. S. Kelso, "NORAD Two-Line Element Set Format" (CelesTrak), as sgp4io.cpp (AIAA 2006-6753) reads
# it. Its templates: N a digit (a number's leading zeros may be blanks), A a letter, '+' a sign or a blank, '-' a
# sign; an "assumed" decimal point leads the digits. "All other columns are blank or fixed."
_NUMBER = "N a digit, blanks before the first"
_ANGLE, _ANGLE_WORDS = r" *\d+\.\d{4}", f"'NNN.NNNN' ({_NUMBER})"
_EXPONENTIAL = r"[ +-]\d{5}[+-]\d| {8}"  # the digits after an assumed point, then the power of ten; blank: none
_EXPONENTIAL_WORDS = "'+NNNNN-N' (+ a sign or a blank, N a digit, - the exponent's sign) or blanks"
_SATELLITE = r" *\d+|[A-HJ-NP-Z]\d{4}"  # Alpha-5 (CelesTrak): a letter but I and O for the ten-thousands past 99,999
_SATELLITE_WORDS = f"'NNNNN' ({_NUMBER}) or Alpha-5's 'ANNNN' (A a capital letter but I and O)"
TLE_FIELDS = (
    TleField(1, 3, 7, "satellite number", _SATELLITE, _SATELLITE_WORDS),
    TleField(1, 8, 8, "classification", r"[UCS ]", "'U', 'C', 'S' or a blank"),
    TleField(1, 10, 17, "international designator", r"[\d ]{5}[A-Z ]{3}", "'NNNNNAAA' (A a capital letter) or blanks"),
    TleField(1, 19, 20, "epoch year", r"\d\d", "'NN' (N a digit)"),
    TleField(1, 21, 32, "epoch day", r" *\d+\.\d{8}", f"'NNN.NNNNNNNN' ({_NUMBER})"),
    TleField(1, 34, 43, "mean motion's first derivative / 2", r"[ +-]\.\d{8}", "'+.NNNNNNNN' (+ a sign or a blank)"),
    TleField(1, 45, 52, "mean motion's second derivative / 6", _EXPONENTIAL, _EXPONENTIAL_WORDS),
    TleField(1, 54, 61, "BSTAR drag term", _EXPONENTIAL, _EXPONENTIAL_WORDS),
    TleField(1, 63, 63, "ephemeris type", r"[\d ]", "a digit or a blank"),
    TleField(1, 65, 68, "element set number", r" *\d*", f"'NNNN' ({_NUMBER})"),
    TleField(2, 3, 7, "satellite number", _SATELLITE, _SATELLITE_WORDS),
    TleField(2, 9, 16, "inclination", _ANGLE, _ANGLE_WORDS, 0.0, 180.0, "deg"),
    TleField(2, 18, 25, "right ascension of the ascending node", _ANGLE, _ANGLE_WORDS, 0.0, 360.0, "deg"),
    TleField(2, 27, 33, "eccentricity", r"\d{7}", "'NNNNNNN' (7 digits after an assumed point: 0 to 0.9999999)"),
    TleField(2, 35, 42, "argument of perigee", _ANGLE, _ANGLE_WORDS, 0.0, 360.0, "deg"),
    TleField(2, 44, 51, "mean anomaly", _ANGLE, _ANGLE_WORDS, 0.0, 360.0, "deg"),
    TleField(2, 53, 63, "mean motion", r" *\d+\.\d{8}", f"'NN.NNNNNNNN' ({_NUMBER})"),
    TleField(2, 64, 68, "revolution number at epoch", r" *\d*", f"'NNNNN' ({_NUMBER})"),
)
BLANK_COLUMNS = {1: (9, 18, 33, 44, 53, 62, 64), 2: (8, 17, 26, 34, 43, 52)}  # the columns between fields
_BY_NAME = {(f.line, f.name): f for f in TLE_FIELDS}
EPOCH_DAY, ECCENTRICITY = _BY_NAME[1, "epoch day"], _BY_NAME[2, "eccentricity"]
MEAN_MOTION = _BY_NAME[2, "mean motion"]


def perigee_radius_km(mean_motion_rev_day: float, eccentricity: float) -> float:
    """The two-body perigee radius a (1 - e) (km), a by Kepler's third law n^2 a^3 = mu with SGP4's WGS-72 mu (the
    Kozai mean motion taken as two-body's: within 3 km of SGP4's own perigee, J2's share of a)."""
    n_rad_s = mean_motion_rev_day * 2.0 * math.pi / 86_400.0
    radius_km: float = (c.WGS72.mu_km3_s2 / n_rad_s**2) ** (1.0 / 3.0) * (1.0 - eccentricity)
    return radius_km


def mean_motion_range_rev_day(eccentricity: float) -> tuple[float, float]:
    """The mean motions (rev/day) of an earth orbit at this eccentricity, n = sqrt(mu (1 - e)^3 / r_p^3) from r_p =
    a (1 - e) and Kepler's third law: its perigee above the earth's surface (WGS-72's radius; faster, the orbit
    meets the ground) and within the Moon's distance (slower, the Moon's pull rivals the earth's: no earth orbit)."""

    def at_perigee(radius_km: float) -> float:
        a_km = radius_km / (1.0 - eccentricity)
        return math.sqrt(c.WGS72.mu_km3_s2 / a_km**3) * 86_400.0 / (2.0 * math.pi)

    return at_perigee(c.MOON_DISTANCE_KM), at_perigee(c.WGS72.radius_km)


def _not_ascii(text: str, label: str) -> str | None:
    """The first character of a line that is not printable ASCII (a TLE is nothing else), said with its column."""
    for column, ch in enumerate(text, 1):
        if not " " <= ch <= "~":
            what = "is not ASCII" if ord(ch) > 127 else "does not print"
            return f"{label} column {column}: {ch!r} (U+{ord(ch):04X}) {what}: a TLE is printable ASCII"
    return None


def _check_line(line: str, number: int) -> str | None:
    if len(line) != LINE_CHARS or not line.startswith(f"{number} "):
        return f"line {number} must be {LINE_CHARS} characters starting '{number} ' ({len(line)} given)"
    return None


def _layout_errors(lines: dict[int, str]) -> list[str]:
    """Each blank column that is not, each field whose characters are not its template's, each angle out of range."""
    errors = [
        f"line {n} column {k} must be blank ({lines[n][k - 1]!r} given)"
        for n, columns in BLANK_COLUMNS.items()
        for k in columns
        if lines[n][k - 1] != " "
    ]
    for f in TLE_FIELDS:
        text = f.text(lines[f.line])
        if not re.fullmatch(f.pattern, text):
            errors.append(f"{f.where}: {text!r} is not {f.allowed}")
        elif f.low is not None and f.high is not None and not f.low <= float(text) <= f.high:
            errors.append(f"{f.where}: {text.strip()} is outside the allowed range {f.low:g} to {f.high:g} {f.unit}")
    return errors


def _epoch_day_error(line1: str) -> str | None:
    """The epoch's day within its year: from 1 to the year's days (1957-2056: SGP4's two-digit years)."""
    year = int(line1[18:20])
    year += 1900 if year >= 57 else 2000
    days = 366 if year % 4 == 0 and (year % 100 != 0 or year % 400 == 0) else 365
    day = float(EPOCH_DAY.text(line1))
    if 1.0 <= day < days + 1:
        return None
    return f"{EPOCH_DAY.where}: {day:.8f} is outside the allowed range 1 to {days}.99999999 (the days of {year})"


def _orbit_error(line2: str) -> str | None:
    """A mean motion whose orbit, at the set's eccentricity, is an earth orbit (mean_motion_range_rev_day)."""
    n, e = float(MEAN_MOTION.text(line2)), float("0." + ECCENTRICITY.text(line2))
    slowest, fastest = mean_motion_range_rev_day(e)
    if slowest <= n <= fastest:
        return None
    perigee = f"{perigee_radius_km(n, e):,.0f} km" if n > 0.0 else "infinite"
    return (
        f"{MEAN_MOTION.where}: {n:.8f} is outside the allowed range {slowest:.6g} to {fastest:.6g} rev/day at the "
        f"eccentricity {e:.7f} (a perigee above the earth's surface, {c.WGS72.radius_km:,.3f} km from its centre, and "
        f"within the Moon's distance, {c.MOON_DISTANCE_KM:,.0f} km; this one's is {perigee})"
    )


def _check_digit_error(line: str, number: int) -> str | None:
    if line[-1] in "0123456789" and int(line[-1]) == checksum(line):
        return None
    return f"line {number}: its check digit is {line[-1]!r}, its characters give {checksum(line)}"


def check_lines(text: str, field: str = "tle") -> tuple[str | None, str, str]:
    """A TLE's name (or None) and element lines, checked as the format defines them: printable ASCII, two lines
    (three with a name first) of 69 columns, each field's characters, the angles' and the epoch day's ranges, an
    earth orbit's mean motion, the check digits and one satellite number; else one line naming `field`, each
    mistake by its line, columns and field."""
    lines = [ln.strip(" \t") for ln in re.split(r"\r\n|\r|\n", text)]
    lines = [ln for ln in lines if ln]
    if len(lines) not in (2, 3):
        raise InputError(field, f"a TLE has two lines (three with a name first); {len(lines)} given")
    labels = ("line 0 (the name)", "line 1", "line 2")[3 - len(lines) :]
    wrong = [e for ln, label in zip(lines, labels) if (e := _not_ascii(ln, label))]
    wrong = wrong or [e for number, ln in ((1, lines[-2]), (2, lines[-1])) if (e := _check_line(ln, number))]
    if wrong:
        raise InputError(field, "; ".join(wrong))
    name, line1, line2 = (lines[0] if len(lines) == 3 else None), lines[-2], lines[-1]
    wrong = _layout_errors({1: line1, 2: line2})
    if not wrong:
        wrong = [e for e in (_epoch_day_error(line1), _orbit_error(line2)) if e]
    wrong += [e for number, ln in ((1, line1), (2, line2)) if (e := _check_digit_error(ln, number))]
    if line1[2:7] != line2[2:7]:
        wrong.append(f"line 1 is satellite {line1[2:7].strip()}, line 2 satellite {line2[2:7].strip()}")
    if wrong:
        raise InputError(field, "; ".join(wrong))
    return name, line1, line2


def parse_tle(text: str, field: str = "tle") -> Elements:
    """A TLE (two lines, or three with a name first) checked (check_lines) and parsed; a mistake names `field` and
    says what is wrong."""
    name, line1, line2 = check_lines(text, field)
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
        revolution_number=int(sat.revnum),
    )


def gmst_deg(utc: Sequence[datetime]) -> NDArray[np.float64]:
    """Greenwich mean sidereal time (deg) at each UTC time, from UT1 (skyfield's bundled IERS data)."""
    return np.asarray(times(utc).gmst, float) * 15.0


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


@dataclass(frozen=True)
class UtcRange:
    """The UTC times from `first` to before `end` that an orbit can be read at, and why these."""

    first: datetime
    end: datetime
    why: str

    def check(self, t: datetime) -> datetime:
        """t as given when within the range; else ValueError, one line naming the range (an aware time near year 1
        or 9999 whose offset carries it past datetime's years has no UTC: outside too)."""
        try:
            inside = self.first <= t.astimezone(UTC) < self.end
        except OverflowError:
            inside = False
        if not inside:
            last = (self.end - timedelta(seconds=1)).isoformat()
            raise ValueError(
                f"{t.isoformat()} is outside the allowed range {self.first.isoformat()} to {last} ({self.why})"
            )
        return t


# SGP4's epochs have two-digit years, 57-99 for 1957-1999 and 00-56 for 2000-2056 (AIAA 2006-6753's reader): a window
# lies in those years. skyfield's UTC follows its leap-second table from 1972 (before, it takes TAI - 10 s, 10.8 s
# from UT1 in 1957): a state vector's epoch, turned earth-fixed by it, lies in 1972-2056. Its UT1 - UTC is measured
# from 1973 to its table's end (2027-01-23 in skyfield 1.55, IERS predictions in the last year), extrapolated after.
WINDOW_UTC = UtcRange(
    datetime(1957, 1, 1, tzinfo=UTC), datetime(2057, 1, 1, tzinfo=UTC), "SGP4's two-digit epoch years"
)
STATE_EPOCH_UTC = UtcRange(datetime(1972, 1, 1, tzinfo=UTC), WINDOW_UTC.end, "skyfield's UTC: leap seconds from 1972")

MAX_EPOCH_AGE_DAYS = 14.0  # SGP4's mean elements go stale: a window farther than this from the epoch is refused


def check_window_times(
    epoch: datetime, start: datetime, end: datetime, field: str = "window", epoch_of: str = "the elements'"
) -> None:
    """A UTC window within WINDOW_UTC, in order, and within MAX_EPOCH_AGE_DAYS of the epoch (`epoch_of` the elements
    or a state) at both ends; else one line naming `field`."""
    for name, t in (("start", start), ("end", end)):
        try:
            WINDOW_UTC.check(t)
        except ValueError as exc:
            raise InputError(f"{field}.{name}", str(exc)) from exc
    if end <= start:
        raise InputError(f"{field}.end", f"{end.isoformat()} is not after the start {start.isoformat()}")
    for name, t in (("start", start), ("end", end)):
        days = abs((t - epoch).total_seconds()) / 86400.0
        if days > MAX_EPOCH_AGE_DAYS:
            raise InputError(
                f"{field}.{name}",
                f"{t.isoformat()} is {days:,.1f} days from {epoch_of} epoch {epoch.isoformat()} "
                f"(at most {MAX_EPOCH_AGE_DAYS:g}: take a newer one)",
            )


def check_window(orbit: Orbit, start: datetime, end: datetime, field: str = "window") -> None:
    """A UTC window the orbit can answer for: its times (check_window_times) and the orbit not decayed before its
    end (its propagation says so); else one line naming `field`."""
    check_window_times(orbit.epoch, start, end, field)
    hours = max(1, math.ceil((end - start).total_seconds() / 3600.0))
    try:
        orbit.teme_km([start + (end - start) * k / hours for k in range(hours + 1)])
    except InputError as exc:
        raise InputError(field, f"the orbit does not last the window: {str(exc).split(': ', 1)[1]}") from exc
