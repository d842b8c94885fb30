"""Mesh refinement by the controls' error (core.collocation.solve) against a converged transcription, same process.

Betts' Space Shuttle maximum cross-range under his heat-rate limit (examples/optimize_betts_heat_limited.json,
q <= 70 Btu/ft^2/s; Practical Methods for Optimal Control, 2nd ed., sec. 6.1, published 30.6255 deg) and
variants of it (other limits, final velocities and flight-path angles, entry angles). Each problem is solved
three ways in this process:
- "before": one uniform 100-interval mesh, what the solver answered before the refinement (its re-flight agreed
  there, so the mesh was never doubled);
- "refined": today's default (100 intervals, then the intervals where the linear controls bend most are halved
  until the objective may move by less than 0.001 deg: collocation.remaining_move);
- "converged": a uniform 400-interval mesh (the issue's reference) and a uniform 800-interval one.

    python3 bench/bench_collocation_mesh.py      # prints the table, writes bench/results/collocation_mesh.json
"""

import json
import os
import time
from dataclasses import replace
from pathlib import Path

from _timing import save_result  # noqa: E402

from footprint.contracts import parse
from footprint.contracts.optimization import collocation_problem
from footprint.core import collocation as col
from footprint.core.optimize import Constraint

HERE = Path(__file__).resolve().parent
STUDY = json.loads((HERE.parent / "examples" / "optimize_betts_heat_limited.json").read_text())


def problem(limit=70.0, final_velocity_fps=2500.0, final_gamma_deg=-5.0, entry_gamma_deg=-1.0):
    study = json.loads(json.dumps(STUDY))
    study["case"]["entry"]["gamma_deg"] = entry_gamma_deg
    pr = collocation_problem(parse("optimize", study))
    constraints = (
        Constraint("final_velocity_fps", "equals", final_velocity_fps),
        Constraint("final_gamma_deg", "equals", final_gamma_deg),
        Constraint("max_heat_rate_btu_ft2_s", "at_most", limit),
    )
    return replace(pr, constraints=constraints)


VARIANTS = {
    "q <= 70 (Betts)": {},
    "q <= 65": {"limit": 65.0},
    "q <= 60": {"limit": 60.0},
    "q <= 70, V_f 2,300 ft/s": {"final_velocity_fps": 2300.0},
    "q <= 70, V_f 2,700 ft/s": {"final_velocity_fps": 2700.0},
    "q <= 70, gamma_f -4 deg": {"final_gamma_deg": -4.0},
    "q <= 70, gamma_f -6 deg": {"final_gamma_deg": -6.0},
    "q <= 70, entry gamma -1.2 deg": {"entry_gamma_deg": -1.2},
}


def timed(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t0, time.process_time() - c0


def uniform(pr, n):
    return replace(pr, intervals=n, max_intervals=n)


def main():
    col.solve(uniform(problem(), 20))  # numba's and CasADi's first-call costs out of the figures
    rows = {}
    for name, changes in VARIANTS.items():
        pr = problem(**changes)
        before, before_s, _ = timed(lambda: col.solve(uniform(pr, 100)))
        refined, refined_s, refined_cpu = timed(lambda: col.solve(pr))
        ref400, ref400_s, _ = timed(lambda: col.solve(uniform(pr, 400)))
        ref800, ref800_s, _ = timed(lambda: col.solve(uniform(pr, 800)))
        rows[name] = {
            "before_deg": before.objective,
            "before_s": before_s,
            "refined_deg": refined.objective,
            "refined_status": refined.status,
            "refined_intervals": refined.intervals,
            "refined_iterations": refined.iterations,
            "refined_s": refined_s,
            "refined_cpu_s": refined_cpu,
            "refined_last_change_deg": refined.mesh_change,
            "refined_remaining_deg": refined.mesh_remaining,
            "uniform400_deg": ref400.objective,
            "uniform400_s": ref400_s,
            "uniform800_deg": ref800.objective,
            "uniform800_s": ref800_s,
        }
        r = rows[name]
        print(
            f"{name:32s} before {r['before_deg'] - r['uniform400_deg']:+.4f}  refined "
            f"{r['refined_deg'] - r['uniform400_deg']:+.4f} ({r['refined_intervals']} intervals, {refined_s:.1f} s)  "
            f"400: {r['uniform400_deg']:.5f} ({ref400_s:.1f} s)  "
            f"800 - 400: {r['uniform800_deg'] - r['uniform400_deg']:+.5f}",
            flush=True,
        )
    out = {"load": os.getloadavg(), "rows": rows}
    save_result("collocation_mesh", out)
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
