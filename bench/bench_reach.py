"""One day of reach analysis on one core (AFWAL-TR-82-3036 Section IV, question 3).

Single-threaded numpy (the BLAS thread variables are set to 1 before it loads); the median of 9 runs and
the fastest are reported (the machine may be shared: the median moves with other load).

The request of examples/reach_20_sites.json: 20 sites, a 28.5 deg / 100 nmi circular orbit, every revolution
that starts within 24 h (17, the last cut at 86,400 s), a deorbit point every 1 deg of argument of latitude
(6,120 placements), earth rotation "approximate". The footprint is the example's L/D 1.89 study flown with
bank0 = 0, 10, ..., 140 deg: 30 boundary points (axis, 14 left, 14 right, the zero-bank point). Its flight is
not timed here (bench_footprint.py times footprints).

Baseline, in the same process: footprint.core.reach.margins_reference, a plain Python loop (math only) over
placements, sites, branches and edges, run on a subset (the placements of revolution 1, 360 of the 6,120)
and scaled up by 6,120 / 360; its margins are checked against the vectorized ones on that subset.

    python3 bench/bench_reach.py      # prints the figures, writes bench/results/reach.json
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one core, before numpy loads

import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from _timing import save_result, timings_s  # noqa: E402

from footprint.api import footprint  # noqa: E402
from footprint.contracts import parse  # noqa: E402
from footprint.core.orbits import frames  # noqa: E402
from footprint.core.reach import margins_reference, reach  # noqa: E402

HERE = Path(__file__).resolve().parent
REQUEST = json.loads((HERE.parent / "examples" / "reach_20_sites.json").read_text())
BANK0_DEG = list(range(0, 141, 10))


def main():
    req = parse("reach", REQUEST)
    study = dict(REQUEST["footprint"]["study"], bank0_deg=BANK0_DEG)
    fp = footprint(study)
    d = np.array([p.downrange_nmi for p in fp.points])
    c = np.array([p.crossrange_nmi for p in fp.points])
    t = np.array([p.flight_time_s for p in fp.points])
    lat = [s.latitude_deg for s in req.sites]
    lon = [s.longitude_deg for s in req.sites]
    orbit = req.orbit.to_orbit()
    revs, span_s = req.revolutions.span(orbit)

    def day():
        return reach(d, c, t, lat, lon, orbit, revs, u_step_deg=1.0, earth_rotation="approximate", time_span_s=span_s)

    result = day()
    placements = result.inside.shape[0] * result.inside.shape[1]
    seconds, fastest = timings_s(day, 9)

    # the baseline: a plain Python loop over the placements of revolution 1, scaled up
    u = result.u_deg
    p0, d0, n, _ = frames(orbit, np.ones_like(u), u)
    subset = list(zip(p0, d0, n))
    t0 = time.perf_counter()
    rows = margins_reference(subset, d, c, t, list(zip(lat, lon)), orbit.rotation_rate_deg_s)
    loop_subset_s = time.perf_counter() - t0
    loop_day_s = loop_subset_s * placements / len(subset)
    worst = float(np.max(np.abs(np.array([[m for m, _ in row] for row in rows]) - result.margin_nmi[0])))
    same_inside = bool((np.array([[i for _, i in row] for row in rows]) == result.inside[0]).all())

    out = {
        "one_day_reach_s": round(seconds, 3),  # median of 9
        "one_day_reach_fastest_s": round(fastest, 3),
        "target_s": 2.0,
        "placements": placements,
        "revolutions": [int(revs[0]), int(revs[-1])],
        "sites": len(lat),
        "footprint_points": len(d),
        "max_downrange_nmi": round(float(d.max())),
        "placement_site_edge_tests_per_s": round(placements * len(lat) * len(d) / seconds),
        "windows": len(result.windows),
        "python_loop_subset": "revolution 1: 360 placements",
        "python_loop_subset_s": round(loop_subset_s, 2),
        "python_loop_day_scaled_s": round(loop_day_s, 1),
        "speedup_vs_python_loop": round(loop_day_s / seconds, 1),
        "python_loop_max_margin_difference_nmi": worst,
        "python_loop_same_inside": same_inside,
        "cores": 1,
    }
    save_result("reach", out)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
