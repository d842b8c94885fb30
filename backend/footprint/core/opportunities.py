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
   one candidate. Its burn window (where the scan's footprints hold the site: the zero crossings about its peak,
   linear on the grid) leads, and the burn is the window's middle, where the outcome is least sensitive (_pass; the
   peak's when the site is never held); a window still open at the search's first or last burn is flagged
   `burn_window_clipped`. That burn is flown again from its own state (its Δv solved again for a target entry angle)
   and its footprint from its own entry state (`refly`: the vertices about the edge nearest the site, or all of
   them), which sets the margin (the nearest way, and along each axis of the chart), the site's down-range and
   cross-range and the flight time (linear in the footprint's boundary along the site's down-range line, between
   its two crossings). A burn that, flown again, leaves the site outside is a near miss, given with the change of
   the deorbit that would take the site in (needed_change). Revolutions are the elements' (revolution_number_at:
   NORAD's count from their epoch).
4. Each burn's entry flown guided to the site (Flier.guided_flight: the guided law's spec per site, the vehicle's
   limits held): its terminal-area interface and the touchdown estimated after it (interface_utc, touchdown_utc).
5. The sun at the site at the touchdown (at the arrival over the site, landing_utc, when the guided flight does not
   reach its interface) (core.sun): its elevation and the local apparent solar time; `daylight` when the sun is up
   (above -0.833 deg), `meets_rules` when it is at least the rule's elevation and the margin the rule's.

Times (core.utc): the burn grid and every elapsed time are SI seconds from the window's start, labelled in UTC across
leap seconds; a candidate's burn is taken on the whole millisecond it is written with, so the time written is the
burn flown; entry and landing follow by the coast's and the flight's seconds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, astuple, dataclass, field
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
GUIDED_KEYS = ("flight_time_s", "final_latitude_deg", "final_longitude_deg", "final_altitude_ft", "final_velocity_fps",
               "max_load_factor", "max_dynamic_pressure_psf", "max_heat_rate_btu_ft2_s", "max_temperature_R",
               "limits_held", "limits_broken", "limits_unchecked")  # fmt: skip


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
    revolution: int  # the window's (1 from its start: its part and ground track)
    revolution_number: int  # the elements' (their number at epoch and the ascending nodes since) at the burn
    burn_utc: datetime
    burn_altitude_ft: float  # geodetic, on the report's ellipsoid (as the ground track)
    burn_latitude_deg: float
    burn_longitude_deg: float
    delta_v_fps: float
    coast_s: float
    entry_utc: datetime
    entry: dict[str, float]  # altitude_ft, velocity_fps, gamma_deg, heading_deg, latitude_deg, longitude_deg
    flight_time_s: float
    landing_utc: datetime  # the arrival over the site at the footprint's stop altitude (50,000 ft by default)
    downrange_nmi: float
    crossrange_nmi: float
    margin_nmi: float  # to the footprint's boundary, the nearest way (positive inside)
    downrange_margin_nmi: float | None  # along the chart's down-range, the cross-range held (axis_margins)
    crossrange_margin_nmi: float | None  # along its cross-range, the down-range held
    sun_elevation_deg: float  # at sun_at's time
    local_solar_time_h: float
    daylight: bool
    meets_rules: bool
    # the guided flight's terminal-area interface and the touchdown estimated after it (its guidance's allowance),
    # when it reached the interface; the sun is taken at the touchdown then, else at the arrival (landing_utc)
    interface_utc: datetime | None
    touchdown_utc: datetime | None
    sun_at: Literal["touchdown", "arrival"]
    burn_window_start_utc: datetime
    burn_window_end_utc: datetime
    burn_window_clipped: bool  # the site still held at the search's first or last burn: not an optimum
    scan_margin_nmi: float  # the scan's footprint's margin at this burn
    # a near miss's (margin < 0) change of the deorbit that would take the site in (needed_change); None: reached
    needed_change: dict[str, float] | None
    coast_track: list[list[float]]  # [latitude, longitude] deg from the burn to the entry interface
    footprint_ring: dict[str, Any]  # the footprint about this entry (placed): ranges, places, outline
    limits: dict[str, Any]  # its vertices' flights that broke a vehicle limit (core.limits.tally)
    guided: dict[str, Any] | None = None  # the flight guided to the site from this entry (Flier.guided_flight)

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
    first_revolution_number: int = 1  # the elements' revolution at the window's start (revolution_number_at)
    revolution: NDArray[np.int64] = field(init=False)

    def __post_init__(self) -> None:
        self.revolution = self.revolution_at(self.times_s)

    def revolution_at(self, seconds: ArrayLike) -> NDArray[np.int64]:
        """The window's revolution (1 from its start, a new one at each ascending node) at each time."""
        return 1 + np.searchsorted(self.node_s, seconds, side="right")

    def revolution_number(self, seconds: float) -> int:
        """The elements' revolution number at a time: their count at the window's start plus the nodes since."""
        return self.first_revolution_number + int(self.revolution_at([seconds])[0]) - 1

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
    return Plan(orbit, start, times, nodes, revolution_number_at(orbit, start))


def revolution_number_at(orbit: Orbit, utc: datetime) -> int:
    """The elements' revolution number at a time: the number at their epoch (a TLE's line 2 columns 64-68; a state
    vector's when given, else 1 at its epoch) plus the ascending nodes between (NORAD's count: a revolution starts at
    an ascending node), found as z's upward sign changes in TEME every eighth of an orbit (one per node)."""
    at_epoch = 1 if orbit.revolution_number is None else orbit.revolution_number
    span = float(elapsed_s(orbit.epoch, [utc])[0])
    if span == 0.0:
        return at_epoch
    step = period_s(orbit.mean_motion_rev_day) / 8.0
    seconds = np.linspace(0.0, span, max(2, math.ceil(abs(span) / step) + 1))
    z = orbit.teme_km(after_s(orbit.epoch, seconds))[0][:, 2]
    near, far = z[:-1], z[1:]  # each step's ends, nearer the epoch and farther towards utc
    nodes = int(np.count_nonzero((near < 0.0) & (far >= 0.0) if span > 0 else (far < 0.0) & (near >= 0.0)))
    return at_epoch + nodes if span > 0 else at_epoch - nodes


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

    def __init__(self, spec: FlightSpec, settings: MethodSettings, guided: Sequence[FlightSpec] = ()):
        self.spec, self.settings = spec, settings
        self.makers = (
            {p.key(): make for p, make, _ in control_family(settings)[0]} if type(settings) in FAMILIES else None
        )
        self.guided = tuple(guided)  # per site, the spec flown guided to it (none: no guided flights)

    def at_entry(self, row: NDArray[np.float64]) -> FlightSpec:
        return dorb.entered(self.spec, row)

    def guided_flight(self, row: NDArray[np.float64], site: int) -> dict[str, Any] | None:
        """The flight from this entry guided to the site (issue 52 item 5), within the limits its guidance holds:
        where and when it ends, its peaks and limits, and the guidance's own summary (its miss and status)."""
        if not self.guided:
            return None
        summary = simulate_summary(dorb.entered(self.guided[site], row))
        return {k: summary[k] for k in GUIDED_KEYS} | {"guidance": summary["guidance"]}

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


def _line_crossings(
    u: NDArray[np.float64], w: NDArray[np.float64], t: NDArray[np.float64], value: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where a ring's boundary (its vertices' chart coordinates u and w, and a quantity t at each) crosses the line
    u = value: w and t at each crossing, linear along its edge."""
    u2, w2, t2 = np.roll(u, -1), np.roll(w, -1), np.roll(t, -1)
    straddle = ((u - value) * (u2 - value) <= 0.0) & (u != u2)
    f = (value - u[straddle]) / (u2[straddle] - u[straddle])
    return w[straddle] + f * (w2[straddle] - w[straddle]), t[straddle] + f * (t2[straddle] - t[straddle])


def flight_time_at(ring: Ring, downrange_nmi: float, crossrange_nmi: float) -> float:
    """The flight time (s) to a point of the footprint: along the line of its down-range, linear between the
    boundary's two crossings that bracket it in cross-range (each crossing's time linear along its edge); the
    nearest boundary point's time where no crossing brackets it."""
    d, c, t = ring.downrange_nmi, ring.crossrange_nmi, ring.flight_time_s
    cx, tx = _line_crossings(d, c, t, downrange_nmi)
    below, above = cx <= crossrange_nmi, cx >= crossrange_nmi
    if below.any() and above.any():
        i, j = np.flatnonzero(below)[np.argmax(cx[below])], np.flatnonzero(above)[np.argmin(cx[above])]
        if cx[j] == cx[i]:
            return float(tx[i])
        return float(tx[i] + (crossrange_nmi - cx[i]) / (cx[j] - cx[i]) * (tx[j] - tx[i]))
    nearest = np.argmin(np.hypot(d - downrange_nmi, c - crossrange_nmi))
    return float(t[nearest])


def _line_margin(crossings: NDArray[np.float64], at: float) -> float | None:
    """The distance along a line from `at` to the nearest of the boundary's crossings of it: positive between two
    that bracket it (inside), negative outside them; None where the line misses the footprint."""
    if not crossings.size:
        return None
    below, above = crossings[crossings <= at], crossings[crossings >= at]
    if below.size and above.size:
        return float(min(at - below.max(), above.min() - at))
    return -float(np.abs(crossings - at).min())


def axis_margins(ring: Ring, downrange_nmi: float, crossrange_nmi: float) -> tuple[float | None, float | None]:
    """(down-range, cross-range) margins (nmi) of a chart point: how far the landing can move along each axis of the
    chart (the other held) before it leaves the footprint; negative: how far it must move to come in."""
    d, c, t = ring.downrange_nmi, ring.crossrange_nmi, ring.flight_time_s
    along_down, _ = _line_crossings(c, d, t, crossrange_nmi)
    along_cross, _ = _line_crossings(d, c, t, downrange_nmi)
    return _line_margin(along_down, downrange_nmi), _line_margin(along_cross, crossrange_nmi)


def _crossing(times: NDArray[np.float64], m: NDArray[np.float64], i: int, j: int) -> float:
    """Where the margin crosses zero between grid indices i and j (linear), or times[j] if it does not."""
    if m[i] < 0.0 <= m[j] or m[j] < 0.0 <= m[i]:
        return float(times[i] + (times[j] - times[i]) * (-m[i]) / (m[j] - m[i]))
    return float(times[j])


@dataclass(frozen=True)
class Pass:
    """A run of the scan's burns that bring a site near: the burn chosen in it and the window that holds the site."""

    burn_s: float  # the burn window's middle (the peak's when the site is never held), s from start
    scan_margin_nmi: float  # the scan's margin there (linear on the grid)
    window: tuple[float, float]  # where the scan's footprints start and stop holding the site, s from start
    clipped: bool  # the site still held at the first or last burn scanned: the window, and the burn, cut there


# The burn is the middle of its window, not the peak of the margin curve: the curve is flat at its top (the
# cross-range bounds it while the burn time moves the landing along the footprint's length) and steep at the window's
# ends (the landing moves at about the orbit's ground speed), so its peak wanders with any small change while the ends
# do not. Measured (6 h, 4 sites of the example): a 60 s grid and 30 deg rings against 20 s and 10 deg moved the peak
# up to 315 s and the window's middle <= 30 s (half the grid step); the margin there is 0.72-1.0 of the peak's.
def _pass(times: NDArray[np.float64], m: NDArray[np.float64], a: int, b: int) -> Pass:
    """The pass of run a..b of a site's scan margins m (the run of burns holding the site about its peak gives the
    window, its ends the zero crossings linear on the grid); clipped when that run reaches the first or last of
    `times` (the search's edge, or a window longer than a part scans)."""
    best = a + int(np.argmax(m[a : b + 1]))
    if m[best] < 0.0:
        burn, scan = parabola_peak(times, m, best)
        return Pass(burn, scan, (burn, burn), False)
    i, j = best, best
    while i > a and m[i - 1] >= 0.0:
        i -= 1
    while j < b and m[j + 1] >= 0.0:
        j += 1
    last = len(times) - 1
    window = (_crossing(times, m, max(i - 1, 0), i), _crossing(times, m, min(j + 1, last), j))
    burn = 0.5 * (window[0] + window[1])
    scan = float(np.interp(burn, times[i : j + 1], m[i : j + 1]))
    return Pass(burn, scan, window, i == 0 or j == last)


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
    decide alike). Each part scans half an orbit into its neighbours so that a pass's whole window is seen (this
    vehicle's are up to 45 min: a quarter orbit cut them, and their middles, at the part's edge)."""
    mine = np.flatnonzero(p.revolution == revolution)
    reach_s = 0.25 * period_s(p.orbit.mean_motion_rev_day)
    lo = int(np.searchsorted(p.times_s, p.times_s[mine[0]] - 2.0 * reach_s))
    hi = int(np.searchsorted(p.times_s, p.times_s[mine[-1]] + 2.0 * reach_s, side="right")) - 1
    times = p.times_s[lo : hi + 1]  # the revolution's burns and half an orbit of each neighbour's
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
        found = _opportunity(
            p, coast, deorbit, table, flier, sites, settings, s,
            _pass(times, m[:, s], a, b),
        )  # fmt: skip
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


def _shortfall_nmi(ring: Ring, down: float, cross: float) -> float | None:
    """How far down-range the footprint must move to take a chart point in, its cross-range held (positive: farther);
    None when the point lies between two crossings of that line (the cross-range misses) or the line misses it."""
    along, _ = _line_crossings(ring.crossrange_nmi, ring.downrange_nmi, ring.flight_time_s, cross)
    if not along.size or (along.min() <= down <= along.max()):
        return None
    return float(down - along[np.argmin(np.abs(along - down))])


FIX_STEPS = (5.0, -0.05)  # a Δv (ft/s) and a target entry angle (deg) step, each the way that still comes down
FIX_SECANTS = 2  # secant steps after the first difference: the entry's down-range is not linear in the angle (a
# 0.64 deg change fell 12% short of Banjul's 1,087 nmi on the first difference alone)


def needed_change(
    coast: dorb.Coast,
    r: NDArray[np.float64],
    v: NDArray[np.float64],
    deorbit: Deorbit,
    row: NDArray[np.float64],
    shortfall_nmi: float | None,
) -> dict[str, float]:
    """The change of the deorbit (`delta_v_change_fps`, or `entry_gamma_change_deg` for a target angle) that moves
    the entry point down-range by the shortfall, the footprint carried with it (a difference of flown coasts, then
    FIX_SECANTS secant steps through no change; the footprint's own change with the entry angle neglected); {} when
    the cross-range misses (a burn's Δv does not move the footprint across its track)."""
    if shortfall_nmi is None:
        return {}
    gamma = deorbit.entry_gamma_deg
    key, change = ("delta_v_change_fps", FIX_STEPS[0]) if gamma is None else ("entry_gamma_change_deg", FIX_STEPS[1])
    p0, d0, _ = great_circle_frame(row[dorb.E_LAT], row[dorb.E_LON], row[dorb.E_HEADING])
    dv = float(deorbit.delta_v_fps or 0.0)
    for _ in range(1 + FIX_SECANTS):
        changed = Deorbit(dv + change) if gamma is None else Deorbit(None, gamma + change)
        try:
            moved = entries(coast, r, v, changed)[1][0]
        except InputError:
            break  # a Δv that no longer comes down: the last estimate stands
        u = unit_vectors(moved[dorb.E_LAT], moved[dorb.E_LON])
        change *= shortfall_nmi / (math.atan2(float(d0 @ u), float(p0 @ u)) * MEAN_RADIUS_NMI)
    return {key: change}


def _guided_times(entry_utc: datetime, guided: dict[str, Any] | None) -> tuple[datetime | None, datetime | None]:
    """(interface, touchdown) UTC of a guided flight that reached its interface, from its entry; else (None, None)."""
    if guided is None or not guided["guidance"]["reached"]:
        return None, None
    g = guided["guidance"]
    interface, touchdown = after_s(entry_utc, [g["interface"]["time_s"], g["touchdown_estimate"]["time_s"]])
    return interface, touchdown


def _opportunity(
    p: Plan,
    coast: dorb.Coast,
    deorbit: Deorbit,
    table: RingTable,
    flier: Flier,
    sites: Sites,
    settings: Settings,
    s: int,
    found: Pass,
) -> Opportunity:
    """The pass's burn flown again: its entry, its footprint, the site's place in it and the sun at landing; a near
    miss (the site outside that footprint) with the change that would take it in."""
    burn_utc = rounded(p.utc([found.burn_s])[0], BURN_TIME_STEP_S)
    burn_s = float(elapsed_s(p.start, [burn_utc])[0])
    r, v = states_at(p.orbit, [burn_utc], coast.omega_rad_s)
    dvs, rows = entries(coast, r, v, deorbit)
    row = rows[0]
    _, track_lat, track_lon = dorb.coast_track(coast, r[0], dorb.burn(r, v, dvs, coast.omega_rad_s)[0])
    lat, lon = float(sites.latitude_deg[s]), float(sites.longitude_deg[s])
    scanned = table.rings[int(table.index(argument_of_latitude_deg(p, np.array([burn_s])))[0])]
    if settings.refly == "full" or (settings.refly == "near" and flier.makers is None):
        ring = flier.ring(row)
    elif settings.refly == "near":
        down, cross, _ = site_in_chart(row, scanned, lat, lon)
        ring = flier.vertices(row, scanned, _near_vertices(scanned, down, cross))
    else:
        ring = scanned
    margin = float(scan_margins(rows, ring, Sites((sites.names[s],), np.array([lat]), np.array([lon])))[0, 0])
    down, cross, _ = site_in_chart(row, ring, lat, lon)
    down_margin, cross_margin = axis_margins(ring, down, cross)
    needed = None if margin >= 0.0 else needed_change(coast, r, v, deorbit, row, _shortfall_nmi(ring, down, cross))
    flight_s = flight_time_at(ring, down, cross)
    entry_utc, landing_utc = after_s(burn_utc, [row[dorb.E_COAST_S], row[dorb.E_COAST_S] + flight_s])
    guided = flier.guided_flight(row, s)
    interface_utc, touchdown_utc = _guided_times(entry_utc, guided)
    sun_utc = landing_utc if touchdown_utc is None else touchdown_utc  # the daylight rule's time (issue 52 item 3)
    elevation = float(sun.elevation_deg([sun_utc], lat, lon)[0])
    sunlit = settings.sun_elevation_min_deg is None or elevation >= settings.sun_elevation_min_deg
    burn_lat, burn_lon, burn_alt = subsatellite_points(p.orbit, [burn_utc])
    return Opportunity(
        site=s,
        site_name=sites.names[s],
        revolution=int(p.revolution_at([burn_s])[0]),
        revolution_number=p.revolution_number(burn_s),
        burn_utc=burn_utc,
        burn_altitude_ft=float(burn_alt[0]),
        burn_latitude_deg=float(burn_lat[0]),
        burn_longitude_deg=float(burn_lon[0]),
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
        downrange_margin_nmi=down_margin,
        crossrange_margin_nmi=cross_margin,
        sun_elevation_deg=elevation,
        local_solar_time_h=float(sun.local_solar_time_h([sun_utc], lon)[0]),
        interface_utc=interface_utc,
        touchdown_utc=touchdown_utc,
        sun_at="arrival" if touchdown_utc is None else "touchdown",
        daylight=elevation >= sun.DAYLIGHT_ELEVATION_DEG,
        meets_rules=sunlit and margin >= settings.min_margin_nmi,
        burn_window_start_utc=p.utc([found.window[0]])[0],
        burn_window_end_utc=p.utc([found.window[1]])[0],
        burn_window_clipped=found.clipped,
        scan_margin_nmi=found.scan_margin_nmi,
        needed_change=needed,
        coast_track=np.column_stack([track_lat, track_lon]).tolist(),
        footprint_ring=placed(ring, row),
        limits=tally(ring.limits_broken),
        guided=guided,
    )
