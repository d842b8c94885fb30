"""AFWAL-TR-82-3036 Section III: heating-constrained footprints of the L/D 1.89 vehicle (Table 2 entry).

Also flies the simple heating-constrained method (beyond the report: single-parameter bank with the
coolest-needed alpha floor, footprint.core.constrained.temperature_limited_footprint) beside the optimized one.
Writes docs/heating.md (ours beside the report's), docs/figures/fig22_crossrange_vs_temperature.png,
docs/figures/fig29_constrained_footprint.png and docs/figures/fig29_histories.png.
Run: python3 scripts/section_iii.py  (about a few minutes on 2 workers)
"""

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

from matplotlib.figure import Figure

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.core.controls import pack_controls
from footprint.core.heating import REFERENCE_RADIUS_FT
from footprint.core.method_settings import TemperatureLimited
from footprint.core.trajectory import simulate
from footprint.parallel import client_map, dask_client
from footprint.pictures.figures import CROSSRANGE_LABEL, DOWNRANGE_LABEL, save

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root, for tests.authorities
from tests.authorities.report import REPORT as PUBLISHED  # noqa: E402
from tests.authorities.report import table2_entry, table2_stop

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
TABLE2_CASE = {
    "vehicle": {"builtin": "lod-1.89"},
    "entry": table2_entry(),
    "stop": table2_stop(),
    "heating": {"model": "reference"},
}
# the report's numbers (Section III)
REPORT = {
    f"{end}_{which}_nmi": PUBLISHED[f"sec3.{end}{'' if which == 'unconstrained' else '_2550'}_nmi"].value
    for end in ("max_crossrange", "max_downrange", "min_downrange")
    for which in ("unconstrained", "2550")
}
LIMIT_R = PUBLISHED["sec3.limit_R"].value
# Fig. 22's limits, and lower ones: in our heating model 2,550 degR is far from the plunge's floor (see notes)
FIG22_LIMITS_R = (None, 2_600.0, 2_550.0, 2_500.0, 2_450.0, 2_400.0, 2_350.0)
DOWNRANGES_NMI = (2_000.0, 4_000.0, 8_000.0, 11_000.0)
MAX_EVALUATIONS = 1_500
HOT_MAX_EVALUATIONS = 3_000  # the constrained footprint points: at 1,500 some ended 1-8 degR outside the band
WORKERS = 2  # Dask worker processes for the optimized points


def main():
    t0 = time.perf_counter()
    spec = parse("case", TABLE2_CASE).to_spec()
    with dask_client(workers=WORKERS) as client:
        map_tasks = client_map(client)
        fig22 = C.max_crossrange_vs_temperature(
            spec, FIG22_LIMITS_R, max_evaluations=MAX_EVALUATIONS, map_tasks=map_tasks
        )
        print(
            "fig22",
            [(lim, round(r.payoff, 1), round(r.summary["max_temperature_R"], 1)) for lim, r in fig22],
            flush=True,
        )
        free = C.optimal_footprint(
            spec,
            DOWNRANGES_NMI,
            controls="bank",
            min_downrange=True,
            max_evaluations=MAX_EVALUATIONS,
            map_tasks=map_tasks,
        )
        print("free", [(p.label, round(p.downrange_nmi), round(p.crossrange_nmi)) for p in free.points], flush=True)
        hot = C.optimal_footprint(
            spec,
            DOWNRANGES_NMI,
            constraints=(C.temperature_limit(LIMIT_R),),
            controls="bank_alpha",
            min_downrange=True,
            max_evaluations=HOT_MAX_EVALUATIONS,
            map_tasks=map_tasks,
        )
    print(
        "2550",
        [(p.label, round(p.downrange_nmi), round(p.crossrange_nmi), p.result.feasible) for p in hot.points],
        flush=True,
    )
    C.temperature_limited_footprint(
        spec, TemperatureLimited(limit_R=LIMIT_R, bank0_deg=(0.0,))
    )  # compile in this process: time the method
    simple = C.temperature_limited_footprint(spec, TemperatureLimited(limit_R=LIMIT_R))
    print("simple", simple.trajectories, [(p.bank0_deg, p.floor_deg) for p in simple.points], flush=True)
    # the unconstrained Fig. 22 point replaces the footprint's own max cross-range point when better (same problem)
    results = {
        "fig22": [
            {
                "limit_R": lim,
                "crossrange_nmi": r.payoff,
                "downrange_nmi": r.summary["downrange_nmi"],
                "max_temperature_R": r.summary["max_temperature_R"],
                "feasible": r.feasible,
                "trajectories": r.trajectories,
                "parameters": dict(zip(r.names, map(float, r.params))),
            }
            for lim, r in fig22
        ],
        "unconstrained_footprint": free.to_dict(),
        "footprint_2550": hot.to_dict(),
        "simple_2550": {
            "trajectories": simple.trajectories,
            "seconds": simple.seconds,
            "footprint": simple.footprint.to_dict(),
            "settings": [
                {
                    "bank0_deg": p.bank0_deg,
                    "alpha_floor_deg": p.floor_deg,
                    "max_temperature_R": p.summary["max_temperature_R"],
                    "flights": p.flights,
                }
                for p in simple.points
            ],
        },
        "seconds": time.perf_counter() - t0,
    }
    (DOCS / "figures").mkdir(parents=True, exist_ok=True)
    (DOCS / "figures" / "section_iii.json").write_text(json.dumps(results, indent=1, default=float))
    figures(spec, fig22, free, hot, simple)
    plunge = {
        law: simulate(replace(spec, ctrl=pack_controls(bank_law="zero", alpha_law=law))).summary["max_temperature_R"]
        for law in ("max_ld", "cl_max")
    }  # the zero-bank plunge at both ends of alpha
    write_markdown(fig22, free, hot, simple, results["seconds"], plunge)
    print(f"done in {results['seconds']:.0f} s", flush=True)


def outline(points):
    """The closed outline (down-range, cross-range in nmi) of a left half's points, mirrored to the right."""
    pts = sorted(points, key=lambda p: p.downrange_nmi)
    x, y = [p.downrange_nmi for p in pts], [p.crossrange_nmi for p in pts]
    return x + x[::-1], y + [-v for v in y[::-1]]


def finish(fig, ax, xlabel, ylabel, title, name):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    save(fig, DOCS / "figures" / name)


def figures(spec, fig22, free, hot, simple):
    fig = Figure(figsize=(7.0, 5.0), layout="constrained")
    ax = fig.add_subplot()
    ok = [(r.summary["max_temperature_R"] if lim is None else lim, r.payoff) for lim, r in fig22 if r.feasible]
    bad = [(r.summary["max_temperature_R"], r.payoff) for _, r in fig22 if not r.feasible]
    ax.plot(*zip(*ok), "o-k", label="ours (bank + alpha tables)")
    if bad:
        ax.plot(*zip(*bad), "o", mfc="none", color="k", label="ours, limit not met (at the RET reached)")
    t = [x for x, _ in ok + bad]
    ax.plot(
        [PUBLISHED["sec3.max_temperature_R"].value, LIMIT_R],
        [REPORT["max_crossrange_unconstrained_nmi"], REPORT["max_crossrange_2550_nmi"]],
        "s--",
        color="0.5",
        label="report (Fig. 22 end points)",
    )
    ax.set_xlim(min(t) - 50, 2_700)
    ax.set_ylim(1_000, 2_200)
    finish(
        fig,
        ax,
        "Maximum allowable surface temperature (°R)",
        CROSSRANGE_LABEL,
        "Fig. 22: cross-range vs allowable temperature, L/D 1.89, γ₀ = −2°",
        "fig22_crossrange_vs_temperature.png",
    )

    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    ax = fig.add_subplot()
    for fp, style, name in ((free, "o-k", "unconstrained"), (hot, "s--", f"RET ≤ {LIMIT_R:,.0f} °R")):
        ax.plot(*outline(fp.points), style, label=name)
    ax.plot(
        *outline(simple.footprint.points),
        "^:",
        color="tab:red",
        label=f"simple method, RET ≤ {LIMIT_R:,.0f} °R ({simple.trajectories} trajectories)",
    )
    finish(
        fig,
        ax,
        DOWNRANGE_LABEL,
        CROSSRANGE_LABEL,
        "Fig. 29: optimal footprints, unconstrained and temperature-constrained (mirrored)",
        "fig29_constrained_footprint.png",
    )

    fig = Figure(figsize=(11.0, 4.5), layout="constrained")
    axs = fig.subplots(1, 3)
    for (lim, r), style in zip([(lim, r) for lim, r in fig22 if lim in (None, 2_600.0, LIMIT_R)], ("-k", "--", "-.")):
        ctrl = C.control_problem(spec, controls="bank" if lim is None else "bank_alpha").controls
        h = simulate(ctrl(spec, r.params)).history
        name = "unconstrained" if lim is None else f"≤ {lim:,.0f} °R"
        axs[0].plot(h["time_s"], h["temperature_R"], style, label=name)
        axs[1].plot(h["time_s"], h["alpha_deg"], style, label=name)
        axs[2].plot(h["time_s"], h["bank_deg"], style, label=name)
    for ax, lab in zip(axs, ("Surface temperature (°R)", "Angle of attack (deg)", "Bank angle (deg)")):
        ax.set_xlabel("Time (s)")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
    axs[0].legend()
    fig.suptitle("Figs. 23-28: max cross-range histories")
    save(fig, DOCS / "figures" / "fig29_histories.png")


def write_markdown(fig22, free, hot, simple, seconds, plunge):
    by = dict(fig22)
    floor_R = min(r.summary["max_temperature_R"] for _, r in fig22)
    r0, r26, r25 = by[None], by[2_600.0], by[LIMIT_R]
    cr0 = max(r0.payoff, free.point("max_crossrange").crossrange_nmi)
    loss = 100.0 * (1.0 - r25.payoff / cr0)
    fmax, hmax = free.point("max_downrange"), hot.point("max_downrange")
    fmin, hmin = free.point("min_downrange"), hot.point("min_downrange")

    def row(name, ours, report, note=""):
        return f"| {name} | {ours} | {report} | {note} |"

    lines = [
        "# Section III: heating-constrained footprints (L/D 1.89, Table 2 entry)",
        "",
        "Generated by `scripts/section_iii.py` (`footprint.core.constrained`); raw numbers in",
        "`docs/figures/section_iii.json`. Entry 364,800 ft, 24,480 ft/s relative, γ₀ −2°, stop at 50,000 ft;",
        "heating `ReferenceHeating()` (eqs. 5-7, Table 1), calibrated so the unconstrained optimum (bank table)",
        "peaks at 2,670 °R. Unconstrained: (L/D)max alpha, 8-point bank table from pull-out (Fig. 20).",
        (
            "Constrained: bank table plus an alpha table vs velocity at "
            f"{', '.join(f'{v:,.0f}' for v in C.ALPHA_TABLE_VELOCITIES_FPS)} ft/s, alpha in "
            f"{C.ALPHA_BOUNDS_DEG[0]}-{C.ALPHA_BOUNDS_DEG[1]} deg ((L/D)max to C_L max), zero bank in the plunge,"
        ),
        (
            f"RET ≤ limit with TTOL {C.TTOL_TEMPERATURE_R} °R. Creep + pattern with the penalty of eq. (4), "
            f"≤ {MAX_EVALUATIONS} trajectories per point ({HOT_MAX_EVALUATIONS} for the constrained footprint),"
            f" run {seconds:.0f} s on 2 workers."
        ),
        "",
        "| quantity | ours | report | note |",
        "|---|---|---|---|",
        row(
            "max cross-range, unconstrained (nmi)",
            f"{cr0:,.0f} (RET {r0.summary['max_temperature_R']:,.0f} °R)",
            "1,964 (RET 2,670 °R)",
            "bank table only",
        ),
        row(
            "max cross-range, RET ≤ 2,600 °R (nmi)",
            f"{r26.payoff:,.0f} (RET {r26.summary['max_temperature_R']:,.1f})",
            "between (curve only)",
            "",
        ),
        row(
            "max cross-range, RET ≤ 2,550 °R (nmi)",
            f"{r25.payoff:,.0f} (RET {r25.summary['max_temperature_R']:,.1f})",
            "1,780",
            "",
        ),
        row("cross-range loss at 2,550 °R", f"{loss:.1f} %", "9.4 %", ""),
        row(
            "max down-range, unconstrained (nmi)",
            f"{fmax.downrange_nmi:,.0f} (RET {fmax.result.summary['max_temperature_R']:,.0f})",
            "14,500",
            "",
        ),
        row(
            "max down-range, RET ≤ 2,550 °R (nmi)",
            f"{hmax.downrange_nmi:,.0f} (RET "
            f"{hmax.result.summary['max_temperature_R']:,.1f}, feasible {hmax.result.feasible})",
            "11,700 (−19 %)",
            f"{100.0 * (hmax.downrange_nmi / fmax.downrange_nmi - 1.0):+.1f} %",
        ),
        row(
            "min down-range, unconstrained (nmi)",
            f"{fmin.downrange_nmi:,.0f} (RET {fmin.result.summary['max_temperature_R']:,.0f})",
            "≈1,000",
            "minimize down-range, bank table",
        ),
        row(
            "min down-range, RET ≤ 2,550 °R (nmi)",
            f"{hmin.downrange_nmi:,.0f} (RET "
            f"{hmin.result.summary['max_temperature_R']:,.1f}, feasible {hmin.result.feasible})",
            "≈2,000 (doubled)",
            f"x{hmin.downrange_nmi / fmin.downrange_nmi:.2f}",
        ),
    ]
    lines += [
        row(
            f"max cross-range, RET ≤ {lim:,.0f} °R (nmi)",
            f"{r.payoff:,.0f} (RET {r.summary['max_temperature_R']:,.1f}, feasible {r.feasible})",
            "—",
            f"{100.0 * (r.payoff / cr0 - 1.0):+.1f} %, below the report's range",
        )
        for lim, r in fig22
        if lim is not None and lim < LIMIT_R
    ]
    lines += [
        "",
        "## Fig. 29: optimal footprint points (left half)",
        "",
        "| point | unconstrained down / cross (nmi) | RET ≤ 2,550 °R down / cross (nmi), feasible |",
        "|---|---|---|",
    ]
    for pf, ph in zip(free.points, hot.points):
        lines.append(
            f"| {pf.label} | {pf.downrange_nmi:,.0f} / {pf.crossrange_nmi:,.0f} | "
            f"{ph.downrange_nmi:,.0f} / {ph.crossrange_nmi:,.0f}, {ph.result.feasible} |"
        )
    lines += [
        "",
        *simple_section(hot, simple),
        "![Fig. 22](figures/fig22_crossrange_vs_temperature.png)",
        "![Fig. 29](figures/fig29_constrained_footprint.png)",
        "![Histories](figures/fig29_histories.png)",
        "",
        "## Notes",
        "",
        (
            "* Calibration (Section III.1): the unconstrained optimum, the bank table `heating.CALIBRATION_BANK_DEG`, "
            f"peaks at 2,670 °R with R_ref = {REFERENCE_RADIUS_FT} ft, ε 0.8. The report's R_N, emissivity and wall"
        ),
        "  model are not given, so how the peak RET responds to alpha and to the pull-out altitude is ours.",
        (
            f"* The plunge: at zero bank it peaks at {plunge['max_ld']:,.0f} °R at (L/D)max and {plunge['cl_max']:,.0f} °R"
            ' at C_L max, where the report calls 2,550 °R "about the lowest that can be achieved on the initial'
        ),
        '  plunge". So 2,550 °R is a much milder limit here than in the report, and the losses are smaller: the',
        "  comparison of magnitudes checks the machinery (the limit held within the 5 °R band, alpha raised where",
        "  the peak occurs), not the heating model. [heating_sensitivity.md](heating_sensitivity.md) shows what",
        "  moves the floor: the lost lift table (fill (b) puts it at the report's ≈2,550 °R), not conduction.",
        "* The unconstrained max cross-range differs from the report's 1,964 nmi because our bank-table optimum",
        "  on this aero/atmosphere already exceeds it (see docs on Section II); the percentage loss is the",
        "  comparable quantity.",
        "* Where the heat peaks: our unconstrained optimum peaks on the banked descent after pull-out (~770 s,",
        "  ~21,700 ft/s), above its plunge (~230 s). Under the limit the search raises alpha at the 20,000 and",
        "  26,000 ft/s nodes and keeps the bank schedule (fig29_histories.png; the 2,000 ft/s node sits at 20°, the",
        "  (L/D)max of Mach 2); the report's case approaches C_L max.",
        (
            f"* Floor: the lowest peak reached on the max cross-range problem is {floor_R:,.0f} °R (rows below it end"
            " infeasible with that best violation); the loss becomes report-sized (~5 %) only there."
        ),
        "* The unconstrained min down-range flight banks steeply right after pull-out and heats far past",
        "  2,670 °R (the RET in the table); under the limit it cannot, which is what lengthens it.",
        "* Min down-range: the report does not say how its ≈1,000 nmi rear point was produced; ours minimizes",
        "  down-range over the bank table (alpha table too when constrained), which is not the zero-lift point.",
        "* Searched flights are limited to 20,000 integrator steps and must end at the stop altitude; a few",
        "  steep-bank, high-alpha corners chatter and are rejected (constrained.SEARCH_MAX_STEPS).",
        "* Each point is one creep/pattern search with a budget; a larger budget or restarts may improve them.",
    ]
    (DOCS / "heating.md").write_text("\n".join(lines) + "\n")


def simple_section(hot, simple):
    fp = simple.footprint
    pairs = (
        ("max cross-range (nmi)", fp.max_crossrange_nmi, hot.point("max_crossrange").crossrange_nmi),
        ("max down-range (nmi)", fp.max_downrange_nmi, hot.point("max_downrange").downrange_nmi),
        ("min down-range (nmi)", fp.min_downrange_nmi, hot.point("min_downrange").downrange_nmi),
    )
    lines = [
        "",
        f"## Beyond the report: a simple method for the heating constraint (RET ≤ {LIMIT_R:,.0f} °R)",
        "",
        "The report's conclusion 3 found no simple method. Ours (`constrained.temperature_limited_footprint`):",
        "the single-parameter bank law of Section II.6 (φ₀ = 0-150° every 15°), alpha = max((L/D)max, floor),",
        f"the floor zero below {C.FLOOR_VELOCITIES_FPS[0]:,.0f} ft/s and rising to a value a at "
        f"{C.FLOOR_VELOCITIES_FPS[1]:,.0f} ft/s and above",
        "(where both heat pulses lie: the plunge and the banked descent). For each φ₀, a is the smallest in",
        "12.5-40° whose flight meets the limit (a 2.5° scan, then 5 bisections); a φ₀ that no a can cool is",
        "left out, and bounds the near side. The 15° grid is halved twice around its max cross-range setting",
        "(the floor grows with φ₀ there).",
        "",
        "| | simple method | optimized (bank + alpha tables) | difference |",
        "|---|---|---|---|",
    ]
    lines += [f"| {name} | {a:,.0f} | {b:,.0f} | {100.0 * (a / b - 1.0):+.1f} % |" for name, a, b in pairs]
    lines += [
        f"| trajectories | {simple.trajectories:,} | {hot.trajectories:,} | {hot.trajectories / simple.trajectories:.0f}× fewer |",
        f"| seconds | {simple.seconds:.2f} (1 process) | {hot.seconds:.1f} (2 workers) | "
        f"{hot.seconds / simple.seconds:.0f}× |",
        "",
        "| φ₀ (deg) | alpha floor a (deg) | peak RET (°R) | flights |",
        "|---|---|---|---|",
    ]
    lines += [
        f"| {p.bank0_deg:.0f} | {'left out' if p.floor_deg is None else f'{p.floor_deg:.2f}'} | "
        f"{p.summary['max_temperature_R']:,.0f} | {p.flights} |"
        for p in simple.points
    ]
    lines += [
        "",
        (
            "The optimized min down-range point misses the limit (it is the search's best violation); the simple"
            if not hot.point("min_downrange").result.feasible
            else "The optimized min down-range point banks and raises alpha within the limit; the simple"
        ),
        "method's near side is the steepest bank it can still cool, about twice the unconstrained",
        "single-parameter minimum, as the report's 1,000 → 2,000 nmi. Between 11,000 nmi and the maximum",
        "down-range the optimized footprint has no point, so the simple method's 30° and 15° settings lie",
        "outside its polygon there (fig29_constrained_footprint.png): each polygon is only its points' outline.",
        "",
    ]
    return lines


if __name__ == "__main__":
    sys.exit(main())
