"""The guided reach of landing sites: each site made the target of a guided case (core.guidance) and flown in the
dispersed samples; the probability that the guided vehicle ends within R of its terminal-area interface circle, with
its Clopper-Pearson interval (Clopper & Pearson, Biometrika 26, 1934), the CEP of its misses and the undispersed
flight's miss and interface state."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from footprint.core.dispersion import Samples, sample_spec
from footprint.core.errors import Stopped
from footprint.core.limits import tally
from footprint.core.monte_carlo import CONFIDENCE_INTERVAL, clopper_pearson
from footprint.core.trajectory import FlightSpec, simulate_summary


def aimed_at(spec: FlightSpec, latitude_deg: float, longitude_deg: float) -> FlightSpec:
    """The guided spec with its target at (latitude, longitude)."""
    assert spec.guidance is not None
    guidance = replace(spec.guidance, target_latitude_deg=latitude_deg, target_longitude_deg=longitude_deg)
    return replace(spec, guidance=guidance)


def landed_miss_nmi(summary: dict[str, Any]) -> float:
    """A guided flight's miss of its terminal-area interface circle about the target (nmi: core.guidance's
    interface_miss_nmi); infinite when it did not end at its terminal energy (it skipped out, ran out of time or hit
    the ground first)."""
    return float(summary["guidance"]["miss_nmi"]) if summary["stop_reason"] == "energy" else math.inf


def site_reach(
    spec: FlightSpec,
    name: str,
    latitude_deg: float,
    longitude_deg: float,
    samples: Samples,
    radius_nmi: float,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> dict[str, Any]:
    """One site: its P(within R) over the samples with the interval, the landings' CEP and the nominal flight."""
    aimed = aimed_at(spec, latitude_deg, longitude_deg)
    nominal = simulate_summary(aimed)
    misses = np.empty(len(samples))
    broken: list[list[str]] = []
    for i in range(len(samples)):
        if on_progress is not None and on_progress(i / len(samples), f"{name}: sample {i + 1:,}"):
            raise Stopped(f"stopped at {name}, sample {i + 1:,}")
        summary = simulate_summary(sample_spec(aimed, samples, i))
        misses[i] = landed_miss_nmi(summary)
        broken.append(summary["limits_broken"])
    n, k = len(samples), int(np.count_nonzero(misses <= radius_nmi))
    low, high = clopper_pearson(k, n)
    landed = misses[np.isfinite(misses)]
    return {
        "name": name,
        "latitude_deg": latitude_deg,
        "longitude_deg": longitude_deg,
        "samples_within": k,
        "samples": n,
        "probability": k / n,
        "interval": [low, high],
        "level": CONFIDENCE_INTERVAL,
        "cep_nmi": float(np.median(landed)) if landed.size else None,
        "landed": int(landed.size),
        "nominal_miss_nmi": float(nominal["guidance"]["miss_nmi"]),  # of the terminal-area interface circle
        "nominal_status": nominal["guidance"]["status"],
        "nominal_interface": nominal["guidance"]["interface"],  # where and how the undispersed flight hands over
        "nominal_touchdown_estimate": nominal["guidance"]["touchdown_estimate"],
        "nominal_limits_broken": nominal["limits_broken"],
        "limits": tally(broken),  # the samples' flights that broke a vehicle limit
    }
