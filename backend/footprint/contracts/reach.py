"""The reach study contract: which landing sites a footprint reaches from which parts of which revolutions
(AFWAL-TR-82-3036 Section IV, questions 1-3). One pydantic request, shared by the CLI and the REST API:

    {"footprint": {"points": [{"downrange_nmi", "crossrange_nmi", "flight_time_s"}, ...], "mirror": false}
                  or {"study": <a footprint study, as footprint.contracts.footprint accepts>},
     "orbit": {"inclination_deg", "altitude_ft" | "altitude_nmi",
               "node_longitude_deg" | "right_ascension_deg" + "greenwich_sidereal_deg", "nodal_regression", ...},
     "sites": [{"name", "latitude_deg", "longitude_deg"}, ...],
     "revolutions": {"first": 1, "last": 16} | {"first": 1, "hours": 24},
     "u_step_deg": 1.0, "earth_rotation": "approximate" | "none", "entry_offset_nmi": 0}

`run_reach(request) -> dict`: the windows (contiguous runs of deorbit argument of latitude per revolution and
site) and a summary per site. The footprint's points are about its own reference, the entry point, with
flight times from entry; a study's footprint should be flown on a non-rotating earth when the earth's
rotation is applied here (Section IV.3 takes its flight times from non-rotating runs).
"""

import csv
import math
import os
import time
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.bounds import SITE_NAME_CHARS
from footprint.contracts.doors import context_of, door_limit, validated
from footprint.contracts.fields import Range, Strict
from footprint.contracts.footprint import FootprintStudy
from footprint.contracts.footprint import fly as fly_study
from footprint.contracts.records import csv_cell, plain
from footprint.contracts.work import OnProgress, Stored, Work, stop_question
from footprint.core import constants as c
from footprint.core.orbits import J2, CircularOrbit
from footprint.core.reach import Window, reach
from footprint.core.sphere import close_half_along_axis

MAX_PLACEMENTS = 2_000_000  # revolutions x (360 / u_step_deg): ~80 s of work for 20 sites and 30 points
MAX_WORK = 5e9  # placements x sites x footprint points
MAX_WORK_SYNC = 2e7  # the same in the API process itself: ~1.7 s (8e-8 s a unit; 20 sites, a day, 21 points: 2.6e6)


class ReachPoint(Strict):
    downrange_nmi: Annotated[float, Range(-21_600, 43_200, "nmi")]
    crossrange_nmi: Annotated[float, Range(-5_400, 5_400, "nmi")]
    flight_time_s: Annotated[float, Range(0, 100_000, "s")] = 0.0


class ReachFootprint(Strict):
    """A footprint given by its boundary points (closed, in order) or a footprint study to fly."""

    points: list[ReachPoint] | None = Field(default=None, min_length=3, max_length=5_000)
    mirror: bool = False  # points: the left half only; the right half is its reflection (Section IV)
    study: FootprintStudy | None = None

    @model_validator(mode="after")
    def _one_source(self) -> "ReachFootprint":
        if (self.points is None) == (self.study is None):
            raise ValueError("give exactly one of 'points' (the boundary) or 'study' (a footprint study to fly)")
        if self.study is not None and self.mirror:
            raise ValueError("'mirror' applies to 'points'; a study has its own 'mirror'")
        return self


class ReachOrbit(Strict):
    """A circular orbit. The node: its earth-fixed longitude when revolution 1 crosses it at the epoch, or its
    right ascension with the Greenwich sidereal angle at the epoch."""

    inclination_deg: Annotated[float, Range(0, 180, "deg")]
    altitude_ft: Annotated[float, Range(100_000, 100_000_000, "ft")] | None = None
    altitude_nmi: Annotated[float, Range(16, 16_000, "nmi")] | None = None
    node_longitude_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    right_ascension_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    greenwich_sidereal_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    nodal_regression: bool = True
    mu_ft3_s2: Annotated[float, Range(1e10, 1e22, "ft^3/s^2")] = c.MU_EARTH_FT3_S2
    radius_ft: Annotated[float, Range(1e5, 1e9, "ft")] = c.RADIUS_EQUATORIAL_FT
    rotation_rate_deg_s: Annotated[float, Range(-0.1, 0.1, "deg/s")] = c.OMEGA_EARTH_DEG_S
    j2: Annotated[float, Range(-0.1, 0.1)] = J2

    @model_validator(mode="after")
    def _choices(self) -> "ReachOrbit":
        if (self.altitude_ft is None) == (self.altitude_nmi is None):
            raise ValueError("give exactly one of altitude_ft or altitude_nmi")
        by_ra = self.right_ascension_deg is not None or self.greenwich_sidereal_deg is not None
        if by_ra and (self.right_ascension_deg is None or self.greenwich_sidereal_deg is None):
            raise ValueError("right_ascension_deg needs greenwich_sidereal_deg (and the other way round)")
        if by_ra and self.node_longitude_deg is not None:
            raise ValueError("give node_longitude_deg or right_ascension_deg with greenwich_sidereal_deg, not both")
        return self

    def to_orbit(self) -> CircularOrbit:
        alt = self.altitude_ft
        if alt is None:
            assert self.altitude_nmi is not None  # _choices: exactly one of altitude_ft or altitude_nmi
            alt = self.altitude_nmi * c.FT_PER_NMI
        kw: dict[str, Any] = dict(
            inclination_deg=self.inclination_deg,
            altitude_ft=alt,
            mu_ft3_s2=self.mu_ft3_s2,
            radius_ft=self.radius_ft,
            rotation_rate_deg_s=self.rotation_rate_deg_s,
            j2=self.j2,
            nodal_regression=self.nodal_regression,
        )
        if self.right_ascension_deg is not None:
            assert self.greenwich_sidereal_deg is not None  # _choices: given with right_ascension_deg
            orbit: CircularOrbit = CircularOrbit.from_right_ascension(
                right_ascension_deg=self.right_ascension_deg, greenwich_sidereal_deg=self.greenwich_sidereal_deg, **kw
            )
            return orbit
        return CircularOrbit(node_longitude_deg=self.node_longitude_deg or 0.0, **kw)


class Site(Strict):
    name: str = Field(min_length=1, max_length=SITE_NAME_CHARS)
    latitude_deg: Annotated[float, Range(-90, 90, "deg")]
    longitude_deg: Annotated[float, Range(-360, 360, "deg")]


class Revolutions(Strict):
    """Revolutions first..last, or every revolution that starts within `hours` of the start of `first`
    (placements past the span are left out)."""

    first: int = Field(default=1, ge=1, le=100_000)
    last: int | None = Field(default=None, ge=1, le=100_000)
    hours: Annotated[float, Range(0.01, 720, "h")] | None = None

    @model_validator(mode="after")
    def _span(self) -> "Revolutions":
        if (self.last is None) == (self.hours is None):
            raise ValueError("give exactly one of 'last' or 'hours'")
        if self.last is not None and self.last < self.first:
            raise ValueError(f"last {self.last} must be at least first {self.first}")
        return self

    def span(self, orbit: CircularOrbit) -> tuple[NDArray[np.int_], float | None]:
        """(revolution numbers, time span end in seconds since the epoch or None)."""
        if self.last is not None:
            return np.arange(self.first, self.last + 1), None
        assert self.hours is not None  # _span: exactly one of last or hours
        count = math.ceil(self.hours * 3600.0 / orbit.period_s - 1e-12)
        start_s = (self.first - 1) * orbit.period_s
        return np.arange(self.first, self.first + count), start_s + self.hours * 3600.0


class ReachRequest(Strict):
    description: str | None = Field(default=None, max_length=4_000)
    footprint: ReachFootprint
    orbit: ReachOrbit
    sites: list[Site] = Field(default=[], max_length=1_000)  # the service's stored sites when none are given
    revolutions: Revolutions = Revolutions(hours=24.0)
    u_step_deg: Annotated[float, Range(0.01, 30, "deg")] = 1.0
    earth_rotation: Literal["none", "approximate"] = "approximate"
    entry_offset_nmi: Annotated[float, Range(0, 21_600, "nmi")] = 0.0

    @model_validator(mode="before")
    @classmethod
    def _stored_sites(cls, data: Any, info: ValidationInfo) -> Any:
        stored = context_of(info).get("sites")
        if stored is None or not isinstance(data, dict) or data.get("sites"):
            return data
        sites = stored()
        if not sites:
            raise ValueError("sites: none given and none stored (POST /api/sites)")
        return {**data, "sites": sites}

    @model_validator(mode="after")
    def _size(self, info: ValidationInfo) -> "ReachRequest":
        if not self.sites:
            raise ValueError("sites: give at least 1 site (allowed: 1 to 1,000)")
        revs, _ = self.revolutions.span(self.orbit.to_orbit())
        placements = len(revs) * len(np.arange(0.0, 360.0 - 1e-9, self.u_step_deg))
        if placements > MAX_PLACEMENTS:
            raise ValueError(
                f"revolutions and u_step_deg: {placements:,} deorbit points is outside the allowed "
                f"range 1 to {MAX_PLACEMENTS:,}; use fewer revolutions or a larger u_step_deg"
            )
        fp = self.footprint
        if fp.points:
            points = len(fp.points) * (2 if fp.mirror else 1)
        else:  # a study's boundary: its settings on each side flown, and the two points closing it on the axis
            assert fp.study is not None  # _one_source: the points or a study, exactly one
            points = fp.study.settings()[1] * (2 if fp.study.mirror else 1) + 2
        limit, where = door_limit(info, MAX_WORK, MAX_WORK, MAX_WORK_SYNC)
        if placements * len(self.sites) * points > limit:
            work = placements * len(self.sites) * points
            raise ValueError(
                f"sites: sites x deorbit points x footprint points = {work:.3g} is outside the allowed "
                f"range (at most {limit:.0e}{where})"
            )
        return self


REQUEST = ReachRequest  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> ReachRequest:
    """Validate a request; a footprint study inside it is validated too (errors name footprint.study...)."""
    request: ReachRequest = validated(ADAPTER, data, ReachRequest, ctx)
    return request


def footprint_polygon(
    req: ReachRequest, on_progress: OnProgress | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], dict[str, Any]]:
    """(down-range nmi, cross-range nmi, flight time s) of the closed boundary, and a description; a study's flights
    ask on_progress before each (True stops them: errors.Stopped)."""
    fp = req.footprint
    if fp.study is not None:
        study = fp.study
        flown = fly_study(study, stop_asked=stop_question(on_progress, "flying the footprint"))
        pts = [(p.downrange_nmi, p.crossrange_nmi, p.flight_time_s) for p in flown.points]
        info: dict[str, Any] = {
            "source": "study",
            "method": study.method,
            "trajectories": flown.trajectories,
            "reference": flown.entry,
            "planet_rotating": study.case.planet.rotating,
            "limits": flown.limits(),  # its flights that broke a vehicle limit
        }
    else:
        assert fp.points is not None  # _one_source: the points or a study, exactly one
        pts = [(p.downrange_nmi, p.crossrange_nmi, p.flight_time_s) for p in fp.points]
        if fp.mirror:
            pts += [(d, -cross, t) for d, cross, t in reversed(pts) if cross != 0.0]
        info = {"source": "points"}
    pts = close_half_along_axis(pts)
    arr = np.array(pts, float)
    info |= {
        "points": len(pts),
        "max_downrange_nmi": float(arr[:, 0].max()),
        "min_downrange_nmi": float(arr[:, 0].min()),
        "max_crossrange_nmi": float(np.abs(arr[:, 1]).max()),
    }
    return arr[:, 0], arr[:, 1], arr[:, 2], info


def analysis(req: ReachRequest, part: Any = None, on_progress: OnProgress | None = None) -> dict[str, Any]:
    """The reach analysis: windows and a per-site summary, as a JSON-ready dict; on_progress(fraction, note) over
    the placements (True stops)."""
    orbit = req.orbit.to_orbit()
    revs, span_end_s = req.revolutions.span(orbit)
    down, cross, flight_time, info = footprint_polygon(req, on_progress)
    notes: list[str] = []
    if info.get("planet_rotating") and req.earth_rotation == "approximate":
        notes.append(
            "the footprint study was flown on a rotating earth and earth_rotation is 'approximate': the "
            "rotation is counted twice (Section IV.3 shifts footprints flown on a non-rotating earth); "
            "fly the study with planet.rotating false, or use earth_rotation 'none'"
        )
    if req.earth_rotation == "approximate" and not np.any(flight_time):
        notes.append("every flight_time_s is 0: the earth-rotation shift moves nothing")
    t0 = time.perf_counter()
    result = reach(
        down,
        cross,
        flight_time,
        [s.latitude_deg for s in req.sites],
        [s.longitude_deg for s in req.sites],
        orbit,
        revs,
        u_step_deg=req.u_step_deg,
        earth_rotation=req.earth_rotation,
        entry_offset_nmi=req.entry_offset_nmi,
        time_span_s=span_end_s,
        on_progress=on_progress,
    )
    seconds = time.perf_counter() - t0
    names = [s.name for s in req.sites]
    windows = [
        w.to_dict()
        | {
            "site": names[w.site],
            "u_width_deg": w.u_end_deg - w.u_start_deg,
            "deorbit_points": _deorbit_points(orbit, w, req.u_step_deg),
        }
        for w in result.windows
    ]
    sites = []
    for i, s in enumerate(req.sites):
        mine = [w for w in result.windows if w.site == i]
        column = result.margin_nmi[..., i]
        best = float(np.nanmax(column)) if np.isfinite(column).any() else None
        sites.append(
            {
                "name": s.name,
                "latitude_deg": s.latitude_deg,
                "longitude_deg": s.longitude_deg,
                "reachable": bool(mine),
                "passes": len(result.passes(i)),  # windows joined across the node
                "windows": len(mine),
                "revolutions": sorted({w.revolution for w in mine}),
                "coverage_u_deg": sum(w.samples for w in mine) * req.u_step_deg,
                "best_margin_nmi": best,  # negative: how far short the nearest placement falls
                "first_deorbit_time_s": mine[0].deorbit_time_start_s if mine else None,
            }
        )
    return {
        "orbit": {
            "inclination_deg": orbit.inclination_deg,
            "altitude_ft": orbit.altitude_ft,
            "period_s": orbit.period_s,
            "node_longitude_deg": orbit.node_longitude_deg,
            "node_step_deg_per_revolution": orbit.node_step_deg,
            "nodal_regression_deg_per_day": orbit.node_rate_deg_s * 86_400.0,
        },
        "footprint": info,
        "analysis": {
            "revolutions": [int(revs[0]), int(revs[-1])],
            "time_span_end_s": span_end_s,
            "u_step_deg": req.u_step_deg,
            "placements": int(result.inside.shape[0] * result.inside.shape[1]),
            "earth_rotation": req.earth_rotation,
            "entry_offset_nmi": req.entry_offset_nmi,
            "heading": "inertial azimuth of the orbit (the orbit plane's trace)",
            "seconds": seconds,
        },
        "sites": sites,
        "windows": windows,
        "notes": notes,
    }


def _deorbit_points(orbit: CircularOrbit, window: Window, u_step_deg: float) -> dict[str, Any]:
    """Where the vehicle is when it deorbits within a window: the ground points under the orbit at the window's
    grid values of u (core.orbits.position), for the map."""
    from footprint.core.orbits import position

    u = np.arange(window.u_start_deg, window.u_end_deg + 0.5 * u_step_deg, u_step_deg)
    lat, lon = position(orbit, window.revolution, u)
    return {"latitude_deg": np.atleast_1d(lat).tolist(), "longitude_deg": np.atleast_1d(lon).tolist()}


def store(req: ReachRequest, result: dict[str, Any], name: str | None) -> Stored:
    return Stored(result={"reach": plain(result)})


WORK = Work(run_part=analysis, store=store, part_unit="analysis")


WINDOW_COLUMNS = (
    "site",
    "revolution",
    "u_start_deg",
    "u_end_deg",
    "u_width_deg",
    "samples",
    "max_margin_nmi",
    "deorbit_time_start_s",
    "deorbit_time_end_s",
)


def write_windows_csv(result: dict[str, Any], path: str | os.PathLike[str]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=WINDOW_COLUMNS, extrasaction="ignore")
        w.writeheader()
        for row in result["windows"]:
            w.writerow({k: csv_cell(v) for k, v in row.items()})
