"""The guided Monte Carlo's open-loop baseline (issue 50 item 5): the nominal guided flight's bank flown open loop
against time (before) and against energy height h + V^2/(2 g0) (core.guided_dispersion.open_loop, after), on the
same samples of examples/disperse_guided_lod189.json; each mode's CEP, p90 and landed count.

    python3 bench/bench_open_loop.py [SAMPLES]   # 300 by default (the issue's); bench/results/open_loop.json
"""

import os
import sys
from dataclasses import replace

import numpy as np
from _timing import example, save_result

SAMPLES = int(sys.argv[1]) if len(sys.argv) > 1 else 300


def against_time(spec, nominal):
    """The baseline before issue 50: the nominal bank as a time table."""
    from footprint.core.controls import replace_bank_table

    table = nominal.bank_table
    ctrl = replace_bank_table(spec.ctrl, table["bank_deg"], table["time_s"], "time")
    return replace(spec, guidance=None, ctrl=ctrl, stop=replace(spec.stop, energy_ft=spec.guidance.terminal_energy_ft))


def main() -> None:
    from footprint.contracts.guided_dispersion import Plan, parse_request
    from footprint.core import guided_dispersion as gdisp

    plan = Plan(parse_request(example("disperse_guided_lod189") | {"samples": SAMPLES}))
    load = [round(os.getloadavg()[0], 2)]
    out = {}
    for name, spec in (("time", against_time(plan.spec, plan.nominal)), ("energy", plan.open_spec)):
        landings = gdisp.fly_samples(spec, None, plan.samples)
        mode = gdisp.statistics(plan.spec, landings, plan.nominal).modes["guided"]  # the one mode flown
        out[name] = {"landed": mode["landed"], **{k: round(v, 1) for k, v in mode["miss_nmi"].items()}}
        print(name, out[name], flush=True)
    load.append(round(os.getloadavg()[0], 2))
    ratio = out["time"]["cep"] / out["energy"]["cep"]
    print(f"CEP against time / against energy: {ratio:.2f}")
    save_result("open_loop", {"samples": SAMPLES, "seed": 1, "open_loop": out, "cep_ratio": ratio, "load_1min": load})
    assert np.isfinite(ratio)


if __name__ == "__main__":
    main()
