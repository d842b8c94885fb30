"""Optimal and heating-constrained footprints (AFWAL-TR-82-3036 Section II.5 Figs. 12/21, Section III Figs. 20-29).

* `optimal_footprint`: the report's optimal footprint. Each point is its own parameter optimization:
  maximum cross-range at a prescribed down-range (held within TTOL 50 nmi), plus the unconstrained
  maximum cross-range and the maximum down-range point ("except for the maximum down-range point, all of the
  points on the footprint were obtained by maximizing the lateral range at various down-range distances").
  The points are independent: the caller's `map_tasks` (builtin map, or footprint.parallel.client_map) runs them.
* Section III controls ("bank_alpha"): the eight-point bank table vs zeta (Fig. 2) plus an angle-of-attack
  table vs earth-relative velocity, "both of the control parameters were modulated over the entire trajectory
  with the exception that during the initial plunge into the atmosphere the bank angle was set to zero" (the
  bank law starts at pull-out, as the spec's ctrl has it). The temperature limit is a `max_temperature_R`
  at-most constraint with TTOL 5 degR (Section II.4); the spec must carry a heating model.

Pure core: numpy and the standard library only.
"""

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.controls import (
    ALPHA_MAX_LD_FLOOR,
    ALPHA_TABLE_BY_ABSCISSA,
    ALPHA_TABLE_VELOCITY,
    replace_alpha_table,
)
from footprint.core.errors import InputError
from footprint.core.footprints import SIGMA0_DEG, Footprint, footprint_of_family, mirror_is_exact, with_bank
from footprint.core.method_settings import TemperatureLimited
from footprint.core.optimize import (
    BANK_BOUNDS_DEG,
    BANK_TABLE_HEADINGS_DEG,
    CONSTRAINED_CROSS_RANGE_SEARCH,
    CROSS_RANGE_SEARCH,
    TTOL_DOWNRANGE_NMI,
    TTOL_TEMPERATURE_R,
    Constraint,
    Problem,
    Result,
    creep_pattern_feasible,
    nominal_bank_deg,
    with_bank_table,
)
from footprint.core.setting import ControlSetting
from footprint.core.trajectory import FlightSpec, simulate_summary

# Section III: the alpha table's abscissa, earth-relative velocity (ft/s), ascending as table_interp needs;
# 26,000 ft/s lies above the Table 2 entry speed (24,480 ft/s), so the first segment shapes the plunge.
ALPHA_TABLE_VELOCITIES_FPS = (2_000.0, 8_000.0, 14_000.0, 20_000.0, 26_000.0)
# Bounds from the lod-1.89 aero (footprint.core.aero): alpha of (L/D)max is 12.5 deg above Mach ~10 (20 deg
# below Mach 5), alpha of C_L max is 40 deg at every Mach. The report: the 2,550 degR case "approaches C_L max".
ALPHA_BOUNDS_DEG = (12.5, 40.0)
ALPHA_MAX_LD_HYPERSONIC_DEG = 12.5  # lod-1.89, Mach >= 10
# creep steps: bank in deg (as CROSS_RANGE_SEARCH), alpha in deg
ALPHA_STEP_DEG = 5.0
ALPHA_MIN_STEP_DEG = 0.2
CONTROLS = ("bank", "bank_alpha")
# integrator steps allowed per searched flight: a normal Table 2 flight takes 100-600 steps; some steep-bank,
# high-alpha corners chatter to the 200,000-step default (0.5 s each). Such a flight ends "max_steps".
SEARCH_MAX_STEPS = 20_000
_Task = tuple[str, float | None, FlightSpec, dict[str, Any]]  # (label, target down-range, spec, solve's options)


# ------------------------------------------------------------------------------------------------- controls
def with_alpha_table(
    spec: FlightSpec,
    alpha_deg: ArrayLike,
    velocities_fps: Sequence[float] = ALPHA_TABLE_VELOCITIES_FPS,
    law: int = ALPHA_TABLE_VELOCITY,
) -> FlightSpec:
    """The spec flying alpha = linear interpolation in (V, alpha), held at the table's ends, over the whole
    flight (law ALPHA_TABLE_TIME / ALPHA_TABLE_ENERGY: the nodes are times in s / energy heights in ft;
    ALPHA_MAX_LD_FLOOR: (L/D)max, never below the table); the rest of the control laws kept."""
    return replace(spec, ctrl=replace_alpha_table(spec.ctrl, alpha_deg, velocities_fps, law))


def bank_alpha_controls(
    spec: FlightSpec,
    params: NDArray[np.float64],
    velocities_fps: Sequence[float] = ALPHA_TABLE_VELOCITIES_FPS,
    law: int = ALPHA_TABLE_VELOCITY,
) -> FlightSpec:
    """params = 8 bank-table angles (deg, at zeta -15..90) then the alpha-table angles (deg, at velocities_fps;
    at times in s when law is ALPHA_TABLE_TIME)."""
    n = len(BANK_TABLE_HEADINGS_DEG)
    return with_alpha_table(with_bank_table(spec, params[:n]), params[n:], velocities_fps, law=law)


# a searched table's parameter names: "<angle>_deg_at_<label>_<node>"
NODE_LABELS = {
    "zeta": "zeta",
    "heading": "heading_deg",
    "time": "time_s",
    "velocity": "velocity_fps",
    "energy": "energy_ft",
}


@dataclass(frozen=True)
class ControlTable:
    """A searched control table: its abscissa (pack_controls' bank_variable or alpha_table_abscissa), the nodes
    in the abscissa's unit (deg, s, ft/s, ft), and the bounds and starting value of the angle at each node (deg)."""

    abscissa: str  # bank: zeta | heading | time | velocity | energy; alpha: velocity | time | energy
    nodes: tuple[float, ...]
    bounds_deg: tuple[float, ...]  # (lower, upper), the same at every node
    initial_deg: tuple[float, ...]  # one per node

    def names(self, angle: str) -> tuple[str, ...]:
        return tuple(f"{angle}_deg_at_{NODE_LABELS[self.abscissa]}_{x:.10g}" for x in self.nodes)


# Section II.5 / Fig. 2: the eight bank points vs zeta from the ramp K = 1; Section III: alpha vs velocity
REPORT_BANK_TABLE = ControlTable("zeta", BANK_TABLE_HEADINGS_DEG, BANK_BOUNDS_DEG, tuple(nominal_bank_deg(1.0)))


def section_iii_alpha_table(
    velocities_fps: Sequence[float] = ALPHA_TABLE_VELOCITIES_FPS,
    times_s: Sequence[float] | None = None,
    bounds_deg: tuple[float, float] = ALPHA_BOUNDS_DEG,
) -> ControlTable:
    """Section III's alpha table: against velocity (or time when times_s is given), from (L/D)max of lod-1.89."""
    nodes = tuple(velocities_fps if times_s is None else times_s)
    return ControlTable(
        "velocity" if times_s is None else "time", nodes, tuple(bounds_deg), (ALPHA_MAX_LD_HYPERSONIC_DEG,) * len(nodes)
    )


@dataclass(frozen=True)
class TableControls:
    """(spec, params) -> the spec flying the bank table at params[:n_bank] and the alpha table (if any) at
    the rest, each on its own abscissa."""

    bank: ControlTable
    alpha: ControlTable | None = None

    def __call__(self, spec: FlightSpec, params: NDArray[np.float64]) -> FlightSpec:
        nb = len(self.bank.nodes)
        spec = with_bank_table(spec, params[:nb], self.bank.nodes, self.bank.abscissa)
        if self.alpha is None:
            return spec
        return with_alpha_table(spec, params[nb:], self.alpha.nodes, law=ALPHA_TABLE_BY_ABSCISSA[self.alpha.abscissa])

    @property
    def tables(self) -> tuple[ControlTable, ...]:
        return (self.bank,) if self.alpha is None else (self.bank, self.alpha)


# ------------------------------------------------------------------------------------------------- problems
def temperature_limit(max_temperature_R: float, tolerance_R: float = TTOL_TEMPERATURE_R) -> Constraint:
    """Section III: the radiation-equilibrium temperature held at most `max_temperature_R` (TTOL 5 degR)."""
    return Constraint("max_temperature_R", "at_most", float(max_temperature_R), tolerance_R)


def downrange_target(downrange_nmi: float, tolerance_nmi: float = TTOL_DOWNRANGE_NMI) -> Constraint:
    return Constraint("downrange_nmi", "equals", float(downrange_nmi), tolerance_nmi)


def control_problem(
    spec: FlightSpec,
    *,
    payoff: str = "crossrange_nmi",
    goal: str = "max",
    constraints: Iterable[Constraint] = (),
    controls: str = "bank",
    initial: ArrayLike | None = None,
    alpha_bounds_deg: tuple[float, float] = ALPHA_BOUNDS_DEG,
    velocities_fps: Sequence[float] = ALPHA_TABLE_VELOCITIES_FPS,
    alpha_times_s: Sequence[float] | None = None,
    bank_table: ControlTable = REPORT_BANK_TABLE,
    alpha_table: ControlTable | None = None,
) -> Problem:
    """A Problem over the bank table ("bank") or bank and alpha tables ("bank_alpha"): the report's eight bank
    points vs zeta unless bank_table says otherwise; the alpha table against velocity at velocities_fps, or
    against time at alpha_times_s when given, within alpha_bounds_deg, unless alpha_table says otherwise.
    initial: the whole starting vector (default: each table's initial_deg)."""
    if controls not in CONTROLS:
        raise ValueError(f"controls {controls!r} not in {CONTROLS}")
    if any(c.quantity.startswith("max_temperature") for c in constraints) and spec.heating is None:
        raise ValueError("a temperature constraint needs a spec with a heating model (heating.ReferenceHeating())")
    if controls == "bank" and alpha_table is not None:
        raise ValueError("an alpha table needs controls 'bank_alpha'")
    if controls == "bank_alpha" and alpha_table is None:
        alpha_table = section_iii_alpha_table(velocities_fps, alpha_times_s, alpha_bounds_deg)
    fly = TableControls(bank_table, alpha_table)
    lower: tuple[float, ...] = ()
    upper: tuple[float, ...] = ()
    default: tuple[float, ...] = ()
    names: tuple[str, ...] = ()
    for t, angle in zip(fly.tables, ("bank", "alpha")):
        lower += (t.bounds_deg[0],) * len(t.nodes)
        upper += (t.bounds_deg[1],) * len(t.nodes)
        default += tuple(t.initial_deg)
        names += t.names(angle)
    return Problem(
        lower=np.array(lower),
        upper=np.array(upper),
        initial=np.asarray(default if initial is None else initial, dtype=np.float64),
        payoff=payoff,
        goal=goal,
        constraints=tuple(constraints),
        base=spec,
        controls=fly,
        names=names,
        evaluate=_Flight(spec, fly, payoff),
    )


def accepted_stops(spec: FlightSpec) -> tuple[str, ...]:
    """The stop reasons of a flight that ended where the spec asks: at its stop altitude, velocity, time or energy
    (a guided flight's terminal energy)."""
    st = spec.stop
    energy = st.energy_ft if spec.guidance is None else spec.guidance.terminal_energy_ft
    stops = (("altitude", st.altitude_ft), ("velocity", st.velocity_fps), ("time", st.time_s), ("energy", energy))
    return tuple(r for r, v in stops if v is not None)


@dataclass(frozen=True)
class _Flight:
    """params -> summary; a flight that does not end at one of the spec's stops (max steps, skip-out, the
    default time stop) has no payoff, so the search never takes a truncated flight for a short one."""

    base: FlightSpec
    controls: Callable[[FlightSpec, NDArray[np.float64]], FlightSpec]
    payoff: str

    def __call__(self, params: NDArray[np.float64]) -> dict[str, Any]:
        s = simulate_summary(replace(self.controls(self.base, params), max_steps=SEARCH_MAX_STEPS))
        return s if s["stop_reason"] in accepted_stops(self.base) else dict(s, **{self.payoff: None})


def search_options(
    controls: str = "bank",
    constrained: bool = True,
    velocities_fps: Sequence[float] = ALPHA_TABLE_VELOCITIES_FPS,
    bank_nodes: Sequence[float] = BANK_TABLE_HEADINGS_DEG,
) -> dict[str, float | NDArray[np.float64]]:
    """Creep/pattern settings: the bank-table ones (optimize.py), with alpha steps in their own degrees
    (velocities_fps, bank_nodes: the tables' nodes, whatever their abscissa)."""
    base: dict[str, float | NDArray[np.float64]] = dict(
        CONSTRAINED_CROSS_RANGE_SEARCH if constrained else CROSS_RANGE_SEARCH
    )
    if controls == "bank_alpha":
        nb, na = len(bank_nodes), len(velocities_fps)
        base["step"] = np.concatenate((np.full(nb, base["step"]), np.full(na, ALPHA_STEP_DEG)))
        base["min_step"] = np.concatenate((np.full(nb, base["min_step"]), np.full(na, ALPHA_MIN_STEP_DEG)))
    return base


def solve(
    spec: FlightSpec,
    *,
    payoff: str = "crossrange_nmi",
    goal: str = "max",
    constraints: Iterable[Constraint] = (),
    controls: str = "bank",
    initial: ArrayLike | None = None,
    max_evaluations: int = 1_500,
    **options: Any,
) -> Result:
    """One point: build the problem and run the report's creep + pattern search with the penalty stages."""
    pr = control_problem(spec, payoff=payoff, goal=goal, constraints=constraints, controls=controls, initial=initial)
    opts: dict[str, Any] = search_options(controls, constrained=bool(constraints))  # creep_pattern's keywords
    opts.update(options)
    return creep_pattern_feasible(pr, max_evaluations=max_evaluations, **opts)


# ------------------------------------------------------------------------------------------ optimal footprint
@dataclass
class OptimalPoint:
    label: str  # "max_crossrange", "max_downrange", "min_downrange" or "downrange_<nmi>"
    target_downrange_nmi: float | None
    result: Result

    @property
    def downrange_nmi(self) -> float | None:
        value: float | None = self.result.summary["downrange_nmi"]  # None: the payoff of a flight _Flight refused
        return value

    @property
    def crossrange_nmi(self) -> float | None:
        value: float | None = self.result.summary["crossrange_nmi"]
        return value

    def to_dict(self) -> dict[str, Any]:
        s = self.result.summary
        return {
            "label": self.label,
            "target_downrange_nmi": self.target_downrange_nmi,
            "downrange_nmi": s["downrange_nmi"],
            "crossrange_nmi": s["crossrange_nmi"],
            "max_temperature_R": s.get("max_temperature_R"),
            "feasible": self.result.feasible,
            "max_violation": self.result.max_violation,
            "trajectories": self.result.trajectories,
            "seconds": self.result.seconds,
            "parameters": {n: float(v) for n, v in zip(self.result.names, self.result.params)},
        }


@dataclass
class OptimalFootprint:
    points: list[OptimalPoint]
    trajectories: int
    seconds: float  # wall clock
    controls: str
    constraints: tuple[Constraint, ...] = field(default_factory=tuple)

    def point(self, label: str) -> OptimalPoint:
        return next(p for p in self.points if p.label == label)

    def to_dict(self) -> dict[str, Any]:
        return {
            "controls": self.controls,
            "trajectories": self.trajectories,
            "seconds": self.seconds,
            "constraints": [c.__dict__ for c in self.constraints],
            "points": [p.to_dict() for p in self.points],
        }


def _solve_task(task: _Task) -> OptimalPoint:
    label, target, spec, kw = task
    return OptimalPoint(label, target, solve(spec, **kw))


def optimal_footprint(
    spec: FlightSpec,
    downranges_nmi: Iterable[float] = (),
    constraints: Iterable[Constraint] = (),
    controls: str = "bank",
    *,
    max_crossrange: bool = True,
    max_downrange: bool = True,
    min_downrange: bool = False,
    map_tasks: Callable[[Callable[[_Task], OptimalPoint], list[_Task]], Iterable[OptimalPoint]] = map,
    max_evaluations: int = 1_500,
    initial: Sequence[float] | NDArray[np.float64] | None = None,
    **options: Any,
) -> OptimalFootprint:
    """Section II.5 / Fig. 12, 21 (and Fig. 29 with a temperature constraint): maximum cross-range at each
    prescribed down-range (TTOL 50 nmi), the unconstrained maximum cross-range, the maximum down-range and,
    when asked, the minimum down-range, all subject to `constraints` (e.g. temperature_limit(2_550)).

    Each point is an independent optimization, run by map_tasks (builtin map's signature, results in order; a
    parallel one such as footprint.parallel.client_map gives the serial points exactly, the search being
    deterministic). Returns the points in the order max cross-range, the down-ranges as given, max down-range,
    min down-range."""
    cons = tuple(constraints)
    nb = len(BANK_TABLE_HEADINGS_DEG)
    common = dict(controls=controls, max_evaluations=max_evaluations, **options)
    tasks: list[_Task] = []
    if max_crossrange:
        tasks.append(("max_crossrange", None, spec, dict(common, constraints=cons, initial=initial)))
    for d in downranges_nmi:
        tasks.append(
            (
                f"downrange_{d:g}",
                float(d),
                spec,
                dict(common, constraints=cons + (downrange_target(d),), initial=initial),
            )
        )
    extra = (
        None
        if controls == "bank"
        else (
            initial[nb:]
            if initial is not None
            else np.full(len(ALPHA_TABLE_VELOCITIES_FPS), ALPHA_MAX_LD_HYPERSONIC_DEG)
        )
    )
    if max_downrange:  # start wings level: the longest glide of the bank table
        x0 = np.zeros(nb) if extra is None else np.concatenate((np.zeros(nb), extra))
        tasks.append(
            (
                "max_downrange",
                None,
                spec,
                dict(common, payoff="downrange_nmi", goal="max", constraints=cons, initial=x0),
            )
        )
    if min_downrange:  # start steeply banked: the shortest of the bank table
        x0 = np.full(nb, 150.0) if extra is None else np.concatenate((np.full(nb, 150.0), extra))
        tasks.append(
            (
                "min_downrange",
                None,
                spec,
                dict(common, payoff="downrange_nmi", goal="min", constraints=cons, initial=x0),
            )
        )
    t0 = time.perf_counter()
    points = list(map_tasks(_solve_task, tasks))
    return OptimalFootprint(
        points=points,
        trajectories=sum(p.result.trajectories for p in points),
        seconds=time.perf_counter() - t0,
        controls=controls,
        constraints=cons,
    )


def max_crossrange_vs_temperature(
    spec: FlightSpec,
    limits_R: Sequence[float | None],
    *,
    map_tasks: Callable[[Callable[[_Task], OptimalPoint], list[_Task]], Iterable[OptimalPoint]] = map,
    max_evaluations: int = 1_500,
    initial: ArrayLike | None = None,
    **options: Any,
) -> list[tuple[float | None, Result]]:
    """Fig. 22: the maximum cross-range with bank and alpha tables under each RET limit (None: unconstrained,
    bank only at (L/D)max alpha, as Fig. 20's unconstrained case), one task per limit run by map_tasks (as in
    optimal_footprint). Returns [(limit, Result)]."""
    tasks: list[_Task] = []
    for lim in limits_R:
        if lim is None or (isinstance(lim, float) and math.isinf(lim)):
            tasks.append(
                ("unconstrained", None, spec, dict(controls="bank", max_evaluations=max_evaluations, **options))
            )
        else:
            tasks.append(
                (
                    f"ret_{lim:g}",
                    None,
                    spec,
                    dict(
                        controls="bank_alpha",
                        constraints=(temperature_limit(lim),),
                        max_evaluations=max_evaluations,
                        initial=initial,
                        **options,
                    ),
                )
            )
    points = list(map_tasks(_solve_task, tasks))
    return [(lim, p.result) for lim, p in zip(limits_R, points)]


# ----------------------------------------------------------------- beyond the report: a simple heating method
# The report's conclusion 3: no simple method was found for heating constraints. Ours: the single-parameter
# bank law (Section II.6) with alpha = max((L/D)max, floor(V)); the floor is zero below 12,000 ft/s and
# rises linearly to `floor_deg` at 16,000 ft/s and above, where the heat pulses lie (the plunge at ~24,300
# ft/s, the banked descent at 18,000-23,000 ft/s for the lod-1.89 Table 2 flights), and leaves the slow glide
# at (L/D)max. For each bank setting floor_deg is the smallest in [12.5, 40] deg ((L/D)max to C_L max) whose
# flight keeps the RET within the limit: a coarse scan, then bisection. Cost: 1-17 flights per setting.
FLOOR_VELOCITIES_FPS = (12_000.0, 16_000.0)
FLOOR_SCAN_STEP_DEG = 2.5
FLOOR_BISECTIONS = 5  # 2.5 deg / 2^5 = 0.08 deg
REFINE_HALVINGS = 2  # bank settings added between the max cross-range setting and its neighbours, twice


def with_alpha_floor(spec: FlightSpec, floor_deg: float) -> FlightSpec:
    """The spec flying alpha = max((L/D)max, floor), the floor 0 below 12,000 ft/s, floor_deg above 16,000."""
    return with_alpha_table(spec, (0.0, float(floor_deg)), FLOOR_VELOCITIES_FPS, law=ALPHA_MAX_LD_FLOOR)


@dataclass
class LimitedPoint:
    bank0_deg: float
    floor_deg: float | None  # None: no floor in the bounds meets the limit (the point is left out)
    summary: dict[str, Any]  # the kept flight's summary, or the coolest flight's when none meets the limit
    flights: int


def coolest_floor(
    spec: FlightSpec,
    limit_R: float,
    tolerance_R: float = TTOL_TEMPERATURE_R,
    bounds_deg: tuple[float, float] = ALPHA_BOUNDS_DEG,
    bank0_deg: float = 0.0,
) -> LimitedPoint:
    """The smallest alpha floor (deg) whose flight ends at the stop altitude with max RET <= limit + tolerance."""

    def fly(floor_deg: float) -> dict[str, Any]:
        return simulate_summary(replace(with_alpha_floor(spec, floor_deg), max_steps=SEARCH_MAX_STEPS))

    def ok(s: dict[str, Any]) -> bool:
        return s["stop_reason"] in accepted_stops(spec) and s["max_temperature_R"] <= limit_R + tolerance_R

    hot = bounds_deg[0]
    s, flights = fly(hot), 1
    if ok(s):
        return LimitedPoint(bank0_deg, hot, s, flights)
    coolest = s
    for cool in np.arange(hot + FLOOR_SCAN_STEP_DEG, bounds_deg[1] + 1e-9, FLOOR_SCAN_STEP_DEG):
        s, flights = fly(cool), flights + 1
        if ok(s):
            break
        coolest = min(coolest, s, key=lambda x: x["max_temperature_R"])
        hot = cool
    else:
        return LimitedPoint(bank0_deg, None, coolest, flights)
    for _ in range(FLOOR_BISECTIONS):  # the RET need not fall monotonically with the floor: keep a met bracket
        mid = 0.5 * (hot + cool)
        m, flights = fly(mid), flights + 1
        if ok(m):
            cool, s = mid, m
        else:
            hot = mid
    return LimitedPoint(bank0_deg, float(cool), s, flights)


@dataclass
class LimitedFootprint:
    footprint: Footprint  # the kept settings' footprint; its `trajectories` counts the searches too
    points: list[LimitedPoint]  # every bank setting, kept or not (left half)
    seconds: float

    @property
    def trajectories(self) -> int:
        return self.footprint.trajectories


def temperature_limited_footprint(spec: FlightSpec, s: TemperatureLimited) -> LimitedFootprint:
    """The simple heating-constrained footprint: single-parameter bank settings phi0 = bank0_deg, each with the
    coolest-needed alpha floor; settings no floor can cool are left out (they bound the near side). The grid is
    halved REFINE_HALVINGS times around its max cross-range setting (the floor varies with phi0 there). With
    mirror on a rotating earth the right half is searched and flown for itself."""
    t0 = time.perf_counter()
    limit_R, tolerance_R, mirror = s.limit_R, s.tolerance_R, s.mirror

    def search(settings: Iterable[float], right: bool = False) -> list[LimitedPoint]:
        return [
            coolest_floor(
                with_bank(spec, "single_parameter", bank_gain=b / SIGMA0_DEG, right=right),
                limit_R,
                tolerance_R,
                bank0_deg=float(b),
            )
            for b in settings
        ]

    left = search(s.bank0_deg)
    for _ in range(REFINE_HALVINGS):  # the grid halved around its max cross-range setting
        kept = sorted((p for p in left if p.floor_deg is not None), key=lambda p: p.bank0_deg)
        if len(kept) < 2:
            break
        i = max(range(len(kept)), key=lambda j: abs(kept[j].summary["crossrange_nmi"]))
        between = {0.5 * (kept[i].bank0_deg + kept[j].bank0_deg) for j in (i - 1, i + 1) if 0 <= j < len(kept)}
        left = sorted(left + search(sorted(between)), key=lambda p: p.bank0_deg)
    right = search([p.bank0_deg for p in left], True) if mirror and not mirror_is_exact(spec) else left
    family = [
        (
            ControlSetting(bank0_deg=p.bank0_deg, bank_gain=p.bank0_deg / SIGMA0_DEG, alpha_floor_deg=p.floor_deg),
            lambda s, to_right, p=p, q=q: with_alpha_floor(
                with_bank(s, "single_parameter", bank_gain=p.bank0_deg / SIGMA0_DEG, right=to_right),
                q.floor_deg if to_right else p.floor_deg,
            ),
            p.bank0_deg == 0.0,
        )
        for p, q in zip(left, right)
        if p.floor_deg is not None and q.floor_deg is not None
    ]
    if not family:  # the user's limit, not a solver's failure
        raise InputError(
            "limit_R",
            f"{limit_R:g} degR cannot be met: no bank setting of bank0_deg is held to it, "
            "even with the coolest alpha floor; raise the limit or change the entry",
        )
    fp = footprint_of_family("temperature_limited", spec, family, mirror)
    if right is not left:  # a flown right point names its own floor
        # keyed as a point's ControlSetting.bank0_deg (float | None) is looked up: every point here has one
        floors: dict[float | None, float | None] = {q.bank0_deg: q.floor_deg for q in right}
        fp.points = [
            replace(pt, parameter=replace(pt.parameter, alpha_floor_deg=floors[pt.parameter.bank0_deg]))
            if pt.side == "right"
            else pt
            for pt in fp.points
        ]
        fp.trajectories += sum(q.flights for q in right)
    fp.trajectories += sum(p.flights for p in left)
    return LimitedFootprint(fp, left, time.perf_counter() - t0)
