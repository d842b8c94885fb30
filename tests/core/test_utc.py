"""The opportunities' times (core/utc.py, issue 52 item 2) against the published leap second of 2016-12-31: TAI - UTC
was 36 s to 23:59:60 and is 37 s from 2017-01-01 00:00:00 (IERS Bulletin C 52), typed here; the expected labels are
worked out from it with plain datetime arithmetic, not skyfield. Written to the millisecond, rounded to the nearest
(they were cut to the whole second: burns 0-1 s early, entry and landing 1 s late across the leap second)."""

from datetime import UTC, datetime, timedelta, timezone

import pytest

from footprint.core import utc

LEAP_DAY = datetime(2016, 12, 31, tzinfo=UTC)
AFTER_LEAP = datetime(2017, 1, 1, tzinfo=UTC)


def tai_minus_utc_s(label: datetime) -> float:
    """IERS Bulletin C 52: 36 s until the leap second, 37 s from 2017-01-01 00:00:00 UTC."""
    return 37.0 if label >= AFTER_LEAP else 36.0


def label_after(start: datetime, seconds: float) -> datetime:
    """The UTC label `seconds` of SI time after `start` (not in the leap second itself), from TAI = UTC + step."""
    tai = start + timedelta(seconds=tai_minus_utc_s(start) + seconds)  # naive TAI "label"
    before = tai - timedelta(seconds=36.0)
    return before if before < LEAP_DAY + timedelta(days=1) else tai - timedelta(seconds=37.0)


@pytest.mark.parametrize("seconds", [10.0, 29.5, 31.0, 95.25, 3_600.0])  # from 23:59:30: before, past, long past
def test_an_elapsed_time_across_the_leap_second_is_labelled_by_the_true_utc(seconds):
    start = datetime(2016, 12, 31, 23, 59, 30, tzinfo=UTC)
    (got,) = utc.after_s(start, [seconds])
    expected = label_after(start, seconds)
    assert got == expected and utc.iso(got) == expected.isoformat(timespec="milliseconds").replace("+00:00", "Z")
    assert utc.elapsed_s(start, [got])[0] == pytest.approx(seconds, abs=1e-6)  # and back


def test_the_leap_second_itself_is_second_60():
    start = datetime(2016, 12, 31, 23, 59, 59, 250_000, tzinfo=UTC)
    inside, after = utc.after_s(start, [1.0, 2.0])
    assert utc.isos([inside, after]) == ["2016-12-31T23:59:60.250Z", "2017-01-01T00:00:00.250Z"]
    assert utc.parse_iso("2016-12-31T23:59:60.250Z") == inside and utc.parse_iso("2016-12-31T23:59:60.250Z").fold == 1
    assert utc.elapsed_s(start, [utc.parse_iso("2016-12-31T23:59:60.250Z")])[0] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(
    ("t", "written"),
    [
        (datetime(2008, 9, 21, 0, 18, 18, 380_600, tzinfo=UTC), "2008-09-21T00:18:18.381Z"),  # nearest, not cut
        (datetime(2008, 9, 21, 0, 18, 18, 380_400, tzinfo=UTC), "2008-09-21T00:18:18.380Z"),
        (datetime(2008, 9, 21, 23, 59, 59, 999_600, tzinfo=UTC), "2008-09-22T00:00:00.000Z"),
        (datetime(2016, 12, 31, 23, 59, 59, 999_600, tzinfo=UTC), "2016-12-31T23:59:60.000Z"),  # a leap second next
        (datetime(2008, 9, 21, 2, 0, tzinfo=timezone(timedelta(hours=2))), "2008-09-21T00:00:00.000Z"),
    ],
)
def test_every_time_is_written_to_the_nearest_millisecond(t, written):
    assert utc.iso(t) == written
    assert utc.iso(utc.rounded(t, 1e-3)) == written


def test_an_ordinary_day_counts_as_its_labels():
    start = datetime(2008, 9, 21, tzinfo=UTC)
    times = [start + timedelta(seconds=s) for s in (0.0, 0.001, 86_399.999)]
    assert list(utc.elapsed_s(start, times)) == pytest.approx([0.0, 0.001, 86_399.999], abs=1e-6)
    assert utc.after_s(start, [0.001, 86_399.999]) == times[1:]
