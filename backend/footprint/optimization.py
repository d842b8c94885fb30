"""The optimization study contract (DESIGN.md): a case, a payoff, constraints with tolerances, the controls
to vary and the method; `run_optimization` turns it into a core Problem (footprint.core.optimize).

Controls: "bank" is the report's eight-parameter bank table against the remaining heading change
(-15 to 90 deg every 15 deg, linear, Section II.5 and Fig. 2), from the case's bank start, bounds 0-180 deg,
started from the single-parameter ramp K = 1. "bank", "alpha" adds Section III's angle-of-attack table
against earth-relative velocity (2,000-26,000 ft/s, alpha between (L/D)max and C_L max of lod-1.89, 12.5-40 deg)
over the whole flight, the bank held at zero in the plunge (footprint.core.constrained).
"""

from typing import Literal

from pydantic import Field, TypeAdapter, model_validator

from footprint.cases import Case, Strict, bounded
from footprint.core import constrained
from footprint.core import optimize as opt

QUANTITIES = ("crossrange_nmi", "downrange_nmi", "final_latitude_deg", "final_longitude_deg", "final_velocity_fps",
              "final_gamma_deg", "final_heading_deg", "flight_time_s", "max_temperature_R",
              "max_heat_rate_btu_ft2_s", "max_dynamic_pressure_psf", "pullout_altitude_ft")
Quantity = Literal[QUANTITIES]
SCIPY_METHODS = ("Nelder-Mead", "Powell", "SLSQP", "COBYLA")
DEFAULT_TOLERANCE = {"downrange_nmi": opt.TTOL_DOWNRANGE_NMI, "max_temperature_R": opt.TTOL_TEMPERATURE_R}


class Payoff(Strict):
    quantity: Quantity = "crossrange_nmi"
    goal: Literal["max", "min"] = "max"


class ConstraintCase(Strict):
    quantity: Quantity
    equals: bounded(-1e7, 1e7) | None = None
    at_most: bounded(-1e7, 1e7) | None = None
    at_least: bounded(-1e7, 1e7) | None = None
    tolerance: bounded(0, 1e6) | None = None  # TTOL, the band's full width; 50 nmi / 5 degR by default
    weight: bounded(1e-9, 1e9) = 1.0

    @model_validator(mode="after")
    def _one_kind(self):
        given = [k for k in ("equals", "at_most", "at_least") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of equals, at_most, at_least")
        return self

    def to_core(self) -> opt.Constraint:
        kind = next(k for k in ("equals", "at_most", "at_least") if getattr(self, k) is not None)
        tol = self.tolerance if self.tolerance is not None else DEFAULT_TOLERANCE.get(self.quantity, 0.0)
        return opt.Constraint(self.quantity, kind, float(getattr(self, kind)), tol, self.weight)


class OptimizationStudy(Strict):
    case: Case
    payoff: Payoff = Payoff()
    constraints: list[ConstraintCase] = Field(default=[], max_length=10)
    controls: list[Literal["bank", "alpha"]] = Field(default=["bank"], min_length=1, max_length=2)
    method: Literal[("creep_pattern",) + SCIPY_METHODS] = "creep_pattern"
    max_trajectories: int = Field(default=3_000, ge=10, le=100_000)

    @model_validator(mode="after")
    def _controls(self):
        if self.controls not in (["bank"], ["bank", "alpha"]):
            raise ValueError(f"controls: ['bank'] or ['bank', 'alpha'] (got {self.controls})")
        return self

    @model_validator(mode="after")
    def _heating(self):
        uses_heat = {c.quantity for c in self.constraints} | {self.payoff.quantity}
        if uses_heat & {"max_temperature_R", "max_heat_rate_btu_ft2_s"} and self.case.heating is None:
            raise ValueError("case.heating: a temperature or heat-rate payoff or constraint needs a heating model")
        return self


_ADAPTER = TypeAdapter(OptimizationStudy)


def parse_optimization(data) -> OptimizationStudy:
    return data if isinstance(data, OptimizationStudy) else _ADAPTER.validate_python(data)


def _bank_alpha(study: OptimizationStudy) -> bool:
    return study.controls == ["bank", "alpha"]


def problem_of(study: OptimizationStudy) -> opt.Problem:
    if _bank_alpha(study):
        return constrained.control_problem(study.case.to_spec(), payoff=study.payoff.quantity,
                                           goal=study.payoff.goal, controls="bank_alpha",
                                           constraints=tuple(c.to_core() for c in study.constraints))
    base = opt.cross_range_problem(study.case.to_spec())
    return opt.Problem(lower=base.lower, upper=base.upper, initial=base.initial, payoff=study.payoff.quantity,
                       goal=study.payoff.goal, constraints=tuple(c.to_core() for c in study.constraints),
                       base=base.base, controls=base.controls, names=base.names)


def run_optimization(study) -> opt.Result:
    study = parse_optimization(study)
    problem = problem_of(study)
    if study.method == "creep_pattern" and _bank_alpha(study):
        search = constrained.search_options("bank_alpha", constrained=bool(study.constraints))
        return opt.optimize(problem, "creep_pattern", max_evaluations=study.max_trajectories, **search)
    if study.method == "creep_pattern":
        search = opt.CONSTRAINED_CROSS_RANGE_SEARCH if study.constraints else opt.CROSS_RANGE_SEARCH
        return opt.optimize(problem, "creep_pattern", max_evaluations=study.max_trajectories, **search)
    return opt.optimize(problem, study.method, max_evaluations=study.max_trajectories)
