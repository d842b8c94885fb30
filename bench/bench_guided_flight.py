"""The guided flight's cost as a ratio to the open-loop flight in the same process (issue 50: before and after a
change to the guidance), with its reversals and miss. The case and the timing are bench_guidance.py's (target 5,000 nmi
down-range, 600 nmi cross-range; open loop: the single-parameter law, K = 0.8, summary path).

    LABEL=now PYTHONPATH=backend python3 bench/bench_guided_flight.py   # bench/results/guided_flight_<LABEL>.json

Run it with PYTHONPATH at another checkout's backend (e.g. `git archive <commit> backend | tar -x -C /tmp/x`) to time
that code: the label names it.
"""

import os
import platform

from _timing import save_result
from bench_guidance import flights

LABEL = os.environ.get("LABEL", "now")  # not an argument: bench_guidance reads its own


def cpu_model() -> str:
    with open("/proc/cpuinfo") as f:
        return next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), platform.machine())


def main() -> None:
    load_before = round(os.getloadavg()[0], 2)
    out = {"label": LABEL, "cpu": cpu_model(), "load_before": load_before, "flight": flights()}
    out["load_after"] = round(os.getloadavg()[0], 2)
    f = out["flight"]
    print(
        f"{LABEL}: guided {f['guided_ms']['median']:.1f} ms, open loop {f['open_loop_ms']['median']:.2f} ms: "
        f"x{f['ratio_median']:.1f}; {f['predictions']} predictions, {f['rhs_evaluations']:,} right-hand sides, "
        f"miss {f['miss_nmi']:.2f} nmi; predicting every cycle {f['every_cycle_ms']['median']:.1f} ms "
        f"(x{f['every_cycle_ratio_median']:.1f}, {f['every_cycle_predictions']} predictions, "
        f"{f['every_cycle_rhs_evaluations']:,} right-hand sides, miss {f['every_cycle_miss_nmi']:.2f} nmi); load "
        f"{load_before} -> {out['load_after']}"
    )
    save_result(f"guided_flight_{LABEL}", out)


if __name__ == "__main__":
    main()
