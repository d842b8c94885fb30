"""Section IV.3: the earth's rotation under a moved footprint, the report's way and exactly.

The report (AFWAL-TR-82-3036 IV.3) flies its footprints on a non-rotating earth, moves them (re-node,
re-incline, step around the orbit) and then shifts every point west by omega_p t, "assuming the basic
trajectory is unchanged by a rotating earth and the predominate effect is that of the earth rotating below
the trajectory". The exact alternative flies the footprint again on the rotating earth from the new
geometry. `approximate_vs_exact` does both and compares them point by point (the same control setting and
side), in nautical miles on the sphere of radius R'.

Which entry speed the exact flight keeps is a choice the report does not make: "inertial" keeps the
non-rotating flight's inertial state (speed, flight-path angle and heading: the approximation's own
premise, a trajectory fixed in space with the earth turning under it); "relative" keeps the earth-relative
numbers, which adds or removes omega r cos(latitude) sin(heading) of inertial speed (1,552 ft/s east at the
equator at the Table 2 altitude) and so changes the flight itself, not just where it lands.

Pure numerics: a FlightSpec and a method's settings in, plain dataclasses out.
"""

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.constants import OMEGA_EARTH_DEG_S
from footprint.core.footprint_methods import footprint
from footprint.core.footprints import Footprint, FootprintPoint
from footprint.core.method_settings import MethodSettings
from footprint.core.setting import ControlSetting
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    downrange_crossrange_nmi,
    great_circle_frame,
    move,
    rotation_shift,
)
from footprint.core.trajectory import FlightSpec

VELOCITY_FRAMES = ("inertial", "relative")


# ----------------------------------------------------------------------------------------- geometry
def reference_of(spec: FlightSpec) -> Reference:
    """The initial point and heading of a flight (the origin of its ranges)."""
    e = spec.entry
    return Reference(e.latitude_deg, e.longitude_deg, e.heading_deg)


def stepped_reference(
    ref: Reference, step_downrange_nmi: float = 0.0, radius_nmi: float = MEAN_RADIUS_NMI
) -> Reference:
    """The point step_downrange_nmi further along the initial great circle, with the great circle's heading
    there: where the deorbit point lands when it is stepped around the orbit (Section IV.1)."""
    if step_downrange_nmi == 0.0:
        return ref
    p0, d0, _ = great_circle_frame(ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    a = step_downrange_nmi / radius_nmi
    p, d = math.cos(a) * p0 + math.sin(a) * d0, -math.sin(a) * p0 + math.cos(a) * d0
    lat, lon = math.atan2(p[2], math.hypot(p[0], p[1])), math.atan2(p[1], p[0])
    north = np.array([-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)])
    east = np.array([-math.sin(lon), math.cos(lon), 0.0])
    return Reference(math.degrees(lat), math.degrees(lon), math.degrees(math.atan2(d @ east, d @ north)))


def distance_nmi(
    lat1_deg: ArrayLike,
    lon1_deg: ArrayLike,
    lat2_deg: ArrayLike,
    lon2_deg: ArrayLike,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> NDArray[np.float64]:
    """Great-circle distance on the sphere of radius R' (atan2 form: accurate at 0 and at 180 deg)."""
    p1, l1, p2, l2 = (np.radians(np.asarray(x, float)) for x in (lat1_deg, lon1_deg, lat2_deg, lon2_deg))
    dl = l2 - l1
    y = np.hypot(np.cos(p2) * np.sin(dl), np.cos(p1) * np.sin(p2) - np.sin(p1) * np.cos(p2) * np.cos(dl))
    x = np.sin(p1) * np.sin(p2) + np.cos(p1) * np.cos(p2) * np.cos(dl)
    distance: NDArray[np.float64] = radius_nmi * np.arctan2(y, x)  # typed: numpy's ufuncs give Any here
    return distance


# -------------------------------------------------------------------------------------------- flights
def at_geometry(
    spec: FlightSpec, dst: Reference, rotating: bool | None = None, velocity_frame: str | None = None
) -> FlightSpec:
    """The same case with its entry latitude, longitude and heading replaced (and, when given, the planet's
    rotation and the frame of the entry speed, flight-path angle and heading)."""
    entry = replace(
        spec.entry,
        latitude_deg=float(dst.latitude_deg),
        longitude_deg=float(dst.longitude_deg),
        heading_deg=float(dst.heading_deg),
    )
    if velocity_frame is not None:
        if velocity_frame not in VELOCITY_FRAMES:
            raise ValueError(f"velocity_frame {velocity_frame!r}: one of {VELOCITY_FRAMES}")
        entry = replace(entry, velocity_frame=velocity_frame)
    planet = spec.planet if rotating is None else replace(spec.planet, rotating=bool(rotating))
    return replace(spec, entry=entry, planet=planet)


def fly_at(
    spec: FlightSpec,
    settings: MethodSettings,
    dst: Reference,
    rotating: bool = True,
    velocity_frame: str | None = None,
) -> Footprint:
    """The exact alternative: the footprint flown again from the new geometry (on the rotating earth)."""
    return footprint(at_geometry(spec, dst, rotating, velocity_frame), settings)


def all_points(fp: Footprint) -> list[FootprintPoint]:
    """Boundary and interior points: a point inside one footprint may be on the boundary of another."""
    return list(fp.points) + list(fp.interior)


def control_key(side: str, parameter: ControlSetting | dict[str, Any]) -> tuple[str, tuple[tuple[str, Any], ...]]:
    """What names a footprint point across two flights of one study: its side and control setting (a stored one
    too)."""
    return side, ControlSetting.of(parameter).key()


def point_key(p: FootprintPoint) -> tuple[str, tuple[tuple[str, Any], ...]]:
    return control_key(p.side, p.parameter)


def approximate_points(
    fp: Footprint,
    dst: Reference,
    step_downrange_nmi: float = 0.0,
    omega_deg_s: float = OMEGA_EARTH_DEG_S,
    points: list[FootprintPoint] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The report's way: each point of a non-rotating footprint moved to dst (plus the step) and shifted
    west by omega_p t with its own flight time (Section IV.3). Returns (latitude_deg, longitude_deg)."""
    pts = all_points(fp) if points is None else points
    src = Reference(fp.entry["latitude_deg"], fp.entry["longitude_deg"], fp.entry["heading_deg"])
    lat, lon = move([p.latitude_deg for p in pts], [p.longitude_deg for p in pts], src, dst, step_downrange_nmi)
    return lat, rotation_shift(lon, [p.flight_time_s for p in pts], omega_deg_s)


# ---------------------------------------------------------------------------------------- comparison
@dataclass
class Comparison:
    """Per-point differences of the first-order rotation shift from the footprint flown on the rotating
    earth; distances in nmi on the sphere of radius R', ranges about the destination's initial point."""

    destination: Reference
    velocity_frame: str
    rows: list[dict[str, Any]]  # one per point flown in both: key, both positions, flight times, errors
    unmatched: int  # points present in only one of the two footprints
    flight_time_nonrotating_s: tuple[float, float]  # (min, max) over the footprint's points
    flight_time_exact_s: tuple[float, float]
    downrange_extent_nmi: dict[str, float]  # max - min down-range: "nonrotating", "approximate", "exact"
    move_error_nmi: dict[str, float] | None = None  # the move alone: non-rotating footprint flown at dst vs moved
    nonrotating: Footprint | None = field(default=None, repr=False)
    exact: Footprint | None = field(default=None, repr=False)

    @property
    def max_error_nmi(self) -> float:
        largest: float = max(r["error_nmi"] for r in self.rows)  # a row's error_nmi is a float
        return largest

    @property
    def mean_error_nmi(self) -> float:
        total: float = sum(r["error_nmi"] for r in self.rows)  # a row's error_nmi is a float
        return total / len(self.rows)

    def to_dict(self) -> dict[str, Any]:
        return {
            "destination": vars(self.destination),
            "velocity_frame": self.velocity_frame,
            "max_error_nmi": self.max_error_nmi,
            "mean_error_nmi": self.mean_error_nmi,
            "unmatched": self.unmatched,
            "flight_time_nonrotating_s": list(self.flight_time_nonrotating_s),
            "flight_time_exact_s": list(self.flight_time_exact_s),
            "downrange_extent_nmi": self.downrange_extent_nmi,
            "move_error_nmi": self.move_error_nmi,
            "rows": self.rows,
        }


def approximate_vs_exact(
    spec: FlightSpec,
    settings: MethodSettings,
    dst: Reference,
    step_downrange_nmi: float = 0.0,
    velocity_frame: str | None = "inertial",
    omega_deg_s: float | None = None,
    nonrotating: Footprint | None = None,
    with_move_error: bool = True,
) -> Comparison:
    """Fly the method of `settings` on a non-rotating earth from the spec's own entry (or take `nonrotating`), move
    it to dst (+ step) and shift it by omega_p t; fly it again on the rotating earth from dst (+ step); compare.

    `with_move_error` also flies the non-rotating footprint at dst: its difference from the moved one is
    what the move itself costs on this planet (the oblate earth is not symmetric under rotations of the
    sphere), so that the rotation's share of the error can be read off.
    """
    base = nonrotating or footprint(replace(spec, planet=replace(spec.planet, rotating=False)), settings)
    omega = spec.planet.rotation_rate_deg_s if omega_deg_s is None else omega_deg_s
    start = stepped_reference(dst, step_downrange_nmi)
    exact = fly_at(spec, settings, start, rotating=True, velocity_frame=velocity_frame)

    ours = {point_key(p): p for p in all_points(base)}
    theirs = {point_key(p): p for p in all_points(exact)}
    keys = [k for k in ours if k in theirs]
    pa, pe = [ours[k] for k in keys], [theirs[k] for k in keys]
    alat, alon = approximate_points(base, dst, step_downrange_nmi, omega, points=pa)
    elat, elon = np.array([p.latitude_deg for p in pe]), np.array([p.longitude_deg for p in pe])
    err = distance_nmi(alat, alon, elat, elon)
    down_a, cross_a = ranges_near(alat, alon, start, [p.downrange_nmi for p in pa])
    rows: list[dict[str, Any]] = []
    for i, (a, e) in enumerate(zip(pa, pe)):
        rows.append(
            {
                "side": a.side,
                "parameter": a.parameter.as_dict(),
                "flight_time_nonrotating_s": a.flight_time_s,
                "flight_time_exact_s": e.flight_time_s,
                "approximate_latitude_deg": float(alat[i]),
                "approximate_longitude_deg": float(alon[i]),
                "exact_latitude_deg": e.latitude_deg,
                "exact_longitude_deg": e.longitude_deg,
                "approximate_downrange_nmi": float(down_a[i]),
                "approximate_crossrange_nmi": float(cross_a[i]),
                "exact_downrange_nmi": e.downrange_nmi,
                "exact_crossrange_nmi": e.crossrange_nmi,
                "error_nmi": float(err[i]),
            }
        )

    # a move keeps each point's ranges: the non-rotating footprint's extent is its own
    extent = {
        "nonrotating": _extent([p.downrange_nmi for p in pa]),
        "approximate": _extent(down_a),
        "exact": _extent([p.downrange_nmi for p in pe]),
    }

    move_error: dict[str, float] | None = None
    if with_move_error:
        flat = fly_at(spec, settings, start, rotating=False)
        there = {point_key(p): p for p in all_points(flat)}
        both = [k for k in keys if k in there]
        src_pts = [ours[k] for k in both]
        mlat2, mlon2 = move(
            [p.latitude_deg for p in src_pts],
            [p.longitude_deg for p in src_pts],
            Reference(**base.entry),
            dst,
            step_downrange_nmi,
        )
        e2 = distance_nmi(mlat2, mlon2, [there[k].latitude_deg for k in both], [there[k].longitude_deg for k in both])
        move_error = {"max_nmi": float(np.max(e2)), "mean_nmi": float(np.mean(e2))}

    def times(pts: list[FootprintPoint]) -> tuple[float, float]:
        t = [p.flight_time_s for p in pts]
        return (min(t), max(t))

    return Comparison(
        destination=start,
        velocity_frame=velocity_frame or spec.entry.velocity_frame,
        rows=rows,
        unmatched=len(ours) + len(theirs) - 2 * len(keys),
        flight_time_nonrotating_s=times(all_points(base)),
        flight_time_exact_s=times(all_points(exact)),
        downrange_extent_nmi=extent,
        move_error_nmi=move_error,
        nonrotating=base,
        exact=exact,
    )


def ranges_near(
    lat: ArrayLike, lon: ArrayLike, ref: Reference, near_downrange_nmi: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Down-range and cross-range about ref, the down-range unwrapped to the turn nearest a known value
    (footprints reach past half the circumference); where that value is NaN, within +-pi R'."""
    down, cross = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    circumference = 2.0 * math.pi * MEAN_RADIUS_NMI
    near = np.asarray(near_downrange_nmi, float)
    turns = np.round((near - down) / circumference)
    return down + circumference * np.where(np.isnan(turns), 0.0, turns), cross


def _extent(down: ArrayLike) -> float:
    down = np.asarray(down, float)
    return float(down.max() - down.min())


def shift_error_nmi(
    stored: list[dict[str, Any]], shifted: list[dict[str, Any]], exact: list[dict[str, Any]]
) -> dict[str, float | None]:
    """Section IV.3's question for a footprint: the approximate shift of each stored point (`shifted`, in the stored
    points' order) against the point of the same control flown again (`exact`): the largest and mean distance on
    the sphere (nmi) over the points in both."""
    flown = {control_key(p["side"], p["parameter"]): p for p in exact}
    pairs = [(a, flown[k]) for s, a in zip(stored, shifted) if (k := control_key(s["side"], s["parameter"])) in flown]
    if not pairs:
        return {"max": None, "mean": None, "points": 0}
    d = distance_nmi(
        [a["latitude_deg"] for a, _ in pairs],
        [a["longitude_deg"] for a, _ in pairs],
        [e["latitude_deg"] for _, e in pairs],
        [e["longitude_deg"] for _, e in pairs],
    )
    return {"max": float(d.max()), "mean": float(d.mean()), "points": len(pairs)}
