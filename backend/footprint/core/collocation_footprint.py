"""The true reachable boundary (issue 12; footprint method "collocation"): cross-range maximized by direct
collocation at stepped down-ranges.

Five optima open the boundary: the maximum cross-range of each half with the down-range free, the maximum
down-range, and each half's minimum down-range (the support function in the directions 0 and 180 deg: on the
L/D 1.89 the nearest point is off the axis, 582 nmi at 292 nmi cross-range where the axis' own nearest is
976 nmi). The maximum cross-range is solved from two starts (the case's own flight, and a glide at the largest
|L/D| banked 45 deg) and the maximum down-range from three (straight from the maximum cross-range, by way of the
support direction FAR_VIA_DEG, and the glide at the largest |L/D|), the farthest kept: their local optima lie
hundreds to thousands of miles apart. Between the
extremes, down-ranges on a cosine grid (closer where the boundary turns, at both ends)
are held as a terminal equality, and each half's cross-range is maximized (the right half's minimized), every
solve warm-started from its neighbour's primal-dual point: IPOPT needs 8-60 iterations a point where a cold
start needs 100-250.
Stepping the down-range rather than the support direction reaches concave stretches of the boundary too.

Every boundary point is where the compiled integrator lands when it flies the optimum's control tables
(collocation.refly), so the boundary is reachable by construction; the NLP's own end point and their
distance (the agreement) are kept in the point's parameter. Where a solve ends without an optimum the point
is left out and counted in Footprint.asymmetry["failed"], never replaced by a guess.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footprint.core import collocation as col
from footprint.core.aero import alpha_sweep_deg, coefficients
from footprint.core.controls import replace_controls
from footprint.core.errors import NoOptimum
from footprint.core.footprints import (
    Footprint,
    FootprintPoint,
    area_nmi2,
    mirror_is_exact,
    point_of_trajectory,
    reflect,
)
from footprint.core.method_settings import Collocation
from footprint.core.optimize import Constraint
from footprint.core.setting import ControlSetting
from footprint.core.trajectory import FlightSpec, Trajectory, simulate

FREE_NMI = 1e6  # the lower end of a free down-range's or cross-range's band
OBJECTIVE = (("downrange_nmi", 0.0), ("crossrange_nmi", 1.0))  # weighted by each solve
FAR_VIA_DEG = 20.0  # the second start of the maximum down-range: the support direction 20 deg off the axis
STRAIGHT_FAR_ITERATIONS = col.POLISH_MAX_ITERATIONS  # IPOPT's limit for the first of them (below)
_Solved = tuple[col.Result, Trajectory]  # a solve that ended optimal, and the re-flight of its controls


def collocation_footprint(
    spec: FlightSpec, s: Collocation = Collocation(), on_progress: Callable[[float, str], bool | None] | None = None
) -> Footprint:
    """The true optimal footprint of `spec` (its vehicle, planet, entry, stop altitude and heating model).

    points_per_half down-ranges between the extremes, each half solved (the right half reflected instead only
    where that is exact, mirror=True on a symmetric planet); limit_R holds the radiation-equilibrium temperature
    along the path and max_load_factor the load (g); fine adds the narrow table corners
    (collocation.SMOOTHING_STAGES) to every point: the re-flight comes closer, at about three times the cost.
    on_progress(fraction, note) after every IPOPT iteration (True stops: NoOptimum)."""
    points_per_half, limit_R, max_load_factor, mirror = s.points_per_half, s.limit_R, s.max_load_factor, s.mirror
    constraints: tuple[Constraint, ...] = (
        Constraint("downrange_nmi", "at_least", -FREE_NMI),
        Constraint("crossrange_nmi", "at_least", -FREE_NMI),
    )
    if limit_R is not None:
        constraints += (Constraint("max_temperature_R", "at_most", float(limit_R)),)
    if max_load_factor is not None:
        constraints += (Constraint("max_load_factor", "at_most", float(max_load_factor)),)
    problem = col.Problem(
        base=spec,
        objective=OBJECTIVE,
        constraints=constraints,
        polish=False,
        intervals=s.intervals,
        alpha_bounds_deg=s.alpha_bounds_deg,
        bank_bounds_deg=s.bank_bounds_deg,
    )
    walk = _Walk(
        problem,
        col.SMOOTHING_STAGES if s.fine else col.SMOOTHING_STAGES[:1],
        total=8 + points_per_half + (0 if mirror and mirror_is_exact(spec) else 2 + points_per_half),
        on_progress=on_progress,
    )
    # Each extreme also from a start of its own at the glide of the largest |L/D|: on Betts' shuttle (3 g) that
    # glide flies inverted at -3.23 deg (|L/D| 2.87 against 1.89 upright), and the other starts found the
    # farthest point among local optima flying inverted for a part (11,274 to 15,164 nmi, picked by round-off) and
    # the widest upright (2,066 nmi) where from the glide they are 17,955 and 3,950 nmi, whatever the round-off.
    flown = simulate(spec)
    glide_banked, glide_level = _glide_guesses(problem, walk, flown, (45.0, 0.0))
    left = _wider(
        walk.first(col.guess_from_trajectory(spec, flown), (0.0, 1.0), "the maximum cross-range"),
        walk.cold(glide_banked, (0.0, 1.0)),
    )
    # the maximum down-range straight from the maximum cross-range and by way of the support direction FAR_VIA_DEG
    # (on the shuttle each took a different local optimum by round-off), and from the glide. The straight step
    # wanders where the other two do not (3,000 IPOPT iterations without an optimum on the inverted shuttle, 1,164 or
    # 51 on the L/D 1.89 by the round-off of its guess, against 5-129 for the others): it has STRAIGHT_FAR_ITERATIONS
    via = walk.step(left, _direction(FAR_VIA_DEG), "axis", point=False)
    far = _farther(
        _farther(
            walk.step(left, (1.0, 0.0), "axis", point=False, max_iterations=STRAIGHT_FAR_ITERATIONS),
            None if via is None else walk.step(via, (1.0, 0.0), "axis", point=False),
        ),
        walk.cold(glide_level, (1.0, 0.0)),
    )
    # the minimum down-range by way of the support direction 135 deg: 35-45 + 42-59 IPOPT iterations, 300 in
    # one step
    between = walk.step(left, _direction(135.0), "left", crossrange_nmi=(0.0, math.inf), point=False)
    near = walk.step(between or left, (-1.0, 0.0), "left", crossrange_nmi=(0.0, math.inf))
    if far is None or near is None:
        raise NoOptimum("collocation footprint: the maximum or minimum down-range did not end optimal")
    lo, hi = near[1].summary["downrange_nmi"], far[1].summary["downrange_nmi"]
    grid = lo + (hi - lo) * 0.5 * (1.0 - np.cos(np.pi * np.arange(1, points_per_half + 1) / (points_per_half + 1)))
    left_half = [_point(near, "left")] + [_point(s, "left", d) for d, s in walk.half(left, grid, +1.0)]
    if mirror and mirror_is_exact(spec):
        right_half = [reflect(spec, p) for p in left_half]
    else:
        right = walk.first(_mirrored_guess(problem, left[0]), (0.0, -1.0), "the right half's maximum cross-range")
        solved = walk.half(right, grid, -1.0)
        # from the half's nearest point: 50 iterations fewer than from its maximum cross-range
        near_right = walk.step(solved[0][1], (-1.0, 0.0), "right", crossrange_nmi=(-math.inf, 0.0))
        right_half = [_point(s, "right", d) for d, s in solved]
        if near_right is not None:
            right_half.insert(0, _point(near_right, "right"))
    # the boundary as the other methods order it: farthest point, left half inwards, right half out
    boundary = [_point(far, "axis")] + left_half[::-1] + right_half
    e = spec.entry
    fp = Footprint(
        method="collocation",
        points=boundary,
        area_nmi2=area_nmi2(boundary),
        trajectories=walk.solves,
        entry={"latitude_deg": e.latitude_deg, "longitude_deg": e.longitude_deg, "heading_deg": e.heading_deg},
    )
    if walk.failed:
        fp.asymmetry = {"failed": walk.failed}
    return fp


class _Walk:
    """The solves of one footprint on one transcription, counted and reported."""

    def __init__(
        self,
        problem: col.Problem,
        stages: tuple[float, ...],
        total: int,
        on_progress: Callable[[float, str], bool | None] | None,
    ) -> None:
        self.problem, self.stages, self.total, self.on_progress = problem, stages, total, on_progress
        self.transcription = col.Transcription(problem)
        self.solves = 0
        self.failed: list[dict[str, Any]] = []
        self.last: col.Result | None = None

    def _solve(self, guess: col.Guess, **options: Any) -> _Solved | None:
        """One solve, its iterations reported as this solve's share of the footprint."""
        report = (
            None
            if self.on_progress is None
            else col.iteration_progress(
                self.on_progress,
                (self.solves / self.total, (self.solves + 1) / self.total),
                f"solve {self.solves + 1} of {self.total}: ",
            )
        )
        result = self.transcription.solve(guess, on_iteration=report, **options)
        if result.status == "stopped":
            raise NoOptimum(f"collocation footprint: stopped at solve {self.solves + 1} of {self.total}")
        self.solves, self.last = self.solves + 1, result
        if not result.ok:
            return None
        return result, col.refly(self.problem, result)

    def first(self, guess: col.Guess, weights: tuple[float, float], what: str) -> _Solved:
        """A cold solve (each stage of the tables' corners); no optimum here ends the footprint, saying why."""
        solved = self.cold(guess, weights)
        if solved is None:
            assert self.last is not None  # _solve keeps every result it returns None for
            raise NoOptimum(f"collocation footprint: {what}: {self.last.one_line()}")
        return solved

    def cold(self, guess: col.Guess, weights: tuple[float, float]) -> _Solved | None:
        """A cold solve (each stage of the tables' corners); None where it ends without an optimum."""
        return self._solve(guess, weights=weights, stages=self.stages)

    def step(
        self,
        seed: _Solved,
        weights: tuple[float, float],
        side: str,
        downrange_nmi: float | None = None,
        crossrange_nmi: tuple[float, float] = (-FREE_NMI, math.inf),
        point: bool = True,
        max_iterations: int | None = None,
    ) -> _Solved | None:
        """A neighbour, warm-started from `seed` (result, trajectory), its down-range held where given and its
        cross-range within a band; None where it ends without an optimum (a boundary point's failure is
        listed)."""
        result = seed[0]
        assert result.guess is not None  # a solved result carries its solution (collocation.Transcription._result)
        down = (-FREE_NMI, math.inf) if downrange_nmi is None else (downrange_nmi, downrange_nmi)
        targets = {"downrange_nmi": down, "crossrange_nmi": crossrange_nmi}
        solved = self._solve(
            result.guess,
            weights=weights,
            warm=result.solver_state,
            constraint_targets=targets,
            stages=self.stages[-1:],
            max_iterations=max_iterations,
        )
        if solved is None and point:
            self.failed.append({"side": side, "downrange_nmi": downrange_nmi, "weights": list(weights)})
        return solved

    def half(self, seed: _Solved, grid: NDArray[np.float64], sign: float) -> list[tuple[float | None, _Solved]]:
        """One half's solves at the grid's down-ranges, walked out from the free optimum both ways:
        [(down-range held or None, (result, trajectory))] by down-range."""
        side = "left" if sign > 0 else "right"
        d_free = seed[1].summary["downrange_nmi"]
        solved: dict[float, _Solved] = {d_free: seed}  # the half's maximum cross-range is a boundary point too
        for targets in (sorted(d for d in grid if d >= d_free), sorted((d for d in grid if d < d_free), reverse=True)):
            at = seed
            for d in targets:
                step = self.step(at, (0.0, sign), side, float(d))
                if step is not None:
                    solved[float(d)] = at = step
        return [(None if d == d_free else d, solved[d]) for d in sorted(solved)]


def _glide_guesses(
    problem: col.Problem, walk: _Walk, flown: Trajectory, tilts_deg: tuple[float, ...]
) -> list[col.Guess]:
    """Flights at the constant alpha of the largest |L/D| within the alpha bounds (at the entry's Mach and
    altitude), the lift turned each of tilts_deg to the left of up: upside down where that lift is negative and the
    bank bounds allow it (Betts' polynomial: |L/D| 2.87 at -3.23 deg, against (L/D)max 1.89 at 17.39)."""
    spec = problem.base
    mach, altitude_ft = float(flown.history["mach"][0]), float(flown.history["altitude_ft"][0])
    alphas = alpha_sweep_deg(*walk.transcription.alpha_bounds_deg())
    ld = np.array([cl / cd for cl, cd in (coefficients(spec.vehicle.blob, mach, a, altitude_ft) for a in alphas)])
    inverted = problem.bank_bounds_deg[0] <= -180.0 or problem.bank_bounds_deg[1] >= 180.0
    best = int(np.argmax(np.abs(ld) if inverted else ld))
    upside_down_deg = 0.0 if ld[best] > 0.0 else 180.0
    return [
        col.guess_from_trajectory(
            spec,
            simulate(
                replace(
                    spec,
                    ctrl=replace_controls(
                        spec.ctrl,
                        bank_law="constant",
                        bank_deg=tilt - upside_down_deg,
                        bank_start="entry",
                        alpha_law="constant",
                        alpha_deg=float(alphas[best]),
                    ),
                )
            ),
        )
        for tilt in tilts_deg
    ]


def _direction(xi_deg: float) -> tuple[float, float]:
    """The objective weights (down-range, cross-range) of the support direction xi_deg."""
    xi = math.radians(xi_deg)
    return (round(math.cos(xi), 12), round(math.sin(xi), 12))


def _mirrored_guess(problem: col.Problem, result: col.Result) -> col.Guess:
    """The right half's first guess: the left optimum's controls with the bank reversed, flown."""
    controls = dict(result.controls, bank_deg=-np.asarray(result.controls["bank_deg"]))
    return col.guess_from_trajectory(problem.base, simulate(col.control_tables_spec(problem.base, controls)))


def _farther(a: _Solved | None, b: _Solved | None, quantity: str = "downrange_nmi") -> _Solved | None:
    """The solve whose re-flight reaches farther in `quantity` (either, if one ended without an optimum)."""
    if a is None or b is None:
        return a or b
    return b if b[1].summary[quantity] > a[1].summary[quantity] else a


def _wider(a: _Solved, b: _Solved | None) -> _Solved:
    """The solve whose re-flight reaches farther left."""
    return _farther(a, b, "crossrange_nmi") or a


def _point(solved: _Solved, side: str, downrange_nmi: float | None = None) -> FootprintPoint:
    result, trajectory = solved
    a = result.agreement
    assert a is not None  # collocation.refly recorded it
    parameter = ControlSetting(
        downrange_target_nmi=downrange_nmi,
        iterations=result.iterations,
        nlp_downrange_nmi=result.summary["downrange_nmi"],
        nlp_crossrange_nmi=result.summary["crossrange_nmi"],
        agreement_deg=a["end_deg"],
        inverted_s=(result.refly or {}).get("inverted_s") or None,  # left out when 0
    )
    return point_of_trajectory(parameter, side, trajectory)
