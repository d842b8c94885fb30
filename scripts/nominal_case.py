"""The report's nominal case (Table 2 entry, zero bank, alpha at (L/D)max, stop at 50,000 ft) for the
L/D 2.2 and 1.89 vehicles and entry angles -2 to -5 deg (the conditions of Fig. 16); writes docs/nominal_case.md.

    python3 scripts/nominal_case.py
"""

import sys
from pathlib import Path

from footprint import fly
from footprint.core.aero import builtin_vehicle

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root, for tests.authorities
from tests.authorities.report import table2_entry, table2_stop  # noqa: E402

DOC = Path(__file__).resolve().parents[1] / "docs" / "nominal_case.md"
GAMMAS = (-2.0, -3.0, -4.0, -5.0)
VEHICLES = ("lod-2.2", "lod-1.89", "lod-2.6")


def case(vehicle, gamma_deg):
    return {
        "vehicle": {"builtin": vehicle},
        "planet": {"rotating": True, "oblate": True, "atmosphere": {"model": "ardc1959"}},
        "entry": table2_entry(gamma_deg=gamma_deg),
        "alpha": {"law": "max_ld"},
        "bank": {"law": "zero"},
        "stop": table2_stop(),
    }


def row(vehicle, gamma_deg):
    t = fly(case(vehicle, gamma_deg))
    ws = builtin_vehicle(vehicle).wing_loading_psf
    s, h = t.summary, t.history
    i = int((h["time_s"] <= s["pullout_time_s"]).nonzero()[0][-1])  # the pull-out row (an event row)
    return (
        f"| {vehicle} | {gamma_deg:g} | {s['pullout_altitude_ft']:,.0f} | {s['pullout_time_s']:.1f} "
        f"| {h['velocity_fps'][i]:,.0f} | {h['cl'][i]:.3f} | {ws / h['cl'][i]:,.0f} | {s['downrange_nmi']:,.1f} | {s['crossrange_nmi']:,.1f} "
        f"| {s['flight_time_s']:,.1f} | {s['max_dynamic_pressure_psf']:,.0f} |"
    )


def main():
    body = [
        "| vehicle | γ_e deg | pull-out altitude ft | at s | V at pull-out ft/s | C_L there | W/(C_L S) psf | down-range nmi "
        "| cross-range nmi | flight time s | max q psf |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    body += [row(v, g) for v in VEHICLES for g in GAMMAS]
    DOC.write_text(DOC.read_text().split("<!-- table -->")[0] + "<!-- table -->\n" + "\n".join(body) + "\n")
    print("\n".join(body))


if __name__ == "__main__":
    main()
