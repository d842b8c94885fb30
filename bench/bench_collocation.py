"""True optima by direct collocation (IPOPT through CasADi) against the report's parameter search, same process.

Betts' Space Shuttle maximum cross-range (Practical Methods for Optimal Control, 2nd ed., sec. 6.1; published
34.1412 deg): the collocation (examples/optimize_betts_collocation.json: cold = build the NLP + guess + solve +
re-flight; warm = a neighbour, final velocity 2,700 ft/s, from the 2,600 ft/s solution) against the creep + pattern
search on bank and alpha tables (examples/optimize_betts_shuttle.json), whose constraints are bands of
+-5 ft/s and +-0.05 deg; the collocation's are met exactly (its band is 0). And the L/D 1.89 vehicle's maximum
cross-range (Table 2 entry, rotating oblate earth, ARDC 1959, Appendix B tables) against creep + pattern on the
report's 8-point bank table (2,044.5 nmi).

    python3 bench/bench_collocation.py      # prints the figures, writes bench/results/collocation.json
"""

import json
import time
from pathlib import Path

from _timing import betts, save_result  # noqa: E402

from footprint.api import run
from footprint.contracts import parse
from footprint.contracts.optimization import collocation_problem
from footprint.core import collocation as col
from footprint.core import optimize as O

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"
BETTS_PUBLISHED_DEG = betts()["final_latitude_deg"]


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def betts():
    study = parse("optimize", json.loads((EXAMPLES / "optimize_betts_collocation.json").read_text()))
    problem = collocation_problem(study)
    col.solve(problem)  # once, so that numba's and CasADi's first-call costs are not in the figures
    cold, cold_s = timed(lambda: col.solve(problem))
    tr = col.Transcription(problem)
    first = tr.solve(cold.guess)
    # the first warm start builds the warm-start solver once (about the cost of the first build); a
    # continuation pays it once, so the neighbour is timed after it: 2,600 -> 2,700 ft/s final velocity
    step, first_warm_s = timed(
        lambda: tr.solve(
            first.guess, warm=first.solver_state, constraint_targets={"final_velocity_fps": (2600.0, 2600.0)}
        )
    )
    warm, warm_s = timed(
        lambda: tr.solve(
            step.guess, warm=step.solver_state, constraint_targets={"final_velocity_fps": (2700.0, 2700.0)}
        )
    )
    search_study = json.loads((EXAMPLES / "optimize_betts_shuttle.json").read_text())
    search, search_s = timed(lambda: run("optimize", search_study))
    return {
        "collocation_cold": {
            "final_latitude_deg": cold.summary["final_latitude_deg"],
            "share_of_published": cold.summary["final_latitude_deg"] / BETTS_PUBLISHED_DEG,
            "refly_final_latitude_deg": cold.refly["final_latitude_deg"],
            "agreement": cold.agreement,
            "iterations": cold.iterations,
            "ipopt_s": cold.seconds,
            "wall_s": cold_s,
        },
        "collocation_warm_neighbour": {
            "final_velocity_fps": warm.summary["final_velocity_fps"],
            "final_latitude_deg": warm.summary["final_latitude_deg"],
            "iterations": warm.iterations,
            "wall_s": warm_s,
            "first_warm_start_with_solver_build_s": first_warm_s,
        },
        "creep_pattern": {
            "final_latitude_deg": search.summary["final_latitude_deg"],
            "share_of_published": search.summary["final_latitude_deg"] / BETTS_PUBLISHED_DEG,
            "final_velocity_fps": search.summary["final_velocity_fps"],
            "final_gamma_deg": search.summary["final_gamma_deg"],
            "trajectories": search.trajectories,
            "wall_s": search_s,
        },
        "ratio_search_to_collocation_cold": search_s / cold_s,
    }


def lod189():
    case = json.loads((EXAMPLES / "footprint_lod189.json").read_text())["case"]
    spec = parse("case", case).to_spec()
    optimum, optimum_s = timed(lambda: col.solve(col.Problem(base=spec)))
    search, search_s = timed(
        lambda: O.optimize(O.cross_range_problem(spec), max_evaluations=1_500, **O.CROSS_RANGE_SEARCH)
    )
    return {
        "collocation": {
            "status": optimum.status,
            "message": optimum.message,
            "intervals": optimum.intervals,
            "crossrange_nmi": optimum.summary["crossrange_nmi"],
            "refly_crossrange_nmi": optimum.refly["crossrange_nmi"],
            "agreement": optimum.agreement,
            "iterations": optimum.iterations,
            "wall_s": optimum_s,
        },
        "creep_pattern": {
            "crossrange_nmi": search.summary["crossrange_nmi"],
            "trajectories": search.trajectories,
            "wall_s": search_s,
        },
    }


def main():
    out = {"betts": betts(), "lod189_max_crossrange": lod189()}
    save_result("collocation", out)
    b, lod = out["betts"], out["lod189_max_crossrange"]
    print(
        f"Betts free: collocation {b['collocation_cold']['final_latitude_deg']:.4f} deg "
        f"({100 * b['collocation_cold']['share_of_published']:.2f} %) cold {b['collocation_cold']['wall_s']:.2f} s, "
        f"warm neighbour {b['collocation_warm_neighbour']['wall_s']:.2f} s; creep + pattern "
        f"{b['creep_pattern']['final_latitude_deg']:.4f} deg ({100 * b['creep_pattern']['share_of_published']:.2f} %)"
        f" in {b['creep_pattern']['wall_s']:.2f} s, {b['creep_pattern']['trajectories']} trajectories "
        f"({b['ratio_search_to_collocation_cold']:.1f}x the collocation's time)"
    )
    print(
        f"L/D 1.89: collocation {lod['collocation']['status']} "
        f"{lod['collocation']['crossrange_nmi']:,.1f} nmi (re-flown "
        f"{lod['collocation']['refly_crossrange_nmi']:,.1f}) in {lod['collocation']['wall_s']:.1f} s; creep + pattern "
        f"{lod['creep_pattern']['crossrange_nmi']:,.1f} nmi in {lod['creep_pattern']['wall_s']:.1f} s; "
        f"{lod['collocation']['iterations']} iterations, {lod['collocation']['intervals']} intervals"
    )


if __name__ == "__main__":
    main()
