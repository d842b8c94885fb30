"""Guided entry (issue 27): one guided flight against the open-loop flight of the same case in the same process, and a
guided dispersion (every sample closed loop, plus the same samples open loop) on a LocalCluster of 2 workers.

The case: the L/D 1.89 vehicle at the Table 2 entry, target 5,000 nmi down-range and 600 nmi cross-range (default
guidance settings). The open-loop baseline is a single-parameter flight (K = 0.8) of the same case, summary path.
The dispersions: entry gamma 0.05 deg, V 15 ft/s, heading 0.05 deg (1 sigma), density 5 % correlated over 30,000 ft,
C_L and C_D 3 % (truncated at 3 sigma). The 1-minute load average is recorded before and after.

    python3 bench/bench_guidance.py [SAMPLES]   # 1,000 by default (~1 min on 2 workers); bench/results/guidance.json
"""

import copy
import os
import sys
import time
from dataclasses import replace

from _timing import example, guided_spreads, save_result, timings_s

SAMPLES = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000
TARGET = {"flight_ms": 50.0, "flight_ratio": 60.0, "samples_1000_s": 60.0, "within_5_nmi": 0.99}
SPREADS = guided_spreads()


def load() -> float:
    return round(os.getloadavg()[0], 2)


def cases():
    from footprint.core.sphere import latlon_from_ranges

    case = copy.deepcopy(example("footprint_lod189")["case"])
    lat, lon = latlon_from_ranges(5000.0, 600.0, 0.0, 0.0, 90.0)
    # the shipped example's bank (examples/fly_guided_lod189.json): its 375 psf lifted, its target being beyond it
    target = {"latitude_deg": float(lat), "longitude_deg": float(lon)}
    guided = case | {"bank": {"law": "guided", "target": target, "max_dynamic_pressure_psf": None}}
    open_loop = case | {"bank": {"law": "single_parameter", "bank_gain": 0.8}}
    return guided, open_loop


def flights() -> dict:
    from footprint.contracts import parse
    from footprint.core.trajectory import simulate_summary

    guided, open_loop = (parse("case", c).to_spec() for c in cases())
    # the same guidance predicting every cycle, as before issue 51's event-triggered predictions
    every = replace(guided, guidance=replace(guided.guidance, max_prediction_interval_s=guided.guidance.cycle_s))
    summary, every_summary = simulate_summary(guided), simulate_summary(every)
    simulate_summary(open_loop)  # compiled
    g_med, g_min = timings_s(lambda: simulate_summary(guided), 20)
    e_med, _ = timings_s(lambda: simulate_summary(every), 10)
    o_med, o_min = timings_s(lambda: simulate_summary(open_loop), 200)
    gd = summary["guidance"]
    return {
        "guided_ms": {"median": 1e3 * g_med, "fastest": 1e3 * g_min},
        "open_loop_ms": {"median": 1e3 * o_med, "fastest": 1e3 * o_min},
        "every_cycle_ms": {"median": 1e3 * e_med},
        "ratio_median": g_med / o_med,
        "every_cycle_ratio_median": e_med / o_med,
        "miss_nmi": gd["miss_nmi"],
        "every_cycle_miss_nmi": every_summary["guidance"]["miss_nmi"],
        "cycles": gd["cycles"],
        "predictions": gd["predictions"],
        "every_cycle_predictions": every_summary["guidance"]["predictions"],
        "rhs_evaluations": summary["rhs_evaluations"],
        "every_cycle_rhs_evaluations": every_summary["rhs_evaluations"],
    }


def dispersion(samples: int) -> dict:
    from footprint import parallel
    from footprint.contracts import module, parse
    from footprint.parallel import start_client

    study = parse("guided_dispersion", {"case": cases()[0], "samples": samples, "seed": 1, "radius_nmi": [1, 5, 10]}
                  | SPREADS)  # fmt: skip
    client, close = start_client(workers=2)
    try:
        warm = parse("guided_dispersion", study.model_dump(exclude_unset=True) | {"samples": 8, "chunk_samples": 4})
        parallel.run("guided_dispersion", warm, client=client)  # the workers' numba caches loaded
        t0 = time.perf_counter()
        stats, info = parallel.run("guided_dispersion", study, client=client)
        wall = time.perf_counter() - t0
    finally:
        close()
    r = module("guided_dispersion").to_dict(study, stats, 0, info)
    return {
        "samples": samples,
        "flights": 2 * samples,
        "seconds": info["seconds"],
        "wall_s": wall,
        "tasks": info["tasks"],
        "guided": {"miss_nmi": r["guided"]["miss_nmi"], "within": r["guided"]["within"]},
        "open_loop": {"miss_nmi": r["open_loop"]["miss_nmi"], "within": r["open_loop"]["within"]},
    }


def main() -> None:
    before = load()
    out = {"load_before": before, "flight": flights()}
    out["load_after_flight"] = load()
    out["dispersion"] = dispersion(SAMPLES)
    out["load_after"] = load()
    out["targets"] = TARGET
    f, d = out["flight"], out["dispersion"]
    print(
        f"guided flight {f['guided_ms']['median']:.1f} ms (fastest {f['guided_ms']['fastest']:.1f}), open loop "
        f"{f['open_loop_ms']['median']:.2f} ms: x{f['ratio_median']:.0f}; miss {f['miss_nmi']:.2f} nmi, "
        f"{f['cycles']} cycles, {f['predictions']} predictions"
    )
    w = {x["radius_nmi"]: x["probability"] for x in d["guided"]["within"]}
    o = {x["radius_nmi"]: x["probability"] for x in d["open_loop"]["within"]}
    print(
        f"{d['samples']:,} samples guided + open loop on 2 workers: {d['seconds']:.1f} s; guided CEP "
        f"{d['guided']['miss_nmi']['cep']:.2f} nmi, p99 {d['guided']['miss_nmi']['p99']:.2f}, P(<=5) {w[5.0]:.3f}; "
        f"open loop CEP {d['open_loop']['miss_nmi']['cep']:.0f} nmi, P(<=5) {o[5.0]:.3f}; load {before} -> "
        f"{out['load_after']}"
    )
    save_result("guidance", out)


if __name__ == "__main__":
    main()
