"""The dispersion study contract: a footprint study flown again in N Monte Carlo samples of its entry state, air
and aerodynamics (footprint.core.dispersion draws them, footprint.core.monte_carlo flies and reads them).

    {"footprint": FOOTPRINT STUDY (method single_parameter, constant_bank or staged),
     "samples": 2000, "design": "sobol" | "lhs" | "random", "seed": 1,
     "entry": {"altitude_ft": {"normal": {"std": 1000}}, "gamma_deg": {"uniform": {"half_width": 0.05}}, ...},
     "vehicle": {"cl_multiplier": {"truncated_normal": {"std": 0.03, "sigmas": 3}}, "wing_loading_psf": ...},
     "density": {"std": 0.05, "correlation_length_ft": 30000},
     "confidence": [0.99], "sites": [{"name", "latitude_deg", "longitude_deg"}, ...],
     "histories": [17, 230]}  (samples whose flights are flown again with their histories: a skip-out's, say)

Every distribution is about its input's nominal value (the footprint study's case; a multiplier's is 1), in the
input's own unit: normal {std, bias}, uniform {half_width, bias} (nominal + bias +- half_width), truncated normal
{std, sigmas, bias} (cut at +- sigmas std). The density factor 1 + delta(h) is a first-order Gauss-Markov process in
altitude (core.dispersion.GaussMarkovDensity): a correlated profile, not one factor for the whole atmosphere, since
the density errors of an atmosphere model change sign between layers; `std` one value or one per 10,000 ft node.
"""

from __future__ import annotations

import csv
import functools
import io
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import AfterValidator, Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.doors import door_limit, synchronous, validated
from footprint.contracts.fields import Range, Strict, by_shape, shape_tag
from footprint.contracts.footprint import METHOD_WORDS, FootprintStudy
from footprint.contracts.reach import Site
from footprint.contracts.records import FLIGHT_KEYS, csv_cell, flown, plain
from footprint.contracts.work import OnProgress, PerStudy, RunInfo, Stored, Work
from footprint.core import dispersion as disp
from footprint.core import monte_carlo as mc
from footprint.core.atmosphere import DENSITY_NODE_COUNT
from footprint.core.errors import InputError

if TYPE_CHECKING:
    from footprint.core.trajectory import FlightSpec

MAX_SAMPLES = 1_000_000  # from the CLI or Python
MAX_SAMPLES_HTTP = 100_000
MAX_FLIGHTS = 20_000_000  # samples x the flights of one sample (~4 h on one core)
MAX_FLIGHTS_HTTP = 2_000_000  # ~12 min on the two workers of a small server
CHUNK_FLIGHTS = 1_000  # a task flies about this many trajectories (~1 s): progress, balance (10-15 % faster than 2,000)
MAX_HISTORY_SAMPLES = 8  # samples whose flights are kept with their histories (each flight ~4,000 values)
HISTORY_POINTS = 200  # a kept flight's histories, decimated
CLOUD_SAMPLES_STORED = 1_000  # the landing points a job's stored result keeps of each flight (the map's clouds)
LAWS = ("single_parameter", "constant_bank", "staged")  # footprint_methods.FAMILIES: fixed control laws


def _positive(v: float) -> float:
    if not v > 0.0:
        raise ValueError(f"{v:g} must be > 0 (a spread)")
    return v


Spread = Annotated[float, AfterValidator(_positive)]


class NormalSpread(Strict):
    std: Spread
    bias: float = 0.0


class UniformSpread(Strict):
    half_width: Spread
    bias: float = 0.0


class TruncatedNormalSpread(Strict):
    std: Spread
    sigmas: Annotated[float, Range(0.1, 10)] = 3.0
    bias: float = 0.0


class Distribution(Strict):
    """One of normal, uniform, truncated_normal, about the nominal value, in the input's unit."""

    normal: NormalSpread | None = None
    uniform: UniformSpread | None = None
    truncated_normal: TruncatedNormalSpread | None = None

    @model_validator(mode="after")
    def _one(self) -> Distribution:
        given = [k for k in ("normal", "uniform", "truncated_normal") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                f"give exactly one of normal, uniform, truncated_normal (got {', '.join(given) or 'none'})"
            )
        return self

    def about(self, nominal: float) -> disp.Distribution:
        """The core's distribution of the input's value."""
        if self.normal is not None:
            return disp.Normal(nominal + self.normal.bias, self.normal.std)
        if self.uniform is not None:
            mid = nominal + self.uniform.bias
            return disp.Uniform(mid - self.uniform.half_width, mid + self.uniform.half_width)
        t = self.truncated_normal
        assert t is not None  # _one: exactly one of the three is given
        mid = nominal + t.bias
        return disp.TruncatedNormal(mid, t.std, mid - t.sigmas * t.std, mid + t.sigmas * t.std)


class EntryDispersion(Strict):
    altitude_ft: Distribution | None = None
    velocity_fps: Distribution | None = None
    gamma_deg: Distribution | None = None
    heading_deg: Distribution | None = None
    latitude_deg: Distribution | None = None
    longitude_deg: Distribution | None = None


class VehicleDispersion(Strict):
    cl_multiplier: Distribution | None = None  # nominal 1: the aero table's C_L
    cd_multiplier: Distribution | None = None
    wing_loading_psf: Distribution | None = None


class DensityDispersion(Strict):
    std: Annotated[  # a fraction of the density: one, or one per node
        Annotated[Annotated[float, Range(0, disp.DENSITY_STD_MAX)], shape_tag("number")]
        | Annotated[list[Annotated[float, Range(0, disp.DENSITY_STD_MAX)]], shape_tag("array")],
        by_shape("number", "array"),
    ]
    correlation_length_ft: Annotated[float, Range(1_000, 1_000_000, "ft")] = disp.CORRELATION_LENGTH_DEFAULT_FT

    @model_validator(mode="after")
    def _nodes(self) -> DensityDispersion:
        if isinstance(self.std, list) and len(self.std) != DENSITY_NODE_COUNT:
            raise ValueError(
                f"std: {len(self.std)} values; give one, or {DENSITY_NODE_COUNT} (0 to 400,000 ft every 10,000 ft)"
            )
        return self


class DispersedInputs(Strict):
    """What every dispersed study draws: how many samples, how, and the spreads of the entry, vehicle and air."""

    samples: int = Field(default=1_000, ge=1, le=MAX_SAMPLES)
    design: Literal["sobol", "lhs", "random"] = "sobol"
    seed: int = Field(default=1, ge=0, le=2**63 - 1)
    entry: EntryDispersion = EntryDispersion()
    vehicle: VehicleDispersion = VehicleDispersion()
    density: DensityDispersion | None = None
    chunk_samples: int | None = Field(default=None, ge=1, le=100_000)  # samples a task flies

    def distributions(self, spec: FlightSpec) -> dict[str, disp.Distribution]:
        """The core's distributions of the dispersed inputs, about the nominal spec's values."""
        nominal = {
            "altitude_ft": spec.entry.altitude_ft,
            "velocity_fps": spec.entry.velocity_fps,
            "gamma_deg": spec.entry.gamma_deg,
            "heading_deg": spec.entry.heading_deg,
            "latitude_deg": spec.entry.latitude_deg,
            "longitude_deg": spec.entry.longitude_deg,
            "cl_multiplier": 1.0,
            "cd_multiplier": 1.0,
            "wing_loading_psf": spec.vehicle.wing_loading_psf,
        }
        given = self.entry.model_dump(exclude_none=True) | self.vehicle.model_dump(exclude_none=True)
        groups = {**{k: self.entry for k in disp.ENTRY_INPUTS}, **{k: self.vehicle for k in disp.VEHICLE_INPUTS}}
        return {name: getattr(groups[name], name).about(nominal[name]) for name in given}

    def draw(self, spec: FlightSpec) -> disp.Samples:
        """The samples (the same bits wherever they are drawn); a core error names the study's field."""
        density = (
            None
            if self.density is None
            else disp.GaussMarkovDensity(
                tuple(self.density.std) if isinstance(self.density.std, list) else self.density.std,
                self.density.correlation_length_ft,
            )
        )
        try:
            return disp.draw(self.distributions(spec), self.samples, self.seed, self.design, density)
        except InputError as exc:  # the core names its own inputs: say the study's field
            name = exc.field.removeprefix("distributions.")
            raise InputError(
                f"{GROUP.get(name, 'density')}.{name}" if name in GROUP else exc.field, exc.message
            ) from None


class DispersionStudy(DispersedInputs):
    description: str | None = Field(default=None, max_length=4_000)
    footprint: FootprintStudy
    confidence: list[Annotated[float, Range(0.01, 0.999)]] = Field(default=[0.99], min_length=1, max_length=5)
    sites: list[Site] = Field(default=[], max_length=1_000)
    histories: list[int] = Field(default=[], max_length=MAX_HISTORY_SAMPLES)  # samples flown again in full

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> DispersionStudy:
        if synchronous(info):
            raise ValueError("a dispersion is run as a job; submit it with POST /api/jobs")
        fp = self.footprint
        if fp.method not in LAWS:
            raise ValueError(
                f"footprint.method: a dispersion flies fixed control laws ({', '.join(LAWS)}); "
                f"{fp.method!r} chooses each point's controls for the world it flies in"
            )
        if fp.contours_fps:
            raise ValueError("footprint.contours_fps: not available in a dispersion")
        samples, where = door_limit(info, MAX_SAMPLES, MAX_SAMPLES_HTTP)
        if self.samples > samples:
            raise ValueError(f"samples: {self.samples:,} is outside the allowed range 1 to {samples:,.0f}{where}")
        for i, index in enumerate(self.histories):
            if not 0 <= index < self.samples:
                raise ValueError(
                    f"histories.{i}: sample {index} is outside the allowed range 0 to "
                    f"{self.samples - 1:,} (the samples, counted from 0)"
                )
        flights, where = door_limit(info, MAX_FLIGHTS, MAX_FLIGHTS_HTTP)
        if self.samples * self.flights_per_sample() > flights:
            raise ValueError(
                f"samples: {self.samples:,} samples x {self.flights_per_sample()} flights = "
                f"{self.samples * self.flights_per_sample():,} trajectories is outside the allowed range "
                f"1 to {flights:,.0f}{where}"
            )
        return self

    def flights_per_sample(self) -> int:
        from footprint.core.footprint_methods import control_family

        return len(mc.flights(*control_family(self.footprint.to_settings())))

    def chunks(self) -> list[tuple[int, int]]:
        """[first, end) sample ranges, one task each."""
        size = self.chunk_samples or max(1, CHUNK_FLIGHTS // self.flights_per_sample())
        return [(a, min(self.samples, a + size)) for a in range(0, self.samples, size)]


REQUEST = DispersionStudy  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)
GROUP = {name: "entry" for name in disp.ENTRY_INPUTS} | {name: "vehicle" for name in disp.VEHICLE_INPUTS}


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> DispersionStudy:
    study: DispersionStudy = validated(ADAPTER, data, DispersionStudy, ctx)
    return study


# --------------------------------------------------------------------------------------------- running
class Plan:
    """What every part of a study needs: the nominal spec, the family's flights and, once a part asks, the samples
    (drawn once per process: the same bits wherever they are drawn)."""

    def __init__(self, study: DispersionStudy) -> None:
        from footprint.core.footprint_methods import control_family

        self.study = study
        self.spec = study.footprint.case.to_spec()
        family, self.mirror = control_family(study.footprint.to_settings())
        self.flights = mc.flights(family, self.mirror)

    @functools.cached_property
    def samples(self) -> disp.Samples:
        return self.study.draw(self.spec)

    def fly(self, first: int, end: int, on_progress: OnProgress | None = None) -> mc.Landings:
        return mc.fly_samples(self.spec, self.flights, self.samples[first:end], first, on_progress)

    def nominal(self) -> mc.Landings:
        return mc.fly_samples(self.spec, self.flights, disp.draw({}, 1, 0))

    def histories(self) -> list[dict[str, Any]]:
        """The flights of the samples the study names, flown again with their histories (decimated)."""
        out: list[dict[str, Any]] = []
        for index in self.study.histories:
            for f, traj in zip(self.flights, mc.sample_trajectories(self.spec, self.flights, self.samples, index)):
                out.append(
                    {
                        "sample": index,
                        "parameter": f.parameter.as_dict(),
                        "side": f.side,
                        **flown(traj, FLIGHT_KEYS, HISTORY_POINTS),
                    }
                )
        return out

    def statistics(self, parts: list[mc.Landings]) -> mc.DispersedFootprint:
        s = self.study
        return mc.statistics(
            self.spec,
            self.flights,
            self.mirror,
            mc.Landings.join(parts),
            self.nominal(),
            levels=tuple(s.confidence),
            sites=[(site.name, site.latitude_deg, site.longitude_deg) for site in s.sites],
        )


def fly_chunk(study: DispersionStudy, chunk: tuple[int, int], on_progress: OnProgress | None = None) -> mc.Landings:
    """A part: samples first..end-1 of the study."""
    first, end = chunk
    return _plan(study).fly(first, end, on_progress)


def combine(
    study: DispersionStudy, parts: list[mc.Landings], info: RunInfo
) -> tuple[mc.DispersedFootprint, dict[str, Any]]:
    """The dispersed footprint and how it ran ({"tasks", "workers", "seconds"}: the flights; the statistics are the
    caller's wait)."""
    return _plan(study).statistics(parts), {"tasks": info.tasks, "workers": info.workers, "seconds": info.seconds}


def store(study: DispersionStudy, answer: tuple[mc.DispersedFootprint, dict[str, Any]], name: str | None) -> Stored:
    """A dispersion job's result: its JSON with each cloud thinned to CLOUD_SAMPLES_STORED samples."""
    stats, info = answer
    return Stored(result={"dispersion": to_dict(study, stats, CLOUD_SAMPLES_STORED, info)})


def to_dict(
    study: DispersionStudy,
    stats: mc.DispersedFootprint,
    cloud_samples: int | None = CLOUD_SAMPLES_STORED,
    info: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """A dispersion's JSON (the job's result, the CLI's --json): the statistics, each cloud thinned to its first
    `cloud_samples` samples, the study's design, seed and trajectories, how it ran, and the flights of the samples
    it asks histories of."""
    result: dict[str, Any] = plain(
        stats.to_dict(cloud_points=cloud_samples)
        | {
            "design": study.design,
            "seed": study.seed,
            "trajectories": study.samples * study.flights_per_sample(),
            "run": info or {},
            "histories": _plan(study).histories(),
        }
    )
    return result


SITE_COLUMNS = (
    "name",
    "latitude_deg",
    "longitude_deg",
    "probability",
    "interval_low",
    "interval_high",
    "interval_level",
    "samples_reaching",
    "samples",
    "inside_nominal",
    "downrange_nmi",
    "crossrange_nmi",
)


def sites_csv(result: dict[str, Any]) -> str:
    """Each site's probability of being reached, its binomial interval and its ranges, one row a site."""
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=SITE_COLUMNS, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for s in result["sites"]:
        row = s | {"interval_low": s["interval"][0], "interval_high": s["interval"][1], "samples": result["samples"]}
        w.writerow({k: csv_cell(v) for k, v in row.items() if k in SITE_COLUMNS})
    return out.getvalue()


_plan = PerStudy(Plan)  # this process's plan of the study it flies (a study's parts share one draw)


def default_name(study: DispersionStudy) -> str:
    """A dispersion's name unless one is given: its footprint's vehicle, method and entry, and its samples."""
    fp = study.footprint
    return fp.case.named(f"{METHOD_WORDS[fp.method]} in {study.samples:,} samples")


WORK = Work(
    split=DispersionStudy.chunks,
    run_part=fly_chunk,
    combine=combine,
    store=store,
    default_name=default_name,
    part_unit="chunk",
)
