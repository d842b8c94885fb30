"""Why our Section III heating losses are smaller than the report's: what the lost data and the unstated models change.

The report (Section III): the unconstrained optimum peaks at 2,670 degR; 2,550 degR is "about the lowest that can be
achieved on the initial plunge"; at 2,550 degR the vehicle enters "approaching C_L max" and loses 9.4 % of its
cross-range and 19 % of its down-range. Three things it does not give decide those numbers here:

* the lift table B-1 (lost in the OCR): fill (a), the default (flat L/D top, (L/D)max at 12.5 deg), against
  fill (b) of shared/data/aero_tables.md (constant axial force, (L/D)max at 17.5 deg), built below;
* "a one-dimensional conduction analysis on a simplified structure": a thin skin (core/heating.py) of several
  heat capacities against the radiation-equilibrium temperature of eq. (7);
* the angle-of-attack parameters: a table against velocity (ours) or against time.

Every variant is calibrated as the issue asks: its own unconstrained optimum (bank table, (L/D)max) peaks at
2,670 degR. Writes docs/heating_sensitivity.md and docs/figures/heating_sensitivity.json.
Run: python3 scripts/heating_sensitivity.py  (about two minutes on 2 workers)
"""

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.core.aero import ld_max
from footprint.core.controls import pack_controls
from footprint.core.dynamics import P_ATM, P_ATM_T, P_RHO0, P_SCALE_H
from footprint.core.heating import ReferenceHeating, calibrate_reference_radius_ft
from footprint.core.optimize import creep_pattern_feasible
from footprint.core.trajectory import pack_parameters, simulate
from footprint.parallel import client_map, dask_client

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root, for tests.authorities
from tests.authorities.report import REPORT, table2_entry  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
LOD189 = ROOT / "backend" / "footprint" / "core" / "data" / "vehicles" / "lod-1.89.json"
ENTRY = table2_entry()
LIMIT_R = REPORT["sec3.limit_R"].value
SKINS_BTU_FT2_R = (0.5, 1.0, 2.0)
TIME_NODES_S = (0.0, 150.0, 300.0, 450.0, 700.0, 1_200.0, 2_500.0)  # the plunge peaks at ~190-240 s
BUDGET = 4_000  # trajectories per constrained point
ALPHA_STARTS_DEG = (25.0, 30.0, 40.0)  # constant alpha starts besides (L/D)max


def fill_b_vehicle():
    """aero_tables.md fill (b): CL = (CD cos a - CA0) / sin a from the continuum drag of B-2 (the 0-100k band,
    185k at Mach 20; drag keeps its altitude increments), CA0 per Mach chosen so that (L/D)max equals fill (a)'s
    at that Mach (1.71, 1.91, 2.08, 1.89 at Mach 2, 5, 8, 20)."""
    d = json.loads(LOD189.read_text())
    t = d["aero"]["tables"]
    alpha = np.array(t["first"]["alpha_deg"])
    cl_a = np.array(t["first"]["values"])[:, :, 0]
    cd = np.array(t["second"]["values"])
    fine = np.linspace(alpha[0], alpha[-1], 2_601)
    lift = []
    for m in range(len(t["first"]["mach"])):
        cd_m = cd[m, :, 2] if t["first"]["mach"][m] >= 20.0 else cd[m, :, 0]

        def ld_max_with(ca0, cd_m=cd_m):
            cl = (cd_m * np.cos(np.radians(alpha)) - ca0) / np.sin(np.radians(alpha))
            return np.max(np.interp(fine, alpha, cl) / np.interp(fine, alpha, cd_m)), cl

        target = np.max(np.interp(fine, alpha, cl_a[m]) / np.interp(fine, alpha, cd_m))
        lo, hi = 0.0, 0.3
        for _ in range(60):  # (L/D)max falls as CA0 grows
            lo, hi = ((lo + hi) / 2, hi) if ld_max_with((lo + hi) / 2)[0] > target else (lo, (lo + hi) / 2)
        lift.append(ld_max_with(lo)[1])
    first = dict(t["first"], values=[[[v] for v in row] for row in np.round(lift, 6).tolist()])
    return {
        "name": "L/D 1.89, lift fill (b)",
        "wing_loading_psf": d["wing_loading_psf"],
        "aero": {"tables": {"form": "lift_drag", "first": first, "second": t["second"]}},
    }


def base_spec(vehicle):
    case = {
        "vehicle": vehicle,
        "entry": ENTRY,
        "alpha": {"law": "max_ld"},
        "bank": {"law": "zero"},
        "stop": {"altitude_ft": 50_000},
    }
    return parse("case", case).to_spec()


def calibrated(spec, free, skin=0.0):
    """The spec with heating calibrated on `free`, its unconstrained optimum (an optimize.Result)."""
    flight = C.control_problem(spec).controls(spec, free.params)
    p, h = pack_parameters(flight), simulate(flight).history
    radius = calibrate_reference_radius_ft(
        h["altitude_ft"],
        h["velocity_fps"],
        h["alpha_deg"],
        (p[P_ATM], p[P_RHO0], p[P_SCALE_H], p[P_ATM_T]),
        skin_heat_capacity_btu_ft2_R=skin,
        time_s=h["time_s"],
    )
    return replace(spec, heating=ReferenceHeating(radius, skin_heat_capacity_btu_ft2_R=skin))


def plunge_R(spec, alpha_law):
    """Peak temperature of the zero-bank flight at (L/D)max or C_L max (the report's 'initial plunge')."""
    ctrl = pack_controls(bank_law="zero", alpha_law=alpha_law)
    return simulate(replace(spec, ctrl=ctrl)).summary["max_temperature_R"]


def limited_max_crossrange(job):
    """Max cross-range under the limit with the bank table and an alpha table (against velocity, or against time
    at `times_s`), from the unconstrained optimum's bank table and a constant alpha0."""
    spec, free_bank, alpha0, times_s = job
    nodes = C.ALPHA_TABLE_VELOCITIES_FPS if times_s is None else times_s
    pr = C.control_problem(
        spec,
        constraints=(C.temperature_limit(LIMIT_R),),
        controls="bank_alpha",
        initial=np.r_[free_bank, np.full(len(nodes), alpha0)],
        alpha_times_s=times_s,
    )
    r = creep_pattern_feasible(pr, max_evaluations=BUDGET, **C.search_options("bank_alpha", velocities_fps=nodes))
    return {
        "crossrange_nmi": r.payoff,
        "max_temperature_R": r.summary["max_temperature_R"],
        "feasible": r.feasible,
        "trajectories": r.trajectories,
        "alpha_deg": [round(float(a), 1) for a in r.params[len(free_bank) :]],
    }


def main():
    t0 = time.perf_counter()
    vehicles = {"fill (a), default": {"builtin": "lod-1.89"}, "fill (b)": fill_b_vehicle()}
    rows, jobs = [], []
    for name, vehicle in vehicles.items():
        spec = base_spec(vehicle)
        free = C.solve(spec, max_evaluations=1_500)  # the unconstrained optimum: bank table, (L/D)max alpha
        _, alpha_ld = ld_max(spec.vehicle, 20.0, 200_000.0)  # deg: 12.5 for fill (a), 17.5 for fill (b)
        for skin in (0.0, *(SKINS_BTU_FT2_R if "(a)" in name else ())):
            hot = calibrated(spec, free, skin)
            rows.append(
                {
                    "lift": name,
                    "skin_btu_ft2_R": skin,
                    "reference_radius_ft": hot.heating.reference_radius_ft,
                    "free_crossrange_nmi": free.payoff,
                    "plunge_max_ld_R": plunge_R(hot, "max_ld"),
                    "plunge_cl_max_R": plunge_R(hot, "cl_max"),
                }
            )
            if skin == 0.0:  # several starts: the penalty search ends in different places
                for times_s, abscissa in ((None, "velocity"), (TIME_NODES_S, "time")):
                    for alpha0 in (alpha_ld, *ALPHA_STARTS_DEG):
                        jobs.append(((name, abscissa, free.payoff), (hot, free.params, alpha0, times_s)))
            print(rows[-1], flush=True)
    with dask_client(workers=2) as client:  # the package's one parallel path (footprint.parallel)
        found = client_map(client)(limited_max_crossrange, [j for _, j in jobs])

    def rank(r):  # a feasible point by its cross-range, an infeasible one by its temperature
        return (r["feasible"], r["crossrange_nmi"] if r["feasible"] else -r["max_temperature_R"])

    best = {}  # per lift and abscissa, the best start
    for (key, _), r in zip(jobs, found):
        if key not in best or rank(r) > rank(best[key]):
            best[key] = r
    limited = [dict(zip(("lift", "alpha_abscissa", "free_crossrange_nmi"), key), **r) for key, r in best.items()]
    for r in limited:
        print(r, flush=True)
    out = {"floors": rows, "limited_2550": limited, "seconds": time.perf_counter() - t0}
    (DOCS / "figures" / "heating_sensitivity.json").write_text(json.dumps(out, indent=1, default=float))
    (DOCS / "heating_sensitivity.md").write_text(markdown(out))
    print(f"done in {out['seconds']:.0f} s")


def markdown(out):
    lines = [
        "# Section III: why our heating losses are smaller than the report's",
        "",
        "Generated by `scripts/heating_sensitivity.py`; raw numbers in `docs/figures/heating_sensitivity.json`.",
        "L/D 1.89 vehicle, Table 2 entry, stop at 50,000 ft. Each row is calibrated as Section III.1 says: its own",
        "unconstrained optimum (8-point bank table, (L/D)max alpha) peaks at 2,670 °R. The report: that optimum",
        'peaks at 2,670 °R, and 2,550 °R "is about the lowest that can be achieved on the initial plunge", i.e. a',
        "C_L-max plunge peaks near 2,550 °R (0.955 of 2,670).",
        "",
        "## The plunge floor",
        "",
        "| lift table B-1 | temperature | reference radius (ft) | unconstrained max cross-range (nmi) |"
        " zero-bank plunge at (L/D)max (°R) | at C_L max (°R) | C_L-max plunge / 2,670 |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in out["floors"]:
        temp = "RET, eq. (7)" if r["skin_btu_ft2_R"] == 0.0 else f"thin skin, {r['skin_btu_ft2_R']:g} Btu/(ft² °R)"
        lines.append(
            f"| {r['lift']} | {temp} | {r['reference_radius_ft']:.3f} | {r['free_crossrange_nmi']:,.0f} | "
            f"{r['plunge_max_ld_R']:,.0f} | {r['plunge_cl_max_R']:,.0f} | "
            f"{r['plunge_cl_max_R'] / 2_670.0:.3f} |"
        )
    lines += [
        "| report | RET (computed with 1-D conduction) | — | 1,964 | ≤ 2,670 | ≈ 2,550 | ≈ 0.955 |",
        "",
        f"## Maximum cross-range at RET ≤ {LIMIT_R:,.0f} °R",
        "",
        f"Bank table plus an alpha table ({C.ALPHA_BOUNDS_DEG[0]}-{C.ALPHA_BOUNDS_DEG[1]} deg) against "
        f"velocity ({', '.join(f'{v:,.0f}' for v in C.ALPHA_TABLE_VELOCITIES_FPS)} ft/s) or time "
        f"({', '.join(f'{t:,.0f}' for t in TIME_NODES_S)} s), creep + pattern from the unconstrained optimum's "
        f"bank table with alpha constant at (L/D)max, {', '.join(f'{a:g}' for a in ALPHA_STARTS_DEG)} deg (the "
        f"best of the starts), ≤ {BUDGET:,} trajectories each.",
        "",
        "| lift table B-1 | alpha against | max cross-range (nmi) | loss | peak RET (°R) | feasible |"
        " trajectories | alpha at the nodes (deg) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in out["limited_2550"]:
        lines.append(
            f"| {r['lift']} | {r['alpha_abscissa']} | {r['crossrange_nmi']:,.0f} | "
            f"{100 * (1 - r['crossrange_nmi'] / r['free_crossrange_nmi']):.1f} % | "
            f"{r['max_temperature_R']:,.1f} | {r['feasible']} | {r['trajectories']:,} | "
            f"{', '.join(f'{a:g}' for a in r['alpha_deg'])} |"
        )
    lines += [
        '| report | (not stated) | 1,780 | 9.4 % | 2,550 | yes | — | "approaching C_L max" at entry |',
        "",
        *NOTES,
    ]
    return "\n".join(lines) + "\n"


NOTES = """## Reading

* **Lift.** The plunge floor is set by how much higher a C_L-max vehicle pulls out (q ~ sqrt(rho) ~ C_L^-1/2)
  against how much more Table 1 heats the point at high alpha (.17 to .23). With fill (a) the (L/D)max alpha is
  12.5 deg (C_L 0.18, the flat L/D top's low end), so C_L max is 4.8 times larger and the floor lies far below
  the report's. Fill (b) flies (L/D)max at 17.5 deg (C_L 0.29): its unconstrained optimum peaks on the plunge
  and its C_L-max plunge lands near 2,550 °R, the report's picture. The lift table is lost; Section III speaks
  for fill (b) over fill (a), and so, weakly, does the unconstrained optimum (2,022 nmi against 2,045; the
  report's 1,964). Fill (a) stays the default: Section II is validated on it (docs/validation.md).
* **Conduction.** A thin skin damps short pulses more than long ones. The plunge pulse is the shorter, so a
  heat capacity lowers the plunge floor relative to the calibrated peak: the report's "one-dimensional
  conduction analysis" does not explain its high floor.
* **Alpha parameters.** With alpha tabulated against velocity the plunge (24,000-24,500 ft/s) and the first
  part of the glide share their nodes, and the search cannot cool one without flying the other at low L/D.
  Against time the plunge has nodes of its own: the optimum raises alpha mainly in the first ~300 s and meets
  2,550 °R for a small loss. The report does not say against what its alpha parameters were tabulated.
* None of the variants loses 9.4 % at a feasible 2,550 °R point. Where the report's losses come from (its
  lift table, its alpha parameters, or where its search stopped) cannot be settled from the surviving text.
""".splitlines()


if __name__ == "__main__":
    main()
