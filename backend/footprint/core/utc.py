"""UTC times of the landing opportunities (issue 52 item 2): a time is an aware datetime in UTC; an elapsed time (a
coast, a flight, a propagation) is SI seconds, added in TAI by skyfield's leap-second table, so a time past a leap
second is labelled by the true UTC; every time is written by `isos`, to the millisecond, rounded to the nearest.

Time scales from skyfield's bundled data (`load.timescale(builtin=True)`: leap seconds and UT1 - UTC, nothing
fetched). A datetime has no second 60: an instant inside a leap second is held as its 23:59:59.xxx with fold=1
(datetime's flag for a wall time that repeats); `times` reads it and `isos` writes 23:59:60.xxx.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from datetime import UTC, datetime, timedelta
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

DAY_S = 86_400.0
TAI_EPOCH_JD = 2451545.0  # seconds of TAI are counted from JD 2451545.0 TAI (2000-01-01 12:00:00 TAI)


@functools.cache
def timescale() -> Any:
    """skyfield's time scale from the files it ships (no download)."""
    from skyfield.api import load

    return load.timescale(builtin=True)


def _in_leap_second(t: datetime) -> bool:
    """A 23:59:59.xxx held with fold=1 before a leap second: the leap second's 60.xxx."""
    if t.fold != 1 or (t.hour, t.minute, t.second) != (23, 59, 59):
        return False
    ts = timescale()
    tai = ts.from_datetimes([t, t + timedelta(seconds=1)])
    return bool((tai.whole[1] - tai.whole[0] + tai.tai_fraction[1] - tai.tai_fraction[0]) * DAY_S > 1.5)


def times(utc: Sequence[datetime]) -> Any:
    """skyfield's Time of each UTC time (aware; one held in a leap second is that second)."""
    aware = [u.astimezone(UTC) for u in utc]  # astimezone keeps a UTC time's fold
    t = timescale().from_datetimes(aware)
    leap = np.array([_in_leap_second(u) for u in aware], float)
    if leap.any():
        t = timescale().tai_jd(t.whole, t.tai_fraction + leap / DAY_S)
    return t


def tai_s(utc: Sequence[datetime]) -> NDArray[np.float64]:
    """Seconds of TAI from TAI_EPOCH_JD at each UTC time (to 1e-7 s over this century)."""
    t = times(utc)
    seconds: NDArray[np.float64] = (np.asarray(t.whole) - TAI_EPOCH_JD) * DAY_S + np.asarray(t.tai_fraction) * DAY_S
    return seconds


def from_tai_s(seconds: ArrayLike) -> list[datetime]:
    """The UTC time (to the microsecond) of each TAI_EPOCH_JD + seconds; one inside a leap second held with fold=1."""
    seconds = np.atleast_1d(np.asarray(seconds, float))
    t = timescale().tai_jd(np.full(seconds.shape, TAI_EPOCH_JD), seconds / DAY_S)
    stamps, leaps = t.utc_datetime_and_leap_second()
    return [d.replace(fold=1) if leap else d for d, leap in zip(stamps, leaps)]


def elapsed_s(start: datetime, utc: Sequence[datetime]) -> NDArray[np.float64]:
    """SI seconds from `start` to each UTC time (a leap second between them counts)."""
    seconds: NDArray[np.float64] = tai_s(utc) - tai_s([start])[0]
    return seconds


def after_s(start: datetime, seconds: ArrayLike) -> list[datetime]:
    """The UTC time of each elapsed `seconds` (SI) after `start`."""
    return from_tai_s(tai_s([start])[0] + np.atleast_1d(np.asarray(seconds, float)))


def rounded(t: datetime, step_s: float) -> datetime:
    """The UTC time nearest t on a whole step of TAI (a second or its decimal part: UTC's steps too, their offset
    whole seconds)."""
    seconds = float(tai_s([t])[0])
    return from_tai_s([round(seconds / step_s) * step_s])[0]


def isos(utc: Sequence[datetime]) -> list[str]:
    """Each UTC time as ISO 8601 to the millisecond, rounded to the nearest ('2016-12-31T23:59:60.250Z' in a leap
    second): the one writer of the opportunities' times."""
    if not utc:
        return []
    written: list[str] = list(times(utc).utc_iso(places=3))
    return written


def iso(t: datetime) -> str:
    return isos([t])[0]


def parse_iso(text: str) -> datetime:
    """An ISO 8601 time as `isos` writes it (a 'Z' or an offset; second 60 of a leap second held as 23:59:59 with
    fold=1) as an aware UTC datetime."""
    text = text.replace("Z", "+00:00")
    leap = text[17:19] == "60"
    t = datetime.fromisoformat(text[:17] + "59" + text[19:] if leap else text).astimezone(UTC)
    return t.replace(fold=1) if leap else t
