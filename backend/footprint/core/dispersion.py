"""Monte Carlo dispersions: N sample inputs drawn in one call, and the flight spec of each sample.

`draw(distributions, n, seed, method, density)` turns n points of the unit cube (scrambled Sobol', Latin hypercube
or plain pseudo-random, seeded) into sample inputs through the inverse distribution function of each dispersed
input; it is deterministic, to the bit, for the same arguments. Chunks of a run are slices of its Samples
(`samples[i:j]`), so a sample's inputs do not depend on how the run is cut up; the draws do depend on n, the
method and which inputs are dispersed (each takes a column of the cube, in INPUTS order, the density nodes last).
With Sobol' and plain random points the first n samples of a larger run are the samples of a run of n; a Latin
hypercube stratifies its n points together, so it has no such prefix property. Sobol' points keep their balance
for n a power of two.

Inputs: the entry state (altitude, earth-relative or inertial speed as the base entry says, flight-path angle,
heading, latitude, longitude), the CL and CD multipliers on the aero tables and the wing loading, each from a named
distribution in its own unit (the distribution gives the value, not an offset from the nominal); an input left out
keeps the base spec's value. The density profile delta(h) at atmosphere.DENSITY_NODES_FT is a first-order
Gauss-Markov process in altitude (GaussMarkovDensity), flown as density times 1 + delta(h) (trajectory.Dispersion).

Plain numpy and scipy inputs; no contract types. The service's parallel layer flies chunks with `summaries`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats
from scipy.stats import qmc

from footprint.core.atmosphere import DENSITY_NODE_COUNT, DENSITY_NODE_SPACING_FT
from footprint.core.errors import InputError
from footprint.core.trajectory import Dispersion, FlightSpec, simulate_summary

ENTRY_INPUTS = ("altitude_ft", "velocity_fps", "gamma_deg", "heading_deg", "latitude_deg", "longitude_deg")
VEHICLE_INPUTS = ("cl_multiplier", "cd_multiplier", "wing_loading_psf")
INPUTS = ENTRY_INPUTS + VEHICLE_INPUTS
METHODS = ("sobol", "lhs", "random")
CORRELATION_LENGTH_DEFAULT_FT = 30_000.0  # vertical correlation length of the density profile, ft (a round value)
DENSITY_STD_MAX = 0.2  # largest standard deviation of delta accepted (20 % of the density)
DELTA_FLOOR = -0.9  # delta is held at or above this (the density at least a tenth of the model's): >= 4.5 std away
# Values a sample may not take (the flight would mean nothing): the lower bound of each input, exclusive.
POSITIVE_INPUTS = ("altitude_ft", "velocity_fps", "cl_multiplier", "cd_multiplier", "wing_loading_psf")
# The unit-cube points are kept inside (0, 1) so that the inverse distribution functions stay finite.
UNIT_MARGIN = 2.0**-53


# ------------------------------------------------------------------------------------------- distributions
@dataclass(frozen=True)
class Normal:
    mean: float
    std: float

    def problem(self) -> str | None:
        return (
            None
            if self.std > 0.0 and math.isfinite(self.mean)
            else f"mean {self.mean!r}, std {self.std!r}: need a finite mean and std > 0"
        )

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        x: NDArray[np.float64] = stats.norm.ppf(u, loc=self.mean, scale=self.std)
        return x


@dataclass(frozen=True)
class Uniform:
    low: float
    high: float

    def problem(self) -> str | None:
        return (
            None
            if math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high
            else f"low {self.low!r}, high {self.high!r}: need finite low < high"
        )

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.low + (self.high - self.low) * u


@dataclass(frozen=True)
class TruncatedNormal:
    """A normal of this mean and std cut to [low, high] (the std is the untruncated one)."""

    mean: float
    std: float
    low: float
    high: float

    def problem(self) -> str | None:
        if not (self.std > 0.0 and math.isfinite(self.mean) and self.low < self.high):
            return (
                f"mean {self.mean!r}, std {self.std!r}, low {self.low!r}, high {self.high!r}: need a finite "
                "mean, std > 0 and low < high"
            )
        return None

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
        x: NDArray[np.float64] = stats.truncnorm.ppf(u, a, b, loc=self.mean, scale=self.std)
        return x


Distribution = Normal | Uniform | TruncatedNormal


@dataclass(frozen=True)
class GaussMarkovDensity:
    """delta(h) at the density nodes: a stationary first-order Gauss-Markov process in altitude, zero mean,
    standard deviation `std` (a fraction of the density; one value, or one per node), correlation between nodes
    Delta h apart exp(-Delta h / L). Node k+1 from node k: x' = phi x + sqrt(1 - phi^2) z, phi = exp(-Delta h / L),
    z standard normal, delta = std x; held at DELTA_FLOOR or above."""

    # After the small-scale perturbation model of NASA's GRAM (Justus et al., GRAM-95, NASA TM-4715, 1995).
    std: float | tuple[float, ...] | NDArray[np.float64]
    correlation_length_ft: float = CORRELATION_LENGTH_DEFAULT_FT

    def problem(self) -> str | None:
        std = np.asarray(self.std, dtype=float)
        if std.shape not in ((), (DENSITY_NODE_COUNT,)):
            return f"std has shape {std.shape}: give one value or {DENSITY_NODE_COUNT}, one per node"
        if not np.all((std >= 0.0) & (std <= DENSITY_STD_MAX)):
            return f"std {self.std!r}: every value must lie in 0 to {DENSITY_STD_MAX}"
        if not (self.correlation_length_ft > 0.0 and math.isfinite(self.correlation_length_ft)):
            return f"correlation_length_ft {self.correlation_length_ft!r} must be a finite number > 0 ft"
        return None

    def profiles(self, z: NDArray[np.float64]) -> NDArray[np.float64]:
        """delta (n, DENSITY_NODE_COUNT) from standard normals z of the same shape."""
        phi = math.exp(-DENSITY_NODE_SPACING_FT / self.correlation_length_ft)
        x = np.empty_like(z)
        x[:, 0] = z[:, 0]  # the stationary distribution at the first node
        for k in range(1, z.shape[1]):
            x[:, k] = phi * x[:, k - 1] + math.sqrt(1.0 - phi * phi) * z[:, k]
        return np.maximum(np.asarray(self.std, dtype=float) * x, DELTA_FLOOR)


# ------------------------------------------------------------------------------------------------- samples
@dataclass(frozen=True)
class Samples:
    """n sample inputs: an array of n per dispersed input (INPUTS names), and the density profiles (n, nodes) or
    None. `samples[i:j]` is a chunk."""

    n: int
    values: dict[str, NDArray[np.float64]]
    density_delta: NDArray[np.float64] | None

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, rows: slice) -> Samples:
        if not isinstance(rows, slice):
            raise TypeError("index Samples with a slice (a chunk); sample_spec takes one sample")
        return Samples(
            len(range(self.n)[rows]),
            {k: v[rows] for k, v in self.values.items()},
            None if self.density_delta is None else self.density_delta[rows],
        )


def unit_points(n: int, dimensions: int, seed: int, method: str = "sobol") -> NDArray[np.float64]:
    """n points (n, dimensions) of the open unit cube: scrambled Sobol', Latin hypercube or pseudo-random."""
    rng = np.random.default_rng(seed)
    if method == "sobol":
        with warnings.catch_warnings():  # scipy warns when n is not a power of two (see the module docstring)
            warnings.simplefilter("ignore", UserWarning)
            u: NDArray[np.float64] = qmc.Sobol(dimensions, scramble=True, seed=rng).random(n)
    elif method == "lhs":
        u = qmc.LatinHypercube(dimensions, seed=rng).random(n)
    else:
        u = rng.random((n, dimensions))
    return np.clip(u, UNIT_MARGIN, 1.0 - UNIT_MARGIN)


def draw(
    distributions: dict[str, Distribution],
    n: int,
    seed: int,
    method: str = "sobol",
    density: GaussMarkovDensity | None = None,
) -> Samples:
    """n sample inputs (module docstring): `distributions` maps INPUTS names to Normal, Uniform or TruncatedNormal;
    `density` draws the density profiles. Deterministic for the same arguments."""
    _check(distributions, n, method, density)
    names = [name for name in INPUTS if name in distributions]
    dimensions = len(names) + (DENSITY_NODE_COUNT if density is not None else 0)
    if dimensions == 0:
        return Samples(int(n), {}, None)
    u = unit_points(int(n), dimensions, seed, method)
    values = {name: np.asarray(distributions[name].ppf(u[:, j]), dtype=float) for j, name in enumerate(names)}
    for name in POSITIVE_INPUTS:
        if name in values and not np.all(values[name] > 0.0):
            raise InputError(
                f"distributions.{name}",
                f"{distributions[name]!r} draws {np.min(values[name]):g}; "
                "every value must be > 0 (a TruncatedNormal keeps it so)",
            )
    delta = None if density is None else density.profiles(stats.norm.ppf(u[:, len(names) :]))
    return Samples(int(n), values, delta)


def _check(distributions: dict[str, Distribution], n: int, method: str, density: GaussMarkovDensity | None) -> None:
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError("n", f"{n!r} must be a whole number >= 1")
    if method not in METHODS:
        raise InputError("method", f"{method!r} must be one of {', '.join(METHODS)}")
    for name, dist in distributions.items():
        if name not in INPUTS:
            raise InputError(f"distributions.{name}", f"not a dispersed input; allowed: {', '.join(INPUTS)}")
        if not isinstance(dist, (Normal, Uniform, TruncatedNormal)):
            raise InputError(f"distributions.{name}", f"{dist!r} must be a Normal, Uniform or TruncatedNormal")
        if (problem := dist.problem()) is not None:
            raise InputError(f"distributions.{name}", problem)
    if density is not None and (problem := density.problem()) is not None:
        raise InputError("density", problem)


def sample_spec(base: FlightSpec, samples: Samples, i: int) -> FlightSpec:
    """The flight spec of sample i: the base spec with the sample's dispersed inputs."""
    v = {name: float(values[i]) for name, values in samples.values.items()}
    entry = {name: v[name] for name in ENTRY_INPUTS if name in v}
    spec = replace(base, entry=replace(base.entry, **entry)) if entry else base  # type: ignore[arg-type]
    if "wing_loading_psf" in v:
        spec = replace(spec, vehicle=replace(spec.vehicle, wing_loading_psf=v["wing_loading_psf"]))
    d = base.dispersion
    dispersion = Dispersion(
        cl_multiplier=v.get("cl_multiplier", d.cl_multiplier),
        cd_multiplier=v.get("cd_multiplier", d.cd_multiplier),
        density_delta=d.density_delta if samples.density_delta is None else samples.density_delta[i],
    )
    return replace(spec, dispersion=dispersion)


def summaries(base: FlightSpec, samples: Samples) -> list[dict[str, Any]]:
    """The summary (trajectory.simulate_summary) of every sample, in order: one chunk of a Monte Carlo run."""
    return [simulate_summary(sample_spec(base, samples, i)) for i in range(len(samples))]
