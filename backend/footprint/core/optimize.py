"""Parameter optimization of the control laws (AFWAL-TR-82-3036 Section II.4-II.6, eq. (4), Figs. 2-4).

The report's search: an adaptive "creeping" search (one parameter at a time, both directions, step sizes
adapted as it goes) followed by a "pattern" search (all parameters moved together along the direction the
creep revealed), repeated until converged. Constraints enter through the penalty of eq. (4):

    phi* = phi + sum_i w_i (| |psi_i| - psibar_i | - TTOL_i / 2)^2          AFWAL-TR-82-3036 eq. (4)

Read as printed, with two decisions (see `penalty`):
  * the penalty applies only outside the tolerance band |psi - psibar| > TTOL/2 (inside it the square
    would otherwise *reward* a constraint met exactly, which cannot be meant), and it always worsens the
    payoff: subtracted when phi is maximized (the report maximizes cross-range and prints "+");
  * the deviation is |psi - psibar| (the printed | |psi| - psibar | equals it for the report's positive
    quantities, down-range and temperature; for a signed key such as a latitude the inner |.| would make
    -psibar as good as +psibar, so it is dropped). An "at_most" / "at_least" constraint counts only the
    excess on its wrong side.

Beyond the report, a constraint may carry a scale s_i (its quantity's unit) that divides the excess,
w_i ((dev_i - TTOL_i/2) / s_i)^2: with s_i = TTOL_i every term is dimensionless (one band's excess costs w_i
units of payoff), so unit weights balance a terminal flight-path angle held to 0.1 deg against a velocity
held to 10 ft/s. This departs from eq. (4), whose unit weights leave each term in its quantity's unit
squared; s_i = 1 (the default) is eq. (4) as printed.

A problem is a base FlightSpec, a function (spec, params) -> FlightSpec, bounds, an initial point, a payoff
key of the trajectory summary with its goal, and constraints on summary keys. Pure core: numpy (and scipy
for the comparison route) only.
"""

import math
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.controls import replace_bank_table
from footprint.core.trajectory import FlightSpec, simulate_summary

# Section II.5 / Fig. 2: the eight table points, heading (remaining heading change) -15 to 90 deg by 15
BANK_TABLE_HEADINGS_DEG = tuple(range(-15, 91, 15))
BANK_BOUNDS_DEG = (0.0, 180.0)  # see cross_range_problem
TTOL_DOWNRANGE_NMI = 50.0  # Section II.4, tolerance on down-range
TTOL_TEMPERATURE_R = 5.0  # Section II.4, tolerance on temperature ("5 deg")
KINDS = ("equals", "at_most", "at_least")
# the search settings of the bank-table problem: steps in deg, ftol in nmi of cross-range (~110 trajectories
# for the unconstrained L/D 1.89 optimum, as Fig. 3 counts). With a down-range constraint the creep stalls
# on the constraint's ridge under unit weights (below the single-parameter control at 2,000-3,000 nmi):
# start soft (weights x 0.01, x 0.1, x 1), no ftol; 500-1,100 trajectories.
CROSS_RANGE_SEARCH = {"step": 15.0, "min_step": 0.5, "ftol": 0.5}
CONSTRAINED_CROSS_RANGE_SEARCH = {"step": 15.0, "min_step": 0.5, "ftol": 0.0, "soft_start": 1e-2}
WORST = 1.0e30  # augmented payoff of a flight whose payoff or a constrained key is missing


@dataclass(frozen=True)
class Constraint:
    """psi = summary[quantity] held to `target` (equals) or on one side of it, within +-tolerance/2."""

    quantity: str
    kind: str  # "equals" | "at_most" | "at_least"
    target: float
    tolerance: float = 0.0  # TTOL_i, full width of the band, same unit as the quantity
    weight: float = 1.0  # w_i (unit matrix in the report)
    scale: float = 1.0  # s_i, same unit as the quantity, divides the excess in the penalty (1: eq. (4))

    def deviation(self, value: float | None) -> float:
        """How far psi is on the wrong side of the target (>= 0), before the band."""
        if value is None or not math.isfinite(value):
            return math.inf
        if self.kind == "equals":
            return abs(value - self.target)
        if self.kind == "at_most":
            return max(0.0, value - self.target)
        return max(0.0, self.target - value)

    def violation(self, value: float | None) -> float:
        """Excess beyond the tolerance band (0 when met)."""
        return max(0.0, self.deviation(value) - 0.5 * self.tolerance)


@dataclass
class Problem:
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    initial: NDArray[np.float64]
    payoff: str = "crossrange_nmi"
    goal: str = "max"  # "max" | "min"
    constraints: tuple[Constraint, ...] = ()
    base: FlightSpec | None = None
    controls: Callable[[FlightSpec, NDArray[np.float64]], FlightSpec] | None = None  # (base spec, params) -> FlightSpec
    # params -> summary dict; overrides base/controls (analytic tests)
    evaluate: Callable[[NDArray[np.float64]], dict[str, Any]] | None = None
    names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        self.lower = np.asarray(self.lower, dtype=float)
        self.upper = np.asarray(self.upper, dtype=float)
        self.initial = np.clip(np.asarray(self.initial, dtype=float), self.lower, self.upper)
        bad = [f"{c.quantity}: kind {c.kind!r} not in {KINDS}" for c in self.constraints if c.kind not in KINDS]
        if self.goal not in ("max", "min"):
            bad.append(f"goal {self.goal!r} not in ('max', 'min')")
        if not (self.lower.shape == self.upper.shape == self.initial.shape):
            bad.append(
                f"bounds and initial differ in shape: {self.lower.shape}, {self.upper.shape}, {self.initial.shape}"
            )
        elif np.any(self.lower > self.upper):
            bad.append("a lower bound exceeds its upper bound")
        if self.evaluate is None and (self.base is None or self.controls is None):
            bad.append("give either evaluate or both base and controls")
        if bad:
            raise ValueError("; ".join(bad))

    def summary(self, params: NDArray[np.float64]) -> dict[str, Any]:
        if self.evaluate is not None:
            return self.evaluate(params)
        # __post_init__ refused a problem with neither evaluate nor both base and controls
        assert self.base is not None and self.controls is not None
        return simulate_summary(self.controls(self.base, params))


def penalty(constraints: Iterable[Constraint], summary: dict[str, Any]) -> float:
    """sum_i w_i ((dev_i - TTOL_i/2) / s_i)^2 outside the band, 0 inside (eq. (4), see the module docstring)."""
    total = 0.0
    for c in constraints:
        v = c.violation(summary.get(c.quantity)) / c.scale
        if v == math.inf:
            return math.inf
        total += c.weight * v * v
    return total


def augmented(problem: Problem, summary: dict[str, Any]) -> float:
    """phi* as a quantity to MINIMIZE: -phi + P for a maximum, phi + P for a minimum."""
    phi: float | None = summary.get(problem.payoff)
    if phi is None or not math.isfinite(phi):
        return WORST
    p = penalty(problem.constraints, summary)
    if p == math.inf:
        return WORST
    return (-phi if problem.goal == "max" else phi) + p


@dataclass
class Result:
    params: NDArray[np.float64]
    summary: dict[str, Any]
    payoff: float | None  # None: the best flight has none (then every flight was WORST)
    augmented_payoff: float  # phi* in the payoff's own sense (penalty subtracted for a maximum)
    feasible: bool
    max_violation: float  # largest excess beyond a tolerance band (quantity's unit), 0 when feasible
    violations: dict[str, float]  # quantity -> excess beyond its band
    history: list[dict[str, Any]]  # per trajectory: iteration, phase, payoff (best so far), augmented, trajectories
    trajectories: int
    seconds: float
    converged: bool
    method: str
    names: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "summary": self.summary,
            "parameters": {n: float(v) for n, v in zip(self.names or range(len(self.params)), self.params)},
            "payoff": self.payoff,
            "augmented_payoff": self.augmented_payoff,
            "feasible": self.feasible,
            "max_violation": self.max_violation,
            "violations": self.violations,
            "history": self.history,
            "trajectories": self.trajectories,
            "seconds": self.seconds,
            "converged": self.converged,
        }


class _Evaluator:
    """Flies (or evaluates) each distinct parameter vector once and keeps the best and the history."""

    def __init__(
        self, problem: Problem, max_evaluations: int, progress: Callable[[int], bool | None] | None = None
    ) -> None:
        self.problem, self.max_evaluations, self.progress = problem, max_evaluations, progress
        self.cache: dict[bytes, tuple[float, dict[str, Any]]] = {}
        self.history: list[dict[str, Any]] = []
        self.n = 0
        self.best_x: NDArray[np.float64] | None = None
        self.best_j = math.inf
        self.best_summary: dict[str, Any] | None = None
        self.phase = "start"

    def __call__(self, x: ArrayLike) -> float:
        x = np.clip(np.asarray(x, dtype=np.float64), self.problem.lower, self.problem.upper)  # never leave bounds
        key = x.tobytes()
        if key in self.cache:
            return self.cache[key][0]
        if self.n >= self.max_evaluations:
            raise _Budget
        s = self.problem.summary(x)
        j = augmented(self.problem, s)
        self.n += 1
        self.cache[key] = (j, s)
        if self.progress is not None and self.progress(self.n):  # the listener asks to stop: the best so far
            self.max_evaluations = self.n
        if j < self.best_j:
            self.best_x, self.best_j, self.best_summary = x.copy(), j, s
        phi = self.best_summary.get(self.problem.payoff) if self.best_summary else None
        self.history.append(
            {
                "iteration": self.n,
                "phase": self.phase,
                "payoff": phi,
                "augmented": self._sense(self.best_j),
                "trajectories": self.n,
            }
        )
        return j

    def summary(self, x: ArrayLike) -> dict[str, Any]:
        """The summary of x (flown once, shared with __call__)."""
        x = np.clip(np.asarray(x, dtype=np.float64), self.problem.lower, self.problem.upper)
        self(x)
        return self.cache[x.tobytes()][1]

    def _sense(self, j: float) -> float:
        return -j if self.problem.goal == "max" else j

    def result(self, t0: float, converged: bool, method: str) -> Result:
        pr, s = self.problem, self.best_summary
        if s is None:
            raise ValueError(f"max_evaluations {self.max_evaluations}: nothing was flown (at least 1)")
        assert self.best_x is not None  # set together with best_summary
        viol = {c.quantity: c.violation(s.get(c.quantity)) for c in pr.constraints}
        worst = max(viol.values(), default=0.0)
        return Result(
            params=self.best_x,
            summary=s,
            payoff=s.get(pr.payoff),
            augmented_payoff=self._sense(self.best_j),
            feasible=worst == 0.0,
            max_violation=worst,
            violations=viol,
            history=self.history,
            trajectories=self.n,
            seconds=time.perf_counter() - t0,
            converged=converged,
            method=method,
            names=pr.names,
        )


class _Budget(Exception):
    pass


def creep_pattern(
    problem: Problem,
    *,
    step: ArrayLike | None = None,
    min_step: ArrayLike | None = None,
    grow: float = 2.0,
    shrink: float = 0.5,
    pattern_growth: float = 2.0,
    max_evaluations: int = 300,
    ftol: float = 0.0,
    progress: Callable[[int], bool | None] | None = None,
) -> Result:
    """Adaptive creeping search followed by a pattern search, repeated (Section II.4).

    step: initial perturbation per parameter (default a tenth of each bound range); min_step: converged
    when every step is below it (default 1e-3 of the range). Creep: each parameter in turn is perturbed
    by its step in its last successful direction, then the other; a success grows that step (x grow) and
    keeps its direction, a failure both ways shrinks it (x shrink). Pattern: along the move the creep cycle
    made, the whole vector is stepped 1, grow, grow^2 ... times that move while it keeps improving.
    ftol: also converged when a whole creep + pattern cycle improves phi* by less than ftol while all steps
    are already small (below 10 min_step). Every trial point is clipped into the bounds. progress(n) after each
    flight; when it returns True the search ends with the best point so far.
    """
    pr = problem
    t0 = time.perf_counter()
    span = np.where(pr.upper > pr.lower, pr.upper - pr.lower, 1.0)
    s = np.array(step, dtype=float) * np.ones_like(span) if step is not None else 0.1 * span
    s_min = np.array(min_step, dtype=float) * np.ones_like(span) if min_step is not None else 1e-3 * span
    ev = _Evaluator(pr, max_evaluations, progress)
    x = pr.initial.copy()
    converged = False
    try:
        j = ev(x)
        while True:
            x_start, j_start = x.copy(), j
            ev.phase = "creep"
            for i in range(len(x)):
                if s[i] == 0.0:
                    continue
                for sign in (1.0, -1.0):
                    trial = x.copy()
                    trial[i] = min(pr.upper[i], max(pr.lower[i], x[i] + sign * s[i]))
                    if trial[i] == x[i]:
                        continue
                    jt = ev(trial)
                    if jt < j:
                        x, j = trial, jt
                        s[i] = sign * abs(s[i]) * grow
                        break
                else:
                    s[i] *= shrink
                s[i] = math.copysign(min(abs(s[i]), span[i]), s[i])
            move = x - x_start
            if np.any(move != 0.0):
                ev.phase = "pattern"
                factor = 1.0
                while True:
                    trial = np.clip(x + factor * move, pr.lower, pr.upper)
                    if np.array_equal(trial, x):
                        break
                    jt = ev(trial)
                    if jt >= j:
                        break
                    x, j = trial, jt
                    factor *= pattern_growth
            if np.all(np.abs(s) < s_min):
                converged = True
                break
            if ftol > 0.0 and j_start - j < ftol and np.all(np.abs(s) < 10.0 * s_min):
                converged = True
                break
    except _Budget:
        pass
    return ev.result(t0, converged, "creep_pattern")


def creep_pattern_feasible(
    problem: Problem,
    *,
    soft_start: float = 1.0,
    soft_factor: float = 10.0,
    weight_factor: float = 100.0,
    rounds: int = 4,
    restarts: int = 0,
    max_evaluations: int = 300,
    on_progress: Callable[[float, str], bool | None] | None = None,
    **options: Any,
) -> Result:
    """creep_pattern in stages that differ only in the penalty weights, each starting from the last optimum,
    all within one trajectory budget:

    * soft_start < 1: the weights start at soft_start times their value and grow by soft_factor up to
      their value (a soft penalty lets the one-at-a-time creep move along a constraint
      ridge that a stiff one walls in);
    * restarts: the creep started afresh (full steps) from the optimum, while that still gains;
    * then, while the optimum is outside a tolerance band (a finite weight trades a little violation for
      payoff: the excess balances (d phi / d psi) / 2w), the weights grow by weight_factor, at most
      `rounds` times, searching on with small steps.

    A constraint that cannot be met stays infeasible: the result says so and gives the smallest violation
    found. The history runs on across the stages (payoff: the best of the current stage). on_progress(fraction,
    note) after each flight (the fraction of the budget flown); a listener that returns True ends the search with
    the best point so far."""
    t0 = time.perf_counter()
    span = np.where(problem.upper > problem.lower, problem.upper - problem.lower, 1.0)
    fine = dict(options, step=np.asarray(options.get("min_step", 1e-3 * span)) * 10.0)
    history: list[dict[str, Any]] = []
    flown, x = 0, problem.initial
    r: Result | None = None
    stopped = False

    def report(n: int) -> bool:  # n: this stage's flights
        nonlocal stopped
        if on_progress is not None and not stopped:
            stopped = bool(
                on_progress((flown + n) / max_evaluations, f"trajectory {flown + n} of at most {max_evaluations}")
            )
        return stopped

    def stage(scale: float, opts: dict[str, Any]) -> Result:
        nonlocal flown
        pr = replace(
            problem, initial=x, constraints=tuple(replace(c, weight=c.weight * scale) for c in problem.constraints)
        )
        r2 = creep_pattern(pr, max_evaluations=max_evaluations - flown, progress=report, **opts)
        for e in r2.history:
            history.append(dict(e, iteration=e["iteration"] + flown, trajectories=e["trajectories"] + flown))
        flown += r2.trajectories
        return r2

    scale = soft_start if problem.constraints else 1.0
    while True:  # soft stages, ending with the problem's own weights
        scale = min(scale, 1.0)
        if (flown >= max_evaluations or stopped) and r is not None:
            break
        r = stage(
            scale, options if r is None else dict(options, step=0.5 * np.asarray(options.get("step", 0.1 * span)))
        )
        x = r.params
        if scale >= 1.0:
            break
        scale *= soft_factor
    assert r is not None  # the loop's first pass flies a stage
    for _ in range(restarts):
        if flown >= max_evaluations or stopped:
            break
        r2 = stage(1.0, options)
        gain = (r2.augmented_payoff - r.augmented_payoff) * (1.0 if problem.goal == "max" else -1.0)
        if r2.trajectories and gain > 0.0:
            r, x = r2, r2.params
        if not r2.trajectories or gain <= options.get("ftol", 0.0):
            break
    scale = 1.0
    for _ in range(rounds):
        if r.feasible or flown >= max_evaluations or stopped:
            break
        scale *= weight_factor
        r2 = stage(scale, fine)
        if r2.trajectories and (r2.feasible or r2.max_violation < r.max_violation):
            r, x = r2, r2.params
    j = augmented(problem, r.summary)
    r.augmented_payoff = -j if problem.goal == "max" else j
    r.history, r.trajectories, r.seconds, r.method = history, flown, time.perf_counter() - t0, "creep_pattern"
    return r


def optimize(problem: Problem, method: str = "creep_pattern", **options: Any) -> Result:
    if method == "creep_pattern":
        return creep_pattern_feasible(problem, **options)
    return optimize_scipy(problem, method, **options)


def optimize_scipy(
    problem: Problem,
    method: str = "Nelder-Mead",
    max_evaluations: int = 2000,
    on_progress: Callable[[float, str], bool | None] | None = None,
    **options: Any,
) -> Result:
    """The same problem by a scipy optimizer, for a side-by-side comparison (STYLE: two routes).

    Nelder-Mead (or any derivative-free method) minimizes the same phi* within the bounds; SLSQP is given
    the constraints themselves (equality psi = psibar, inequalities psi <= / >= psibar, each divided by its
    scale; tolerances are ignored, the band is only used to judge feasibility) and finite-difference
    gradients: pass `eps`, the
    difference step in parameter units (about 1 deg for the bank table; scipy's 1.5e-8 drowns in the
    integrator's noise and SLSQP stops at its start). The result is the best point flown by phi* (the
    same judge as creep_pattern), not necessarily scipy's last iterate.
    """
    from scipy.optimize import Bounds, minimize

    pr = problem
    t0 = time.perf_counter()
    progress = (
        None
        if on_progress is None
        else (lambda n: on_progress(n / max_evaluations, f"trajectory {n} of at most {max_evaluations}"))
    )
    ev = _Evaluator(pr, max_evaluations, progress)
    bounds = Bounds(pr.lower, pr.upper)
    ev.phase = method
    converged = False
    try:
        if method.upper() == "SLSQP":
            summ = ev.summary

            sense = -1.0 if pr.goal == "max" else 1.0

            def fun(x: NDArray[np.float64]) -> float:
                v: float | None = summ(x).get(pr.payoff)
                return sense * v if v is not None else WORST

            cons: list[dict[str, Any]] = []
            for c in pr.constraints:
                if c.kind == "equals":
                    cons.append({"type": "eq", "fun": lambda x, c=c: (summ(x)[c.quantity] - c.target) / c.scale})
                elif c.kind == "at_most":
                    cons.append({"type": "ineq", "fun": lambda x, c=c: (c.target - summ(x)[c.quantity]) / c.scale})
                else:
                    cons.append({"type": "ineq", "fun": lambda x, c=c: (summ(x)[c.quantity] - c.target) / c.scale})
            r = minimize(fun, pr.initial, method="SLSQP", bounds=bounds, constraints=cons, options=options)
        else:
            r = minimize(ev, pr.initial, method=method, bounds=bounds, options=options)
        converged = bool(r.success)
    except _Budget:
        pass
    return ev.result(t0, converged, method)


# ------------------------------------------------------------------ Section II.5: the bank table problem
def with_bank_table(
    spec: FlightSpec, bank_deg: ArrayLike, nodes: Sequence[float] = BANK_TABLE_HEADINGS_DEG, variable: str = "zeta"
) -> FlightSpec:
    """The spec flying bank = linear interpolation in (zeta, bank) (Fig. 2), or in (variable, bank) for another
    abscissa of controls.BANK_VARIABLES (nodes in its unit), held at the table's ends, no limit, left-hand; the
    rest of the control laws (alpha law and its table, bank start) kept."""
    return replace(spec, ctrl=replace_bank_table(spec.ctrl, bank_deg, nodes, variable))


def nominal_bank_deg(
    bank_gain: float = 1.0,
    headings_deg: ArrayLike = BANK_TABLE_HEADINGS_DEG,
    bounds: tuple[float, float] = BANK_BOUNDS_DEG,
) -> NDArray[np.float64]:
    """Fig. 2's nominal schedule: the linear ramp phi_B = K zeta at the table points, within the bounds."""
    return np.clip(bank_gain * np.asarray(headings_deg, dtype=float), *bounds)


def cross_range_problem(
    spec: FlightSpec,
    downrange_nmi: float | None = None,
    tolerance_nmi: float = TTOL_DOWNRANGE_NMI,
    initial: ArrayLike | None = None,
    bounds: tuple[float, float] = BANK_BOUNDS_DEG,
) -> Problem:
    """Section II.5-II.6: maximize cross-range with the eight-point bank table vs zeta, alpha as the spec
    has it ((L/D)max), the bank from the spec's start (pull-out); down-range held to `downrange_nmi`
    within +-tolerance/2 when given.

    Bounds 0-180 deg: a negative bank turns away from the side whose cross-range is maximized, and the
    short-range points of Fig. 10 need banks past 90 deg (the 85 deg limit removed, Section II.6);
    past 180 deg the bank wraps round to the negative side.
    """
    n = len(BANK_TABLE_HEADINGS_DEG)
    cons = (
        () if downrange_nmi is None else (Constraint("downrange_nmi", "equals", float(downrange_nmi), tolerance_nmi),)
    )
    return Problem(
        lower=np.full(n, bounds[0]),
        upper=np.full(n, bounds[1]),
        initial=nominal_bank_deg(1.0) if initial is None else np.asarray(initial, dtype=np.float64),
        payoff="crossrange_nmi",
        goal="max",
        constraints=cons,
        base=spec,
        controls=lambda s, x: with_bank_table(s, x),
        names=tuple(f"bank_deg_at_zeta_{h}" for h in BANK_TABLE_HEADINGS_DEG),
    )
