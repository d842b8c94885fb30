"""One trajectory: Footprint's compiled integrator (DOPRI5, the default) against scipy's solve_ivp on the same
right-hand side, and our DOP853 against our DOPRI5 in the same process.

The case is the report's Table 2 entry with the lod-2.2 vehicle, ARDC 1959, rotating oblate earth,
single-parameter bank (K = .8, 85 deg limit) from pull-out, stop at 50,000 ft. The baseline is
scipy.integrate.solve_ivp (RK45, the same error scale) in two legs, entry to pull-out and pull-out to the
stop altitude, as anyone would write it by hand, on the same right-hand side (dynamics.rhs) twice:
- as plain Python (the same source, loaded a second time with FOOTPRINT_NO_JIT=1): the plain baseline;
- compiled, called from Python: the ratio then measures only the integrator and its events.

Where the integrator's time goes (issue 29 item 4's limit): the right-hand side alone at the flight's own rows, times
the flight's count of right-hand sides, over the integrator alone; and each part of the right-hand side alone.

Also timed: DOP853 against DOPRI5 on the summary path, the full flight and the integrator alone (interleaved rounds),
on the Table 2 case, on it with a dispersed density profile and aero (a Monte Carlo sample) and on the L/D 1.89 case;
a first `footprint fly` in a new process with numba's on-disk cache warm.

    python3 bench/bench_trajectory.py            # prints the figures, writes bench/results/trajectory.json
"""

import importlib
import json
import math
import os
import statistics
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from _timing import median_ms, save_result  # noqa: E402
from scipy.integrate import solve_ivp

from footprint.contracts import parse
from footprint.core import aero as _aero
from footprint.core._jit import njit
from footprint.core.atmosphere import DENSITY_NODE_COUNT, atmosphere
from footprint.core.dynamics import (
    M_BANK_ACTIVE,
    M_PULLED_OUT,
    M_REF_ANGLE,
    P_ATM,
    P_ATM_T,
    P_H,
    P_J,
    P_K,
    P_MU,
    P_OBLATE,
    P_RE,
    P_RHO0,
    P_RP,
    P_SCALE_H,
    P_STOP_ALT,
    _steer_deg,
    evaluate,
    rhs,
)
from footprint.core.frames import altitude_ft
from footprint.core.gravity import gravity_ecef
from footprint.core.integrate import R_ALPHA, R_ALT, R_MACH, integrate
from footprint.core.trajectory import Dispersion, flight_inputs, simulate, simulate_summary

HERE = Path(__file__).resolve().parent
CASE = HERE.parent / "examples" / "table2_lod22.json"


def interpreted_dynamics():
    """A second, uncompiled copy of footprint.core.dynamics and what it imports, in this process."""
    saved = {name: mod for name, mod in sys.modules.items() if name.startswith("footprint.core")}
    for name in saved:
        del sys.modules[name]
    os.environ["FOOTPRINT_NO_JIT"] = "1"
    try:
        return importlib.import_module("footprint.core.dynamics")
    finally:
        del os.environ["FOOTPRINT_NO_JIT"]
        for name in [n for n in sys.modules if n.startswith("footprint.core")]:
            del sys.modules[name]
        sys.modules.update(saved)


def scipy_flight(spec, rhs=rhs, evaluate=evaluate):
    """The baseline: solve_ivp twice, with pull-out and the stop altitude as terminal events."""
    p, s0, mode = flight_inputs(spec)
    aero, ctrl = spec.vehicle.blob, spec.ctrl
    out = np.empty(6)
    v0 = math.sqrt(s0[3] ** 2 + s0[4] ** 2 + s0[5] ** 2)
    atol = np.array([p[P_RE]] * 3 + [v0] * 3) * spec.rtol  # our error scale; rtol ~ 0

    def f(t, s):
        rhs(t, s, p, aero, ctrl, mode, out)
        return out.copy()

    def pullout(t, s):
        return evaluate(t, s, p, aero, ctrl, mode)[11]  # sin(gamma)

    pullout.terminal, pullout.direction = True, 1.0

    def ground(t, s):
        return evaluate(t, s, p, aero, ctrl, mode)[9] - p[P_STOP_ALT]

    ground.terminal, ground.direction = True, -1.0

    kw = dict(method="RK45", rtol=1e-13, atol=atol, max_step=spec.max_step_s)
    leg1 = solve_ivp(f, (0.0, 5.0e4), s0, events=[pullout, ground], **kw)
    t1, s1 = leg1.t[-1], leg1.y[:, -1]
    mode[M_PULLED_OUT] = 1.0
    mode[M_BANK_ACTIVE] = 1.0
    mode[M_REF_ANGLE] = evaluate(t1, s1, p, aero, ctrl, mode)[12]
    leg2 = solve_ivp(f, (t1, 5.0e4), s1, events=[ground], **kw)
    return leg2.t[-1], leg1.nfev + leg2.nfev


def dispersed(spec):
    """A Monte Carlo sample's flight: C_L x 0.98, C_D x 1.03, the density profile 5 % rms (seed 1) at its nodes."""
    delta = 0.05 * np.random.default_rng(1).standard_normal(DENSITY_NODE_COUNT)
    return replace(spec, dispersion=Dispersion(cl_multiplier=0.98, cd_multiplier=1.03, density_delta=tuple(delta)))


METHOD_CASES = {
    "table2": (CASE, lambda spec: spec),
    "table2_dispersed": (CASE, dispersed),
    "lod189": (HERE.parent / "examples" / "footprint_lod189.json", lambda spec: spec),
}


def integrator_methods(rounds=9, calls=20):
    """DOP853 against DOPRI5 (the default) on each of METHOD_CASES, alternating in rounds (same load): median ms of
    the summary path (simulate_summary: issue 29's 0.45 ms), of the full flight with its histories (simulate) and of
    the integrator alone; steps and right-hand sides of each."""
    out = {}
    for name, (path, change) in METHOD_CASES.items():
        data = json.loads(path.read_text())
        case = data.get("case", data)
        for method in ("dop853", "dopri5"):
            spec = change(parse("case", case | {"integrator": {"method": method}}).to_spec())
            p, s0, mode = flight_inputs(spec)

            def alone(spec=spec, p=p, s0=s0, mode=mode):
                integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode.copy(), spec.max_steps)

            paths = {
                "summary_path": lambda spec=spec: simulate_summary(spec),
                "simulate": lambda spec=spec: simulate(spec).history,  # the histories made
                "integrator_alone": alone,
            }
            out[name, method] = {"summary": simulate_summary(spec), "paths": paths, "ms": {k: [] for k in paths}}
    for _ in range(rounds):
        for entry in out.values():
            for path_name, fn in entry["paths"].items():
                t0 = time.perf_counter()
                for _ in range(calls):
                    fn()
                entry["ms"][path_name].append(1e3 * (time.perf_counter() - t0) / calls)
    result = {}
    for (name, method), e in out.items():
        result.setdefault(name, {})[method] = {
            **{f"{k}_ms": round(statistics.median(ms), 3) for k, ms in e["ms"].items()},
            "steps": e["summary"]["steps"],
            "rhs": e["summary"]["rhs_evaluations"],
        }
    for r in result.values():
        for k in ("summary_path", "simulate", "integrator_alone"):
            r[f"{k}_dop853_over_dopri5"] = round(r["dop853"][f"{k}_ms"] / r["dopri5"][f"{k}_ms"], 3)
    return result


RHS_PARTS = (
    "right-hand side",
    "geodetic altitude",
    "atmosphere",
    "gravity",
    "aero coefficients",
    "alpha of (L/D)max",
    "steering angle",
)


@njit
def _rhs_parts(rows, p, aero, ctrl, mode, part, reps):
    """One part of the right-hand side (RHS_PARTS[part]) at every row's state, reps times: a sum, kept."""
    acc = 0.0
    for _ in range(reps):
        for i in range(rows.shape[0]):
            x, y, z, vx, vy, vz = rows[i, 1], rows[i, 2], rows[i, 3], rows[i, 4], rows[i, 5], rows[i, 6]
            if part == 0:
                acc += evaluate(rows[i, 0], rows[i, 1:7], p, aero, ctrl, mode)[0]
            elif part == 1:
                acc += altitude_ft(x, y, z, p[P_RE], p[P_RP], p[P_OBLATE] != 0.0)
            elif part == 2:
                acc += atmosphere(int(p[P_ATM]), rows[i, R_ALT], p[P_RHO0], p[P_SCALE_H], p[P_ATM_T])[0]
            elif part == 3:
                acc += gravity_ecef(x, y, z, p[P_MU], p[P_RE], p[P_J], p[P_H], p[P_K], p[P_OBLATE] != 0.0)[0]
            elif part == 4:
                acc += _aero.coefficients(aero, rows[i, R_MACH], rows[i, R_ALPHA], rows[i, R_ALT])[0]
            elif part == 5:
                acc += _aero.alpha_max_ld_deg(aero, rows[i, R_MACH], rows[i, R_ALT])
            else:
                r = math.sqrt(x * x + y * y + z * z)
                acc += _steer_deg(x / r, y / r, z / r, vx, vy, vz, p, ctrl)
    return acc


def rhs_share(reps=50, rounds=7):
    """The Table 2 flight's right-hand side (dynamics.evaluate) at its own rows, times its count of right-hand sides,
    over the integrator alone (interleaved rounds, medians); each part of the right-hand side alone (ns a call)."""
    spec = parse("case", json.loads(CASE.read_text())).to_spec()
    p, s0, mode = flight_inputs(spec)
    aero, ctrl = spec.vehicle.blob, spec.ctrl
    rows, _, n_rhs = integrate(s0, p, aero, ctrl, mode.copy(), spec.max_steps)
    rows = np.ascontiguousarray(rows)
    flown = mode.copy()  # the mode at the flight's end: pulled out, banking
    ns = {k: [] for k in RHS_PARTS}
    alone = []
    for part in range(len(RHS_PARTS)):
        _rhs_parts(rows, p, aero, ctrl, flown, part, 1)
    for _ in range(rounds):
        alone.append(median_ms(lambda: integrate(s0, p, aero, ctrl, mode.copy(), spec.max_steps), 50))
        for part, name in enumerate(RHS_PARTS):
            t0 = time.perf_counter()
            _rhs_parts(rows, p, aero, ctrl, flown, part, reps)
            ns[name].append(1e9 * (time.perf_counter() - t0) / (reps * len(rows)))
    per_rhs_ns = statistics.median(ns[RHS_PARTS[0]])
    return {
        "integrator_alone_ms": round(statistics.median(alone), 3),
        "rhs_evaluations": int(n_rhs),
        "rhs_ns": round(per_rhs_ns, 1),
        "rhs_share_of_integrator": round(1e-6 * per_rhs_ns * n_rhs / statistics.median(alone), 3),
        "parts_ns": {k: round(statistics.median(v), 1) for k, v in ns.items() if k != RHS_PARTS[0]},
    }


def first_cli_seconds():
    """Wall time of `footprint fly` in a new process (the numba cache was warmed by this process)."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "footprint.cli", "fly", str(CASE)], check=True, capture_output=True)
    return time.perf_counter() - t0


def main():
    spec = parse("case", json.loads(CASE.read_text())).to_spec()
    ours = simulate(spec).summary  # compiles or loads the cache
    plain = interpreted_dynamics()
    t_base, nfev_base = scipy_flight(spec)
    t_plain, _ = scipy_flight(spec, plain.rhs, plain.evaluate)
    ms_ours = median_ms(lambda: simulate(spec).history, 300)  # the histories made, as solve_ivp makes its own
    ms_base = median_ms(lambda: scipy_flight(spec), 7)
    ms_plain = median_ms(lambda: scipy_flight(spec, plain.rhs, plain.evaluate), 3)
    cli_s = min(first_cli_seconds() for _ in range(3))
    result = {
        "case": CASE.name,
        "footprint_ms_per_trajectory": round(ms_ours, 3),
        "scipy_plain_python_rhs_ms_per_trajectory": round(ms_plain, 1),
        "speedup_vs_plain_scipy": round(ms_plain / ms_ours, 1),
        "scipy_compiled_rhs_ms_per_trajectory": round(ms_base, 1),
        "speedup_vs_scipy_with_compiled_rhs": round(ms_base / ms_ours, 1),
        "footprint_rhs_evaluations": ours["rhs_evaluations"],
        "scipy_rhs_evaluations": int(nfev_base),
        "flight_time_s": {
            "footprint": round(ours["flight_time_s"], 3),
            "scipy": round(float(t_base), 3),
            "scipy_plain": round(float(t_plain), 3),
        },
        "first_cli_fly_new_process_s": round(cli_s, 2),
        "dop853_vs_dopri5": integrator_methods(),
        "where_the_integrator_goes": rhs_share(),
        "load_average_1min": round(os.getloadavg()[0], 2),
    }
    save_result("trajectory", result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
