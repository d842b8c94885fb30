"""One Monte Carlo sample: the summary-only flight (trajectory.simulate_summary) against the full one (simulate,
histories and summary), in the same process, on the same specs, to the same bits.

Cases: the report's Table 2 entry flown by examples/table2_lod22.json (lod-2.2, single-parameter bank) and the
L/D 1.89 vehicle's case of examples/footprint_lod189.json (zero bank, 14,869 nmi: past half a circumference, where
the down-range's unwrapping matters), each also with the reference heating of Section III. The floor is the
integrator alone (integrate.integrate on the packed inputs), which both paths call. Baseline and summary-only
flights alternate in rounds so that both see the same load on a shared machine.

    python3 bench/bench_sample.py        # prints the figures, writes bench/results/sample.json
"""

import json
import statistics
import time

from _timing import example, save_result  # noqa: E402

from footprint.contracts import parse
from footprint.core.integrate import integrate
from footprint.core.trajectory import flight_inputs, simulate, simulate_summary

ROUNDS = 15
CALLS_PER_ROUND = 40


def cases():
    table2, lod189 = example("table2_lod22"), example("footprint_lod189")["case"]
    heating = {"model": "reference"}
    return {
        "table2_lod22": table2,
        "lod189": lod189,
        "table2_lod22_heating": {**table2, "heating": heating},
        "lod189_heating": {**lod189, "heating": heating},
    }


def integrator_only(spec):
    p, s0, mode = flight_inputs(spec)
    return lambda: integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode.copy(), spec.max_steps)


def per_call_ms(fns: dict) -> dict:
    """Median over ROUNDS of the mean time of CALLS_PER_ROUND calls (ms), the functions taking turns."""
    times = {name: [] for name in fns}
    for _ in range(ROUNDS):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            for _ in range(CALLS_PER_ROUND):
                fn()
            times[name].append(1e3 * (time.perf_counter() - t0) / CALLS_PER_ROUND)
    return {name: statistics.median(ts) for name, ts in times.items()}


def main():
    result = {}
    for name, case in cases().items():
        spec = parse("case", case).to_spec()
        full, summary = simulate(spec).summary, simulate_summary(spec)  # compiles or loads the cache
        assert {k: v.hex() if isinstance(v, float) else v for k, v in summary.items()} == {
            k: v.hex() if isinstance(v, float) else v for k, v in full.items()
        }, name
        ms = per_call_ms(
            {
                "full": lambda: simulate(spec).history,  # the histories made
                "summary": lambda: simulate_summary(spec),
                "integrator": integrator_only(spec),
            }
        )
        result[name] = {
            "full_simulate_ms_per_trajectory": round(ms["full"], 3),
            "summary_only_ms_per_trajectory": round(ms["summary"], 3),
            "summary_over_full": round(ms["summary"] / ms["full"], 3),
            "integrator_alone_ms": round(ms["integrator"], 3),
            "python_after_the_integrator_ms": {
                "full": round(ms["full"] - ms["integrator"], 3),
                "summary_only": round(ms["summary"] - ms["integrator"], 3),
            },
            "rows": summary["steps"] + 1,
            "downrange_nmi": round(summary["downrange_nmi"], 3),
        }
    save_result("sample", result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
