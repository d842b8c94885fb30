"""Dispersed footprints: a footprint's family of control settings (footprint_methods.control_family) flown again in
every Monte Carlo sample of core.dispersion, and what a planner reads from where the flights land.

A sample is one possible world (entry state, air, aerodynamics); in it the vehicle can fly any of the family's
settings, so the sample's footprint is the polygon through its landing points, drawn as the report draws a
footprint (footprints._assemble: the maximum down-range point, the left half, the minimum-range point where it
lies outside the others, the right half back; a half footprint closed along the axis). From the samples:

- each setting's cloud of landing points, its mean and covariance in down-range and cross-range about the nominal
  entry, and its 1-sigma and 3-sigma ellipses (39 % and 98.9 % of a two-dimensional normal);
- the footprint reached with probability >= p: the fraction of the samples' footprints covering each node of a
  grid (exact, by scanlines), contoured at p (contourpy, linear between nodes);
- each site's probability of being reached, with its Clopper-Pearson interval (Clopper & Pearson, Biometrika 26,
  1934: exact, so 0 of n and n of n keep a finite width);
- the spread of the maximum temperature and of the heat load when the case has a heating model;
- every flight that did not end as the undispersed flights do, counted by its stop reason (its first samples named,
  to fly again with histories: sample_trajectories), never dropped silently.

Ranges are about the nominal entry's great circle on the sphere of radius R' (sphere.downrange_crossrange_nmi), a
landing's down-range on the branch nearest its own flight's (so past half a circumference too). Pure numerics.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from footprint.core._jit import njit
from footprint.core.dispersion import Samples, sample_spec
from footprint.core.errors import Stopped
from footprint.core.footprints import boundary_order
from footprint.core.integrate import STOP_REASONS
from footprint.core.limits import tally_columns
from footprint.core.outline import outline
from footprint.core.plane import inside_polygon
from footprint.core.setting import ControlSetting
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    close_half_along_axis,
    downrange_crossrange_nmi,
    latlon_from_ranges,
)
from footprint.core.trajectory import FlightSpec, Trajectory, simulate, simulate_summary

# what a sample keeps of each flight (the histories are not kept): its columns in Landings.values
KEPT = (
    "final_latitude_deg",
    "final_longitude_deg",
    "downrange_nmi",
    "crossrange_nmi",
    "flight_time_s",
    "max_temperature_R",
    "heat_load_btu_ft2",
    "max_load_factor",
    "max_dynamic_pressure_psf",
    "max_heat_rate_btu_ft2_s",
)
LAT, LON, OWN_DOWN, OWN_CROSS, TIME, TEMPERATURE, HEAT_LOAD = range(7)
OUTCOME_NAMES = {
    "altitude": "hit the stop altitude early",
    "velocity": "slowed to the stop velocity early",
    "time": "ran out of time",
    "skip_out": "skipped out",
    "max_steps": "too many steps",
    "step_underflow": "step underflow",
    "none": "did not end",
}
SIGMAS = (1.0, 3.0)  # the ellipses drawn
OUTCOME_SAMPLES_LISTED = 20  # of each flight's samples that did not land, the first named (to fly again in full)
ELLIPSE_POINTS = 73  # closed: the first point repeated
GRID_NODES = (481, 241)  # the coverage grid (down-range, cross-range) over the samples' footprints
CONFIDENCE_INTERVAL = 0.95  # of a site's probability


@dataclass(frozen=True)
class Flight:
    """One control setting on one side: make(spec, right) is the spec it flies (a family member's)."""

    parameter: ControlSetting
    side: str  # "axis", "left", "right"
    make: Callable[[FlightSpec, bool], FlightSpec]
    right: bool

    @property
    def min_range(self) -> bool:
        return self.parameter.min_range is not None


def flights(family: list[tuple[ControlSetting, Callable[..., FlightSpec], bool]], mirror: bool) -> list[Flight]:
    """The flights of a family [(parameter, make, on_axis)]: the axis settings once, the others on the left and,
    with mirror, on the right (flown: a dispersed entry leaves no plane of symmetry)."""
    out: list[Flight] = []
    for parameter, make, on_axis in family:
        if on_axis:
            out.append(Flight(parameter, "axis", make, False))
            continue
        out.append(Flight(parameter, "left", make, False))
        if mirror:
            out.append(Flight(parameter, "right", make, True))
    return out


@dataclass
class Landings:
    """Where the flights of n samples ended: values (n, flights, KEPT) and their stop reasons (n, flights), indices
    into integrate.STOP_REASONS. `first`: the index of the first sample in the run."""

    first: int
    values: NDArray[np.float64]
    stops: NDArray[np.int8]

    @staticmethod
    def join(parts: list[Landings]) -> Landings:
        parts = sorted(parts, key=lambda p: p.first)
        return Landings(
            parts[0].first, np.concatenate([p.values for p in parts]), np.concatenate([p.stops for p in parts])
        )


def fly_samples(
    base: FlightSpec,
    family: list[Flight],
    samples: Samples,
    first: int = 0,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> Landings:
    """Every flight of every sample (the summary path: trajectory.simulate_summary); a chunk of a run.
    on_progress(fraction, note) before each sample (True stops: errors.Stopped)."""
    values = np.full((len(samples), len(family), len(KEPT)), np.nan)
    stops = np.zeros((len(samples), len(family)), np.int8)
    for i in range(len(samples)):
        if on_progress is not None and on_progress(i / len(samples), f"sample {first + i + 1:,}"):
            raise Stopped(f"stopped at sample {first + i + 1:,}")
        spec = sample_spec(base, samples, i)
        for j, f in enumerate(family):
            summary = simulate_summary(f.make(spec, f.right))
            stops[i, j] = STOP_REASONS.index(summary["stop_reason"])
            values[i, j] = [np.nan if summary[k] is None else summary[k] for k in KEPT]
    return Landings(first, values, stops)


def sample_trajectories(base: FlightSpec, family: list[Flight], samples: Samples, index: int) -> list[Trajectory]:
    """Every flight of sample `index` with its histories (trajectory.simulate): the summary path's landing point
    to the bit, and how it got there (a skip-out, a flight that hit the ground early)."""
    spec = sample_spec(base, samples, index)
    return [simulate(f.make(spec, f.right)) for f in family]


# ------------------------------------------------------------------------------------------- geometry
def nominal_ranges(
    base: FlightSpec, landings: Landings, radius_nmi: float = MEAN_RADIUS_NMI
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(down-range, cross-range) nmi of every landing about the nominal entry, each down-range on the branch
    nearest its own flight's (which grows past half a circumference)."""
    e = base.entry
    v = landings.values
    down, cross = downrange_crossrange_nmi(
        v[..., LAT], v[..., LON], e.latitude_deg, e.longitude_deg, e.heading_deg, radius_nmi
    )
    turn = 2.0 * math.pi * radius_nmi
    return down + turn * np.round((v[..., OWN_DOWN] - down) / turn), cross


def polygons(
    family: list[Flight], mirror: bool, down: NDArray[np.float64], cross: NDArray[np.float64], landed: NDArray[np.bool_]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Each sample's footprint polygon (x: down-range, y: cross-range, padded with NaN; counts): the landed
    flights in the report's boundary order, a minimum-range point only where it lies outside the others."""
    front = [j for j, f in enumerate(family) if f.side == "axis" and not f.min_range][:1]
    back = [j for j, f in enumerate(family) if f.min_range]
    left = [j for j, f in enumerate(family) if f.side == "left"]
    right = [j for j, f in enumerate(family) if f.side == "right"]
    n = down.shape[0]
    size = len(family) + 2
    px, py = np.full((n, size), np.nan), np.full((n, size), np.nan)
    counts = np.zeros(n, np.int64)
    for i in range(n):
        f, lt, rt, b = ([j for j in js if landed[i, j]] for js in (front, left, right, back))
        order = boundary_order(list(zip(down[i], cross[i])), f, lt, rt, b, mirror)
        ring = list(zip(down[i, order], cross[i, order]))
        if not mirror and ring:  # a half footprint: closed along the axis
            ring = close_half_along_axis(ring)
        x, y = [p[0] for p in ring], [p[1] for p in ring]
        if len(x) >= 3:
            px[i, : len(x)], py[i, : len(y)], counts[i] = x, y, len(x)
    return px, py, counts


@njit
def _inside_all(
    px: NDArray[np.float64], py: NDArray[np.float64], counts: NDArray[np.int64], x: float, y: float
) -> NDArray[np.bool_]:
    """Which samples' polygons hold the point (x, y)."""
    out = np.zeros(px.shape[0], np.bool_)
    for s in range(px.shape[0]):
        if counts[s] >= 3:
            out[s] = inside_polygon(px[s], py[s], counts[s], x, y)
    return out


@njit
def _coverage(
    px: NDArray[np.float64],
    py: NDArray[np.float64],
    counts: NDArray[np.int64],
    x0: float,
    dx: float,
    nx: int,
    y0: float,
    dy: float,
    ny: int,
) -> NDArray[np.int64]:
    """How many samples' polygons hold each grid node (ny, nx): each polygon's scanline intervals added to a
    difference array, then summed along the rows (exact for the nodes, the even-odd rule)."""
    diff = np.zeros((ny, nx + 1), np.int64)
    xs = np.empty(px.shape[1])
    for s in range(px.shape[0]):
        m = counts[s]
        if m < 3:
            continue
        for j in range(ny):
            y = y0 + j * dy
            k = 0
            for e in range(m):
                ya, yb = py[s, e], py[s, (e + 1) % m]
                if (ya > y) != (yb > y):
                    xa, xb = px[s, e], px[s, (e + 1) % m]
                    xs[k] = xa + (y - ya) * (xb - xa) / (yb - ya)
                    k += 1
            crossings = np.sort(xs[:k])
            for q in range(0, k - 1, 2):
                i0 = min(max(int(math.ceil((crossings[q] - x0) / dx)), 0), nx)
                i1 = min(max(int(math.ceil((crossings[q + 1] - x0) / dx)), 0), nx)
                if i1 > i0:
                    diff[j, i0] += 1
                    diff[j, i1] -= 1
    out = np.empty((ny, nx), np.int64)
    for j in range(ny):
        total = 0
        for i in range(nx):
            total += diff[j, i]
            out[j, i] = total
    return out


def ellipse(
    mean: NDArray[np.float64], covariance: NDArray[np.float64], sigmas: float, points: int = ELLIPSE_POINTS
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The sigmas-sigma ellipse (down-range, cross-range) of a 2-D normal: mean + sigmas L (cos t, sin t), L L^T the
    covariance (its eigenvectors scaled by the square roots of its eigenvalues)."""
    values, vectors = np.linalg.eigh(covariance)
    t = np.linspace(0.0, 2.0 * math.pi, points)
    circle = np.stack([np.cos(t), np.sin(t)])
    xy = mean[:, None] + sigmas * (vectors * np.sqrt(np.maximum(values, 0.0))) @ circle
    return xy[0], xy[1]


def clopper_pearson(k: int, n: int, level: float = CONFIDENCE_INTERVAL) -> tuple[float, float]:
    """The exact binomial confidence interval of k successes in n trials (Clopper & Pearson 1934)."""
    a = 1.0 - level
    low = 0.0 if k == 0 else float(stats.beta.ppf(a / 2.0, k, n - k + 1))
    high = 1.0 if k == n else float(stats.beta.ppf(1.0 - a / 2.0, k + 1, n - k))
    return low, high


# ------------------------------------------------------------------------------------------- the result
@dataclass
class DispersedFootprint:
    """The statistics of a Monte Carlo run over one family (module docstring); ranges in nmi about the nominal
    entry, positions in degrees."""

    samples: int
    flights: list[dict[str, Any]]  # per flight: parameter, side, landed, outcomes, mean, covariance, ellipses, heating
    nominal: list[dict[str, Any]]  # the undispersed flights: parameter, side, down/cross-range, latitude/longitude
    nominal_boundary: dict[str, Any]  # the undispersed footprint's polygon: down/cross-range, latitude/longitude lists
    confidence: list[dict[str, Any]]  # per level p: the rings of the region covered by >= p of the samples' footprints
    # per site: probability, its interval, samples reaching it, inside the nominal footprint
    sites: list[dict[str, Any]]
    outcomes: dict[str, int]  # every flight's end over the run, by what happened
    limits: dict[str, Any]  # every flight of the run that broke a vehicle limit (core.limits.tally), by limit
    # down-range and cross-range (samples, flights), NaN where a flight did not land
    clouds: dict[str, NDArray[np.float64]]
    entry: dict[str, float]

    def to_dict(self, cloud_points: int | None = None) -> dict[str, Any]:
        """JSON-ready; each cloud thinned to its first `cloud_points` samples (None: all)."""
        keep = slice(None) if cloud_points is None else slice(0, cloud_points)
        return {
            "samples": self.samples,
            "entry": self.entry,
            "outcomes": self.outcomes,
            "limits": self.limits,
            "nominal": self.nominal,
            "nominal_boundary": self.nominal_boundary,
            "flights": self.flights,
            "confidence": self.confidence,
            "sites": self.sites,
            "clouds": {
                k: [[None if not math.isfinite(x) else float(x) for x in row] for row in np.asarray(v)[keep].T]
                for k, v in self.clouds.items()
            },
        }


def statistics(
    base: FlightSpec,
    family: list[Flight],
    mirror: bool,
    landings: Landings,
    nominal: Landings,
    levels: Iterable[float] = (0.99,),
    sites: Iterable[tuple[str, float, float]] = (),
    grid_nodes: tuple[int, int] = GRID_NODES,
) -> DispersedFootprint:
    """What the run says (module docstring). sites: (name, latitude_deg, longitude_deg) each."""
    e = base.entry
    n = landings.values.shape[0]
    # the study's own endings: what its undispersed flights do (a stop at a velocity or an altitude, whichever comes
    # first, ends some settings by one and some by the other); a sample's flight ending otherwise did not land
    endings = np.unique(nominal.stops[0])
    landed = np.isin(landings.stops, endings) & np.isfinite(landings.values[..., LAT])
    down, cross = nominal_ranges(base, landings)
    down, cross = np.where(landed, down, np.nan), np.where(landed, cross, np.nan)
    lat, lon = np.where(landed, landings.values[..., LAT], np.nan), np.where(landed, landings.values[..., LON], np.nan)
    nom_down, nom_cross = nominal_ranges(base, nominal)
    px, py, counts = polygons(family, mirror, down, cross, landed)
    flight_stats = [
        _flight(base, f, down[:, j], cross[:, j], landings.stops[:, j], landed[:, j], landings.values[:, j])
        for j, f in enumerate(family)
    ]
    nom = [
        {
            "parameter": f.parameter.as_dict(),
            "side": f.side,
            "downrange_nmi": float(nom_down[0, j]),
            "crossrange_nmi": float(nom_cross[0, j]),
            "latitude_deg": float(nominal.values[0, j, LAT]),
            "longitude_deg": float(nominal.values[0, j, LON]),
            "stop_reason": STOP_REASONS[int(nominal.stops[0, j])],
        }
        for j, f in enumerate(family)
    ]
    npx, npy, ncounts = polygons(family, mirror, nom_down, nom_cross, np.isin(nominal.stops, endings))
    reasons: dict[str, int] = {}
    for code, count in zip(*np.unique(landings.stops, return_counts=True)):
        label = "landed" if code in endings else OUTCOME_NAMES[STOP_REASONS[code]]
        reasons[label] = reasons.get(label, 0) + int(count)
    m = int(ncounts[0])
    bx, by = npx[0, :m], npy[0, :m]
    blat, blon = latlon_from_ranges(bx, by, e.latitude_deg, e.longitude_deg, e.heading_deg)
    boundary = {
        "downrange_nmi": bx.tolist(),
        "crossrange_nmi": by.tolist(),
        "latitude_deg": blat.tolist(),
        "longitude_deg": blon.tolist(),
        "outline": _outline(base, bx, by),
    }
    return DispersedFootprint(
        samples=n,
        flights=flight_stats,
        nominal=nom,
        nominal_boundary=boundary,
        confidence=[_confidence(base, px, py, counts, p, n, grid_nodes) for p in levels],
        sites=[_site(base, px, py, counts, npx, npy, ncounts, name, la, lo) for name, la, lo in sites],
        outcomes={"flights": int(landings.stops.size), **reasons},
        limits=tally_columns(landings.values, KEPT, base.vehicle.limits),
        clouds={"downrange_nmi": down, "crossrange_nmi": cross, "latitude_deg": lat, "longitude_deg": lon},
        entry={"latitude_deg": e.latitude_deg, "longitude_deg": e.longitude_deg, "heading_deg": e.heading_deg},
    )


def _flight(
    base: FlightSpec,
    f: Flight,
    down: NDArray[np.float64],
    cross: NDArray[np.float64],
    stops: NDArray[np.int8],
    landed: NDArray[np.bool_],
    values: NDArray[np.float64],
) -> dict[str, Any]:
    k = int(landed.sum())
    ended = np.unique(stops[~landed])
    out: dict[str, Any] = {
        "parameter": f.parameter.as_dict(),
        "side": f.side,
        "landed": k,
        "outcomes": {OUTCOME_NAMES[STOP_REASONS[c]]: int(np.sum(stops[~landed] == c)) for c in ended},
        "outcome_samples": {
            OUTCOME_NAMES[STOP_REASONS[c]]: np.flatnonzero(~landed & (stops == c))[:OUTCOME_SAMPLES_LISTED].tolist()
            for c in ended
        },
        "limits": tally_columns(values, KEPT, base.vehicle.limits),
    }
    if k >= 2:
        xy = np.stack([down[landed], cross[landed]])
        mean, cov = xy.mean(axis=1), np.cov(xy)
        e = base.entry
        ellipses: dict[str, dict[str, list[float]]] = {}
        for s in SIGMAS:
            ex, ey = ellipse(mean, cov, s)
            elat, elon = latlon_from_ranges(ex, ey, e.latitude_deg, e.longitude_deg, e.heading_deg)
            ellipses[f"{s:g}"] = {
                "downrange_nmi": ex.tolist(),
                "crossrange_nmi": ey.tolist(),
                "latitude_deg": elat.tolist(),
                "longitude_deg": elon.tolist(),
            }
        out |= {
            "mean_downrange_nmi": float(mean[0]),
            "mean_crossrange_nmi": float(mean[1]),
            "covariance_nmi2": cov.tolist(),
            "ellipses": ellipses,
        }
    for key, col in (("max_temperature_R", TEMPERATURE), ("heat_load_btu_ft2", HEAT_LOAD)):
        if (sp := spread(values[landed, col])) is not None:
            out[key] = sp
    return out


def spread(x: NDArray[np.float64]) -> dict[str, float] | None:
    """mean, standard deviation (n - 1), min, median, 99th percentile and max of the finite values; None if none."""
    x = x[np.isfinite(x)]
    if not x.size:
        return None
    return {
        "mean": float(x.mean()),
        "std": float(x.std(ddof=1)) if x.size > 1 else 0.0,
        "min": float(x.min()),
        "p50": float(np.percentile(x, 50)),
        "p99": float(np.percentile(x, 99)),
        "max": float(x.max()),
    }


def _grid(
    px: NDArray[np.float64], py: NDArray[np.float64], counts: NDArray[np.int64], grid_nodes: tuple[int, int]
) -> tuple[float, float, int, float, float, int]:
    """Node coordinates over the polygons' extent, one empty cell beyond it on every side."""
    ok = counts >= 3
    x_lo, x_hi = np.nanmin(px[ok]), np.nanmax(px[ok])
    y_lo, y_hi = np.nanmin(py[ok]), np.nanmax(py[ok])
    nx, ny = grid_nodes
    dx, dy = (x_hi - x_lo) / (nx - 3), (y_hi - y_lo) / (ny - 3)
    return x_lo - dx, dx, nx, y_lo - dy, dy, ny


def _confidence(
    base: FlightSpec,
    px: NDArray[np.float64],
    py: NDArray[np.float64],
    counts: NDArray[np.int64],
    level: float,
    n: int,
    grid_nodes: tuple[int, int],
) -> dict[str, Any]:
    """The region held by at least `level` of the n samples' footprints, as rings (down/cross-range and lat/lon)."""
    from contourpy import contour_generator

    out: dict[str, Any] = {"level": float(level), "rings": []}
    if not np.any(counts >= 3):
        return out
    x0, dx, nx, y0, dy, ny = _grid(px, py, counts, grid_nodes)
    held = _coverage(px, py, counts, x0, dx, nx, y0, dy, ny) / n
    x, y = x0 + dx * np.arange(nx), y0 + dy * np.arange(ny)
    e = base.entry
    # line_type Separate: lines() gives a list of (n, 2) arrays (contourpy types the union of every line type)
    lines = cast(list[NDArray[np.float64]], contour_generator(x=x, y=y, z=held, line_type="Separate").lines(level))
    for line in lines:
        if len(line) < 4:
            continue
        lat, lon = latlon_from_ranges(line[:, 0], line[:, 1], e.latitude_deg, e.longitude_deg, e.heading_deg)
        area = 0.5 * abs(np.dot(line[:-1, 0], line[1:, 1]) - np.dot(line[1:, 0], line[:-1, 1]))
        out["rings"].append(
            {
                "downrange_nmi": line[:, 0].tolist(),
                "crossrange_nmi": line[:, 1].tolist(),
                "latitude_deg": lat.tolist(),
                "longitude_deg": lon.tolist(),
                "area_nmi2": float(area),
                "outline": _outline(base, line[:-1, 0], line[:-1, 1]),
            }
        )
    out["rings"].sort(key=lambda r: -r["area_nmi2"])
    return out


def _outline(base: FlightSpec, down: NDArray[np.float64], cross: NDArray[np.float64]) -> dict[str, Any]:
    """The ring as the map draws a footprint (core.outline: edges sampled on the sphere, its area on the map)."""
    e = base.entry
    return outline(down, cross, Reference(e.latitude_deg, e.longitude_deg, e.heading_deg)).to_dict()


def _site(
    base: FlightSpec,
    px: NDArray[np.float64],
    py: NDArray[np.float64],
    counts: NDArray[np.int64],
    npx: NDArray[np.float64],
    npy: NDArray[np.float64],
    ncounts: NDArray[np.int64],
    name: str,
    latitude_deg: float,
    longitude_deg: float,
) -> dict[str, Any]:
    """A site's probability: the fraction of samples whose footprint holds it on any branch of its down-range (a
    footprint reaches past half a circumference); its ranges on the branch most samples reach it by."""
    e = base.entry
    d, c = downrange_crossrange_nmi(latitude_deg, longitude_deg, e.latitude_deg, e.longitude_deg, e.heading_deg)
    turn = 2.0 * math.pi * MEAN_RADIUS_NMI
    reached = np.zeros(px.shape[0], bool)
    nominal, best = False, (0, float(d))
    for k in (0, 1, -1, 2):  # at most about one and a half times round
        on_branch = _inside_all(px, py, counts, float(d) + k * turn, float(c))
        nominal |= bool(_inside_all(npx, npy, ncounts, float(d) + k * turn, float(c))[0])
        if on_branch.sum() > best[0]:
            best = (int(on_branch.sum()), float(d) + k * turn)
        reached |= on_branch
    k, n = int(reached.sum()), px.shape[0]
    low, high = clopper_pearson(k, n)
    return {
        "name": name,
        "latitude_deg": latitude_deg,
        "longitude_deg": longitude_deg,
        "downrange_nmi": best[1],
        "crossrange_nmi": float(c),
        "probability": k / n,
        "interval": [low, high],
        "interval_level": CONFIDENCE_INTERVAL,
        "samples_reaching": k,
        "inside_nominal": nominal,
    }
