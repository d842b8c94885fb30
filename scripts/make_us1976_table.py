"""Write backend/footprint/core/data/us1976_upper.csv: U.S. Standard Atmosphere 1976, 86 to 1,000 km.

Run once, from the repository root, with the dev extra installed (`pip install ussa1976`):

    python3 scripts/make_us1976_table.py

The runtime package never imports ussa1976; it reads the CSV this script writes.

Grid: every 1 km from 86 to 150 km geometric, every 2 km from 152 to 300 km, every 5 km from 305 to
1,000 km (280 rows). The kernel interpolates linearly in log density / log pressure and linearly in
temperature; this script checks that value at every mid-interval point against the model. A 5 km step
right above 150 km (where the temperature still climbs 3.7 K/km) would give 0.25 % in density; with the
2 km step the worst is 0.12 % in density and pressure (near 110 km) and 0.2 % in temperature (at
109.5 km, the end of the standard's elliptical temperature segment).

Correction applied to ussa1976 0.3.4 (the latest release on PyPI when this was written)
--------------------------------------------------------------------------------------------
Its atomic-oxygen diffusion term below 115 km (`thermal_diffusion_term_atomic_oxygen`) uses the
molar mass of N2 (28.0134) for the mean molecular weight M in the M*K/D term of the standard's
eq. (36). The standard uses M = M0 = 28.9644 below 100 km and M(N2) from 100 to 115 km (the same
rule ussa1976 itself applies to O2). The package's own test needs a 10 % tolerance on n(O) for this
reason ("TODO: investigate the poor relative tolerance"). The effect is n(O) 7.2 % too high from
100 km up, hence density too high by 0.15 % at 100 km, 1.6 % at 150 km, 3.0 % at 200 km, 5.4 % at
300 km and 6.7 % at 500 km compared with the printed 1976 tables. This script replaces that one
function by the same code with M taken from the package's own mean-molar-mass profile; then every
printed value checked below agrees to better than 0.1 %.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import ussa1976
import ussa1976.core as ussa

FT_PER_M = 1.0 / 0.3048
OUT = Path(__file__).resolve().parents[1] / "backend/footprint/core/data/us1976_upper.csv"
COMMAND = "python3 scripts/make_us1976_table.py"

# Printed values of the U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), geometric altitude:
# z_km -> (T_K, p_Pa, rho_kg_m3 from Table I; M_kg_kmol from Table II). Checked before the file is written.
PUBLISHED_1976 = {
    86.0: (186.87, 3.7338e-1, 6.958e-6, 28.95),
    100.0: (195.08, 3.2011e-2, 5.604e-7, 28.40),
    110.0: (240.00, 7.1042e-3, 9.7099e-8, 27.27),
    120.0: (360.00, 2.5382e-3, 2.2222e-8, 26.20),
    150.0: (634.39, 4.5422e-4, 2.076e-9, 24.10),
    200.0: (854.56, 8.4736e-5, 2.541e-10, 21.30),
    300.0: (976.01, 8.7704e-6, 1.916e-11, 17.73),
    500.0: (999.24, 3.0236e-7, 5.215e-13, 14.33),
    1000.0: (1000.0, 7.5138e-9, 3.561e-15, 3.94),
}


def _thermal_diffusion_term_atomic_oxygen_fixed(z_grid, g, t, dt_dz, d, k):
    """ussa1976's function with M = mean molecular weight (M0 below 100 km, M(N2) above), as in eq. (36)."""
    m = ussa.compute_mean_molar_mass_high_altitude(z=z_grid)
    below, above = z_grid < 115e3, z_grid >= 115e3
    x1 = ussa.f_below_115_km(
        g=g[below], t=t[below], dt_dz=dt_dz[below], m=m[below], mi=ussa.M["O"], alpha=ussa.ALPHA["O"], d=d, k=k
    )
    x2 = ussa.f_above_115_km(g=g[above], t=t[above], dt_dz=dt_dz[above], mi=ussa.M["O"], alpha=ussa.ALPHA["O"])
    return np.concatenate((x1, x2))


def upper_atmosphere_si(z_m: np.ndarray) -> dict[str, np.ndarray]:
    """T (kinetic, K), p (Pa), rho (kg/m^3) and mean molar mass (kg/kmol) from the high-altitude model."""
    ds = ussa.init_data_set(z=z_m)
    ussa.compute_high_altitude(data_set=ds, mask=None, inplace=True)
    rho = ds["rho"].values
    return {
        "temperature_K": ds["t"].values,
        "pressure_Pa": ds["p"].values,
        "density_kg_m3": rho,
        "mean_molar_mass_kg_kmol": rho * ussa.NA / ds["n_tot"].values * 1000.0,
    }


def main() -> int:
    original = ussa.thermal_diffusion_term_atomic_oxygen
    ussa.thermal_diffusion_term_atomic_oxygen = _thermal_diffusion_term_atomic_oxygen_fixed
    try:
        z_km = np.concatenate(
            (np.arange(86.0, 150.5, 1.0), np.arange(152.0, 300.5, 2.0), np.arange(305.0, 1000.5, 5.0))
        )
        table = upper_atmosphere_si(z_km * 1e3)
        mid_km = 0.5 * (z_km[1:] + z_km[:-1])
        mid = upper_atmosphere_si(mid_km * 1e3)
        published = upper_atmosphere_si(np.array(sorted(PUBLISHED_1976)) * 1e3)
    finally:
        ussa.thermal_diffusion_term_atomic_oxygen = original

    # Check 1: printed 1976 values.
    worst = 0.0
    for i, z in enumerate(sorted(PUBLISHED_1976)):
        for name, ref in zip(
            ("temperature_K", "pressure_Pa", "density_kg_m3", "mean_molar_mass_kg_kmol"), PUBLISHED_1976[z]
        ):
            err = published[name][i] / ref - 1.0
            worst = max(worst, abs(err))
            if abs(err) > 2e-3:
                print(f"FAIL {name} at {z} km: {published[name][i]:.5g} vs printed {ref:.5g} ({100 * err:+.3f} %)")
                return 1
    print(f"printed 1976 values: worst relative difference {100 * worst:.3f} %")

    # Check 2: the kernel's interpolation (log-linear in rho and p, linear in T) at mid-interval points.
    for name, use_log, limit in (
        ("density_kg_m3", True, 1.5e-3),
        ("pressure_Pa", True, 1.5e-3),
        ("temperature_K", False, 2.5e-3),
    ):
        lo, hi = table[name][:-1], table[name][1:]
        est = np.sqrt(lo * hi) if use_log else 0.5 * (lo + hi)
        interp_err = float(np.max(np.abs(est / mid[name] - 1.0)))
        print(f"interpolation of {name} at mid-interval points: worst relative error {100 * interp_err:.3f} %")
        if interp_err > limit:
            return 1

    header = [
        "# U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), 86 to 1000 km geometric altitude (high-altitude model).",
        f"# Generated by `{COMMAND}` with the PyPI package ussa1976 {ussa1976.__version__}"
        f" (numpy {np.__version__}, Python {sys.version.split()[0]}),",
        "# with one correction to ussa1976: M = M0 below 100 km (not M(N2)) in the atomic-oxygen diffusion term,",
        "# as in the standard's eq. (36); see the script's docstring. Printed 1976 Tables I-II values (T, p, rho, M at",
        f"# 86-1000 km) are reproduced to {100 * worst:.2f} %. temperature_K is the kinetic temperature.",
        "# Grid: 1 km steps to 150 km, 2 km to 300 km, 5 km to 1000 km; altitude_ft = altitude_km * 1000 / 0.3048.",
    ]
    columns = [
        "altitude_ft",
        "altitude_km",
        "temperature_K",
        "pressure_Pa",
        "density_kg_m3",
        "mean_molar_mass_kg_kmol",
    ]
    lines = header + [",".join(columns)]
    for i, z in enumerate(z_km):
        lines.append(
            f"{z * 1000.0 * FT_PER_M:.4f},{z:.1f},{table['temperature_K'][i]:.6f},{table['pressure_Pa'][i]:.8e},"
            f"{table['density_kg_m3'][i]:.8e},{table['mean_molar_mass_kg_kmol'][i]:.6f}"
        )
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT} ({len(z_km)} rows)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
