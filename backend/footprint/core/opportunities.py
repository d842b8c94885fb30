"""Landing opportunities from a real orbit and a clock (issue 28 item 3): for each revolution of a UTC window and each
site, the deorbit times whose entry puts the site inside the footprint, with the Δv, the entry and landing times,
the down-range and cross-range the site needs, the margin to the footprint's boundary and the sun at the site.

1. The burn times: a grid (burn_step_s) over the window; the orbit (a TLE by SGP4, or a state vector propagated by
   our integrator: core.elements.Orbit) gives each one's state, the burn and the vacuum coast to the interface are
   flown (core.deorbit): an entry state per burn time.
2. The scan: footprints flown from entries spread round one orbit (RingTable, one per ring_step_deg of argument of
   latitude: about its entry point a footprint depends on where in the orbit it starts, the gravity being zonal),
   each burn's nearest moved by the exact rotation of the sphere (core.reach.margins: the entry point and heading
   carried to the burn's own) to its entry; each site's margin to its boundary (nmi, positive inside) per burn
   time. A revolution runs from one ascending node of the orbit to the next (the first and last cut by the window).
3. The opportunities: per revolution and site, each run of burn times within `screen_nmi` of the boundary gives
   one candidate, at its largest margin (a parabola through the grid's three best). That burn is flown again from
   its own state (its Δv solved again for a target entry angle) and its footprint from its own entry state
   (`refly`: the vertices about the edge nearest the site, or all of them), which sets the margin, the site's
   down-range and cross-range and the flight time (linear in the footprint's boundary along the site's down-range
   line, between its two crossings). The burn window is where the scan's footprints hold the site (the grid's zero
   crossings, interpolated).
4. The sun at the site at landing (core.sun): its elevation and the local apparent solar time; `daylight` when the
   sun is up (above -0.833 deg), `meets_rules` when it is at least the rule's elevation and the margin the rule's.

Times (core.utc): the burn grid and every elapsed time are SI seconds from the window's start, labelled in UTC across
leap seconds; a candidate's burn is taken on the whole millisecond it is written with, so the time written is the
burn flown; entry and landing follow by the coast's and the flight's seconds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, astuple, dataclass, field, replace
from datetime import datetime
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core import deorbit as dorb
from footprint.core import sun
from footprint.core.elements import Orbit, subsatellite_points, teme_to_earth_fixed
from footprint.core.errors import InputError, Stopped
from footprint.core.footprint_methods import FAMILIES, control_family, footprint
from footprint.core.limits import tally
from footprint.core.method_settings import MethodSettings
from footprint.core.outline import outline
from footprint.core.plane import inside_points
from footprint.core.reach import branches, margins
from footprint.core.sampled import parabola_peak
from footprint.core.setting import ControlSetting
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, great_circle_frame, latlon_from_ranges, unit_vectors
from footprint.core.trajectory import FlightSpec, simulate_summary
from footprint.core.utc import after_s, elapsed_s, isos, rounded


@dataclass(frozen=True)
class Ring:
    """A footprint's boundary about its entry point (its places follow from an entry: `placed`)."""

    downrange_nmi: NDArray[np.float64]
    crossrange_nmi: NDArray[np.float64]
    flight_time_s: NDArray[np.float64]
    settings: tuple[tuple[ControlSetting, str], ...] = ()  # each vertex's control setting and side
    limits_broken: tuple[tuple[str, ...], ...] = ()  # each vertex's flight's broken limits (core.limits)

    def replaced(self, idx: Sequence[int], points: Sequence[Ring]) -> Ring:
        """This ring with vertices idx replaced by the one-point rings `points` (their settings kept)."""
        columns = {k: getattr(self, k).copy() for k in RING_COLUMNS}
        broken = list(self.limits_broken)
        for i, q in zip(idx, points):
            for k in RING_COLUMNS:
                columns[k][i] = getattr(q, k)[0]
            if broken:
                broken[i] = q.limits_broken[0]
        return Ring(**columns, settings=self.settings, limits_broken=tuple(broken))


RING_COLUMNS = ("downrange_nmi", "crossrange_nmi", "flight_time_s")


@dataclass(frozen=True)
class Sites:
    names: tuple[str, ...]
    latitude_deg: NDArray[np.float64]
    longitude_deg: NDArray[np.float64]

    @property
    def unit(self) -> NDArray[np.float64]:
        return unit_vectors(self.latitude_deg, self.longitude_deg)


@dataclass(frozen=True)
class Deorbit:
    """The burn: a fixed retrograde Δv, or the Δv that gives a target earth-relative flight-path angle at entry."""

    delta_v_fps: float | None = None
    entry_gamma_deg: float | None = None


@dataclass(frozen=True)
class Settings:
    burn_step_s: float = 30.0
    ring_step_deg: float = 10.0  # the scan's footprints, one per this much of the orbit (RingTable)
    screen_nmi: float = 200.0  # candidates from runs of burn times the moved footprint brings this near a site
    # each candidate's footprint from its own entry: "near" flies the vertices about the edge nearest the site again
    # (the rest moved from the scan's), "full" the whole footprint, "none" the scan's footprint moved
    refly: Literal["near", "full", "none"] = "near"
    sun_elevation_min_deg: float | None = None  # the daylight rule (None: none)
    min_margin_nmi: float = 0.0


@dataclass(frozen=True)
class Opportunity:
    site: int
    site_name: str
    revolution: int
    burn_utc: datetime
    delta_v_fps: float
    coast_s: float
    entry_utc: datetime
    entry: dict[str, float]  # altitude_ft, velocity_fps, gamma_deg, heading_deg, latitude_deg, longitude_deg
    flight_time_s: float
    landing_utc: datetime
    downrange_nmi: float
    crossrange_nmi: float
    margin_nmi: float
    sun_elevation_deg: float
    local_solar_time_h: float
    daylight: bool
    meets_rules: bool
    burn_window_start_utc: datetime
    burn_window_end_utc: datetime
    scan_margin_nmi: float  # the scan's footprint's margin at this burn
    coast_track: list[list[float]]  # [latitude, longitude] deg from the burn to the entry interface
    footprint_ring: dict[str, Any]  # the footprint about this entry (placed): ranges, places, outline
    limits: dict[str, Any]  # its vertices' flights that broke a vehicle limit (core.limits.tally)

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        stamps = [k for k, v in d.items() if isinstance(v, datetime)]
        d.update(zip(stamps, isos([d[k] for k in stamps])))
        return d


@dataclass
class Plan:
    """A window's burn grid and revolutions (cheap: one call of the orbit), shared by every part."""

    orbit: Orbit
    start: datetime
    times_s: NDArray[np.float64]  # burn grid, s from start
    node_s: NDArray[np.float64]  # ascending node crossings in the window, s from start
    revolution: NDArray[np.int64] = field(init=False)

    def __post_init__(self) -> None:
        self.revolution = 1 + np.searchsorted(self.node_s, self.times_s, side="right")

    @property
    def revolutions(self) -> list[int]:
        return sorted({int(r) for r in self.revolution})

    def utc(self, seconds: Sequence[float] | NDArray[np.float64]) -> list[datetime]:
        """The UTC time of each SI `seconds` from the window's start."""
        return after_s(self.start, seconds) if len(seconds) else []


def ground_track(p: Plan, every_s: float = 60.0) -> dict[str, list[Any]]:
    """The sub-satellite points over the window (geodetic, on the report's ellipsoid) every `every_s`: UTC,
    latitude, longitude, revolution."""
    seconds = np.arange(0.0, p.times_s[-1] + 1e-9, every_s)
    lat, lon, _ = subsatellite_points(p.orbit, p.utc(seconds))
    return {
        "utc": isos(p.utc(seconds)),
        "latitude_deg": lat.tolist(),
        "longitude_deg": lon.tolist(),
        "revolution": (1 + np.searchsorted(p.node_s, seconds, side="right")).tolist(),
    }


def plan(orbit: Orbit, start: datetime, end: datetime, burn_step_s: float) -> Plan:
    """The burn grid over [start, end] (SI seconds) and the ascending nodes: where the satellite's z crosses zero
    upward, linear on the grid, then one Newton step on the orbit's own z and its rate (4 ms off on a 60 s grid before
    it, a microsecond after)."""
    span = float(elapsed_s(start, [end])[0])
    times = np.arange(0.0, span + 1e-9, burn_step_s)
    r, _ = orbit.teme_km(after_s(start, times))
    z = r[:, 2]
    up = np.flatnonzero((z[:-1] < 0.0) & (z[1:] >= 0.0))
    nodes = times[up] + burn_step_s * (-z[up]) / (z[up + 1] - z[up])
    if nodes.size:
        r, v = orbit.teme_km(after_s(start, nodes))
        nodes = np.clip(nodes - r[:, 2] / v[:, 2], times[up], times[up + 1])  # the root stays in its bracket
    return Plan(orbit, start, times, nodes)


def burn_states(
    p: Plan, seconds: NDArray[np.float64], omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Earth-fixed position (ft) and earth-relative velocity (ft/s) before the burn at each time."""
    return states_at(p.orbit, p.utc(seconds), omega_rad_s)


def states_at(
    orbit: Orbit, utc: Sequence[datetime], omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Earth-fixed position (ft) and earth-relative velocity (ft/s) of the orbit at each UTC time."""
    return teme_to_earth_fixed(*orbit.teme_km(utc), utc, omega_rad_s)


def entries(
    coast: dorb.Coast,
    r: NDArray[np.float64],
    v: NDArray[np.float64],
    deorbit: Deorbit,
    delta_v_fps: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(Δv per burn, entry rows) of burns from these states (burn_states): `delta_v_fps` when given (the scan's), else
    the deorbit's fixed Δv, or each burn's own for its target entry angle (a secant on flown coasts, burn by burn)."""
    if delta_v_fps is None and deorbit.entry_gamma_deg is not None:
        solved = [dorb.delta_v_for_gamma(coast, r[i], v[i], deorbit.entry_gamma_deg) for i in range(len(r))]
        return np.array([dv for dv, _ in solved]), np.array([row for _, row in solved])
    dvs = np.broadcast_to(np.asarray(deorbit.delta_v_fps if delta_v_fps is None else delta_v_fps, float), len(r))
    return np.array(dvs), dorb.entry_states(coast, r, dorb.burn(r, v, dvs, coast.omega_rad_s))


def delta_v_table(coast: dorb.Coast, p: Plan, delta_v_fps: Sequence[float]) -> list[dict[str, float]]:
    """The entry state a burn at the window's start gives for each Δv (ft/s): entry angle, earth-relative speed,
    coast time and the down-range of the entry from the burn point; a Δv too small to come down is left out."""
    r, v = burn_states(p, p.times_s[:1], coast.omega_rad_s)
    out = []
    for dv in delta_v_fps:
        try:
            row = dorb.entry_states(coast, r, dorb.burn(r, v, dv, coast.omega_rad_s))[0]
        except InputError:
            continue
        out.append(
            {
                "delta_v_fps": float(dv),
                "gamma_deg": float(row[dorb.E_GAMMA]),
                "velocity_fps": float(row[dorb.E_V]),
                "coast_s": float(row[dorb.E_COAST_S]),
                "latitude_deg": float(row[dorb.E_LAT]),
                "longitude_deg": float(row[dorb.E_LON]),
            }
        )
    return out


def argument_of_latitude_deg(p: Plan, seconds: NDArray[np.float64]) -> NDArray[np.float64]:
    """The orbit's argument of latitude (deg in [0, 360): from the ascending node, along the motion) at each time,
    from its TEME state: the angle from the node line k x h to r."""
    r, v = p.orbit.teme_km(p.utc(seconds))
    h = np.cross(r, v)
    node = np.column_stack([-h[:, 1], h[:, 0], np.zeros(len(h))])
    node /= np.linalg.norm(node, axis=1)[:, None]
    along = np.cross(h / np.linalg.norm(h, axis=1)[:, None], node)  # in the plane, 90 deg ahead of the node
    u: NDArray[np.float64] = np.degrees(np.arctan2(np.einsum("ij,ij->i", r, along), np.einsum("ij,ij->i", r, node)))
    return u % 360.0


@dataclass(frozen=True)
class RingTable:
    """Footprints flown from burns spread round the orbit, one per `step_deg` of the burn's argument of latitude,
    and each one's Δv: on a planet whose gravity is zonal, the footprint about its entry point depends on where in
    the orbit the burn is (the entry's latitude and heading; for a target entry angle, the Δv the orbit's height
    there needs), not on the longitude, so each burn of the scan takes the nearest."""

    step_deg: float
    rings: tuple[Ring, ...]
    delta_v_fps: NDArray[np.float64]

    def index(self, u_deg: NDArray[np.float64]) -> NDArray[np.int64]:
        return np.rint(u_deg / self.step_deg).astype(np.int64) % len(self.rings)

    def delta_v_at(self, u_deg: NDArray[np.float64]) -> NDArray[np.float64]:
        """The Δv at each argument of latitude, linear between the table's (periodic)."""
        u = np.arange(len(self.rings) + 1) * self.step_deg
        dv: NDArray[np.float64] = np.interp(u_deg % 360.0, u, np.append(self.delta_v_fps, self.delta_v_fps[0]))
        return dv


def period_s(mean_motion_rev_day: float) -> float:
    return 86_400.0 / mean_motion_rev_day


def orbit_span_s(window_s: float, mean_motion_rev_day: float) -> float:
    """How long after the window's start a plan reads the orbit (s): over the window (the burn grid, the nodes, the
    ground track) and over one whole revolution from its start (ring_table's burns), however short the window."""
    return max(window_s, period_s(mean_motion_rev_day))


def ring_table(coast: dorb.Coast, p: Plan, deorbit: Deorbit, flier: Flier, step_deg: float) -> RingTable:
    """The footprints of burns at u = 0, step, 2 step... (deg), each from the burn of the first revolution from the
    window's start nearest it (within 1 deg), with the Δv given or the one its target entry angle needs there."""
    period = period_s(p.orbit.mean_motion_rev_day)
    u_grid = np.arange(0.0, 360.0 - 1e-9, step_deg)
    seconds = np.arange(0.0, period, period / 360.0)  # within orbit_span_s
    u = argument_of_latitude_deg(p, seconds)
    nearest = [int(np.argmin(np.abs((u - uk + 180.0) % 360.0 - 180.0))) for uk in u_grid]
    dvs, rows = entries(coast, *burn_states(p, seconds[nearest], coast.omega_rad_s), deorbit)
    return RingTable(step_deg, tuple(flier.ring(row) for row in rows), dvs)


def scan_margins(
    rows: NDArray[np.float64], ring: Ring, sites: Sites, radius_nmi: float = MEAN_RADIUS_NMI
) -> NDArray[np.float64]:
    """Each site's margin (nmi, (G, S)) to the footprint `ring` moved to each entry row's point and heading."""
    p0, d0, n = great_circle_frame(rows[:, dorb.E_LAT], rows[:, dorb.E_LON], rows[:, dorb.E_HEADING])
    m, _ = margins(p0, d0, n, ring.downrange_nmi, ring.crossrange_nmi, ring.flight_time_s, sites.unit, 0.0, radius_nmi)
    return m


class Flier:
    """Flies the footprint study (`spec`'s vehicle and controls, the method `settings` name) from an entry row (its
    altitude, earth-relative speed, flight-path angle, heading and place) on the spec's planet: the whole footprint,
    or, for a method whose points are fixed control laws (footprint_methods.FAMILIES), some of its vertices."""

    def __init__(self, spec: FlightSpec, settings: MethodSettings):
        self.spec, self.settings = spec, settings
        self.makers = (
            {p.key(): make for p, make, _ in control_family(settings)[0]} if type(settings) in FAMILIES else None
        )

    def at_entry(self, row: NDArray[np.float64]) -> FlightSpec:
        entry = replace(
            self.spec.entry,
            altitude_ft=float(row[dorb.E_ALT]),
            velocity_fps=float(row[dorb.E_V]),
            gamma_deg=float(row[dorb.E_GAMMA]),
            heading_deg=float(row[dorb.E_HEADING]),
            latitude_deg=float(row[dorb.E_LAT]),
            longitude_deg=float(row[dorb.E_LON]),
            velocity_frame="relative",
        )
        return replace(self.spec, entry=entry)

    def ring(self, row: NDArray[np.float64]) -> Ring:
        """The whole footprint from this entry."""
        pts = footprint(self.at_entry(row), self.settings).points
        columns = {k: np.array([getattr(q, k) for q in pts]) for k in RING_COLUMNS}
        settings = tuple((q.parameter, q.side) for q in pts)
        return Ring(**columns, settings=settings, limits_broken=tuple(q.limits_broken for q in pts))

    def vertices(self, row: NDArray[np.float64], ring: Ring, idx: Sequence[int]) -> Ring:
        """`ring` with its vertices idx flown again from this entry (each by its own setting and side)."""
        assert self.makers is not None  # callers check: a method of fixed control laws
        spec = self.at_entry(row)
        flown = []
        for i in idx:
            setting, side = ring.settings[i]
            s = simulate_summary(self.makers[setting.key()](spec, side == "right"))
            flown.append(
                Ring(
                    np.array([s["downrange_nmi"]]),
                    np.array([s["crossrange_nmi"]]),
                    np.array([s["flight_time_s"]]),
                    limits_broken=(tuple(s["limits_broken"]),),
                )
            )
        return ring.replaced(idx, flown)


NEAR_VERTICES = 3  # "near": the nearest edge's ends and this many vertices more on each side are flown again


def _near_vertices(ring: Ring, down: float, cross: float, radius_nmi: float = MEAN_RADIUS_NMI) -> list[int]:
    """The vertices about the edge nearest a chart point (the down-range scaled by cos(cross-range) there)."""
    scale = math.cos(cross / radius_nmi)
    x, y = (ring.downrange_nmi - down) * scale, ring.crossrange_nmi - cross
    ex, ey = np.roll(x, -1) - x, np.roll(y, -1) - y
    t = np.clip(-(x * ex + y * ey) / np.maximum(ex * ex + ey * ey, 1e-12), 0.0, 1.0)
    nearest = int(np.argmin(np.hypot(x + t * ex, y + t * ey)))
    n = len(x)
    return sorted({(nearest + k) % n for k in range(-NEAR_VERTICES, NEAR_VERTICES + 2)})


def site_in_chart(
    row: NDArray[np.float64], ring: Ring, lat_deg: float, lon_deg: float, radius_nmi: float = MEAN_RADIUS_NMI
) -> tuple[float, float, bool]:
    """The site's (down-range, cross-range) nmi in the chart of an entry row, on the branch (down-range past half a
    circumference) that lies inside the ring, else on the one nearest its down-range span; and whether inside."""
    p0, d0, n = great_circle_frame(row[dorb.E_LAT], row[dorb.E_LON], row[dorb.E_HEADING])
    u = unit_vectors(lat_deg, lon_deg)
    ds = math.atan2(float(d0 @ u), float(p0 @ u))
    cs = math.asin(max(-1.0, min(1.0, float(n @ u)))) * radius_nmi
    polygon = list(zip(ring.downrange_nmi.tolist(), ring.crossrange_nmi.tolist()))
    lo, hi = float(ring.downrange_nmi.min()), float(ring.downrange_nmi.max())
    best = None
    for k in branches(lo / radius_nmi, hi / radius_nmi):
        d = (ds + 2.0 * math.pi * k) * radius_nmi
        if inside_points(d, cs, polygon):
            return d, cs, True
        gap = max(lo - d, d - hi, 0.0)
        if best is None or gap < best[0]:
            best = (gap, d)
    return (ds * radius_nmi if best is None else best[1]), cs, False


def flight_time_at(ring: Ring, downrange_nmi: float, crossrange_nmi: float) -> float:
    """The flight time (s) to a point of the footprint: along the line of its down-range, linear between the
    boundary's two crossings that bracket it in cross-range (each crossing's time linear along its edge); the
    nearest boundary point's time where no crossing brackets it."""
    d, c, t = ring.downrange_nmi, ring.crossrange_nmi, ring.flight_time_s
    d2, c2, t2 = np.roll(d, -1), np.roll(c, -1), np.roll(t, -1)
    straddle = (d - downrange_nmi) * (d2 - downrange_nmi) <= 0.0
    straddle &= d != d2
    f = (downrange_nmi - d[straddle]) / (d2[straddle] - d[straddle])
    cx = c[straddle] + f * (c2[straddle] - c[straddle])
    tx = t[straddle] + f * (t2[straddle] - t[straddle])
    below, above = cx <= crossrange_nmi, cx >= crossrange_nmi
    if below.any() and above.any():
        i, j = np.flatnonzero(below)[np.argmax(cx[below])], np.flatnonzero(above)[np.argmin(cx[above])]
        if cx[j] == cx[i]:
            return float(tx[i])
        return float(tx[i] + (crossrange_nmi - cx[i]) / (cx[j] - cx[i]) * (tx[j] - tx[i]))
    nearest = np.argmin(np.hypot(d - downrange_nmi, c - crossrange_nmi))
    return float(t[nearest])


def _crossing(times: NDArray[np.float64], m: NDArray[np.float64], i: int, j: int) -> float:
    """Where the margin crosses zero between grid indices i and j (linear), or times[j] if it does not."""
    if m[i] < 0.0 <= m[j] or m[j] < 0.0 <= m[i]:
        return float(times[i] + (times[j] - times[i]) * (-m[i]) / (m[j] - m[i]))
    return float(times[j])


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """(first, last) index of each run of True."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


def revolution_opportunities(
    p: Plan,
    revolution: int,
    coast: dorb.Coast,
    deorbit: Deorbit,
    table: RingTable,
    flier: Flier,
    sites: Sites,
    settings: Settings,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> list[Opportunity]:
    """One revolution's opportunities at every site (the scan, then each candidate flown again). A run of burns that
    reaches a site across an ascending node is one pass: the revolution whose part of it holds the better peak
    within a quarter of an orbit of the other's takes it (each part scans that far into its neighbours, so both
    decide alike)."""
    mine = np.flatnonzero(p.revolution == revolution)
    reach_s = 0.25 * period_s(p.orbit.mean_motion_rev_day)
    lo = int(np.searchsorted(p.times_s, p.times_s[mine[0]] - reach_s))
    hi = int(np.searchsorted(p.times_s, p.times_s[mine[-1]] + reach_s, side="right")) - 1
    times = p.times_s[lo : hi + 1]  # the revolution's burns and a quarter of an orbit of each neighbour's
    first, last = int(mine[0]) - lo, int(mine[-1]) - lo
    u = argument_of_latitude_deg(p, times)
    _, rows = entries(coast, *burn_states(p, times, coast.omega_rad_s), deorbit, table.delta_v_at(u))
    which = table.index(u)
    m = np.empty((len(times), len(sites.names)))
    for k in np.unique(which):
        m[which == k] = scan_margins(rows[which == k], table.rings[k], sites)
    candidates = [(s, a, b) for s in range(len(sites.names)) for a, b in _runs(m[:, s] >= -settings.screen_nmi)]
    out = []
    for k, (s, a, b) in enumerate(candidates):
        note = f"revolution {revolution} of {p.revolutions[-1]}"
        if on_progress is not None and on_progress(k / max(len(candidates), 1), note):
            raise Stopped("stopped")
        if b < first or a > last:
            continue  # a neighbour's run
        best = max(a, first) + int(np.argmax(m[max(a, first) : min(b, last) + 1, s]))
        theirs = [i for i in range(a, b + 1) if not first <= i <= last]
        if any(m[i, s] > m[best, s] and abs(times[i] - times[best]) <= reach_s for i in theirs):
            continue  # the pass peaks better in the neighbouring revolution, close by: that one's opportunity
        inside = np.flatnonzero(m[a : b + 1, s] >= 0.0) + a
        window = (times[inside[0]], times[inside[-1]]) if inside.size else (times[best], times[best])
        if inside.size:  # the zero crossings next to the first and last burns inside
            window = (
                _crossing(times, m[:, s], max(inside[0] - 1, 0), inside[0]),
                _crossing(times, m[:, s], min(inside[-1] + 1, len(times) - 1), inside[-1]),
            )
        found = _opportunity(
            p, revolution, coast, deorbit, table.rings[which[best]], flier, sites, settings, s,
            parabola_peak(times, m[:, s], best)[0], float(m[best, s]), window,
        )  # fmt: skip
        if found is not None:
            out.append(found)
    return out


def placed(ring: Ring, row: NDArray[np.float64]) -> dict[str, Any]:
    """A footprint's boundary about an entry row, on the map: its ranges, the places they give about the entry (the
    points flown from it land there; the scan's moved ones by the exact rotation) and its outline (core.outline: the
    edges sampled on the sphere, cut at 180 deg, a pole taken in)."""
    reference = Reference(float(row[dorb.E_LAT]), float(row[dorb.E_LON]), float(row[dorb.E_HEADING]))
    lat, lon = latlon_from_ranges(ring.downrange_nmi, ring.crossrange_nmi, *astuple(reference))
    return {
        "downrange_nmi": ring.downrange_nmi.tolist(),
        "crossrange_nmi": ring.crossrange_nmi.tolist(),
        "latitude_deg": np.atleast_1d(lat).tolist(),
        "longitude_deg": np.atleast_1d(lon).tolist(),
        "outline": _rounded(outline(ring.downrange_nmi, ring.crossrange_nmi, reference, OUTLINE_EDGE_NMI).to_dict()),
    }


OUTLINE_EDGE_NMI = 400.0  # an opportunity's outline samples its edges this finely (a day's answer holds hundreds)
OUTLINE_DIGITS = 4  # and keeps 1e-4 deg (11 m)


def _rounded(value: Any) -> Any:
    """Nested lists of floats rounded to OUTLINE_DIGITS."""
    if isinstance(value, float):
        return round(value, OUTLINE_DIGITS)
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    return value


BURN_TIME_STEP_S = 1e-3  # a candidate's burn is flown at the millisecond it is written with (4 m along the orbit)


def _opportunity(
    p: Plan,
    revolution: int,
    coast: dorb.Coast,
    deorbit: Deorbit,
    scanned: Ring,
    flier: Flier,
    sites: Sites,
    settings: Settings,
    s: int,
    burn_s: float,
    scan_margin: float,
    window: tuple[float, float],
) -> Opportunity | None:
    """The candidate burn flown again: its entry, its footprint, the site's place in it and the sun at landing;
    None when the site is outside that footprint."""
    burn_utc = rounded(p.utc([burn_s])[0], BURN_TIME_STEP_S)
    r, v = states_at(p.orbit, [burn_utc], coast.omega_rad_s)
    dvs, rows = entries(coast, r, v, deorbit)
    row = rows[0]
    _, track_lat, track_lon = dorb.coast_track(coast, r[0], dorb.burn(r, v, dvs, coast.omega_rad_s)[0])
    lat, lon = float(sites.latitude_deg[s]), float(sites.longitude_deg[s])
    if settings.refly == "full" or (settings.refly == "near" and flier.makers is None):
        ring = flier.ring(row)
    elif settings.refly == "near":
        down, cross, _ = site_in_chart(row, scanned, lat, lon)
        ring = flier.vertices(row, scanned, _near_vertices(scanned, down, cross))
    else:
        ring = scanned
    margin = float(scan_margins(rows, ring, Sites((sites.names[s],), np.array([lat]), np.array([lon])))[0, 0])
    if margin < 0.0:
        return None
    down, cross, _ = site_in_chart(row, ring, lat, lon)
    flight_s = flight_time_at(ring, down, cross)
    entry_utc, landing_utc = after_s(burn_utc, [row[dorb.E_COAST_S], row[dorb.E_COAST_S] + flight_s])
    elevation = float(sun.elevation_deg([landing_utc], lat, lon)[0])
    sunlit = settings.sun_elevation_min_deg is None or elevation >= settings.sun_elevation_min_deg
    return Opportunity(
        site=s,
        site_name=sites.names[s],
        revolution=revolution,
        burn_utc=burn_utc,
        delta_v_fps=float(dvs[0]),
        coast_s=float(row[dorb.E_COAST_S]),
        entry_utc=entry_utc,
        entry={
            "altitude_ft": float(row[dorb.E_ALT]),
            "velocity_fps": float(row[dorb.E_V]),
            "gamma_deg": float(row[dorb.E_GAMMA]),
            "heading_deg": float(row[dorb.E_HEADING]),
            "latitude_deg": float(row[dorb.E_LAT]),
            "longitude_deg": float(row[dorb.E_LON]),
        },
        flight_time_s=flight_s,
        landing_utc=landing_utc,
        downrange_nmi=down,
        crossrange_nmi=cross,
        margin_nmi=margin,
        sun_elevation_deg=elevation,
        local_solar_time_h=float(sun.local_solar_time_h([landing_utc], lon)[0]),
        daylight=elevation >= sun.DAYLIGHT_ELEVATION_DEG,
        meets_rules=sunlit and margin >= settings.min_margin_nmi,
        burn_window_start_utc=p.utc([window[0]])[0],
        burn_window_end_utc=p.utc([window[1]])[0],
        scan_margin_nmi=scan_margin,
        coast_track=np.column_stack([track_lat, track_lon]).tolist(),
        footprint_ring=placed(ring, row),
        limits=tally(ring.limits_broken),
    )
