"""The guided dispersion contract: a guided case flown closed loop in N Monte Carlo samples (footprint.core.
guided_dispersion), and, for the same samples, open loop with the nominal guided flight's bank.

    {"case": CASE whose bank law is "guided",
     "samples": 1000, "design", "seed", "entry", "vehicle", "density" (as a dispersion study's),
     "radius_nmi": [1, 5, 10], "open_loop": true, "chunk_samples": 20,
     "burn": {"tle" | "state", "burn_utc", "delta_v_fps", "interface_altitude_ft", "errors": {...}}}

With "burn" (an opportunity's deorbit burn, issue 52 item 5) the entry is the burn's: the nominal flight starts where
the planned burn's coast reaches the interface (the case's entry is replaced by it), and each sample where its
executed burn's does (core.burn_errors: magnitude, pointing and time dispersed, each coasted); the entry spreads are
then not given.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from datetime import UTC, timedelta
from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import AwareDatetime, Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.case import Case
from footprint.contracts.dispersion import DispersedInputs
from footprint.contracts.doors import door_limit, validated
from footprint.contracts.fields import Range, Strict
from footprint.contracts.guidance import check_guided_study
from footprint.contracts.opportunities import STATE_EARTH, StateVector
from footprint.contracts.records import plain
from footprint.contracts.work import OnProgress, PerStudy, RunInfo, Stored, Work
from footprint.core import burn_errors as be
from footprint.core import deorbit as dorb
from footprint.core import dispersion as disp
from footprint.core import guided_dispersion as gdisp
from footprint.core.constants import Earth
from footprint.core.elements import Orbit, check_window, check_window_times, parse_tle
from footprint.core.monte_carlo import Landings
from footprint.core.trajectory import FlightSpec

MAX_SAMPLES = 1_000_000  # from the CLI or Python
MAX_SAMPLES_HTTP = 20_000  # ~50 ms each guided, twice with the open loop: ~15 min on the two workers of a small server
CHUNK_SAMPLES = 20  # a task flies about this many samples (~1-2 s): progress, balance
CLOUD_SAMPLES_STORED = 1_000  # the landing points a job's stored result keeps of each mode


_ERRORS = be.BurnErrors()
BURN_SPAN_S = 120.0  # s past the planned burn a state vector is propagated: its executed burns' times (sigma <= 10 s)


class BurnExecutionErrors(Strict):
    """One standard deviation of each execution error (core.burn_errors.BurnErrors: the defaults' source)."""

    delta_v_fps: Annotated[float, Range(0, 100, "ft/s")] = _ERRORS.delta_v_fps
    pitch_deg: Annotated[float, Range(0, 10, "deg")] = _ERRORS.pitch_deg
    yaw_deg: Annotated[float, Range(0, 10, "deg")] = _ERRORS.yaw_deg
    time_s: Annotated[float, Range(0, 10, "s")] = _ERRORS.time_s


class ExecutedBurn(Strict):
    """An opportunity's deorbit burn (its orbit, time and Δv, as the opportunities' answer gives them) and the errors
    of its execution: the guided dispersion's entries (module docstring)."""

    tle: str | None = Field(default=None, min_length=1, max_length=400)
    state: StateVector | None = None
    burn_utc: AwareDatetime
    delta_v_fps: Annotated[float, Range(1, 10_000, "ft/s")]
    interface_altitude_ft: Annotated[float, Range(150_000, 1_000_000, "ft")] = dorb.INTERFACE_ALTITUDE_FT
    errors: BurnExecutionErrors = BurnExecutionErrors()

    @model_validator(mode="after")
    def _one(self) -> ExecutedBurn:
        if (self.tle is None) == (self.state is None):
            raise ValueError("give exactly one of 'tle' or 'state'")
        burn = self.burn_utc.astimezone(UTC)
        span = (burn, burn + timedelta(seconds=BURN_SPAN_S))  # the executed burns' times
        if self.tle is not None:
            check_window(parse_tle(self.tle), *span, field="burn_utc")
        else:
            assert self.state is not None
            if burn < self.state.epoch:
                raise ValueError("burn_utc: before the state's epoch")
            check_window_times(self.state.epoch, *span, field="burn_utc", epoch_of="the state's")
        return self

    def orbit(self, coast_in: Callable[[Earth], dorb.Coast]) -> Orbit:
        if self.tle is not None:
            return parse_tle(self.tle)
        assert self.state is not None  # _one
        return self.state.propagated(coast_in(STATE_EARTH), self.burn_utc.astimezone(UTC), BURN_SPAN_S)

    def entries(self, spec: FlightSpec, z: NDArray[np.float64]) -> NDArray[np.float64]:
        """The entry rows (core.deorbit E_*) of the burn executed with errors errors x z (z: rows of normals)."""

        def coast_in(earth: Earth) -> dorb.Coast:
            return dorb.Coast.of(spec.vehicle, spec.planet, self.interface_altitude_ft, earth)

        orbit = self.orbit(coast_in)
        errors = be.BurnErrors(**self.errors.model_dump())
        return be.executed_entries(coast_in(orbit.earth), orbit, self.burn_utc.astimezone(UTC), self.delta_v_fps,
                                   errors, z)  # fmt: skip


class GuidedDispersionStudy(DispersedInputs):
    description: str | None = Field(default=None, max_length=4_000)
    case: Case
    radius_nmi: list[Annotated[float, Range(0.001, 10_000, "nmi")]] = Field(
        default=[1.0, 5.0, 10.0], min_length=1, max_length=10
    )
    open_loop: bool = True  # the same samples flown with the nominal guided flight's bank, open loop
    burn: ExecutedBurn | None = None  # the entries from an executed deorbit burn (module docstring)

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> GuidedDispersionStudy:
        check_guided_study(self.case.bank, info, "guided dispersion")
        samples, where = door_limit(info, MAX_SAMPLES, MAX_SAMPLES_HTTP)
        if self.samples > samples:
            raise ValueError(f"samples: {self.samples:,} is outside the allowed range 1 to {samples:,.0f}{where}")
        if self.burn is not None and self.entry.model_dump(exclude_none=True):
            raise ValueError("entry: with 'burn' the executed burns set the entries; give no entry spreads")
        return self

    def chunks(self) -> list[tuple[int, int]]:
        """[first, end) sample ranges, one task each."""
        size = self.chunk_samples or CHUNK_SAMPLES
        return [(a, min(self.samples, a + size)) for a in range(0, self.samples, size)]


REQUEST = GuidedDispersionStudy  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> GuidedDispersionStudy:
    study: GuidedDispersionStudy = validated(ADAPTER, data, GuidedDispersionStudy, ctx)
    return study


class Plan:
    """What every part needs, once per process: the spec, the nominal guided flight, its open-loop spec, the
    samples."""

    def __init__(self, study: GuidedDispersionStudy) -> None:
        self.study = study
        spec = study.case.to_spec()
        # with a burn: the planned burn's entry (no error) first, then each sample's executed burn's, coasted at once
        self.burn_rows = None
        if study.burn is not None:
            z = np.vstack([np.zeros((1, 4)), be.normals(study.samples, study.seed)])
            self.burn_rows = study.burn.entries(spec, z)
            spec = dorb.entered(spec, self.burn_rows[0])
        self.spec = spec
        self.nominal = gdisp.nominal_flight(self.spec)
        self.open_spec = gdisp.open_loop(self.spec, self.nominal) if study.open_loop else None

    @functools.cached_property
    def samples(self) -> disp.Samples:
        drawn = self.study.draw(self.spec)
        if self.burn_rows is None:
            return drawn
        entries = {name: self.burn_rows[1:, col] for name, col in dorb.ENTRY_INPUT_COLUMNS.items()}
        return disp.Samples(drawn.n, drawn.values | entries, drawn.density_delta)


_plan = PerStudy(Plan)  # this process's plan of the study it flies (a study's parts share one draw)


def fly_chunk(study: GuidedDispersionStudy, chunk: tuple[int, int], on_progress: OnProgress | None = None) -> Landings:
    """A part: samples first..end-1, guided (and open loop)."""
    first, end = chunk
    plan = _plan(study)
    return gdisp.fly_samples(plan.spec, plan.open_spec, plan.samples[first:end], first, on_progress)


def combine(
    study: GuidedDispersionStudy, parts: list[Landings], info: RunInfo
) -> tuple[gdisp.GuidedDispersion, dict[str, Any]]:
    plan = _plan(study)
    stats = gdisp.statistics(plan.spec, Landings.join(parts), plan.nominal, study.radius_nmi)
    return stats, {"tasks": info.tasks, "workers": info.workers, "seconds": info.seconds}


def to_dict(
    study: GuidedDispersionStudy,
    stats: gdisp.GuidedDispersion,
    cloud_samples: int | None = CLOUD_SAMPLES_STORED,
    info: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """A guided dispersion's JSON (the job's result, the CLI's --json): the statistics, each cloud thinned, the design,
    seed and how it ran, and the nominal guided flight's track."""
    from footprint.contracts.records import flown

    nominal = _plan(study).nominal
    result: dict[str, Any] = plain(
        stats.to_dict(cloud_points=cloud_samples)
        | {
            "design": study.design,
            "seed": study.seed,
            "run": info or {},
            "nominal_flight": flown(nominal, ("time_s", "latitude_deg", "longitude_deg", "bank_deg",
                                              "bank_command_deg", "altitude_ft", "velocity_fps")),
        }
    )  # fmt: skip
    return result


def store(
    study: GuidedDispersionStudy, answer: tuple[gdisp.GuidedDispersion, dict[str, Any]], name: str | None
) -> Stored:
    stats, info = answer
    return Stored(result={"guided_dispersion": to_dict(study, stats, CLOUD_SAMPLES_STORED, info)})


WITHIN_COLUMNS = ("mode", "radius_nmi", "probability", "interval_low", "interval_high", "level", "samples_within",
                  "samples")  # fmt: skip


def within_csv(result: dict[str, Any]) -> str:
    """Each mode's probability of landing within each radius of the target, its interval: one row each."""
    import csv
    import io

    from footprint.contracts.records import csv_cell

    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=WITHIN_COLUMNS, lineterminator="\n")
    w.writeheader()
    for mode in ("guided", "open_loop"):
        for x in result.get(mode, {}).get("within", []):
            row = {"mode": mode, **x, "interval_low": x["interval"][0], "interval_high": x["interval"][1]}
            w.writerow({k: csv_cell(row[k] if k != "samples" else result["samples"]) for k in WITHIN_COLUMNS})
    return out.getvalue()


WORK = Work(split=GuidedDispersionStudy.chunks, run_part=fly_chunk, combine=combine, store=store, part_unit="chunk")
