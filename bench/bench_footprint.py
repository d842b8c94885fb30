"""One footprint on one core: the report's 13-trajectory single-parameter footprint (Section II.6).

lod-2.2, Table 2 entry, rotating oblate earth, ARDC 1959, stop at 50,000 ft. Thirteen trajectories as the
report counts them (its procedure's 0-150 deg in 15 deg steps plus zero lift makes 12; we add 165 deg),
the left half; then the whole footprint with the right half flown too (the rotating earth). The
baseline, in the same process, is the same 13 trajectories flown by scipy's solve_ivp on our compiled
right-hand side (bench_trajectory.scipy_flight: the stricter of its two baselines).

    python3 bench/bench_footprint.py      # prints the figures, writes bench/results/footprint.json
"""

import json
from pathlib import Path

from _timing import median_ms, save_result  # noqa: E402
from bench_trajectory import scipy_flight

from footprint.contracts import parse
from footprint.core.footprints import single_parameter, with_bank
from footprint.core.method_settings import SingleParameter

HERE = Path(__file__).resolve().parent
CASE = json.loads((HERE.parent / "examples" / "table2_lod22.json").read_text())
BANK0_DEG = tuple(range(0, 166, 15))


def by_scipy(spec):
    for b in BANK0_DEG:
        scipy_flight(with_bank(spec, "single_parameter", bank_gain=b / 90.0))
    scipy_flight(with_bank(spec, "zero_lift"))


def main():
    spec = parse("case", CASE).to_spec()
    half = single_parameter(spec, SingleParameter(bank0_deg=BANK0_DEG, mirror=False))
    whole = single_parameter(spec, SingleParameter(bank0_deg=BANK0_DEG, mirror=True))
    ms_half = median_ms(lambda: single_parameter(spec, SingleParameter(bank0_deg=BANK0_DEG, mirror=False)), 50)
    ms_whole = median_ms(lambda: single_parameter(spec, SingleParameter(bank0_deg=BANK0_DEG, mirror=True)), 30)
    ms_scipy = median_ms(lambda: by_scipy(spec), 3)
    result = {
        "footprint_13_trajectories_ms": round(ms_half, 2),
        "trajectories": half.trajectories,
        "ms_per_trajectory": round(ms_half / half.trajectories, 3),
        "whole_footprint_both_halves_flown_ms": round(ms_whole, 2),
        "whole_footprint_trajectories": whole.trajectories,
        "same_13_scipy_solve_ivp_compiled_rhs_ms": round(ms_scipy, 1),
        "speedup_vs_scipy": round(ms_scipy / ms_half, 1),
        "report_cyber175_s": 13 * 30,
        "max_crossrange_nmi": round(half.max_crossrange_nmi, 1),
        "area_nmi2_whole": round(whole.area_nmi2),
    }
    save_result("footprint", result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
