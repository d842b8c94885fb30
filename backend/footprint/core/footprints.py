"""Landing footprints: families of trajectories that differ only in the bank law (AFWAL-TR-82-3036 II.5-II.7).

Every generator takes a FlightSpec (the vehicle, planet, entry, alpha law, bank start and stop of the
case; its bank law is replaced) and returns a Footprint: the points of the left half (positive bank,
positive cross-range) in the order of the parameter, the points on the axis, and, with `mirror`, the
right half. The right half is the reflection of the left where the planet makes that exact (no rotation,
and a spherical earth or an equatorial track without the odd zonal term H); otherwise it is flown, and
the footprint says how far the two halves are from mirror images.
"""

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field, replace
from itertools import chain
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from footprint.core.controls import replace_alpha_law, replace_bank_law
from footprint.core.limits import tally
from footprint.core.method_settings import ConstantAltitude, ConstantBank, SingleParameter, Staged, TwoParameter
from footprint.core.plane import inside_points
from footprint.core.setting import ControlSetting
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    close_half_along_axis,
    great_circle_frame,
    unit_vectors,
    wrap_longitude,
)
from footprint.core.trajectory import FlightSpec, Trajectory, simulate

# a method's control settings: (the setting, make(spec, right) -> the spec it flies, whether it lands on the axis)
Family = list[tuple[ControlSetting, Callable[..., FlightSpec], bool]]
SIGMA0_DEG = 90.0  # Section II.6 a: the initial heading (remaining heading change) of the procedure
WIDEST_TURN_DEG = 179.0  # constant-altitude turns: further round only comes back (and 180 is where |wrap| folds)


@dataclass(frozen=True)
class FootprintPoint:
    """One trajectory's end point. `parameter` is the control setting that produced it."""

    parameter: ControlSetting
    side: str  # "left", "right" or "axis" (on the initial great circle by symmetry: zero bank, zero lift)
    downrange_nmi: float
    crossrange_nmi: float
    flight_time_s: float
    latitude_deg: float  # final, geodetic, earth-fixed
    longitude_deg: float
    heading_deg: float
    final_velocity_fps: float
    final_altitude_ft: float
    pullout_altitude_ft: float | None
    stop_reason: str
    pullout_downrange_nmi: float | None = None
    pullout_velocity_fps: float | None = None
    pullout_time_s: float | None = None
    turn_deg: float | None = None  # heading change flown before the wings came level (staged, constant altitude)
    # where the flight passed each requested velocity (Appendix C iso-velocity contours)
    contours: tuple[dict[str, float], ...] = ()
    mirrored: bool = False  # True: reflected from the left half, not flown
    limits_broken: tuple[str, ...] = ()  # the vehicle's limits its flight broke (core.limits)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self) | {"parameter": self.parameter.as_dict()}


@dataclass
class Footprint:
    method: str
    points: list[FootprintPoint]  # the boundary in order, closed (the last joins the first)
    area_nmi2: float
    trajectories: int  # flown, not reflected
    entry: dict[str, float]  # latitude_deg, longitude_deg, heading_deg of the initial point (the ranges' origin)
    sets: dict[float, list[FootprintPoint]] = field(default_factory=dict)  # two_parameter: one set per K
    interior: list[FootprintPoint] = field(default_factory=list)  # flown, inside the boundary
    outer_boundary: list[tuple[float, float]] = field(default_factory=list)  # (down, cross) nmi, left half
    asymmetry: dict[str, Any] | None = None  # flown halves: largest departure from mirror images, nmi

    @property
    def max_crossrange_nmi(self) -> float:
        return max(p.crossrange_nmi for p in self.points)

    @property
    def max_downrange_nmi(self) -> float:
        return max(p.downrange_nmi for p in self.points)

    @property
    def min_downrange_nmi(self) -> float:
        return min(p.downrange_nmi for p in self.points)

    def limits(self) -> dict[str, Any]:
        """The flown points' broken limits (core.limits.tally): a footprint shows them, never drops them."""
        every = (*self.points, *self.interior, *chain(*self.sets.values()))  # a set's points are also the boundary's
        flown = {id(p): p for p in every if not p.mirrored}
        return tally(p.limits_broken for p in flown.values())

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "points": [p.to_dict() for p in self.points],
            "area_nmi2": self.area_nmi2,
            "max_crossrange_nmi": self.max_crossrange_nmi,
            "max_downrange_nmi": self.max_downrange_nmi,
            "min_downrange_nmi": self.min_downrange_nmi,
            "trajectories": self.trajectories,
            "entry": self.entry,
            "sets": {f"bank_gain={k:g}": [p.to_dict() for p in v] for k, v in self.sets.items()},
            "interior": [p.to_dict() for p in self.interior],
            "outer_boundary": [list(b) for b in self.outer_boundary],
            "asymmetry": self.asymmetry,
            "limits": self.limits(),
        }


# ------------------------------------------------------------------------------------ control variants
def with_bank(spec: FlightSpec, law: str, **variant: Any) -> FlightSpec:
    """The spec with its bank law replaced (controls.replace_bank_law: bank_deg, bank_gain, limit_deg,
    sigma_f_deg, turn_deg, right); everything else in the control array (alpha law, start) kept."""
    return replace(spec, ctrl=replace_bank_law(spec.ctrl, law, **variant))


def with_alpha(spec: FlightSpec, law: str) -> FlightSpec:
    return replace(spec, ctrl=replace_alpha_law(spec.ctrl, law))


# ------------------------------------------------------------------------------------------ the methods
def single_parameter(spec: FlightSpec, s: SingleParameter = SingleParameter()) -> "Footprint":
    """Section II.6 a-d: phi_B = K zeta with K = phi0 / 90 deg, phi0 stepped 0-150 deg, plus one
    minimum-down-range point: zero lift (Section II.6 d) or C_L max at zero bank (Appendix C data set 1)."""
    return footprint_of_family("single_parameter", spec, single_parameter_family(s), s.mirror, s.contours_fps)


def single_parameter_family(s: SingleParameter) -> Family:
    """single_parameter's control settings [(parameter, make(spec, right) -> spec, on_axis)]."""
    limit_deg = s.limit_deg
    return [
        (
            ControlSetting(bank0_deg=float(b), bank_gain=b / SIGMA0_DEG),
            lambda sp, right, b=b: with_bank(
                sp, "single_parameter", bank_gain=b / SIGMA0_DEG, limit_deg=limit_deg, right=right
            ),
            b == 0,
        )
        for b in s.bank0_deg
    ] + _min_range(s.min_range)


def constant_bank(spec: FlightSpec, s: ConstantBank = ConstantBank()) -> "Footprint":
    """Fig. 14: constant bank (Staged: until the heading has changed turn_deg, then wings level)."""
    method = "staged" if isinstance(s, Staged) else "constant"
    return footprint_of_family(method, spec, constant_bank_family(s), s.mirror, s.contours_fps)


def constant_bank_family(s: ConstantBank) -> Family:
    """constant_bank's (and staged's) control settings [(parameter, make(spec, right) -> spec, on_axis)]."""
    staged = isinstance(s, Staged)
    law, turn_deg = ("staged", s.turn_deg) if isinstance(s, Staged) else ("constant", 90.0)
    return [
        (
            ControlSetting(bank_deg=float(b), turn_deg=turn_deg if staged else None),
            lambda sp, right, b=b: with_bank(sp, law, bank_deg=b, turn_deg=turn_deg, right=right),
            b == 0,
        )
        for b in s.bank_deg
    ] + _min_range(s.min_range)


def two_parameter(spec: FlightSpec, s: TwoParameter = TwoParameter()) -> "Footprint":
    """Figs. 5-7: phi_B = K (zeta - sigma_f), limited to 75 deg; one set per K, sigma_f varied.

    The footprint's boundary is the outer boundary of all sets (the report's "fairing through the outer
    boundary of the parametric data", as the upper convex chain); each set is kept in `sets`.
    """
    sets, flights, mirror, limit_deg = {}, [], s.mirror, s.limit_deg
    for gain in s.bank_gain:
        family = [
            (
                ControlSetting(bank_gain=float(gain), sigma_f_deg=float(sf)),
                lambda sp, right, gain=gain, sf=sf: with_bank(
                    sp, "two_parameter", bank_gain=gain, limit_deg=limit_deg, sigma_f_deg=sf, right=right
                ),
                sf >= SIGMA0_DEG,
            )
            for sf in s.sigma_f_deg
        ]
        f = _fly(spec, family, mirror, s.contours_fps)
        sets[float(gain)] = f.axis + f.left
        flights.append(f)
    # a fresh list of Nones pads a half flown without mirror (mypy would type the pad as f.right's list)
    pairs = [
        (lp, rp)
        for f in flights
        for lp, rp in zip(f.left, f.right or cast(list[FootprintPoint | None], [None] * len(f.left)))
    ]
    hull = upper_boundary([(p.downrange_nmi, p.crossrange_nmi) for f in flights for p in f.axis + f.left])
    on_hull = set(hull)  # the chain's vertices are the points' own (down, cross) floats
    outer = sorted(
        (lr for lr in pairs if (lr[0].downrange_nmi, lr[0].crossrange_nmi) in on_hull),
        key=lambda lr: -lr[0].downrange_nmi,
    )
    merged = _Flights(
        axis=flights[0].axis,
        left=[lp for lp, _ in outer],
        right=cast(list[FootprintPoint], [r for _, r in outer]) if mirror else [],  # mirror: no None pad
        flown=sum(f.flown for f in flights),
        asymmetry=_worst([f.asymmetry for f in flights]),
    )
    fp = _assemble("two_parameter", spec, merged)
    fp.sets, fp.outer_boundary = sets, hull
    return fp


def constant_altitude(spec: FlightSpec, s: ConstantAltitude = ConstantAltitude()) -> "Footprint":
    """Fig. 19 / Appendix C data set 2: after pull-out hold the pull-out altitude. The straight point
    holds it with alpha until (L/D)max is reached; turning points fly (L/D)max and bank to hold altitude
    until the heading has changed turn_deg, then wings level, holding the altitude with alpha until
    (L/D)max is reached; the widest turn keeps the bank until no lift is left to turn with (the dashed
    line of Fig. 19), or 179 deg. Without turn_deg the turns are `steps` equal
    parts of the widest one."""
    widest = simulate(with_bank(spec, "constant_altitude", turn_deg=WIDEST_TURN_DEG)).summary["turn_deg"] or 0.0
    if s.turn_deg is None:
        turns = [widest * i / s.steps for i in range(1, s.steps)]
    else:
        turns = [float(t) for t in s.turn_deg if 0.0 < t < widest]
    straight = with_bank(with_alpha(spec, "level_flight"), "zero")
    family: Family = [(ControlSetting(turn_deg=0.0), lambda sp, right: straight, True)]
    family += [
        (
            ControlSetting(turn_deg=t),
            lambda sp, right, t=t: with_bank(sp, "constant_altitude", turn_deg=t, right=right),
            False,
        )
        for t in turns
    ]
    family.append(
        (
            ControlSetting(turn_deg=widest, until="wings_level"),
            lambda sp, right: with_bank(sp, "constant_altitude", turn_deg=WIDEST_TURN_DEG, right=right),
            False,
        )
    )
    fp = footprint_of_family("constant_altitude", spec, family, s.mirror, s.contours_fps)
    fp.trajectories += 1  # the widest turn, flown first to find its size
    return fp


def staged(spec: FlightSpec, s: Staged = Staged()) -> "Footprint":
    """Fig. 14: constant bank until the heading has changed turn_deg (90 deg), then wings level."""
    return constant_bank(spec, s)


# ------------------------------------------------------------------------------------------ machinery
def _min_range(kind: str | None) -> Family:
    if kind is None:
        return []
    if kind == "zero_lift":
        return [(ControlSetting(min_range="zero_lift"), lambda sp, right: with_bank(sp, "zero_lift"), True)]
    return [(ControlSetting(min_range="cl_max"), lambda sp, right: with_alpha(with_bank(sp, "zero"), "cl_max"), True)]


def velocity_crossings(traj: Trajectory, velocities_fps: Iterable[float]) -> tuple[dict[str, float], ...]:
    """Where a trajectory first slows through each velocity, interpolated linearly between integration
    steps (at most 50 s apart; good to about a nautical mile at 10,000 ft/s)."""
    h = traj.history
    v = h["velocity_fps"]
    out = []
    for vc in velocities_fps:
        below = np.nonzero(v <= vc)[0]
        if len(below) == 0 or below[0] == 0:
            continue
        i = below[0]
        w = (v[i - 1] - vc) / (v[i - 1] - v[i])
        at = {
            k: float(h[k][i - 1] + w * (h[k][i] - h[k][i - 1]))
            for k in ("downrange_nmi", "crossrange_nmi", "time_s", "altitude_ft", "latitude_deg")
        }
        dlon = wrap_longitude(h["longitude_deg"][i] - h["longitude_deg"][i - 1])
        at["longitude_deg"] = float(wrap_longitude(h["longitude_deg"][i - 1] + w * dlon))
        out.append(
            {
                "velocity_fps": float(vc),
                "downrange_nmi": at["downrange_nmi"],
                "crossrange_nmi": at["crossrange_nmi"],
                "flight_time_s": at["time_s"],
                "altitude_ft": at["altitude_ft"],
                "latitude_deg": at["latitude_deg"],
                "longitude_deg": at["longitude_deg"],
            }
        )
    return tuple(out)


def point_of_trajectory(
    parameter: ControlSetting, side: str, traj: Trajectory, contours_fps: Sequence[float] = ()
) -> FootprintPoint:
    """The footprint point where a flown trajectory ends."""
    s = traj.summary
    return FootprintPoint(
        parameter=parameter,
        side=side,
        downrange_nmi=s["downrange_nmi"],
        crossrange_nmi=s["crossrange_nmi"],
        flight_time_s=s["flight_time_s"],
        latitude_deg=s["final_latitude_deg"],
        longitude_deg=s["final_longitude_deg"],
        heading_deg=s["final_heading_deg"],
        final_velocity_fps=s["final_velocity_fps"],
        final_altitude_ft=s["final_altitude_ft"],
        pullout_altitude_ft=s["pullout_altitude_ft"],
        stop_reason=s["stop_reason"],
        pullout_downrange_nmi=s["pullout_downrange_nmi"],
        pullout_velocity_fps=s["pullout_velocity_fps"],
        pullout_time_s=s["pullout_time_s"],
        turn_deg=s["turn_deg"],
        contours=velocity_crossings(traj, contours_fps) if contours_fps else (),
        limits_broken=tuple(s["limits_broken"]),
    )


@dataclass
class _Flights:
    axis: list[FootprintPoint]  # zero bank first (maximum down-range), the minimum-range point last
    left: list[FootprintPoint]
    right: list[FootprintPoint]  # paired with `left`, empty without mirror
    flown: int
    asymmetry: dict[str, float] | None


def _fly(spec: FlightSpec, family: Family, mirror: bool, contours_fps: Sequence[float] = ()) -> _Flights:
    """Fly a family [(parameter, make(spec, right) -> spec, on_axis)]: the left half, and the right half
    by reflection where that is exact, else flown."""
    axis: list[FootprintPoint] = []
    left: list[FootprintPoint] = []
    right: list[FootprintPoint] = []
    flown = 0
    exact = mirror_is_exact(spec)
    for parameter, make, on_axis in family:
        pt = _landing(parameter, "axis" if on_axis else "left", make(spec, False), contours_fps)
        flown += 1
        if on_axis:
            axis.append(pt)
            continue
        if left and _same_place(pt, left[-1]):  # e.g. turns beyond the largest one: wings level earlier
            continue
        left.append(pt)
        if mirror and exact:
            right.append(reflect(spec, pt))
        elif mirror:
            right.append(_landing(parameter, "right", make(spec, True), contours_fps))
            flown += 1
    asym: dict[str, float] | None = None
    if right and not exact:  # how far the flown halves are from mirror images
        asym = {
            "crossrange_nmi": max(abs(lp.crossrange_nmi + rp.crossrange_nmi) for lp, rp in zip(left, right)),
            "downrange_nmi": max(abs(lp.downrange_nmi - rp.downrange_nmi) for lp, rp in zip(left, right)),
        }
    return _Flights(axis, left, right, flown, asym)


def _landing(parameter: ControlSetting, side: str, spec: FlightSpec, contours_fps: Sequence[float]) -> FootprintPoint:
    """One setting's footprint point: its histories are made only if its iso-velocity contours read them."""
    return point_of_trajectory(parameter, side, simulate(spec), contours_fps)


def _same_place(a: FootprintPoint, b: FootprintPoint) -> bool:
    return abs(a.downrange_nmi - b.downrange_nmi) < 1e-6 and abs(a.crossrange_nmi - b.crossrange_nmi) < 1e-6


def _worst(asyms: Sequence[dict[str, float] | None]) -> dict[str, float] | None:
    present: list[dict[str, float]] = [a for a in asyms if a]  # typed: the None (and empty) ones left out
    return {k: max(a[k] for a in present) for k in present[0]} if present else None


def footprint_of_family(
    method: str, spec: FlightSpec, family: Family, mirror: bool, contours_fps: Sequence[float] = ()
) -> Footprint:
    """The footprint a family [(parameter, make(spec, right) -> spec, on_axis)] of control settings draws."""
    return _assemble(method, spec, _fly(spec, family, mirror, contours_fps))


def _assemble(method: str, spec: FlightSpec, f: _Flights) -> Footprint:
    """The footprint of a family's flights: their points in the report's boundary order (boundary_order); a
    minimum-range point inside the footprint the banked points draw is kept in `interior`."""
    pts = f.axis + f.left + f.right
    na, nl = len(f.axis), len(f.left)
    front = [i for i in range(na) if pts[i].parameter.min_range is None][:1]
    back = [i for i in range(na) if pts[i].parameter.min_range is not None]
    xy = [(p.downrange_nmi, p.crossrange_nmi) for p in pts]
    order = boundary_order(xy, front, list(range(na, na + nl)), list(range(na + nl, len(pts))), back, bool(f.right))
    boundary = [pts[i] for i in order]
    e = spec.entry
    return Footprint(
        method=method,
        points=boundary,
        area_nmi2=area_nmi2(boundary),
        trajectories=f.flown,
        entry={"latitude_deg": e.latitude_deg, "longitude_deg": e.longitude_deg, "heading_deg": e.heading_deg},
        interior=[pts[i] for i in back if i not in order],
        asymmetry=f.asymmetry,
    )


def boundary_order(
    xy: Sequence[tuple[float, float]],
    front: list[int],
    left: list[int],
    right: list[int],
    back: list[int],
    mirror: bool,
) -> list[int]:
    """The report's boundary (Section II.6, Figs. 9-14: the points joined in the order of their parameter) through a
    family's landings (indices into xy, (down-range, cross-range) nmi each): the farthest axis point, the left half
    inwards, the minimum-range points (zero lift, C_L max) that lie outside the polygon the others draw (a half
    footprint's closed along the axis, as area_nmi2 closes it), the right half (paired with the left, in its order)
    back out. The footprint methods and each dispersed sample's footprint draw it."""
    ring = front + left + right[::-1]
    polygon = [xy[j] for j in ring]
    if not mirror and polygon:
        polygon = close_half_along_axis(polygon)
    outside = [j for j in back if len(polygon) < 3 or not inside_points(*xy[j], polygon)]
    return front + left + outside + right[::-1]


def mirror_is_exact(spec: FlightSpec) -> bool:
    """True where the planet is symmetric about the initial great circle's plane."""
    pl, e = spec.planet, spec.entry
    if pl.rotating:  # rotation is symmetric about the equator only, where the odd term H still breaks it
        return False
    equatorial = e.latitude_deg == 0.0 and abs(abs(e.heading_deg) - 90.0) < 1e-12
    return not pl.oblate or (equatorial and pl.h == 0.0)


def reflect(spec: FlightSpec, p: FootprintPoint) -> FootprintPoint:
    """The mirror image of a left-half point across the initial great circle (a sphere's, or the equator)."""
    e = spec.entry
    _, _, n = great_circle_frame(e.latitude_deg, e.longitude_deg, e.heading_deg)
    lat, lon, hdg = _reflect(n, p.latitude_deg, p.longitude_deg, p.heading_deg)
    contours = []
    for c in p.contours:
        clat, clon, _ = _reflect(n, c["latitude_deg"], c["longitude_deg"], 0.0)
        contours.append(c | {"crossrange_nmi": -c["crossrange_nmi"], "latitude_deg": clat, "longitude_deg": clon})
    return replace(
        p,
        side="right",
        crossrange_nmi=-p.crossrange_nmi,
        latitude_deg=lat,
        longitude_deg=lon,
        heading_deg=hdg,
        contours=tuple(contours),
        mirrored=True,
    )


def _reflect(
    n: NDArray[np.float64], latitude_deg: float, longitude_deg: float, heading_deg: float
) -> tuple[float, float, float]:
    """A point and a heading there, reflected in the plane with unit normal n."""

    def horizon(lat: float, lon: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return (
            np.array([-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)]),
            np.array([-math.sin(lon), math.cos(lon), 0.0]),
        )

    u = unit_vectors(latitude_deg, longitude_deg)
    north, east = horizon(math.radians(latitude_deg), math.radians(longitude_deg))
    h = math.radians(heading_deg)
    d = math.cos(h) * north + math.sin(h) * east
    u2, d2 = u - 2 * (u @ n) * n, d - 2 * (d @ n) * n
    lat2, lon2 = math.asin(max(-1.0, min(1.0, u2[2]))), math.atan2(u2[1], u2[0])
    north2, east2 = horizon(lat2, lon2)
    return math.degrees(lat2), math.degrees(lon2), math.degrees(math.atan2(d2 @ east2, d2 @ north2))


def area_nmi2(points: Iterable[FootprintPoint], radius_nmi: float = MEAN_RADIUS_NMI) -> float:
    """The area inside a footprint's boundary points (ring_area_nmi2)."""
    return ring_area_nmi2([(p.downrange_nmi, p.crossrange_nmi) for p in points], radius_nmi)


def ring_area_nmi2(pts: list[tuple[float, float]], radius_nmi: float = MEAN_RADIUS_NMI) -> float:
    """Area on the sphere of radius R' inside the polygon (down-range, cross-range) nmi whose edges are straight in
    those coordinates: dA = cos(c/R') dd dc, integrated by Green's theorem edge by edge in closed form.
    A half footprint is closed along the initial great circle (cross-range 0)."""
    if len(pts) < 2:
        return 0.0
    pts = close_half_along_axis(pts)
    total = 0.0
    for (d0, c0), (d1, c1) in zip(pts, pts[1:] + pts[:1]):
        b0, b1 = c0 / radius_nmi, c1 / radius_nmi
        db = b1 - b0
        mean_sin = (math.cos(b0) - math.cos(b1)) / db if abs(db) > 1e-12 else math.sin(0.5 * (b0 + b1))
        total += (d1 - d0) / radius_nmi * mean_sin
    return abs(total) * radius_nmi**2


def crossrange_at_nmi(points: Iterable[FootprintPoint], downrange_nmi: float) -> float | None:
    """The left half's cross-range at a down-range, linear between its points (on a convex stretch the chord
    lies inside the boundary it samples); None outside the down-ranges the half reaches."""
    left = sorted((p.downrange_nmi, p.crossrange_nmi) for p in points if p.crossrange_nmi >= 0.0)
    d, c = np.array(left).T
    return float(np.interp(downrange_nmi, d, c)) if d[0] <= downrange_nmi <= d[-1] else None


def upper_boundary(points: Iterable[tuple[float, float]]) -> list[tuple[float, float]]:
    """The outer (upper) convex chain of (down-range, cross-range) points from the shortest down-range to
    the longest, dropped to the axis at both ends."""
    top: dict[float, float] = {}
    for d, c in points:  # at equal down-range only the widest point can be on the boundary
        top[d] = max(c, top.get(d, c))
    chain: list[tuple[float, float]] = []
    for q in sorted(top.items()):  # Andrew's monotone chain, upper half
        while len(chain) >= 2 and _turn(chain[-2], chain[-1], q) >= 0.0:
            chain.pop()
        chain.append(q)
    return [(chain[0][0], 0.0)] + chain + [(chain[-1][0], 0.0)]


def _turn(o: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
