"""One optimized footprint point: maximum cross-range of the L/D 1.89 vehicle (Section II.5, Figs. 2-3).

Table 2 entry (364,800 ft, 24,480 ft/s, -2 deg), rotating oblate earth, ARDC 1959, (L/D)max, bank from
pull-out as an eight-point table vs zeta (-15 to 90 deg), stop at 50,000 ft. The report: about 110
trajectories per optimum, 30 s each on a CDC CYBER-175. Baseline in the same process: scipy's Nelder-Mead
(bounded) on the same penalty function, started from the same nominal ramp. Also one down-range
constrained point (4,000 nmi) both ways.

    python3 bench/bench_optimize.py      # prints the figures, writes bench/results/optimize.json
"""

import json
import statistics

from _timing import REPORT, save_result, table2_entry, table2_stop  # noqa: E402

from footprint.contracts import parse
from footprint.core import optimize as O

CASE = {"vehicle": {"builtin": "lod-1.89"}, "entry": table2_entry(), "stop": table2_stop()}
REPEAT = 5


def median_run(fn, repeat=REPEAT):
    runs = [fn() for _ in range(repeat)]
    return runs[0], statistics.median(r.seconds for r in runs)


def main():
    spec = parse("case", CASE).to_spec()
    O.creep_pattern(O.cross_range_problem(spec), max_evaluations=3)  # compile the table law
    out = {}
    for name, dr, opts in (
        ("unconstrained", None, O.CROSS_RANGE_SEARCH),
        ("downrange_4000_nmi", 4000.0, O.CONSTRAINED_CROSS_RANGE_SEARCH),
    ):
        cp, cp_s = median_run(
            lambda dr=dr, opts=opts: O.optimize(O.cross_range_problem(spec, dr), max_evaluations=1_500, **opts)
        )
        nm, nm_s = median_run(
            lambda dr=dr: O.optimize_scipy(O.cross_range_problem(spec, dr), "Nelder-Mead", max_evaluations=3_000), 1
        )
        h = [e["payoff"] for e in cp.history]
        out[name] = {
            "creep_pattern": {
                "crossrange_nmi": round(cp.payoff, 1),
                "downrange_nmi": round(cp.summary["downrange_nmi"], 1),
                "trajectories": cp.trajectories,
                "seconds": round(cp_s, 3),
                "ms_per_trajectory": round(1e3 * cp_s / cp.trajectories, 2),
                "crossrange_after_30_nmi": round(h[min(29, len(h) - 1)], 1),
                "feasible": cp.feasible,
                "converged": cp.converged,
                "bank_deg": [round(float(b), 2) for b in cp.params],
            },
            "scipy_nelder_mead": {
                "crossrange_nmi": round(nm.payoff, 1),
                "downrange_nmi": round(nm.summary["downrange_nmi"], 1),
                "trajectories": nm.trajectories,
                "seconds": round(nm_s, 3),
                "feasible": nm.feasible,
                "converged": nm.converged,
            },
            "ratio_seconds_nelder_mead_over_creep_pattern": round(nm_s / cp_s, 2),
            "ratio_trajectories_nelder_mead_over_creep_pattern": round(nm.trajectories / cp.trajectories, 2),
        }
    sq = O.optimize_scipy(O.cross_range_problem(spec), "SLSQP", max_evaluations=1_500, eps=1.0)
    out["unconstrained"]["scipy_slsqp_eps_1deg"] = {
        "crossrange_nmi": round(sq.payoff, 1),
        "trajectories": sq.trajectories,
        "seconds": round(sq.seconds, 3),
    }
    per_optimum, s_each = REPORT["sec2.iterations_per_optimum"].value, REPORT["sec2.cyber175_s_per_trajectory"].value
    out["report"] = {
        "trajectories_per_optimum": per_optimum,
        "cyber175_s_per_trajectory": int(s_each),
        "cyber175_s_per_optimum": int(per_optimum * s_each),
        "max_crossrange_lod189_nmi": int(REPORT["sec3.max_crossrange_nmi"].value),
    }
    save_result("optimize", out)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
