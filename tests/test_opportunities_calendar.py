"""The landing opportunities' iCalendar (issue 49 item 3): written by the `icalendar` package (RFC 5545's escaping and
folding), a site's name unable to break a line. The hand-written writer escaped only backslash, semicolon, comma and
LF: a CR, VT, FF, NEL or U+2028/2029 in a name reached the file, and a reader that breaks lines there read the
name's SUMMARY: and ATTACH: as properties of their own."""

import re
from datetime import UTC, datetime

import pytest
from icalendar import Calendar

from footprint.contracts.opportunities import opportunities_ics

EPOCH = "2008-09-20T12:25:40.104Z"  # the example TLE's
# each ends a line for some reader: CR and LF (RFC 5545), VT, FF, NEL, U+2028 and U+2029 (Unicode's line breaks)
BREAKS = ("\r", "\n", "\x0b", "\x0c", "\x85", "\u2028", "\u2029")
INJECTED = ("SUMMARY:evil", "ATTACH")


def _lines(ics: str) -> list[str]:
    """The file's lines as a reader that breaks at any of BREAKS reads them."""
    return re.split("|".join(map(re.escape, ("\r\n", *BREAKS))), ics)


def _opportunity(site: int, name: str, meets_rules: bool = True) -> dict:
    return {
        "site": site, "site_name": name, "revolution": 3, "revolution_number": 56358, "meets_rules": meets_rules,
        "burn_utc": f"2008-09-21T00:{10 + site:02d}:00Z", "entry_utc": f"2008-09-21T00:{30 + site:02d}:00Z",
        "landing_utc": f"2008-09-21T00:{50 + site:02d}:30Z", "delta_v_fps": 409.1, "downrange_nmi": 4000.0,
        "crossrange_nmi": 100.0, "margin_nmi": 250.0, "downrange_margin_nmi": 120.0, "crossrange_margin_nmi": 80.0,
        "sun_elevation_deg": 12.5, "local_solar_time_h": 9.25,
    }  # fmt: skip


def _answer(names: list[str]) -> dict:
    found = [_opportunity(i, name) for i, name in enumerate(names)] + [_opportunity(len(names), "Night", False)]
    return {"elements": {"satellite_number": 25544, "epoch_utc": EPOCH}, "opportunities": found}


HOSTILE = [f"Edwards{ch}SUMMARY:evil{ch}ATTACH:http://x" for ch in BREAKS] + [
    "Edwards\r\nSUMMARY:evil\r\nEND:VCALENDAR",
    "Moron Air Base, Spain; \\ and a long name past the fold: Base a\u00e9rienne d'\u00c9vreux \u2014 \u00e9t\u00e9",
    "Edwards\x00\x1b[31m\x7fAFB",
]


def test_a_site_name_cannot_break_a_line_of_the_calendar():
    ics = opportunities_ics(_answer(HOSTILE), made_utc=datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC))
    data = ics.encode()
    assert data.count(b"\n") == data.count(b"\r\n") == data.count(b"\r")  # CRLF only
    for ch in BREAKS[2:] + ("\x00", "\x1b", "\x7f"):
        assert ch not in ics, repr(ch)
    lines = _lines(ics)
    assert not [line for line in lines if line.startswith(INJECTED)]
    assert lines.count("END:VCALENDAR") == 1 and sum(line.startswith("SUMMARY:") for line in lines) == len(HOSTILE)
    assert all(len(line) <= 75 for line in data.split(b"\r\n"))  # RFC 5545 3.1: folded at 75 octets
    events = Calendar.from_ical(ics).walk("VEVENT")
    assert len(events) == len(HOSTILE)  # the one that does not meet the rules left out
    for i, (event, name) in enumerate(zip(events, HOSTILE)):
        summary = str(event["SUMMARY"])
        visible = [part for part in re.split("[\x00-\x1f\x7f\x85\u2028\u2029]", name) if part]
        assert all(part in summary for part in visible), (summary, visible)
        assert summary.startswith("Landing at ") and summary.endswith(", revolution 56358")
        assert event.decoded("DTSTART") == datetime(2008, 9, 21, 0, 10 + i, tzinfo=UTC)
        assert event.decoded("DTEND") == datetime(2008, 9, 21, 0, 50 + i, 30, tzinfo=UTC)
        assert event.decoded("DTSTAMP") == datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)
        assert "deorbit burn 409.1 ft/s at 2008-09-21T00:" in str(event["DESCRIPTION"])
        assert "margin 250 nmi (120 nmi along the down-range, 80 nmi across)" in str(event["DESCRIPTION"])
    calendar = Calendar.from_ical(ics)
    assert (str(calendar["VERSION"]), str(calendar["CALSCALE"])) == ("2.0", "GREGORIAN")
    assert str(calendar["PRODID"]) == "-//Footprint//landing opportunities//EN"


@pytest.mark.parametrize("ch", BREAKS)
def test_each_line_break_alone_is_no_line_of_its_own(ch):
    ics = opportunities_ics(_answer([f"Edwards{ch}ATTACH:http://x"]))
    assert not [line for line in _lines(ics) if line.startswith(INJECTED)], repr(ics)


def test_the_events_are_to_the_nearest_second_and_their_words_to_the_millisecond():
    """RFC 5545's DATE-TIME (3.3.5) has no fraction of a second: DTSTART and DTEND are the burn and the landing rounded
    to the nearest second (they were cut); the description keeps the milliseconds. A landing in a leap second is
    written 23:59:59 (no datetime holds second 60; its nearest second is 23:59:60)."""
    day = "2016-12-31T23:"
    o = _opportunity(0, "Edwards") | {"burn_utc": f"{day}10:00.600Z", "entry_utc": f"{day}34:00.250Z",
                                       "landing_utc": f"{day}59:60.300Z"}  # fmt: skip
    late = _opportunity(1, "Woomera") | {"burn_utc": f"{day}20:00.499Z", "landing_utc": f"{day}59:60.700Z"}
    ics = opportunities_ics({"elements": {"satellite_number": 25544, "epoch_utc": EPOCH}, "opportunities": [o, late]})
    first, second = Calendar.from_ical(ics).walk("VEVENT")
    assert first.decoded("DTSTART") == datetime(2016, 12, 31, 23, 10, 1, tzinfo=UTC)
    assert first.decoded("DTEND") == datetime(2016, 12, 31, 23, 59, 59, tzinfo=UTC)
    assert second.decoded("DTSTART") == datetime(2016, 12, 31, 23, 20, 0, tzinfo=UTC)
    assert second.decoded("DTEND") == datetime(2017, 1, 1, 0, 0, 0, tzinfo=UTC)
    words = str(first["DESCRIPTION"])
    assert all(t in words for t in ("2016-12-31T23:10:00.600Z", "2016-12-31T23:34:00.250Z", "2016-12-31T23:59:60.300Z"))


def _uids(answer: dict) -> dict[str, str]:
    return {str(e["SUMMARY"]): str(e["UID"]) for e in Calendar.from_ical(opportunities_ics(answer)).walk("VEVENT")}


def test_a_uid_is_the_site_revolution_and_landing_day_and_its_sequence_the_elements_epoch():
    """Issue 52 item 4: the UID held the site's place in the list and the burn's second, so a re-plan (sites reordered,
    a burn a few seconds later) made new events beside the old. Now the same for either; a new one for another
    revolution, landing day or site (names alike in ASCII kept apart); SEQUENCE grows with the elements' epoch (in
    minutes: 2008-09-20 12:25 is 18,890 days and 745 minutes, 27,202,345 minutes, after 1957-01-01; a day later
    1,440 more)."""
    names = ["Edwards AFB", "Woomera", "Moron Air Base", "Mor\u00f3n Air Base"]
    base = _uids(_answer(names))
    assert len(set(base.values())) == len(names)
    moved = _answer(names[::-1])
    for o in moved["opportunities"]:
        o["burn_utc"] = o["burn_utc"].replace(":00Z", ":07.250Z")
    assert _uids(moved) == base
    for change in ({"revolution_number": 56359}, {"landing_utc": "2008-09-22T00:50:30Z"}):
        changed = _answer(names)
        changed["opportunities"][0] |= change
        assert (
            _uids(changed)[f"Landing at {names[0]}, revolution {changed['opportunities'][0]['revolution_number']}"]
            != base[f"Landing at {names[0]}, revolution 56358"]
        )
    events = Calendar.from_ical(opportunities_ics(_answer(names[:1]))).walk("VEVENT")
    assert int(events[0]["SEQUENCE"]) == 27_202_345
    later = _answer(names[:1]) | {"elements": {"satellite_number": 25544, "epoch_utc": "2008-09-21T12:25:40Z"}}
    assert int(Calendar.from_ical(opportunities_ics(later)).walk("VEVENT")[0]["SEQUENCE"]) == 27_202_345 + 1_440


def test_two_passes_in_one_revolution_have_two_uids():
    """Two passes of one site whose burns fall in one revolution, landing the same day (Mataveri on the example's
    day: burns 09:23:01 and 10:54:17, 9 s after and 8 s before the revolution's nodes): one UID each."""
    answer = _answer(["Mataveri", "Mataveri"])
    uids = [str(e["UID"]) for e in Calendar.from_ical(opportunities_ics(answer)).walk("VEVENT")]
    assert len(uids) == len(set(uids)) == 2
