"""docs/guidance.md's figures and numbers: the guided flight of examples/fly_guided_lod189.json (its bank history,
its predicted miss, the flown bank re-flown open loop), a guided dispersion beside the open loop for the same samples,
a temperature-limited guided flight, and the guided footprint of bench/results/guided_footprint.json (written by
bench/bench_guided_footprint.py) in ranges and on the map.

    python3 scripts/guidance_figures.py [SAMPLES]   # docs/figures/guided_*.png; the numbers printed (200 samples)
"""

import copy
import json
import math
import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from footprint import parallel
from footprint.api import fly
from footprint.contracts import module, parse
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference
from footprint.pictures.figures import guided_dispersion_figure, guided_footprint_figure, save
from footprint.pictures.maps import footprint_layer, panels_figure

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"
EXAMPLES = ROOT / "examples"
SAMPLES = int(sys.argv[1]) if len(sys.argv) > 1 else 200
ALPHA_20 = {"law": "table", "velocity_fps": [2000, 14000, 20000, 26000], "alpha_deg": [12.5, 12.5, 20, 20]}


def haversine_nmi(lat1, lon1, lat2, lon2):
    p1, p2, dl = math.radians(lat1), math.radians(lat2), math.radians(lon2 - lon1)
    a = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * MEAN_RADIUS_NMI * math.asin(math.sqrt(a))


def histories(case: dict) -> None:
    flight = fly(case)
    s, h = flight.summary, flight.history
    g = s["guidance"]
    fig = Figure(figsize=(11.0, 7.5), layout="constrained")
    bank, miss, alt = fig.add_subplot(3, 1, 1), fig.add_subplot(3, 1, 2), fig.add_subplot(3, 1, 3)
    bank.plot(h["time_s"], h["bank_command_deg"], color="0.2", ls="--", lw=0.9, label="commanded")
    bank.plot(h["time_s"], h["bank_deg"], color="tab:red", lw=1.4, label="flown (rate 10°/s, 5°/s² actuator)")
    bank.axhline(0.0, color="0.6", lw=0.6)
    bank.set_ylabel("Bank (deg)")
    bank.legend(fontsize="small", loc="upper right")
    bank.set_title(f"Guided to 5,000 nmi down-range, 600 cross-range: miss {g['miss_nmi']:.2f} nmi, {g['cycles']} "
                   f"cycles, {g['reversals']} reversals, {g['saturated_cycles']} saturated")  # fmt: skip
    miss.plot(h["time_s"], h["predicted_miss_nmi"], color="tab:green", lw=1.2)
    miss.axhline(0.0, color="0.6", lw=0.6)
    miss.set_ylabel("Predicted miss (nmi)")
    miss.set_yscale("symlog", linthresh=1.0)
    alt.plot(h["time_s"], np.asarray(h["altitude_ft"]) / 1e3, color="tab:blue", lw=1.2)
    alt.set_ylabel("Altitude (1,000 ft)")
    alt.set_xlabel("Flight time (s)")
    for ax in (bank, miss, alt):
        ax.grid(True, color="0.92", lw=0.6)
    save(fig, FIGURES / "guided_histories.png")
    # the flown bank as a time table, flown open loop to the same energy (tight tolerance: see test_guidance)
    tight = copy.deepcopy(case) | {"integrator": {"rtol": 1e-11}}
    fine = fly(tight)
    again = copy.deepcopy(tight)
    table = fine.bank_table
    again["bank"] = {"law": "table", "time_s": table["time_s"].tolist(), "bank_deg": table["bank_deg"].tolist()}
    again["stop"] = dict(again["stop"], energy_ft=fine.summary["final_energy_ft"])
    a, f = fly(again).summary, fine.summary
    gap = haversine_nmi(f["final_latitude_deg"], f["final_longitude_deg"], a["final_latitude_deg"],
                        a["final_longitude_deg"])  # fmt: skip
    print(f"guided flight: miss {g['miss_nmi']:.3f} nmi, {g['cycles']} cycles, {g['predictions']} predictions, "
          f"{g['reversals']} reversals, {g['saturated_cycles']} saturated cycles, {s['flight_time_s']:.0f} s; "
          f"re-flown open loop (rtol 1e-11): {gap:.3f} nmi apart")  # fmt: skip


def temperature_limit(case: dict) -> None:
    base = copy.deepcopy(case)
    base["alpha"], base["heating"] = ALPHA_20, {"model": "reference"}
    free = fly(base).summary
    limited = fly(copy.deepcopy(base) | {"bank": base["bank"] | {"max_temperature_R": 2550}}).summary
    print(f"alpha 20 deg above 14,000 ft/s, reference heating: free peak {free['max_temperature_R']:.0f} R, "
          f"limited to 2,550 R: peak {limited['max_temperature_R']:.1f} R, miss {limited['guidance']['miss_nmi']:.2f}"
          f" nmi ({limited['guidance']['status']}), {limited['guidance']['limit_bound_cycles']} cycles bound")  # fmt: skip


def dispersion(case: dict) -> None:
    data = json.loads((EXAMPLES / "disperse_guided_lod189.json").read_text()) | {"samples": SAMPLES, "case": case}
    study = parse("guided_dispersion", data)
    stats, info = parallel.run("guided_dispersion", study, workers=2)
    r = module("guided_dispersion").to_dict(study, stats, SAMPLES, info)
    save(guided_dispersion_figure(r, title=f"{SAMPLES} dispersed samples, guided and open loop"),
         FIGURES / "guided_vs_open_loop.png")  # fmt: skip
    for mode in ("guided", "open_loop"):
        m = r[mode]["miss_nmi"]
        w = {x["radius_nmi"]: x for x in r[mode]["within"]}[5.0]
        print(f"{mode}: CEP {m['cep']:.2f} nmi, p99 {m['p99']:.2f}, P(<=5 nmi) {w['probability']:.3f} "
              f"[{w['interval'][0]:.3f}, {w['interval'][1]:.3f}]")  # fmt: skip


def guided_footprint() -> None:
    bench = json.loads((ROOT / "bench" / "results" / "guided_footprint.json").read_text())
    r = bench["answer"]
    save(guided_footprint_figure(r), FIGURES / "guided_footprint.png")
    ref = Reference(**r["entry"])
    styles = {"optimal": ("k", "--", "true optimal"), "report": ("0.45", "-", "report's law"),
              "nominal_guided": ("tab:blue", ":", "guided, undispersed"), "guided": ("tab:blue", "-", "guided, 99 %")}  # fmt: skip
    layers = [
        footprint_layer(
            r[k]["latitude_deg"],
            r[k]["longitude_deg"],
            reference=ref if k == "guided" else None,
            downrange_nmi=r[k]["downrange_nmi"],
            label=label,
            color=color,
            linestyle=ls,
            shade=k == "guided",
        )  # fmt: skip
        for k, (color, ls, label) in styles.items()
        if r.get(k)
    ]
    panels = [
        {"projection": "cylindrical", "layers": layers, "extent": None, "title": "Cylindrical: past half-way round"},
        {"projection": "orthographic", "layers": layers, "center": (10.0, 100.0), "title": "Globe"},
    ]
    save(panels_figure(panels, ncols=2, panel_size=(7.0, 4.6)), FIGURES / "guided_footprint_map.png")
    for k in ("report", "optimal"):
        m = r.get(f"margin_to_{k}")
        if m:
            print(f"margin to the {k}: {m['area_nmi2']:,.0f} nmi² ({m['percent']:.1f} %), inside at every ray: "
                  f"{m['inside_at_every_ray']}")  # fmt: skip


def main() -> None:
    case = json.loads((EXAMPLES / "fly_guided_lod189.json").read_text())
    histories(case)
    temperature_limit(case)
    dispersion(case)
    guided_footprint()


if __name__ == "__main__":
    main()
