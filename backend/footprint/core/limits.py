"""A vehicle's flight limits (issue 50): the load factor, dynamic pressure, stagnation heat rate and
radiation-equilibrium temperature it may see, what a flight's summary says of each (its peak, the limit, the
margin, whether it held) and the count of broken limits over many flights (footprints, dispersions, reach,
opportunities). A limit is reported, never enforced here: the flight is flown as its controls say.

The peaks are the summary's own (trajectory._summary: max_load_factor, max_dynamic_pressure_psf,
max_heat_rate_btu_ft2_s, max_temperature_R); heat rate and temperature exist only with a heating model, and a
limit without its peak is listed as unchecked, not as held.
"""

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray


class Limit(NamedTuple):
    name: str  # the limit's name in lists: quantity_unit
    quantity: str
    unit: str
    peak_key: str  # the summary's peak of the quantity


LIMITS = (
    Limit("load_factor_g", "load_factor", "g", "max_load_factor"),
    Limit("dynamic_pressure_psf", "dynamic_pressure", "psf", "max_dynamic_pressure_psf"),
    Limit("heat_rate_btu_ft2_s", "heat_rate", "btu_ft2_s", "max_heat_rate_btu_ft2_s"),
    Limit("temperature_R", "temperature", "R", "max_temperature_R"),
)
LIMIT_NAMES = tuple(lim.name for lim in LIMITS)


@dataclass(frozen=True)
class Limits:
    """A vehicle's limits (None: no limit). The defaults are a crewed, reusable glider's, the Shuttle orbiter's."""

    # Shuttle orbiter entry: 2.5 g structural and crew limit (Harpold & Graves, Shuttle Entry Guidance, J. Astronaut.
    # Sci. 27(3), 1979); here on the total aerodynamic load sqrt(L^2 + D^2)/W, the orbiter's on the normal load
    load_factor_g: float | None = 2.5
    # chosen design value: 375 psf, the orbiter's entry q-bar limit as commonly quoted (secondary sources; no primary
    # document at hand), within the 350-400 psf band of crewed lifting entry
    dynamic_pressure_psf: float | None = 375.0
    # Betts, Practical Methods for Optimal Control, 2nd ed. (SIAM 2010), sec. 6.1, Shuttle reentry: q <= 70 Btu/ft^2/s
    heat_rate_btu_ft2_s: float | None = 70.0
    # chosen design value: 3,460 R (3,000 F), the reuse limit commonly given for the orbiter's RCC nose cap and wing
    # leading edges (about 1,650 C)
    temperature_R: float | None = 3460.0

    def value(self, name: str) -> float | None:
        return getattr(self, name)  # type: ignore[no-any-return]


NO_LIMITS = Limits(None, None, None, None)


def broken_mask(peaks: Mapping[str, ArrayLike | None], limits: Limits) -> dict[str, NDArray[np.bool_]]:
    """Per limit name, where its peak (the summary's key; NaN or None: not evaluated) exceeds the limit."""
    out: dict[str, NDArray[np.bool_]] = {}
    for lim in LIMITS:
        bound, peak = limits.value(lim.name), peaks.get(lim.peak_key)
        if bound is None or peak is None:
            continue
        with np.errstate(invalid="ignore"):
            out[lim.name] = np.asarray(np.asarray(peak, dtype=float) > bound)
    return out


def flight_limits(summary: Mapping[str, Any], limits: Limits) -> dict[str, Any]:
    """What a flight's summary adds of its limits: each limit and margin (limit - peak; negative: broken),
    limits_held, limits_broken and limits_unchecked (a limit whose peak the flight does not evaluate)."""
    out: dict[str, Any] = {}
    broken = {name for name, hit in broken_mask(summary, limits).items() if bool(hit)}
    unchecked = []
    for lim in LIMITS:
        bound, peak = limits.value(lim.name), summary.get(lim.peak_key)
        out[f"{lim.quantity}_limit_{lim.unit}"] = bound
        out[f"{lim.quantity}_margin_{lim.unit}"] = None if bound is None or peak is None else bound - peak
        if bound is not None and peak is None:
            unchecked.append(lim.name)
    names = [name for name in LIMIT_NAMES if name in broken]
    return out | {"limits_held": not names, "limits_broken": names, "limits_unchecked": unchecked}


def tally(broken: Iterable[Sequence[str]]) -> dict[str, Any]:
    """Over flights (each its limits_broken): how many flew, how many broke a limit, and the count per limit."""
    lists = list(broken)
    masks = {name: np.array([name in b for b in lists], bool) for name in LIMIT_NAMES}
    return tally_masks(masks, np.ones(len(lists), bool))


def tally_masks(masks: Mapping[str, NDArray[np.bool_]], flown: NDArray[np.bool_]) -> dict[str, Any]:
    """tally() over arrays: masks (per limit, one entry per flight) counted where `flown`."""
    any_broken = np.zeros(flown.shape, bool)
    for hit in masks.values():
        any_broken |= hit & flown
    by_limit = {name: int(np.sum(masks[name] & flown)) for name in LIMIT_NAMES if name in masks}
    return {
        "flights": int(flown.sum()),
        "broke_a_limit": int(any_broken.sum()),
        "by_limit": {k: v for k, v in by_limit.items() if v},
    }


def tally_columns(values: NDArray[np.float64], columns: Sequence[str], limits: Limits) -> dict[str, Any]:
    """tally() over a run's kept summary values (..., columns): every flight in it counted, NaN peaks unchecked."""
    peaks = {lim.peak_key: values[..., columns.index(lim.peak_key)] for lim in LIMITS if lim.peak_key in columns}
    return tally_masks(broken_mask(peaks, limits), np.ones(values.shape[:-1], bool))
