"""The transform contract (DESIGN.md "Transform"): move footprint points to another node, inclination or
deorbit point, add the mirror half, and allow for the earth's rotation (AFWAL-TR-82-3036 Section IV).

Request (JSON object; the CLI's `footprint transform FILE.json` and, later, the REST endpoint):

    {"points": [{"latitude_deg", "longitude_deg", "flight_time_s"?, "downrange_nmi"?}, ...],
     "from": {"latitude_deg", "longitude_deg", "heading_deg"},
     "to":   {"latitude_deg", "longitude_deg", "heading_deg"}
           | {"latitude_deg", "longitude_deg", "inclination_deg", "ascending": true}
           | {"node_longitude_deg", "inclination_deg", "argument_of_latitude_deg"},
     "step_downrange_nmi": 0, "mirror": false,
     "earth_rotation": "none" | "approximate" | "exact", "study": {...a footprint study...}}

The steps, in order: `mirror` adds each point's image across the `from` great circle (the other half of a
symmetric footprint, in reverse order so that a half from the front to the back closes; points on that
great circle are their own images and are not repeated); every point is
carried from `from` to `to` and `step_downrange_nmi` further along the new great circle (re-node,
re-incline, step around the orbit: one rotation of the sphere); "approximate" then shifts each longitude
west by omega_p t with the point's own flight time (Section IV.3), which every point must then carry.
"exact" instead flies the `study` again on the rotating earth from the destination (stepped) and returns
that footprint's points; the request's points are then not used (they may be left out) and the study's own
`mirror` setting applies.

Response: {"points": [{"latitude_deg", "longitude_deg", "flight_time_s", "downrange_nmi",
"crossrange_nmi", "mirrored"}...], "reference": the destination's initial point and heading after the step
(the origin of the ranges), "earth_rotation", "points_in"}; "exact" points also carry "side" and
"parameter". Longitudes are in [-180, 180) (core.sphere.wrap_longitude: +180 is given as -180). A point's
down-range is its flown one where the request gives it (a move keeps the ranges about the moved reference;
"approximate" takes the turn of the circumference nearest it): a footprint past half-way round stays continuous
(18,108 nmi, not -3,507); without it the down-range lies within +-pi R'.
"""

import csv
import os
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import ConfigDict, Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.doors import door_limit, validated
from footprint.contracts.fields import Range, Strict
from footprint.contracts.footprint import FootprintStudy
from footprint.contracts.records import csv_cell
from footprint.contracts.work import OnProgress, Work, stop_question
from footprint.core.constants import OMEGA_EARTH_DEG_S
from footprint.core.errors import InputError
from footprint.core.rotation import ranges_near
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    downrange_crossrange_nmi,
    heading_for_inclination,
    inclination_for_heading,
    mirror,
    move,
    rotation_shift,
    wrap_longitude,
)

MAX_POINTS = 1_000_000  # a request's points; the core moves 100,000 in a few milliseconds
MAX_POINTS_HTTP = 10_000  # over HTTP
MAX_STEP_NMI = 250_000.0  # about 11 circuits of the earth (2 pi R' = 21,615 nmi)
MAX_FLIGHT_TIME_S = 100_000.0  # the longest flight a case may ask for (stop.time_s)
MAX_DOWNRANGE_NMI = 250_000.0  # a flown down-range (the longest flight at orbital speed is ~140,000 nmi)
ON_AXIS_NMI = 1e-6  # cross-range below which a point lies on the initial great circle (no mirror image)


class Point(Strict):
    latitude_deg: Annotated[float, Range(-90, 90, "deg")]
    longitude_deg: Annotated[float, Range(-360, 360, "deg")]
    flight_time_s: Annotated[float, Range(0, MAX_FLIGHT_TIME_S, "s")] | None = None
    downrange_nmi: Annotated[float, Range(-MAX_DOWNRANGE_NMI, MAX_DOWNRANGE_NMI, "nmi")] | None = (
        None  # the flown, continuous one
    )


class Place(Strict):
    """An initial point and the direction of the initial great circle there: a heading (deg from north,
    clockwise) or an orbit's inclination with the pass (ascending: northbound); or the point of an orbit its
    argument of latitude past the ascending node (the orbit's own direction there), as the map's controls say
    it."""

    latitude_deg: Annotated[float, Range(-90, 90, "deg")] | None = None
    longitude_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    heading_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    inclination_deg: Annotated[float, Range(0, 180, "deg")] | None = None
    ascending: bool = True
    node_longitude_deg: Annotated[float, Range(-360, 360, "deg")] | None = None
    argument_of_latitude_deg: Annotated[float, Range(-360, 360, "deg")] | None = None

    @model_validator(mode="after")
    def _one_direction(self) -> "Place":
        orbit = ("node_longitude_deg", "argument_of_latitude_deg")
        if any(getattr(self, k) is not None for k in orbit):
            given = [
                k for k in ("latitude_deg", "longitude_deg", "heading_deg", "ascending") if k in self.model_fields_set
            ]
            missing = [k for k in orbit + ("inclination_deg",) if getattr(self, k) is None]
            if given or missing:
                raise ValueError(
                    "an orbit's point is node_longitude_deg (-360 to 360 deg), inclination_deg (0 to "
                    "180 deg) and argument_of_latitude_deg (-360 to 360 deg) "
                    + (f"(missing {', '.join(missing)})" if missing else f"without {', '.join(given)}")
                )
            return self
        if self.latitude_deg is None or self.longitude_deg is None:
            raise ValueError(
                "give latitude_deg (-90 to 90 deg) and longitude_deg (-360 to 360 deg), or an orbit's "
                "node_longitude_deg, inclination_deg and argument_of_latitude_deg"
            )
        if (self.heading_deg is None) == (self.inclination_deg is None):
            raise ValueError("give exactly one of heading_deg (-360 to 360 deg) or inclination_deg (0 to 180 deg)")
        if self.heading_deg is not None and "ascending" in self.model_fields_set:
            raise ValueError("ascending goes with inclination_deg, not with heading_deg")
        return self

    def reference(self, where: str) -> Reference:
        if self.node_longitude_deg is not None:  # from the ascending node along the orbit, u as an arc of R'
            assert self.inclination_deg is not None and self.argument_of_latitude_deg is not None  # _one_direction
            from footprint.core.rotation import stepped_reference

            node = Reference(0.0, self.node_longitude_deg, float(heading_for_inclination(0.0, self.inclination_deg)))
            return stepped_reference(node, np.radians(self.argument_of_latitude_deg) * MEAN_RADIUS_NMI)
        assert self.latitude_deg is not None and self.longitude_deg is not None  # _one_direction: a place is given
        if self.heading_deg is not None:
            return Reference(self.latitude_deg, self.longitude_deg, self.heading_deg)
        assert self.inclination_deg is not None  # _one_direction: a heading or an inclination, exactly one
        try:
            hdg = heading_for_inclination(self.latitude_deg, self.inclination_deg, self.ascending)
        except InputError as exc:
            raise InputError(f"{where}.inclination_deg", exc.message) from None
        return Reference(self.latitude_deg, self.longitude_deg, float(hdg))


class TransformRequest(Strict):
    model_config = ConfigDict(extra="forbid", populate_by_name=True)

    points: list[Point] = Field(default=[], max_length=MAX_POINTS)
    from_: Place = Field(alias="from")
    to: Place
    step_downrange_nmi: Annotated[float, Range(-MAX_STEP_NMI, MAX_STEP_NMI, "nmi")] = 0.0
    mirror: bool = False
    earth_rotation: Literal["none", "approximate", "exact"] = "none"
    rotation_rate_deg_s: Annotated[float, Range(-0.1, 0.1, "deg/s")] = OMEGA_EARTH_DEG_S  # omega_p of the shift
    study: FootprintStudy | None = None  # "exact" flies it again

    @model_validator(mode="after")
    def _consistent(self, info: ValidationInfo) -> "TransformRequest":
        limit, where = door_limit(info, MAX_POINTS, MAX_POINTS_HTTP)
        if len(self.points) > limit:
            raise ValueError(f"points: {len(self.points)} points is outside the allowed range 1 to {limit:,}{where}")
        if self.earth_rotation != "exact" and not self.points:
            raise ValueError("points: give at least one point (1 to 1000000), or earth_rotation 'exact' with a study")
        if self.earth_rotation == "approximate":
            missing = [i for i, p in enumerate(self.points) if p.flight_time_s is None]
            if missing:
                at = ", ".join(map(str, missing[:5])) + (f" and {len(missing) - 5} more" if len(missing) > 5 else "")
                raise ValueError(
                    f"points.{missing[0]}.flight_time_s: required for every point with earth_rotation "
                    f"'approximate' (the shift is omega_p t, 0 to {MAX_FLIGHT_TIME_S:g} s); "
                    f"missing at points {at}"
                )
        if self.earth_rotation == "exact":
            if self.study is None:
                raise ValueError(
                    "study: required with earth_rotation 'exact' (a footprint study to fly again on the "
                    "rotating earth from the destination)"
                )
            if self.study.method == "collocation":  # a minute of NLP solves is a job, not a synchronous request
                raise ValueError(
                    "study.method: 'collocation' is not re-solved by a transform; submit a footprint job "
                    "with the destination's entry instead"
                )
        elif self.study is not None:
            raise ValueError(f"study: only used with earth_rotation 'exact' (got '{self.earth_rotation}')")
        return self


REQUEST = TransformRequest  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> TransformRequest:
    request: TransformRequest = validated(ADAPTER, data, TransformRequest, ctx)
    return request


def transform(req: TransformRequest, part: Any = None, on_progress: OnProgress | None = None) -> dict[str, Any]:
    """Carry out a transform request; raises InputError for a user's mistake the contract cannot see."""
    src, dst0 = req.from_.reference("from"), req.to.reference("to")
    from footprint.core.rotation import stepped_reference

    dst = stepped_reference(dst0, req.step_downrange_nmi)
    if req.earth_rotation == "exact":
        points = _exact_points(req, dst, stop_question(on_progress, "flying the footprint again"))
    else:
        points = _moved_points(req, src, dst0, dst)
    return {
        "points": points,
        "reference": _reference_dict(dst),
        "earth_rotation": req.earth_rotation,
        "points_in": len(req.points),
    }


def _moved_points(req: TransformRequest, src: Reference, dst0: Reference, dst: Reference) -> list[dict[str, Any]]:
    lat = np.array([p.latitude_deg for p in req.points])
    lon = np.array([p.longitude_deg for p in req.points])
    has_time = all(p.flight_time_s is not None for p in req.points)
    t = np.array([p.flight_time_s if p.flight_time_s is not None else np.nan for p in req.points])
    flown = np.array([np.nan if p.downrange_nmi is None else p.downrange_nmi for p in req.points])
    mirrored = np.zeros(len(lat), bool)
    if req.mirror:
        _, cross = downrange_crossrange_nmi(lat, lon, src.latitude_deg, src.longitude_deg, src.heading_deg)
        off = np.abs(cross) > ON_AXIS_NMI  # a point on the initial great circle is its own image
        mlat, mlon = mirror(lat[off], lon[off], src)
        lat, lon = np.concatenate([lat, mlat[::-1]]), np.concatenate([lon, mlon[::-1]])
        t, mirrored = np.concatenate([t, t[off][::-1]]), np.concatenate([mirrored, np.ones(len(mlat), bool)])
        flown = np.concatenate([flown, flown[off][::-1]])  # an image keeps its down-range
    lat, lon = move(lat, lon, src, dst0, req.step_downrange_nmi)
    if req.earth_rotation == "approximate":
        lon = rotation_shift(lon, t, req.rotation_rate_deg_s)
    lon = wrap_longitude(lon)
    down, cross = ranges_near(lat, lon, dst, flown)
    rows = []
    for i in range(len(lat)):
        row: dict[str, Any] = {"latitude_deg": float(lat[i]), "longitude_deg": float(lon[i])}
        if has_time or not np.isnan(t[i]):
            row["flight_time_s"] = float(t[i])
        row.update(downrange_nmi=float(down[i]), crossrange_nmi=float(cross[i]), mirrored=bool(mirrored[i]))
        rows.append(row)
    return rows


def _exact_points(
    req: TransformRequest, dst: Reference, stop_asked: Callable[[], bool] | None = None
) -> list[dict[str, Any]]:
    from footprint.core.rotation import all_points, fly_at

    study = req.study
    assert study is not None  # an exact transform carries its study (the request's check)
    spec = replace(study.case.to_spec(), stop_asked=stop_asked)
    fp = fly_at(spec, study.to_settings(), dst, rotating=True)
    return [
        {
            "latitude_deg": p.latitude_deg,
            "longitude_deg": float(wrap_longitude(p.longitude_deg)),
            "flight_time_s": p.flight_time_s,
            "downrange_nmi": p.downrange_nmi,
            "crossrange_nmi": p.crossrange_nmi,
            "mirrored": p.mirrored,
            "side": p.side,
            "parameter": p.parameter.as_dict(),
            "on_boundary": p in fp.points,
        }
        for p in all_points(fp)
    ]


def _reference_dict(ref: Reference) -> dict[str, Any]:
    return {
        "latitude_deg": ref.latitude_deg,
        "longitude_deg": float(wrap_longitude(ref.longitude_deg)),
        "heading_deg": ref.heading_deg,
        "inclination_deg": float(inclination_for_heading(ref.latitude_deg, ref.heading_deg)),
    }


CSV_COLUMNS = (
    "latitude_deg",
    "longitude_deg",
    "flight_time_s",
    "downrange_nmi",
    "crossrange_nmi",
    "mirrored",
    "side",
    "parameter",
)


def write_csv(result: dict[str, Any], path: str | os.PathLike[str]) -> Path:
    """The moved points as CSV, one row each (columns a point lacks are left empty)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    columns = [c for c in CSV_COLUMNS if any(c in p for p in result["points"])]
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for p in result["points"]:
            w.writerow([csv_cell(p.get(c)) for c in columns])
    return path


WORK = Work(run_part=transform, part_unit="transform")  # answered at once, never a job
