"""The optimization study contract (DESIGN.md): a case, a payoff, constraints with tolerances, the controls
to vary and the method; `run` turns it into a core Problem (footprint.core.optimize).

Controls: "bank" is the report's eight-parameter bank table against the remaining heading change
(-15 to 90 deg every 15 deg, linear, Section II.5 and Fig. 2), from the case's bank start, bounds 0-180 deg,
started from the single-parameter ramp K = 1. "bank", "alpha" adds Section III's angle-of-attack table
against earth-relative velocity (2,000-26,000 ft/s, alpha between (L/D)max and C_L max of lod-1.89, 12.5-40 deg)
over the whole flight, the bank held at zero in the plunge (footprint.core.constrained).

Beyond the report, optional blocks set each table's knobs (without them every number is the report's setting):

    "bank_table":  {"zeta_deg" | "heading_deg" | "time_s" | "velocity_fps" | "energy_ft": [nodes...],
                    "count": n, "bounds_deg": [lo, hi], "initial_deg": [one per node] | one for all},
    "alpha_table": {"velocity_fps" | "time_s" | "energy_ft": [nodes...], "count", "bounds_deg", "initial_deg"}

The node field names the abscissa and its unit (energy: energy height h + V^2/(2 g0)); with `count` it holds
the first and last of `count` evenly spaced nodes. Defaults: the report's nodes; bank bounds 0-180 deg, alpha
bounds the vehicle's valid alpha range; the bank starts from the ramp K = 1 on a heading abscissa and from the
middle of its bounds on the others, alpha from the vehicle's (L/D)max at Mach 20 and 200,000 ft. A searched
flight counts only when it ends at one of the case's stops. `constraint_scaling` "tolerance" divides each
constraint's excess by its tolerance (or its own `scale`) so that unit weights balance constraints in different
units (core.optimize: a departure from eq. (4)); it is the default when a table block is given, else "none".
"""

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import BeforeValidator, Field, TypeAdapter, model_validator

from footprint.contracts import parse
from footprint.contracts.case import (
    AlphaBound,
    Bank,
    Case,
    EnergyNode,
    HeadingNode,
    TimeNode,
    VelocityNode,
    check_bounds,
    check_increasing,
    table_abscissa,
)
from footprint.contracts.doors import validated
from footprint.contracts.fields import Range, Strict, number
from footprint.contracts.records import FLIGHT_KEYS, flown, plain
from footprint.contracts.work import OnProgress, Stored, Work
from footprint.core import collocation as col
from footprint.core import constrained
from footprint.core import optimize as opt
from footprint.core.aero import SUMMARY_ALTITUDE_FT, SUMMARY_MACH, Vehicle, alpha_range_deg, ld_max
from footprint.core.errors import InputError, NoOptimum
from footprint.core.trajectory import Trajectory, simulate

Quantity = Literal[
    "crossrange_nmi",
    "downrange_nmi",
    "final_latitude_deg",
    "final_longitude_deg",
    "final_velocity_fps",
    "final_gamma_deg",
    "final_heading_deg",
    "flight_time_s",
    "max_temperature_R",
    "max_heat_rate_btu_ft2_s",
    "max_dynamic_pressure_psf",
    "pullout_altitude_ft",
    "final_energy_ft",
    "heat_load_btu_ft2",
    "max_load_factor",
]
QUANTITIES: tuple[str, ...] = get_args(Quantity)
ScipyMethod = Literal["Nelder-Mead", "Powell", "SLSQP", "COBYLA"]
Method = Literal["creep_pattern", "collocation", ScipyMethod]
SCIPY_METHODS: tuple[str, ...] = get_args(ScipyMethod)
METHODS: tuple[str, ...] = get_args(Method)  # ("creep_pattern", "collocation") + SCIPY_METHODS
DEFAULT_TOLERANCE = {"downrange_nmi": opt.TTOL_DOWNRANGE_NMI, "max_temperature_R": opt.TTOL_TEMPERATURE_R}
Scaling = Literal["tolerance", "none"]
SCALINGS: tuple[str, ...] = get_args(Scaling)
SEARCH_MAX_NODES = 64  # nodes (search parameters) per table
# what a quantity can be at all, (lowest, highest, the lowest itself allowed): a constraint outside it can never be
# met (issue 53 item 6: a down-range of -4,000 nmi was flown to a 139 g dive marked "constraints not met")
QUANTITY_DOMAIN: dict[str, tuple[float, float, bool]] = {
    "downrange_nmi": (0.0, math.inf, False),  # measured forward from the entry along its heading
    "final_latitude_deg": (-90.0, 90.0, True),
    "final_gamma_deg": (-90.0, 90.0, True),
    "final_velocity_fps": (0.0, math.inf, True),
    "flight_time_s": (0.0, math.inf, False),
    "max_temperature_R": (0.0, math.inf, False),  # absolute
    "max_heat_rate_btu_ft2_s": (0.0, math.inf, True),
    "max_dynamic_pressure_psf": (0.0, math.inf, True),
    "heat_load_btu_ft2": (0.0, math.inf, True),
    "max_load_factor": (0.0, math.inf, True),
}


class Term(Strict):
    quantity: Quantity
    weight: Annotated[float, Range(-1e9, 1e9)] = 1.0


class Payoff(Strict):
    """One quantity, or (collocation) a weighted sum of `terms`, maximized or minimized."""

    quantity: Quantity = "crossrange_nmi"
    goal: Literal["max", "min"] = "max"
    terms: list[Term] | None = Field(default=None, min_length=1, max_length=10)

    def objective(self) -> tuple[tuple[str, float], ...]:
        """((quantity, weight), ...)"""
        return tuple((t.quantity, t.weight) for t in self.terms) if self.terms else ((self.quantity, 1.0),)


class CollocationOptions(Strict):
    """Direct collocation (footprint.core.collocation): the mesh, the controls' bounds and rate limits."""

    intervals: int = Field(default=100, ge=4, le=1_000)
    degree: int = Field(default=3, ge=1, le=8)  # Radau points per interval
    max_intervals: int = Field(default=400, ge=4, le=2_000)  # the mesh refinement stops here
    # the objective's change under a mesh refinement that counts as settled, in the objective's unit (default:
    # 0.001 deg for an objective in degrees, 1e-4 of its value for any other; collocation.objective_tolerance)
    mesh_tolerance: Annotated[float, Range(1e-12, 1e9, "(the objective's unit)")] | None = None
    alpha_bounds_deg: tuple[AlphaBound, AlphaBound] | None = None  # default: the vehicle's valid alpha range
    bank_bounds_deg: tuple[Bank, Bank] = (-180.0, 180.0)
    alpha_rate_deg_s: Annotated[float, Range(1e-3, 1e3, "deg/s")] | None = None
    bank_rate_deg_s: Annotated[float, Range(1e-3, 1e3, "deg/s")] | None = None
    max_iterations: int = Field(default=3_000, ge=1, le=100_000)
    max_seconds: Annotated[float, Range(1, 86_400, "s")] = 600.0  # IPOPT's wall time per solve
    # first guesses solved on the first mesh, the best kept: the case's laws, then constant banks 90 k / starts deg
    # (collocation.first_guesses), for a payoff with several local optima (the most final energy at a site)
    starts: int = Field(default=1, ge=1, le=8)

    @model_validator(mode="after")
    def _bounds(self) -> "CollocationOptions":
        check_bounds(self.alpha_bounds_deg, "alpha_bounds_deg")
        check_bounds(self.bank_bounds_deg, "bank_bounds_deg")
        if self.max_intervals < self.intervals:
            raise ValueError(f"max_intervals {self.max_intervals} must be at least intervals {self.intervals}")
        return self


class ConstraintCase(Strict):
    quantity: Quantity
    equals: Annotated[float, Range(-1e7, 1e7)] | None = None
    at_most: Annotated[float, Range(-1e7, 1e7)] | None = None
    at_least: Annotated[float, Range(-1e7, 1e7)] | None = None
    tolerance: Annotated[float, Range(0, 1e6)] | None = None  # TTOL, the band's full width; 50 nmi / 5 degR by default
    weight: Annotated[float, Range(1e-9, 1e9)] = 1.0
    scale: Annotated[float, Range(1e-9, 1e9)] | None = (
        None  # the quantity's unit: divides the excess (default: constraint_scaling)
    )

    @model_validator(mode="after")
    def _one_kind(self) -> "ConstraintCase":
        given = [k for k in ("equals", "at_most", "at_least") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of equals, at_most, at_least")
        lo, hi, lo_allowed = QUANTITY_DOMAIN.get(self.quantity, (-math.inf, math.inf, True))
        value = getattr(self, given[0])
        if not (lo <= value if lo_allowed else lo < value) or value > hi:
            allowed = (
                f"{'at least' if lo_allowed else 'more than'} {number(lo)}"
                if hi == math.inf
                else f"{number(lo)} to {number(hi)}"
            )
            said = f"{given[0]}: {number(value)} is outside the allowed range"
            raise ValueError(f"{said} for {self.quantity} ({allowed})")
        return self

    def band(self) -> float:
        """TTOL, the tolerance band's full width (the quantity's default when not given)."""
        return self.tolerance if self.tolerance is not None else DEFAULT_TOLERANCE.get(self.quantity, 0.0)

    def to_core(self, scaling: str = "none") -> opt.Constraint:
        kind = next(k for k in ("equals", "at_most", "at_least") if getattr(self, k) is not None)
        scale = self.scale if self.scale is not None else (self.band() if scaling == "tolerance" else 1.0)
        return opt.Constraint(self.quantity, kind, float(getattr(self, kind)), self.band(), self.weight, scale)


def _one_or_list(v: Any) -> Any:
    return [v] if isinstance(v, (int, float)) and not isinstance(v, bool) else v


class _SearchTable(Strict):
    """A searched control table: nodes on one abscissa (the field naming it and its unit), the angle's bounds at
    every node and the search's start (one value per node, or one for all)."""

    ABSCISSAE: ClassVar[dict[str, str]]  # node field -> pack_controls' abscissa name
    DEFAULT_NODES: ClassVar[tuple[str, tuple[float, ...]]]  # (node field, nodes) when no node field is given
    count: Annotated[int, Range(2, SEARCH_MAX_NODES)] | None = None  # with it the node field is [first, last]
    if TYPE_CHECKING:  # each table's model declares them, with its angle's bounds
        bounds_deg: tuple[float, float] | None
        initial_deg: list[float] | None

    @model_validator(mode="after")
    def _nodes(self) -> "_SearchTable":
        name, x = table_abscissa(self, tuple(self.ABSCISSAE), default=(None, None))
        if self.count is not None and (name is None or len(x) != 2):
            raise ValueError(
                f"count {self.count} needs the first and last node as the node field, e.g. "
                f"{next(iter(self.ABSCISSAE))}: [first, last]"
                + ("" if name is None else f" (got {len(x)} values in {name})")
            )
        if name is not None:
            check_increasing(x, name)
        check_bounds(self.bounds_deg, "bounds_deg")
        n = len(self.nodes()[1])
        if self.initial_deg is not None and len(self.initial_deg) not in (1, n):
            raise ValueError(
                f"initial_deg has {len(self.initial_deg)} values for {n} nodes: give one per node or a single value"
            )
        if self.bounds_deg is not None:
            self.check_start(self.bounds_deg, "bounds_deg")
        return self

    def check_start(self, bounds_deg: Sequence[float], what: str) -> None:
        bad = [v for v in self.initial_deg or () if not bounds_deg[0] <= v <= bounds_deg[1]]
        if bad:
            raise ValueError(f"initial_deg {bad[0]:g} is outside {what} {bounds_deg[0]:g} to {bounds_deg[1]:g} deg")

    def nodes(self) -> tuple[str, tuple[float, ...]]:
        """(pack_controls' abscissa name, the nodes in its unit)."""
        name, x = table_abscissa(self, tuple(self.ABSCISSAE), default=self.DEFAULT_NODES)
        if self.count is not None:
            x = np.linspace(x[0], x[1], self.count)
        return self.ABSCISSAE[name], tuple(float(v) for v in x)

    def _core(
        self,
        bounds_deg: tuple[float, float],
        start_deg: Callable[[str, tuple[float, ...], tuple[float, float]], ArrayLike],
    ) -> constrained.ControlTable:
        """The core table; start_deg(abscissa, nodes, bounds) gives the start when initial_deg is not given."""
        abscissa, nodes = self.nodes()
        start = self.initial_deg if self.initial_deg is not None else start_deg(abscissa, nodes, bounds_deg)
        return constrained.ControlTable(
            abscissa, nodes, tuple(bounds_deg), tuple(float(v) for v in np.broadcast_to(start, len(nodes)))
        )


class BankSearchTable(_SearchTable):
    ABSCISSAE: ClassVar[dict[str, str]] = {
        "zeta_deg": "zeta",
        "heading_deg": "heading",
        "time_s": "time",
        "velocity_fps": "velocity",
        "energy_ft": "energy",
    }
    DEFAULT_NODES: ClassVar[tuple[str, tuple[float, ...]]] = ("zeta_deg", opt.BANK_TABLE_HEADINGS_DEG)
    zeta_deg: list[HeadingNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    heading_deg: list[HeadingNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    time_s: list[TimeNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    velocity_fps: list[VelocityNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    energy_ft: list[EnergyNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    bounds_deg: tuple[Bank, Bank] = opt.BANK_BOUNDS_DEG
    initial_deg: Annotated[list[Bank], BeforeValidator(_one_or_list)] | None = Field(
        default=None, max_length=SEARCH_MAX_NODES
    )

    def to_core(self) -> constrained.ControlTable:
        return self._core(self.bounds_deg, _bank_start_deg)


def _bank_start_deg(
    abscissa: str, nodes: tuple[float, ...], bounds_deg: tuple[float, float]
) -> NDArray[np.float64] | float:
    """The ramp K = 1 (Fig. 2's nominal schedule) on a heading abscissa, else the middle of the bounds."""
    if abscissa in ("zeta", "heading"):
        return opt.nominal_bank_deg(1.0, nodes, bounds_deg)
    return 0.5 * (bounds_deg[0] + bounds_deg[1])


class AlphaSearchTable(_SearchTable):
    ABSCISSAE: ClassVar[dict[str, str]] = {"velocity_fps": "velocity", "time_s": "time", "energy_ft": "energy"}
    DEFAULT_NODES: ClassVar[tuple[str, tuple[float, ...]]] = ("velocity_fps", constrained.ALPHA_TABLE_VELOCITIES_FPS)
    velocity_fps: list[VelocityNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    time_s: list[TimeNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    energy_ft: list[EnergyNode] | None = Field(default=None, min_length=2, max_length=SEARCH_MAX_NODES)
    bounds_deg: tuple[AlphaBound, AlphaBound] | None = None  # default: the vehicle's valid alpha range
    initial_deg: Annotated[list[AlphaBound], BeforeValidator(_one_or_list)] | None = Field(
        default=None, max_length=SEARCH_MAX_NODES
    )

    def to_core(self, vehicle: Vehicle) -> constrained.ControlTable:
        """Bounds default to the vehicle's alpha range; the start to its (L/D)max alpha (Mach 20, 200,000 ft)."""
        alpha_ld_deg = ld_max(vehicle, SUMMARY_MACH, SUMMARY_ALTITUDE_FT)[1]
        return self._core(
            self.bounds_deg or alpha_range_deg(vehicle),
            lambda _abscissa, _nodes, bounds: float(np.clip(alpha_ld_deg, *bounds)),
        )


class OptimizationStudy(Strict):
    case: Case
    payoff: Payoff = Payoff()
    constraints: list[ConstraintCase] = Field(default=[], max_length=10)
    controls: list[Literal["bank", "alpha"]] = Field(default=["bank"], min_length=1, max_length=2)
    method: Method = "creep_pattern"
    collocation: CollocationOptions | None = None  # method "collocation" only
    max_trajectories: int = Field(default=3_000, ge=10, le=100_000)
    bank_table: BankSearchTable | None = None
    alpha_table: AlphaSearchTable | None = None
    constraint_scaling: Scaling | None = None  # default: "tolerance" with a table block, else "none"

    @model_validator(mode="after")
    def _controls(self) -> "OptimizationStudy":
        if self.controls not in (["bank"], ["bank", "alpha"]):
            raise ValueError(f"controls: ['bank'] or ['bank', 'alpha'] (got {self.controls})")
        if self.alpha_table is not None and self.controls != ["bank", "alpha"]:
            raise ValueError(
                f"alpha_table: the alpha table is searched with controls ['bank', 'alpha'] (got {self.controls})"
            )
        return self

    def collocation_constraints(self) -> tuple[opt.Constraint, ...]:
        """The constraints as the collocation takes them (a band's full width 0 unless given)."""
        return tuple(
            opt.Constraint(c.quantity, kind, float(getattr(c, kind)), c.tolerance or 0.0)
            for c in self.constraints
            for kind in ("equals", "at_most", "at_least")
            if getattr(c, kind) is not None
        )

    @model_validator(mode="after")
    def _method(self) -> "OptimizationStudy":
        if self.method == "collocation":
            if self.bank_table is not None or self.alpha_table is not None:
                raise ValueError(
                    "bank_table, alpha_table: the collocation optimizes alpha(t) and bank(t) themselves; "
                    "bound them in 'collocation'"
                )
            if self.case.stop.altitude_ft is None:
                raise ValueError("case.stop.altitude_ft: the collocation ends at a stop altitude; give one")
            bad = [
                q
                for q in [c.quantity for c in self.constraints] + [q for q, _ in self.payoff.objective()]
                if q not in COLLOCATION_QUANTITIES
            ]
            if bad:
                raise ValueError(
                    f"{bad[0]}: not available to the collocation; allowed: {', '.join(COLLOCATION_QUANTITIES)}"
                )
            refused = col.pole_and_longitude(self.collocation_constraints())
            if refused:
                raise ValueError(refused)
        else:
            if self.collocation is not None:
                raise ValueError(f"collocation: options for method 'collocation' (the method is {self.method!r})")
            if self.payoff.terms is not None:
                raise ValueError("payoff.terms: a weighted sum is optimized by method 'collocation' only")
        return self

    @model_validator(mode="after")
    def _heating(self) -> "OptimizationStudy":
        uses_heat = {c.quantity for c in self.constraints} | {q for q, _ in self.payoff.objective()}
        if (
            uses_heat & {"max_temperature_R", "max_heat_rate_btu_ft2_s", "heat_load_btu_ft2"}
            and self.case.heating is None
        ):
            raise ValueError("case.heating: a temperature or heat-rate payoff or constraint needs a heating model")
        return self

    @model_validator(mode="after")
    def _scales(self) -> "OptimizationStudy":
        for i, c in enumerate(self.constraints):
            if self.scaling() == "tolerance" and c.scale is None and c.band() == 0.0:
                raise ValueError(
                    f"constraints.{i}.tolerance: constraint_scaling 'tolerance' divides by it: give a "
                    "tolerance > 0 or a scale"
                )
        return self

    @model_validator(mode="after")
    def _alpha_range(self) -> "OptimizationStudy":
        if self.alpha_table is None:
            return self
        try:
            lo, hi = alpha_range_deg(self.case.vehicle.to_vehicle())
        except InputError:
            return self  # the case's own error is reported when it is flown
        bounds = self.alpha_table.bounds_deg
        if bounds is not None and not lo <= bounds[0] < bounds[1] <= hi:
            raise ValueError(
                f"alpha_table: bounds_deg {bounds[0]:g} to {bounds[1]:g} must lie within the vehicle's "
                f"alpha range {lo:g} to {hi:g} deg"
            )
        try:
            self.alpha_table.check_start(bounds or (lo, hi), "bounds_deg" if bounds else "the vehicle's alpha range")
        except ValueError as exc:
            raise ValueError(f"alpha_table: {exc}") from None
        return self

    def scaling(self) -> str:
        if self.constraint_scaling is not None:
            return self.constraint_scaling
        return "none" if self.bank_table is None and self.alpha_table is None else "tolerance"

    def core_constraints(self) -> tuple[opt.Constraint, ...]:
        return tuple(c.to_core(self.scaling()) for c in self.constraints)


COLLOCATION_QUANTITIES = col.QUANTITIES
REQUEST = OptimizationStudy  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> OptimizationStudy:
    study: OptimizationStudy = validated(ADAPTER, data, OptimizationStudy, ctx)
    return study


def _bank_alpha(study: OptimizationStudy) -> bool:
    return study.controls == ["bank", "alpha"]


def tables_of(
    study: OptimizationStudy, vehicle: Vehicle
) -> tuple[constrained.ControlTable, constrained.ControlTable | None]:
    """(bank table, alpha table or None) searched by the study: its blocks, else the report's tables."""
    bank = (study.bank_table or BankSearchTable()).to_core()
    if not _bank_alpha(study):
        return bank, None
    return bank, (
        constrained.section_iii_alpha_table() if study.alpha_table is None else study.alpha_table.to_core(vehicle)
    )


def problem_of(study: OptimizationStudy) -> opt.Problem:
    spec = study.case.to_spec()
    if study.bank_table is not None or _bank_alpha(study):
        bank, alpha = tables_of(study, spec.vehicle)
        return constrained.control_problem(
            spec,
            payoff=study.payoff.quantity,
            goal=study.payoff.goal,
            controls="bank_alpha" if _bank_alpha(study) else "bank",
            constraints=study.core_constraints(),
            bank_table=bank,
            alpha_table=alpha,
        )
    base = opt.cross_range_problem(spec)  # the report's bank table, every flight taken as it ends (as before)
    return opt.Problem(
        lower=base.lower,
        upper=base.upper,
        initial=base.initial,
        payoff=study.payoff.quantity,
        goal=study.payoff.goal,
        constraints=study.core_constraints(),
        base=base.base,
        controls=base.controls,
        names=base.names,
    )


def collocation_problem(study: OptimizationStudy) -> col.Problem:
    """The study as an optimal-control problem: constraints exactly (equals within +- tolerance/2 only when a
    tolerance is given), the case's control laws flown as the first guess."""
    o = study.collocation or CollocationOptions()
    return col.Problem(
        base=study.case.to_spec(),
        objective=study.payoff.objective(),
        goal=study.payoff.goal,
        constraints=study.collocation_constraints(),
        alpha_bounds_deg=o.alpha_bounds_deg,
        bank_bounds_deg=o.bank_bounds_deg,
        alpha_rate_deg_s=o.alpha_rate_deg_s,
        bank_rate_deg_s=o.bank_rate_deg_s,
        intervals=o.intervals,
        degree=o.degree,
        max_intervals=o.max_intervals,
        mesh_tolerance=o.mesh_tolerance,
        max_iterations=o.max_iterations,
        max_seconds=o.max_seconds,
        starts=o.starts,
    )


def fly_optimum(study: OptimizationStudy | dict[str, Any], result: opt.Result | col.Result) -> Trajectory:
    """The optimum flown by the integrator: the collocation's control tables (its re-flight), or the parameter
    search's best parameters through the study's control laws."""
    parsed: OptimizationStudy = parse("optimize", study)
    if parsed.method == "collocation":
        assert isinstance(result, col.Result)  # optimum(): a collocation study's result is the collocation's
        return col.refly(collocation_problem(parsed), result)
    assert isinstance(result, opt.Result)  # optimum(): any other method's is the parameter search's
    problem = problem_of(parsed)
    assert problem.base is not None and problem.controls is not None  # problem_of builds both
    return simulate(problem.controls(problem.base, result.params))


def optimum(
    study: OptimizationStudy, part: Any = None, on_progress: OnProgress | None = None
) -> opt.Result | col.Result:
    """The study's optimum; on_progress(fraction, note) on the collocation's IPOPT iterations or the search's
    flights (True from it stops the search with the best point so far)."""
    if study.method == "collocation":
        return col.solve(collocation_problem(study), on_progress=on_progress)
    problem = problem_of(study)
    if study.method != "creep_pattern":
        return opt.optimize(problem, study.method, max_evaluations=study.max_trajectories, on_progress=on_progress)
    assert problem.base is not None  # problem_of builds it
    bank, alpha = tables_of(study, problem.base.vehicle)
    search = constrained.search_options(
        "bank_alpha" if alpha else "bank",
        constrained=bool(study.constraints),
        velocities_fps=alpha.nodes if alpha else (),
        bank_nodes=bank.nodes,
    )
    return opt.optimize(
        problem, "creep_pattern", max_evaluations=study.max_trajectories, on_progress=on_progress, **search
    )


def store(study: OptimizationStudy, result: opt.Result | col.Result, name: str | None) -> Stored:
    """An optimization job's result: the optimum, its parameters and the convergence history, and its flight (the
    integrator's; the ground track and the histories the page plots); a collocation that ends without an optimum
    fails the job with its one line (status and largest violation)."""
    if isinstance(result, col.Result) and not result.ok:
        raise NoOptimum(result.one_line())
    return Stored(
        result={"optimization": {**plain(result.to_dict()), "flight": flown(fly_optimum(study, result), FLIGHT_KEYS)}}
    )


def default_name(study: OptimizationStudy) -> str:
    """An optimization's name unless one is given: vehicle, optimizer in words and entry (Case.named)."""
    return study.case.named(
        {"creep_pattern": "creep+pattern", "collocation": "collocation optimum"}.get(study.method, study.method)
    )


WORK = Work(run_part=optimum, store=store, default_name=default_name, part_unit="optimization")
