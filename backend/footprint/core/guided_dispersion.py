"""Guided dispersions: every Monte Carlo sample flown closed loop by its entry guidance (core.guidance), and the same
samples flown open loop with the nominal guided flight's bank against energy height (open_loop): where each lands
against the target.

What a run says, for each of the two: the miss distance's mean, CEP (its median), 90th and 99th percentiles and
maximum; the probability of landing within R of the target for each R asked, with its Clopper-Pearson interval;
the mean and covariance of the landing about the target in down-range and cross-range (the miss ellipse); the
spreads of peak temperature, heat rate, heat load, load factor and dynamic pressure; how many samples saturated
the bank, were bound by a path limit, or exceeded a limit; the final state's spread; and every sample's end.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footprint.core.constants import G0_FT_S2
from footprint.core.controls import replace_bank_table
from footprint.core.dispersion import Samples, sample_spec
from footprint.core.dynamics import energy_height_ft
from footprint.core.errors import Stopped
from footprint.core.guidance import interface_miss_nmi
from footprint.core.integrate import STOP_REASONS
from footprint.core.limits import tally_columns
from footprint.core.monte_carlo import CONFIDENCE_INTERVAL, Landings, clopper_pearson, ellipse, spread
from footprint.core.sphere import MEAN_RADIUS_NMI, downrange_crossrange_nmi, latlon_from_ranges
from footprint.core.trajectory import FlightSpec, Trajectory, simulate, simulate_summary

KEPT = (  # what a sample keeps of each flight: its columns in Landings.values
    "final_latitude_deg",
    "final_longitude_deg",
    "downrange_nmi",
    "flight_time_s",
    "max_temperature_R",
    "max_heat_rate_btu_ft2_s",
    "heat_load_btu_ft2",
    "max_load_factor",
    "max_dynamic_pressure_psf",
    "final_energy_ft",
    "final_altitude_ft",
    "final_velocity_fps",
)
GUIDED_KEPT = ("saturated_cycles", "limit_bound_cycles", "unconverged_cycles", "reversals")  # NaN open loop
COLUMNS = KEPT + GUIDED_KEPT
LAT, LON, OWN_DOWN = 0, 1, 2
MODES = ("guided", "open_loop")
SPREADS = ("max_temperature_R", "max_heat_rate_btu_ft2_s", "heat_load_btu_ft2", "max_load_factor",
           "max_dynamic_pressure_psf")  # fmt: skip
FINAL = ("final_energy_ft", "final_altitude_ft", "final_velocity_fps", "flight_time_s")
LIMITS = {  # a guidance limit -> the summary's peak it bounds
    "max_heat_rate_btu_ft2_s": "max_heat_rate_btu_ft2_s",
    "max_temperature_R": "max_temperature_R",
    "max_load_factor": "max_load_factor",
    "max_dynamic_pressure_psf": "max_dynamic_pressure_psf",
}


def open_loop(spec: FlightSpec, nominal: Trajectory) -> FlightSpec:
    """The guided spec flown open loop: the nominal guided flight's bank against energy height h + V^2/(2 g0), to
    the terminal energy. Against energy, not time: in a dispersed world time slides and a time table flies the
    nominal's bank at the wrong point of the entry (issue 50 item 5: CEP 773 against time, 293 against energy)."""
    assert spec.guidance is not None and nominal.bank_table is not None
    energy_ft, bank_deg = bank_against_energy(nominal)
    return replace(
        spec,
        guidance=None,
        ctrl=replace_bank_table(spec.ctrl, bank_deg, energy_ft, "energy"),
        stop=replace(spec.stop, energy_ft=spec.guidance.terminal_energy_ft),
    )


def bank_against_energy(nominal: Trajectory) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The nominal's bank nodes against the energy height it had then, ascending for the table: energy falls in
    flight but for a climb or the thin air's rounding, so each node takes the lowest energy reached by its time
    and only the nodes where that falls strictly are kept (the first of a flat run)."""
    table, h = nominal.bank_table, nominal.history
    assert table is not None
    # the table's abscissa, the integrator's own function over every row (numba compiles it for arrays too)
    energy = energy_height_ft(h["altitude_ft"], h["velocity_fps"], G0_FT_S2)  # type: ignore[arg-type]
    at_nodes = np.minimum.accumulate(np.interp(table["time_s"], h["time_s"], energy))
    keep = np.concatenate(([True], np.diff(at_nodes) < 0.0))
    return at_nodes[keep][::-1], table["bank_deg"][keep][::-1]


def _row(summary: dict[str, Any]) -> list[float]:
    guided = summary.get("guidance") or {}
    values = [summary[k] for k in KEPT] + [guided.get(k) for k in GUIDED_KEPT]
    return [np.nan if v is None else float(v) for v in values]


def fly_samples(
    spec: FlightSpec,
    open_spec: FlightSpec | None,
    samples: Samples,
    first: int = 0,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> Landings:
    """Every sample flown guided and (with open_spec) open loop: values (n, modes, COLUMNS). A chunk of a run."""
    modes = [spec] if open_spec is None else [spec, open_spec]
    values = np.full((len(samples), len(modes), len(COLUMNS)), np.nan)
    stops = np.zeros((len(samples), len(modes)), np.int8)
    for i in range(len(samples)):
        if on_progress is not None and on_progress(i / len(samples), f"sample {first + i + 1:,}"):
            raise Stopped(f"stopped at sample {first + i + 1:,}")
        for j, base in enumerate(modes):
            summary = simulate_summary(sample_spec(base, samples, i))
            stops[i, j] = STOP_REASONS.index(summary["stop_reason"])
            values[i, j] = _row(summary)
    return Landings(first, values, stops)


def nominal_flight(spec: FlightSpec) -> Trajectory:
    """The undispersed guided flight (its histories: the open loop's bank table)."""
    return simulate(spec)


@dataclass
class GuidedDispersion:
    """A guided run's statistics (module docstring): per mode (guided, open_loop), and the nominal flight."""

    samples: int
    target: dict[str, float]  # latitude_deg, longitude_deg, downrange_nmi, crossrange_nmi about the entry
    radii_nmi: tuple[float, ...]
    nominal: dict[str, Any]  # the undispersed guided flight's landing and guidance summary
    modes: dict[str, dict[str, Any]]  # guided / open_loop -> statistics
    clouds: dict[str, dict[str, NDArray[np.float64]]]  # mode -> latitude/longitude/downrange/crossrange per sample
    entry: dict[str, float]

    def to_dict(self, cloud_points: int | None = None) -> dict[str, Any]:
        keep = slice(None) if cloud_points is None else slice(0, cloud_points)
        return {
            "samples": self.samples,
            "target": self.target,
            "radii_nmi": list(self.radii_nmi),
            "entry": self.entry,
            "nominal": self.nominal,
            **self.modes,
            "clouds": {
                mode: {k: [None if not np.isfinite(x) else float(x) for x in v[keep]] for k, v in cloud.items()}
                for mode, cloud in self.clouds.items()
            },
        }


def statistics(
    spec: FlightSpec,
    landings: Landings,
    nominal: Trajectory,
    radii_nmi: Iterable[float] = (1.0, 5.0, 10.0),
    level: float = CONFIDENCE_INTERVAL,
) -> GuidedDispersion:
    """What the run says (module docstring)."""
    g = spec.guidance
    assert g is not None
    e = spec.entry
    radii = tuple(float(r) for r in radii_nmi)
    t_down, t_cross = downrange_crossrange_nmi(
        np.array(g.target_latitude_deg), np.array(g.target_longitude_deg), e.latitude_deg, e.longitude_deg,
        e.heading_deg,
    )  # fmt: skip
    target = {
        "latitude_deg": g.target_latitude_deg,
        "longitude_deg": g.target_longitude_deg,
        "downrange_nmi": float(t_down),
        "crossrange_nmi": float(t_cross),
        "interface_range_nmi": g.interface_range_nmi,  # the misses are of the circle of this radius about the target
    }
    ns = nominal.summary
    nominal_info = {
        "latitude_deg": ns["final_latitude_deg"],
        "longitude_deg": ns["final_longitude_deg"],
        "downrange_nmi": ns["downrange_nmi"],
        "crossrange_nmi": ns["crossrange_nmi"],
        "stop_reason": ns["stop_reason"],
        "max_temperature_R": ns["max_temperature_R"],
        "guidance": ns["guidance"],
    }
    modes, clouds = {}, {}
    for j in range(landings.values.shape[1]):
        name = MODES[j]
        modes[name], clouds[name] = _mode(spec, landings.values[:, j], landings.stops[:, j], radii, level)
    return GuidedDispersion(
        samples=int(landings.values.shape[0]),
        target=target,
        radii_nmi=radii,
        nominal=nominal_info,
        modes=modes,
        clouds=clouds,
        entry={"latitude_deg": e.latitude_deg, "longitude_deg": e.longitude_deg, "heading_deg": e.heading_deg},
    )


def _mode(
    spec: FlightSpec,
    values: NDArray[np.float64],
    stops: NDArray[np.int8],
    radii: tuple[float, ...],
    level: float,
) -> tuple[dict[str, Any], dict[str, NDArray[np.float64]]]:
    """One mode's statistics and cloud (values: samples x COLUMNS)."""
    g = spec.guidance
    assert g is not None
    e = spec.entry
    n = values.shape[0]
    landed = (stops == STOP_REASONS.index("energy")) & np.isfinite(values[:, LAT])
    lat, lon = np.where(landed, values[:, LAT], np.nan), np.where(landed, values[:, LON], np.nan)
    miss = np.where(landed, interface_miss_nmi(np.nan_to_num(lat), np.nan_to_num(lon), g), np.inf)
    down, cross = downrange_crossrange_nmi(lat, lon, e.latitude_deg, e.longitude_deg, e.heading_deg)
    turn = 2.0 * np.pi * MEAN_RADIUS_NMI
    down = down + turn * np.round((values[:, OWN_DOWN] - down) / turn)  # past half a circumference
    out: dict[str, Any] = {
        "landed": int(landed.sum()),
        "outcomes": {STOP_REASONS[c]: int(np.sum(stops == c)) for c in np.unique(stops)},
        "miss_nmi": _miss_spread(miss[landed]),
        "within": [],
    }
    for r in radii:
        k = int(np.sum(miss <= r))  # a flight that did not land is not within any radius
        low, high = clopper_pearson(k, n, level)
        out["within"].append(
            {"radius_nmi": r, "samples_within": k, "probability": k / n, "interval": [low, high], "level": level}
        )
    if int(landed.sum()) >= 2:
        xy = np.stack([down[landed], cross[landed]])
        mean, cov = xy.mean(axis=1), np.cov(xy)
        ex, ey = ellipse(mean, cov, 3.0)
        elat, elon = latlon_from_ranges(ex, ey, e.latitude_deg, e.longitude_deg, e.heading_deg)
        out["landing"] = {
            "mean_downrange_nmi": float(mean[0]),
            "mean_crossrange_nmi": float(mean[1]),
            "covariance_nmi2": cov.tolist(),
            "ellipse_3sigma": {"latitude_deg": elat.tolist(), "longitude_deg": elon.tolist()},
        }
    col = {name: i for i, name in enumerate(COLUMNS)}
    out["spreads"] = {k: s for k in SPREADS if (s := spread(values[landed, col[k]])) is not None}
    out["final"] = {k: s for k in FINAL if (s := spread(values[landed, col[k]])) is not None}
    out["saturated_samples"] = int(np.sum(values[:, col["saturated_cycles"]] > 0))
    out["limit_bound_samples"] = int(np.sum(values[:, col["limit_bound_cycles"]] > 0))
    out["unconverged_samples"] = int(np.sum(values[:, col["unconverged_cycles"]] > 0))
    out["limits"] = tally_columns(values, COLUMNS, spec.vehicle.limits)  # the vehicle's, every sample flown
    out["violations"] = {
        name: int(np.sum(values[:, col[peak]] > limit))
        for name, peak in LIMITS.items()
        if (limit := getattr(g, name)) is not None
    }
    cloud = {
        "latitude_deg": lat,
        "longitude_deg": lon,
        "downrange_nmi": down,
        "crossrange_nmi": cross,
        "miss_nmi": miss,
    }
    return out, cloud


def _miss_spread(miss: NDArray[np.float64]) -> dict[str, float] | None:
    if not miss.size:
        return None
    return {
        "mean": float(miss.mean()),
        "cep": float(np.median(miss)),  # circular error probable: half the landings fall within it
        "p90": float(np.percentile(miss, 90)),
        "p99": float(np.percentile(miss, 99)),
        "max": float(miss.max()),
    }
