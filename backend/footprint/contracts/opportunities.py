"""The landing opportunities contract (issue 28): a TLE, a UTC window, sites, the deorbit burn and a footprint study;
one part per revolution (footprint.core.opportunities), combined into the opportunities ranked per site.

    {"tle": "NAME\\n1 ...\\n2 ..." or "state": {"epoch", "frame": "teme" | "earth_fixed", "position_km",
     "velocity_km_s"}, "window": {"start": "2008-09-21T00:00:00Z", "hours": 24} (or "end"),
     "sites": [{"name", "latitude_deg", "longitude_deg"}, ...],
     "deorbit": {"entry_gamma_deg": -2.0} | {"delta_v_fps": 400}, "interface_altitude_ft": 400000,
     "footprint": a footprint study (its case's vehicle, controls and planet; the entry is each burn's),
     "rules": {"sun_elevation_min_deg": -0.833, "min_margin_nmi": 0},
     "burn_step_s": 30, "ring_step_deg": 10, "screen_nmi": 200, "refly": "near"}
"""

from __future__ import annotations

import csv
import functools
import hashlib
import io
import re
import unicodedata
from collections import Counter
from datetime import UTC, datetime, timedelta
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import AfterValidator, AwareDatetime, Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.case import Case
from footprint.contracts.doors import door_limit, validated
from footprint.contracts.fields import Range, Strict
from footprint.contracts.footprint import FootprintStudy
from footprint.contracts.reach import Site
from footprint.contracts.records import csv_cell, plain
from footprint.contracts.work import OnProgress, PerStudy, RunInfo, Stored, Work
from footprint.core import deorbit as dorb
from footprint.core import opportunities as op
from footprint.core import sun
from footprint.core.constants import WGS84, Earth
from footprint.core.elements import (
    MAX_EPOCH_AGE_DAYS,
    STATE_EPOCH_UTC,
    WINDOW_UTC,
    Orbit,
    check_window,
    check_window_times,
    parse_tle,
)
from footprint.core.errors import InputError
from footprint.core.trajectory import FlightSpec
from footprint.core.utc import elapsed_s, iso, isos, parse_iso, rounded

MAX_WORK = 2e6  # burn times x sites, from the CLI or Python (14 days every 10 s for 200 sites: 2.4e7 is too many)
MAX_WORK_HTTP = 2e5  # a day every 30 s for 69 sites
NIGHT_PAST_WINDOW = timedelta(hours=3)  # a site's nights are given this far past the window: its last landings
DELTA_V_TABLE_FPS = tuple(range(250, 1_001, 50))  # the entry each Δv gives at the window's start (ft/s)
STATE_EARTH = WGS84  # a given state vector's: the earth of GPS and of most state vectors handed on
FAST_METHODS = ("single_parameter", "constant_bank", "staged", "two_parameter", "constant_altitude")


WindowTime = Annotated[AwareDatetime, AfterValidator(WINDOW_UTC.check)]


class UtcWindow(Strict):
    start: WindowTime
    end: WindowTime | None = None
    hours: Annotated[float, Range(0.1, 24 * 2 * MAX_EPOCH_AGE_DAYS, "h")] | None = None

    @model_validator(mode="after")
    def _span(self) -> UtcWindow:
        if (self.end is None) == (self.hours is None):
            raise ValueError("give exactly one of 'end' or 'hours'")
        if self.hours is not None:  # the start is in range: its end a few weeks on is a datetime
            try:
                WINDOW_UTC.check(self.bounds[1])
            except ValueError as exc:
                raise ValueError(f"hours: {self.hours:g} h after the start, the end {exc}") from exc
        return self

    @property
    def bounds(self) -> tuple[datetime, datetime]:
        start = self.start.astimezone(UTC)
        end = self.end.astimezone(UTC) if self.end is not None else start + timedelta(hours=self.hours or 0.0)
        return start, end


class DeorbitBurn(Strict):
    """A fixed retrograde Δv, or the target earth-relative flight-path angle at the interface that sets it."""

    delta_v_fps: Annotated[float, Range(1, 10_000, "ft/s")] | None = None
    entry_gamma_deg: Annotated[float, Range(-30, -0.01, "deg")] | None = None
    interface_altitude_ft: Annotated[float, Range(150_000, 1_000_000, "ft")] = dorb.INTERFACE_ALTITUDE_FT

    @model_validator(mode="after")
    def _one(self) -> DeorbitBurn:
        if (self.delta_v_fps is None) == (self.entry_gamma_deg is None):
            raise ValueError("give exactly one of 'delta_v_fps' or 'entry_gamma_deg'")
        return self


class Rules(Strict):
    """Which opportunities a planner takes: the sun at least this high at the site at landing (deg; -0.833 is
    sunrise and sunset, -6 civil twilight; none: any hour) and a margin to the footprint's boundary."""

    sun_elevation_min_deg: Annotated[float, Range(-90, 90, "deg")] | None = None
    min_margin_nmi: Annotated[float, Range(0, 10_000, "nmi")] = 0.0


class StateVector(Strict):
    """The vehicle's state at a UTC epoch: in TEME (true equator, mean equinox of date, as SGP4 gives it) or
    earth-fixed (the velocity relative to the earth); propagated by our integrator in WGS-84's gravity (its point
    mass and EGM96's J2-J4) and rotation, without drag."""

    epoch: Annotated[AwareDatetime, AfterValidator(STATE_EPOCH_UTC.check)]
    frame: Literal["teme", "earth_fixed"] = "teme"
    position_km: list[Annotated[float, Range(-100_000, 100_000, "km")]] = Field(min_length=3, max_length=3)
    velocity_km_s: list[Annotated[float, Range(-20, 20, "km/s")]] = Field(min_length=3, max_length=3)
    # the satellite and its revolution at the epoch, as its elements number them: the calendar's UIDs and the
    # opportunities' revolutions match its TLE's (without them, revolutions count from 1 at the epoch)
    satellite_number: Annotated[int, Range(0, 999_999_999, "")] | None = None
    revolution_number: Annotated[int, Range(0, 999_999_999, "")] | None = None

    def earth_fixed(self, coast: dorb.Coast) -> tuple[Any, Any]:
        """The state as the integrator flies it: earth-fixed position (ft) and earth-relative velocity (ft/s)."""
        epoch = self.epoch.astimezone(UTC)
        return dorb.state_earth_fixed(epoch, self.frame, self.position_km, self.velocity_km_s, coast.omega_rad_s)

    def propagated(self, coast: dorb.Coast, start: datetime, span_s: float) -> dorb.PropagatedState:
        """The orbit propagated in the coast's earth (STATE_EARTH) from the epoch to span_s (SI) after start."""
        r, v = self.earth_fixed(coast)
        horizon_s = float(elapsed_s(self.epoch, [start])[0]) + span_s
        return dorb.PropagatedState(self.epoch.astimezone(UTC), r, v, coast, horizon_s, self.satellite_number,
                                    self.revolution_number)  # fmt: skip


class OpportunitiesStudy(Strict):
    description: str | None = Field(default=None, max_length=4_000)
    tle: str | None = Field(default=None, min_length=1, max_length=400)
    state: StateVector | None = None
    window: UtcWindow
    sites: list[Site] = Field(min_length=1, max_length=500)
    deorbit: DeorbitBurn
    footprint: FootprintStudy
    rules: Rules = Rules()
    burn_step_s: Annotated[float, Range(1, 600, "s")] = 30.0
    ring_step_deg: Annotated[float, Range(1, 90, "deg")] = 10.0
    screen_nmi: Annotated[float, Range(0, 5_000, "nmi")] = 200.0
    refly: Literal["near", "full", "none"] = "near"
    # each opportunity also flown guided to its site from its entry, within the limits the guidance holds (the
    # footprint case's vehicle's, its alpha law, the guided law's defaults): issue 52 item 5
    guided: bool = True

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> OpportunitiesStudy:
        if self.footprint.method not in FAST_METHODS:
            raise ValueError(f"footprint.method: {self.footprint.method!r} is too slow to fly per opportunity; "
                             f"one of {', '.join(FAST_METHODS)}")  # fmt: skip
        if (self.tle is None) == (self.state is None):
            raise ValueError("give exactly one of 'tle' or 'state'")
        start, end = self.window.bounds
        if self.state is not None:  # the window checked against the epoch before the state is propagated over it
            if start < self.state.epoch:
                raise InputError("window.start", f"{iso(start)} is before the state's epoch {iso(self.state.epoch)}")
            check_window_times(self.state.epoch, start, end, epoch_of="the state's")
        check_window(self.orbit, start, end)
        first = op.Plan(self.orbit, start, np.zeros(1), np.zeros(0))  # the first burn comes down to the interface
        states = op.burn_states(first, first.times_s, self.coast.omega_rad_s)
        op.entries(self.coast, *states, op.Deorbit(self.deorbit.delta_v_fps, self.deorbit.entry_gamma_deg))
        work, where = door_limit(info, MAX_WORK, MAX_WORK_HTTP)
        burns = (end - start).total_seconds() / self.burn_step_s
        if burns * len(self.sites) > work:
            raise ValueError(
                f"burn_step_s: {burns:,.0f} burn times x {len(self.sites)} sites is outside the allowed range of 1 to "
                f"{work:,.0f}{where} (a longer step or a shorter window)"
            )
        return self

    def parts(self) -> list[int]:
        """One revolution each."""
        return _plan(self).plan.revolutions

    @functools.cached_property
    def spec(self) -> FlightSpec:
        """The footprint study's case, as the core flies it (built once)."""
        return self.footprint.case.to_spec()

    def guided_specs(self) -> list[FlightSpec]:
        """Per site, the footprint study's case with the guided bank law to it (its entry each burn's)."""
        case = self.footprint.case.model_dump(mode="json", exclude_unset=True)
        targets = [{"latitude_deg": s.latitude_deg, "longitude_deg": (s.longitude_deg + 180.0) % 360.0 - 180.0}
                   for s in self.sites]  # fmt: skip
        return [Case.model_validate(case | {"bank": {"law": "guided", "target": t}}).to_spec() for t in targets]

    def coast_in(self, earth: Earth) -> dorb.Coast:
        """A coast's packed parameters: the footprint's vehicle and planet, the air removed, in an orbit's earth."""
        return dorb.Coast.of(self.spec.vehicle, self.spec.planet, self.deorbit.interface_altitude_ft, earth)

    @functools.cached_property
    def coast(self) -> dorb.Coast:
        """The coast of the orbit's burns, in the orbit's earth (SGP4's WGS-72, or a state vector's WGS-84)."""
        return self.coast_in(self.orbit.earth)

    @functools.cached_property
    def orbit(self) -> Orbit:
        """The TLE's elements, or the state vector propagated over what the plan reads (op.orbit_span_s)."""
        if self.tle is not None:
            return parse_tle(self.tle)
        assert self.state is not None  # _checks: exactly one of tle or state
        (start, end), coast = self.window.bounds, self.coast_in(STATE_EARTH)
        r, v = self.state.earth_fixed(coast)
        n_rev_day = dorb.state_orbit(coast, r, v).mean_motion_rev_day
        span_s = op.orbit_span_s(float(elapsed_s(start, [end])[0]), n_rev_day)  # SI: a leap second counts
        return self.state.propagated(coast, start, span_s)


REQUEST = OpportunitiesStudy
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> OpportunitiesStudy:
    study: OpportunitiesStudy = validated(ADAPTER, data, OpportunitiesStudy, ctx)
    return study


class Plan:
    """Once per process: the elements, the burn grid, the coast, the footprint maker and the scan's footprints."""

    def __init__(self, study: OpportunitiesStudy) -> None:
        self.study = study
        start, end = study.window.bounds
        self.plan = op.plan(study.orbit, start, end, study.burn_step_s)
        self.spec = study.spec
        self.coast = study.coast
        self.deorbit = op.Deorbit(study.deorbit.delta_v_fps, study.deorbit.entry_gamma_deg)
        self.flier = op.Flier(self.spec, study.footprint.to_settings(), study.guided_specs() if study.guided else ())
        self.sites = op.Sites(
            tuple(s.name for s in study.sites),
            np.array([s.latitude_deg for s in study.sites]),
            np.array([s.longitude_deg for s in study.sites]),
        )
        self.settings = op.Settings(
            burn_step_s=study.burn_step_s,
            ring_step_deg=study.ring_step_deg,
            screen_nmi=study.screen_nmi,
            refly=study.refly,
            sun_elevation_min_deg=study.rules.sun_elevation_min_deg,
            min_margin_nmi=study.rules.min_margin_nmi,
        )

    @functools.cached_property
    def table(self) -> op.RingTable:
        return op.ring_table(self.coast, self.plan, self.deorbit, self.flier, self.study.ring_step_deg)


_plan = PerStudy(Plan)  # this process's plan of the study it works on (a study's revolutions share it)


def revolution(study: OpportunitiesStudy, number: int, on_progress: OnProgress | None = None) -> list[dict[str, Any]]:
    plan = _plan(study)
    found = op.revolution_opportunities(
        plan.plan, number, plan.coast, plan.deorbit, plan.table, plan.flier, plan.sites, plan.settings,
        on_progress,
    )  # fmt: skip
    return [o.to_dict() for o in found]


def combine(study: OpportunitiesStudy, parts: list[list[dict[str, Any]]], info: RunInfo) -> dict[str, Any]:
    """The opportunities in landing order, each ranked within its site (1: the largest margin of those that meet
    the rules), a summary per site and the elements' facts."""
    flown = sorted((o for part in parts for o in part), key=lambda o: o["landing_utc"])
    found = [{k: v for k, v in o.items() if k != "needed_change"} for o in flown if o["margin_nmi"] >= 0.0]
    near_misses = [_near_miss(o) for o in flown if o["margin_nmi"] < 0.0]
    for s in range(len(study.sites)):
        mine = sorted((o for o in found if o["site"] == s and o["meets_rules"]), key=lambda o: -o["margin_nmi"])
        for rank, o in enumerate(mine, 1):
            o["rank"] = rank
    plan = _plan(study)
    elements, (start, end) = plan.plan.orbit, study.window.bounds
    sites = []
    for s, site in enumerate(study.sites):
        mine = [o for o in found if o["site"] == s]
        taken = [o for o in mine if o["meets_rules"]]
        sites.append(
            {
                "name": site.name,
                "latitude_deg": site.latitude_deg,
                "longitude_deg": site.longitude_deg,
                "opportunities": len(mine),
                "meeting_rules": len(taken),
                "near_misses": sum(o["site"] == s for o in near_misses),
                "first_landing_utc": taken[0]["landing_utc"] if taken else None,
                "best_margin_nmi": max((o["margin_nmi"] for o in taken), default=None),
                "night_utc": [
                    isos(pair)
                    for pair in sun.night_intervals(
                        start, end + NIGHT_PAST_WINDOW, site.latitude_deg, site.longitude_deg
                    )
                ],
            }
        )
    answer: dict[str, Any] = plain(
        {
            "elements": {
                "name": elements.name,
                "satellite_number": elements.satellite_number,
                "epoch_utc": iso(elements.epoch),
                "revolution_number": elements.revolution_number,  # at epoch (None: a state vector's, not given)
                "inclination_deg": elements.inclination_deg,
                "eccentricity": elements.eccentricity,
                "period_min": 1440.0 / elements.mean_motion_rev_day,
            },
            "window": {"start_utc": iso(start), "end_utc": iso(end)},
            "ascending_nodes_utc": isos(plan.plan.utc(plan.plan.node_s)),
            "ground_track": op.ground_track(plan.plan),
            "delta_v_table": op.delta_v_table(plan.coast, plan.plan, DELTA_V_TABLE_FPS),
            "deorbit": study.deorbit.model_dump(exclude_none=True),
            "rules": study.rules.model_dump(),
            "sites": sites,
            "opportunities": found,
            "near_misses": near_misses,
            "settings": {
                "burn_step_s": study.burn_step_s,
                "ring_step_deg": study.ring_step_deg,
                "screen_nmi": study.screen_nmi,
                "refly": study.refly,
                "guided": study.guided,
                "footprint_method": study.footprint.method,
            },
            "run": {"tasks": info.tasks, "workers": info.workers, "seconds": info.seconds},
        }
    )
    return answer


NEAR_MISS_DROPPED = ("footprint_ring", "coast_track", "rank", "needed_change")


def _near_miss(o: dict[str, Any]) -> dict[str, Any]:
    """A near miss as the answer lists it: a screened pass whose burn, flown again, leaves the site outside its
    footprint, with the change that would take it in (core.opportunities.needed_change) and without the drawing."""
    near: dict[str, Any] = {k: v for k, v in o.items() if k not in NEAR_MISS_DROPPED} | o["needed_change"]
    return near


def store(study: OpportunitiesStudy, answer: dict[str, Any], name: str | None) -> Stored:
    return Stored(result={"opportunities": answer})


WORK = Work(split=OpportunitiesStudy.parts, run_part=revolution, combine=combine, store=store, part_unit="revolution")


# ------------------------------------------------------------------------------------------------ outputs
CSV_COLUMNS = (
    "site_name", "rank", "revolution_number", "burn_utc", "burn_altitude_ft", "burn_latitude_deg",
    "burn_longitude_deg", "delta_v_fps", "entry_utc", "landing_utc", "flight_time_s", "downrange_nmi",
    "crossrange_nmi", "margin_nmi", "downrange_margin_nmi", "crossrange_margin_nmi", "sun_elevation_deg",
    "local_solar_time_h", "daylight", "meets_rules", "burn_window_start_utc", "burn_window_end_utc",
    "burn_window_clipped", "revolution", "interface_utc", "touchdown_utc", "sun_at",
)  # fmt: skip


def opportunities_csv(answer: dict[str, Any]) -> str:
    """One row per opportunity, in landing order."""
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=CSV_COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for o in answer["opportunities"]:
        w.writerow({k: csv_cell(o.get(k)) for k in CSV_COLUMNS})
    return out.getvalue()


def _calendar_time(text: str) -> datetime:
    """A time of the answer to the second, rounded to the nearest: RFC 5545's DATE-TIME (3.3.5) has no fraction. A
    time in a leap second is written 23:59:59 (datetime, and so the icalendar package, has no second 60)."""
    return rounded(parse_iso(text), 1.0).replace(fold=0)


def _calendar_text(text: str) -> str:
    """Text for an iCalendar TEXT value: RFC 5545 (3.3.11) allows no control character but HTAB there. icalendar
    escapes CR and LF (as \\n) but passes NUL, ESC, VT, FF, NEL (U+0085) and U+2028/2029 through, and a reader may
    break a line at any of these: each is a space here (a lone surrogate too, which UTF-8 cannot write)."""
    return "".join(" " if ch != "\t" and unicodedata.category(ch) in ("Cc", "Cs", "Zl", "Zp") else ch for ch in text)


CALENDAR_EPOCH = datetime(1957, 1, 1, tzinfo=UTC)  # SEQUENCE counts minutes of elements' epochs from here (WINDOW_UTC)


def event_uid(satellite: int | None, opportunity: dict[str, Any]) -> str:
    """An opportunity's iCalendar UID, the same across re-plans of the pass (RFC 5545 3.8.4.7: a calendar updates the
    event it already has): the satellite, the elements' revolution of the burn, the landing's UTC date and the site's
    name (an ASCII form, and a digest of the whole name so that names alike in ASCII stay apart); not the burn's
    second, the site's place in the list or whether the orbit came as a TLE or a state vector."""
    name = opportunity["site_name"]
    ascii_name = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode()
    slug = re.sub(r"[^a-z0-9]+", "-", ascii_name.lower()).strip("-")[:40] or "site"
    digest = hashlib.sha256(name.encode()).hexdigest()[:8]
    day = parse_iso(opportunity["landing_utc"]).strftime("%Y%m%d")
    return f"{satellite or 'satellite'}-rev{opportunity['revolution_number']}-{day}-{slug}-{digest}@footprint"


def event_sequence(elements: dict[str, Any]) -> int:
    """The events' SEQUENCE (RFC 5545 3.8.7.4, a revision's number): the elements' epoch in whole minutes from
    CALENDAR_EPOCH, so a plan from newer elements supersedes an older one's events (a re-plan from the same elements
    is told apart by its DTSTAMP)."""
    return int((parse_iso(elements["epoch_utc"]) - CALENDAR_EPOCH).total_seconds() // 60)


def _axis_words(o: dict[str, Any]) -> str:
    """The margins along the chart's axes, where the answer has them."""
    down, cross = o.get("downrange_margin_nmi"), o.get("crossrange_margin_nmi")
    if down is None or cross is None:
        return ""
    return f" ({down:.0f} nmi along the down-range, {cross:.0f} nmi across)"


def opportunities_ics(answer: dict[str, Any], made_utc: datetime | None = None) -> str:
    """An iCalendar (RFC 5545, written by the icalendar package: its escaping and folding) of the opportunities that
    meet the rules: one event per opportunity from the burn to the touchdown estimated after the guided flight's
    terminal-area interface (without one, the arrival over the site; to the nearest second), its summary the site and
    revolution, its description the times to the millisecond, the Δv, margins and sun; its UID and
    SEQUENCE stable across re-plans (event_uid, event_sequence)."""
    from icalendar import Calendar, Event

    calendar = Calendar()
    calendar.add("version", "2.0")
    calendar.add("prodid", "-//Footprint//landing opportunities//EN")
    calendar.add("calscale", "GREGORIAN")
    stamp, elements, uids = made_utc or datetime.now(UTC), answer["elements"], Counter[str]()
    for o in answer["opportunities"]:
        if not o["meets_rules"]:
            continue
        uid = event_uid(elements["satellite_number"], o)
        uids[uid] += 1  # two passes whose burns fall in one revolution (each seconds from its nodes): the later's -2
        if uids[uid] > 1:
            uid = uid.replace("@", f"-{uids[uid]}@")
        touchdown = o.get("touchdown_utc")  # the guided flight's estimate (issue 52 item 3), else the arrival
        arrival = f"arrival over the site at the footprint's stop altitude {o['landing_utc']}"
        landed = (
            f"interface {o['interface_utc']}; touchdown (estimated) {touchdown}; {arrival}" if touchdown else arrival
        )
        about = (
            f"deorbit burn {o['delta_v_fps']:.1f} ft/s at {o['burn_utc']}; entry {o['entry_utc']}; {landed}; "
            f"down-range {o['downrange_nmi']:.0f} nmi, cross-range {o['crossrange_nmi']:.0f} nmi, "
            f"margin {o['margin_nmi']:.0f} nmi{_axis_words(o)}; sun at the {o.get('sun_at', 'arrival')} "
            f"{o['sun_elevation_deg']:.1f} deg, local solar time {o['local_solar_time_h']:.2f} h; "
            f"revolution {o['revolution_number']}"
            + ("; the burn window is cut by the search's edge" if o.get("burn_window_clipped") else "")
        )
        event = Event()
        event.add("uid", uid)
        event.add("sequence", event_sequence(elements))
        event.add("dtstamp", stamp)
        event.add("dtstart", _calendar_time(o["burn_utc"]))
        event.add("dtend", _calendar_time(touchdown or o["landing_utc"]))
        event.add("summary", _calendar_text(f"Landing at {o['site_name']}, revolution {o['revolution_number']}"))
        event.add("description", _calendar_text(about))
        calendar.add_component(event)
    ics: bytes = calendar.to_ical()
    return ics.decode()
