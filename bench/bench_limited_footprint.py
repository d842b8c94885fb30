"""The simple heating-constrained footprint against the optimized one (issue 5, beyond the report).

L/D 1.89, Table 2 entry, stop at 50,000 ft, reference heating, RET <= 2,550 degR (Section III.2).
Baseline, in the same process: the optimized constrained footprint of scripts/section_iii.py (bank and
alpha tables, creep + pattern, the penalty of eq. 4: max cross-range, max cross-range at 2,000, 4,000,
8,000 and 11,000 nmi down-range, max and min down-range; <= 3,000 trajectories a point, 2 workers).
Ours: single-parameter bank settings 0-150 deg, each with the smallest alpha floor that keeps the limit
(footprint.core.constrained.temperature_limited_footprint), one process. Targets: max cross-range and max
down-range within 5 % of the optimized ones, at >= 10x less computation.

    python3 bench/bench_limited_footprint.py   # prints the figures, writes bench/results/limited_footprint.json
"""

from _timing import REPORT, save_result, table2_entry, table2_stop  # noqa: E402

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.core.method_settings import TemperatureLimited
from footprint.parallel import client_map, dask_client

CASE = {
    "vehicle": {"builtin": "lod-1.89"},
    "entry": table2_entry(),
    "stop": table2_stop(),
    "heating": {"model": "reference"},
}
LIMIT_R = REPORT["sec3.limit_R"].value
DOWNRANGES_NMI = (2_000.0, 4_000.0, 8_000.0, 11_000.0)  # as scripts/section_iii.py
MAX_EVALUATIONS = 3_000


def main():
    spec = parse("case", CASE).to_spec()
    C.temperature_limited_footprint(
        spec, TemperatureLimited(limit_R=LIMIT_R, bank0_deg=(0.0,))
    )  # compile in this process
    simple = C.temperature_limited_footprint(spec, TemperatureLimited(limit_R=LIMIT_R))
    with dask_client(workers=2) as client:
        opt = C.optimal_footprint(
            spec,
            DOWNRANGES_NMI,
            constraints=(C.temperature_limit(LIMIT_R),),
            controls="bank_alpha",
            min_downrange=True,
            max_evaluations=MAX_EVALUATIONS,
            map_tasks=client_map(client),
        )
    fp = simple.footprint
    best = {
        "max_crossrange_nmi": opt.point("max_crossrange").crossrange_nmi,
        "max_downrange_nmi": opt.point("max_downrange").downrange_nmi,
        "min_downrange_nmi": opt.point("min_downrange").downrange_nmi,
    }
    ours = {
        "max_crossrange_nmi": fp.max_crossrange_nmi,
        "max_downrange_nmi": fp.max_downrange_nmi,
        "min_downrange_nmi": fp.min_downrange_nmi,
    }
    out = {
        "limit_R": LIMIT_R,
        "simple": {
            **{k: round(v, 1) for k, v in ours.items()},
            "trajectories": simple.trajectories,
            "seconds": round(simple.seconds, 3),
            "settings": [
                {
                    "bank0_deg": p.bank0_deg,
                    "alpha_floor_deg": p.floor_deg,
                    "max_temperature_R": round(p.summary["max_temperature_R"], 1),
                    "flights": p.flights,
                }
                for p in simple.points
            ],
        },
        "optimized": {
            **{k: round(v, 1) for k, v in best.items()},
            "trajectories": opt.trajectories,
            "seconds_2_workers": round(opt.seconds, 3),
            "points": [p.to_dict() for p in opt.points],
        },
        "difference_percent": {k: round(100.0 * (ours[k] / best[k] - 1.0), 2) for k in ours},
        "trajectory_ratio": round(opt.trajectories / simple.trajectories, 1),
        "seconds_ratio": round(opt.seconds / simple.seconds, 1),
    }
    print(
        f"simple: {simple.trajectories} trajectories, {simple.seconds:.2f} s; optimized: {opt.trajectories} "
        f"trajectories, {opt.seconds:.1f} s on 2 workers; ratio {out['trajectory_ratio']}x trajectories, "
        f"{out['seconds_ratio']}x seconds"
    )
    for k in ours:
        print(f"  {k:18} simple {ours[k]:8,.0f}  optimized {best[k]:8,.0f}  ({out['difference_percent'][k]:+.1f} %)")
    save_result("limited_footprint", out)


if __name__ == "__main__":
    main()
