"""The guided footprint: the targets the guided vehicle (core.guidance) reaches within R nmi in at least a fraction p
of the dispersed samples, traced as a boundary in down-range and cross-range about the entry.

Rays. The reachable set is taken as star-shaped about a centre on the initial great circle, the middle of the
down-ranges the undispersed guided vehicle reaches on it (`frame`: bisections on the axis, and on the cross-range
at the centre for the rays' scale). A ray at angle theta holds the targets centre + s (a cos theta, b sin theta),
a the half length and b the half width so found. Along each ray (one part of a run each):
  1. s_nominal: the farthest s the undispersed guided flight reaches within R (bisection);
  2. s_guided: the farthest s in [LOWER_FRACTION s_nominal, s_nominal] reached within R with P >= p at 95 %
     confidence: the one-sided Clopper-Pearson lower bound on the fraction of samples reached is at least p
     (`allowed_misses`; issue 50: 198 of 200 is a point estimate of 0.99 whose bound is only 0.964) (bisection; a
     candidate fails as soon as more samples missed than that allows, the samples that missed before flying first,
     so a failure costs a few flights and a pass every sample).
The guided footprint lies inside the undispersed one by construction; the area between the guided footprint and
an outer one (the report's, or the true optimal) is the guidance's margin.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from footprint.core.dispersion import Samples, sample_spec
from footprint.core.errors import InputError, Stopped
from footprint.core.footprints import ring_area_nmi2
from footprint.core.guided_reach import aimed_at, landed_miss_nmi
from footprint.core.monte_carlo import clopper_pearson
from footprint.core.outline import outline
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, latlon_from_ranges
from footprint.core.trajectory import FlightSpec, Stop, simulate_summary

AXIS_GRID = 24  # targets on the axis that find the reached interval
AXIS_BISECTIONS = 10  # the frame's bisections (the reach on the axis to ~0.1 % of its span)
NOMINAL_BISECTIONS = 8  # s_nominal to 1/256 of the ray's first bracket
GUIDED_BISECTIONS = 4  # s_guided to 1/16 of (1 - LOWER_FRACTION) s_nominal
LOWER_FRACTION = 0.8  # s_guided's bracket starts here (lowered by this factor again while it fails)
FAR_S = 1.6  # the rays' first bracket: 0 to FAR_S half-axes
CONFIDENCE = 0.95  # a target is reached "with P >= p at 95 % confidence" (one-sided)


@dataclass(frozen=True)
class GuidedFootprintSettings:
    rays: int = 24
    samples: int = 300  # of the dispersion, per candidate target: 299 is the fewest that can show P >= 0.99
    radius_nmi: float = 5.0
    probability: float = 0.99


class Frame(NamedTuple):
    """The rays' centre (down-range, nmi, on the axis) and half-axes (nmi)."""

    center_nmi: float
    half_length_nmi: float
    half_width_nmi: float


def targeted(spec: FlightSpec, down_nmi: float, cross_nmi: float) -> FlightSpec:
    """The guided spec aimed at the point (down-range, cross-range) about its entry."""
    e = spec.entry
    lat, lon = latlon_from_ranges(down_nmi, cross_nmi, e.latitude_deg, e.longitude_deg, e.heading_deg)
    return aimed_at(spec, float(lat), float(lon))


def _reached(spec: FlightSpec, radius_nmi: float) -> bool:
    return landed_miss_nmi(simulate_summary(spec)) <= radius_nmi


def _bisect(ok: Callable[[float], bool], lo: float, hi: float, steps: int) -> float:
    """The largest s in [lo, hi] with ok(s), ok(lo) assumed, to (hi - lo) / 2^steps."""
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def _bisect_guided(ok: Callable[[float], bool], s_nominal: float) -> float:
    """The largest s in [LOWER_FRACTION s_nominal, s_nominal] with ok(s), to a 2^-GUIDED_BISECTIONS part of the
    bracket. The bracket's floor is flown only when no candidate above it passed (a pass costs every sample); when it
    fails too, the bracket moves down below it, LOWER_FRACTION of it, and is bisected again (0 when nothing passes)."""
    lo, hi = LOWER_FRACTION * s_nominal, s_nominal
    while lo > 1e-3:
        passed = False
        for _ in range(GUIDED_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if ok(mid):
                lo, passed = mid, True
            else:
                hi = mid
        if passed or ok(lo):
            return lo
        lo, hi = LOWER_FRACTION * lo, lo
    return 0.0


def frame(spec: FlightSpec, radius_nmi: float) -> Frame:
    """The rays' centre and half-axes from the undispersed guided reach on the axis and across it: a grid of targets
    on the initial great circle, then bisections past its first and last reached points."""
    grid = np.linspace(500.0, 0.95 * 2.0 * math.pi * MEAN_RADIUS_NMI, AXIS_GRID)  # no glider reaches round the earth
    step = float(grid[1] - grid[0])
    on_axis = [float(d) for d in grid if _reached(targeted(spec, float(d), 0.0), radius_nmi)]
    if not on_axis:
        raise InputError("case", "the guided vehicle reaches no target on its initial great circle from this entry")
    first, last = on_axis[0], on_axis[-1]
    low = first - _bisect(
        lambda d: _reached(targeted(spec, first - d, 0.0), radius_nmi), 0.0, min(step, first), AXIS_BISECTIONS
    )
    high = last + _bisect(lambda d: _reached(targeted(spec, last + d, 0.0), radius_nmi), 0.0, step, AXIS_BISECTIONS)
    center = 0.5 * (low + high)
    width = _bisect(lambda c: _reached(targeted(spec, center, c), radius_nmi), 0.0, high - low, AXIS_BISECTIONS)
    return Frame(center, 0.5 * (high - low), max(width, 1.0))


def ray_point(f: Frame, angle_rad: float, s: float) -> tuple[float, float]:
    return f.center_nmi + s * f.half_length_nmi * math.cos(angle_rad), s * f.half_width_nmi * math.sin(angle_rad)


def lower_bound(reached: int, samples: int, confidence: float = CONFIDENCE) -> float:
    """The one-sided Clopper-Pearson lower bound on P(reach) (Clopper & Pearson, Biometrika 26, 1934): the two-sided
    interval of level 2 confidence - 1 has the same lower end, beta.ppf(1 - confidence, k, n - k + 1)."""
    return clopper_pearson(reached, samples, 2.0 * confidence - 1.0)[0]


def allowed_misses(samples: int, probability: float, confidence: float = CONFIDENCE) -> int:
    """The most misses of `samples` that still show P(reach) >= probability with `confidence`; -1 when even no miss
    cannot (the bound of n of n is (1 - confidence)^(1/n): 299 samples for 0.99, none for 1)."""
    misses = 0
    while misses <= samples and lower_bound(samples - misses, samples, confidence) >= probability:
        misses += 1
    return misses - 1


def fewest_samples(probability: float, confidence: float = CONFIDENCE) -> int | None:
    """The fewest samples that can show P >= probability with `confidence` (all reached); None for probability 1."""
    if probability >= 1.0:
        return None
    return math.ceil(math.log(1.0 - confidence) / math.log(probability) - 1e-12)


def dispersed_ok(
    spec: FlightSpec,
    samples: Samples,
    settings: GuidedFootprintSettings,
    counter: list[int],
    hard: list[int] | None = None,
) -> bool:
    """Whether the target is reached within R with P >= p at 95 % confidence (allowed_misses): stops at the first miss
    too many. The samples
    in `hard` (those that missed a neighbouring target) fly first and each new miss joins them, so a failing target
    is found in a few flights; the verdict does not depend on the order. counter[0] counts the flights."""
    hard = [] if hard is None else hard
    known = set(hard)
    allowed = allowed_misses(len(samples), settings.probability)
    if allowed < 0:
        return False
    misses = 0
    for i in [*hard, *(j for j in range(len(samples)) if j not in known)]:
        counter[0] += 1
        if not _reached(sample_spec(spec, samples, i), settings.radius_nmi):
            misses += 1
            if i not in known:
                hard.append(i)
                known.add(i)
            if misses > allowed:
                return False
    return True


def trace_ray(
    spec: FlightSpec,
    f: Frame,
    angle_rad: float,
    samples: Samples,
    settings: GuidedFootprintSettings,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> dict[str, Any]:
    """One ray: s_nominal, s_guided and the boundary points (module docstring)."""
    flights: list[int] = [0]
    hard: list[int] = []

    def nominal(s: float) -> bool:
        flights[0] += 1
        return _reached(targeted(spec, *ray_point(f, angle_rad, s)), settings.radius_nmi)

    def guided(s: float) -> bool:
        if on_progress is not None and on_progress(0.5, f"ray {math.degrees(angle_rad):.0f} deg, s {s:.3f}"):
            raise Stopped("stopped")
        return dispersed_ok(targeted(spec, *ray_point(f, angle_rad, s)), samples, settings, flights, hard)

    s_nominal = _bisect(nominal, 0.0, FAR_S, NOMINAL_BISECTIONS)
    s_guided = _bisect_guided(guided, s_nominal)
    (nd, nc), (gd, gc) = ray_point(f, angle_rad, s_nominal), ray_point(f, angle_rad, s_guided)
    return {
        "angle_deg": math.degrees(angle_rad),
        "s_nominal": s_nominal,
        "s_guided": s_guided,
        "nominal": {"downrange_nmi": nd, "crossrange_nmi": nc},
        "guided": {"downrange_nmi": gd, "crossrange_nmi": gc},
        "flights": flights[0],
    }


def _ring(d: list[float], c: list[float], spec: FlightSpec) -> dict[str, Any]:
    """A boundary ring (down, cross) nmi with its latitudes, longitudes, area and outline (core.outline: its edges
    sampled on the sphere, its area on the map across +-180 deg and over a pole, as a stored footprint's)."""
    e = spec.entry
    lat, lon = latlon_from_ranges(np.array(d), np.array(c), e.latitude_deg, e.longitude_deg, e.heading_deg)
    return {
        "downrange_nmi": list(d),
        "crossrange_nmi": list(c),
        "latitude_deg": lat.tolist(),
        "longitude_deg": lon.tolist(),
        "area_nmi2": ring_area_nmi2(list(zip(d, c))),
        "outline": outline(d, c, Reference(e.latitude_deg, e.longitude_deg, e.heading_deg)).to_dict(),
    }


def boundary(spec: FlightSpec, rays: list[dict[str, Any]], which: str) -> dict[str, Any]:
    """The ring of the rays' points `which` ("nominal" or "guided")."""
    rays = sorted(rays, key=lambda r: r["angle_deg"])
    return _ring([r[which]["downrange_nmi"] for r in rays], [r[which]["crossrange_nmi"] for r in rays], spec)


def outer_footprints(
    spec: FlightSpec, optimal: bool, on_progress: Callable[[float, str], bool | None] | None = None
) -> dict[str, dict[str, Any] | None]:
    """The guided vehicle's outer bounds, open loop and undispersed: the report's footprint (Sec. II.6, the single-
    parameter bank law, both halves) flown to the guidance's terminal energy, and the true optimal one (collocation)
    to its terminal altitude (the collocation ends at an altitude; a longer flight than to the energy, so an outer
    bound still)."""
    from footprint.core.footprint_methods import footprint
    from footprint.core.method_settings import Collocation, MethodSettings, SingleParameter

    g = spec.guidance
    assert g is not None
    rings: dict[str, dict[str, Any] | None] = {"report": None, "optimal": None}
    stops: dict[str, tuple[Stop, MethodSettings]] = {
        "report": (replace(spec.stop, energy_ft=g.terminal_energy_ft), SingleParameter()),
        "optimal": (replace(spec.stop, altitude_ft=g.terminal_altitude_ft), Collocation()),
    }
    for name, (stop, settings) in stops.items():
        if name == "optimal" and not optimal:
            continue
        fp = footprint(replace(spec, guidance=None, stop=stop), settings, on_progress)
        rings[name] = _ring([p.downrange_nmi for p in fp.points], [p.crossrange_nmi for p in fp.points], spec)
    return rings


def reach_on_ray(points: list[tuple[float, float]], f: Frame, angle_rad: float) -> float | None:
    """The s at which a closed boundary (down, cross) points crosses the ray (the farthest crossing): an outer
    footprint's reach along the ray, to compare with the guided one's."""
    ux, uy = f.half_length_nmi * math.cos(angle_rad), f.half_width_nmi * math.sin(angle_rad)
    best = None
    pts = points + points[:1]
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        # center + s u = p0 + t (p1 - p0)
        ax, ay = x0 - f.center_nmi, y0
        dx, dy = x1 - x0, y1 - y0
        det = ux * (-dy) - uy * (-dx)
        if abs(det) < 1e-12:
            continue
        s = (ax * (-dy) - ay * (-dx)) / det
        t = (ux * ay - uy * ax) / det
        if 0.0 <= t <= 1.0 and s > 0.0:
            best = s if best is None else max(best, s)
    return best
