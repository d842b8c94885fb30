"""An optimal footprint (Section II.5, Figs. 12/21): maximum cross-range at 10 prescribed down-ranges.

L/D 1.89, Table 2 entry (364,800 ft, 24,480 ft/s, -2 deg), (L/D)max alpha, eight-point bank table from
pull-out, stop at 50,000 ft, no heating; down-range held within TTOL 50 nmi; each point <= 1,500
trajectories. The points are independent: solved on a process pool of 2 workers, against 1 (serial, same
process). Target: <= 10 s on 2 workers. The results of both runs must be identical (deterministic search).

    python3 bench/bench_optimal_footprint.py      # prints the figures, writes bench/results/optimal_footprint.json
"""

import numpy as np
from _timing import save_result, table2_entry, table2_stop  # noqa: E402

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.parallel import client_map, dask_client, worker_count

CASE = {"vehicle": {"builtin": "lod-1.89"}, "entry": table2_entry(), "stop": table2_stop()}
DOWNRANGES_NMI = tuple(float(d) for d in range(2_000, 12_001, 1_111))[:10]  # 10 points, 2,000-12,000 nmi
MAX_EVALUATIONS = 1_500
TARGET_S = 10.0


def main():
    spec = parse("case", CASE).to_spec()
    C.solve(spec, max_evaluations=3)  # compile in this process
    kw = {
        "downranges_nmi": DOWNRANGES_NMI,
        "controls": "bank",
        "max_crossrange": False,
        "max_downrange": False,
        "max_evaluations": MAX_EVALUATIONS,
    }
    with dask_client(workers=2) as client:
        workers = worker_count(client)
        par = C.optimal_footprint(spec, map_tasks=client_map(client), **kw)
    ser = C.optimal_footprint(spec, **kw)
    same = all(np.array_equal(a.result.params, b.result.params) for a, b in zip(par.points, ser.points))
    out = {
        "points": len(par.points),
        "workers": workers,
        "seconds_2_workers": round(par.seconds, 3),
        "seconds_1_worker": round(ser.seconds, 3),
        "speedup_1_over_2": round(ser.seconds / par.seconds, 2),
        "trajectories": par.trajectories,
        "target_seconds": TARGET_S,
        "within_target": par.seconds <= TARGET_S,
        "identical_to_serial": same,
        "footprint": [
            {
                "target_downrange_nmi": p.target_downrange_nmi,
                "downrange_nmi": round(p.downrange_nmi, 1),
                "crossrange_nmi": round(p.crossrange_nmi, 1),
                "feasible": p.result.feasible,
                "trajectories": p.result.trajectories,
            }
            for p in par.points
        ],
    }
    print(
        f"{len(par.points)} points, {par.trajectories} trajectories: 2 workers {par.seconds:.2f} s, "
        f"1 worker {ser.seconds:.2f} s, ratio {out['speedup_1_over_2']:.2f}, identical {same}, "
        f"target <= {TARGET_S} s: {'met' if out['within_target'] else 'MISSED'}"
    )
    for p in out["footprint"]:
        print(
            f"  {p['target_downrange_nmi']:8,.0f} -> {p['downrange_nmi']:8,.1f} / {p['crossrange_nmi']:7,.1f} nmi"
            f"  feasible {p['feasible']}  {p['trajectories']} trajectories"
        )
    save_result("optimal_footprint", out)


if __name__ == "__main__":
    main()
