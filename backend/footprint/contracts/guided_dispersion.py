"""The guided dispersion contract: a guided case flown closed loop in N Monte Carlo samples (footprint.core.
guided_dispersion), and, for the same samples, open loop with the nominal guided flight's bank.

    {"case": CASE whose bank law is "guided",
     "samples": 1000, "design", "seed", "entry", "vehicle", "density" (as a dispersion study's),
     "radius_nmi": [1, 5, 10], "open_loop": true, "chunk_samples": 20}
"""

from __future__ import annotations

import functools
from typing import Annotated, Any

from pydantic import Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts.case import Case
from footprint.contracts.dispersion import DispersedInputs
from footprint.contracts.doors import door_limit, validated
from footprint.contracts.fields import Range
from footprint.contracts.guidance import check_guided_study
from footprint.contracts.records import plain
from footprint.contracts.work import OnProgress, PerStudy, RunInfo, Stored, Work
from footprint.core import dispersion as disp
from footprint.core import guided_dispersion as gdisp
from footprint.core.monte_carlo import Landings

MAX_SAMPLES = 1_000_000  # from the CLI or Python
MAX_SAMPLES_HTTP = 20_000  # ~50 ms each guided, twice with the open loop: ~15 min on the two workers of a small server
CHUNK_SAMPLES = 20  # a task flies about this many samples (~1-2 s): progress, balance
CLOUD_SAMPLES_STORED = 1_000  # the landing points a job's stored result keeps of each mode


class GuidedDispersionStudy(DispersedInputs):
    description: str | None = Field(default=None, max_length=4_000)
    case: Case
    radius_nmi: list[Annotated[float, Range(0.001, 10_000, "nmi")]] = Field(
        default=[1.0, 5.0, 10.0], min_length=1, max_length=10
    )
    open_loop: bool = True  # the same samples flown with the nominal guided flight's bank, open loop

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> GuidedDispersionStudy:
        check_guided_study(self.case.bank, info, "guided dispersion")
        samples, where = door_limit(info, MAX_SAMPLES, MAX_SAMPLES_HTTP)
        if self.samples > samples:
            raise ValueError(f"samples: {self.samples:,} is outside the allowed range 1 to {samples:,.0f}{where}")
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
        self.spec = study.case.to_spec()
        self.nominal = gdisp.nominal_flight(self.spec)
        self.open_spec = gdisp.open_loop(self.spec, self.nominal) if study.open_loop else None

    @functools.cached_property
    def samples(self) -> disp.Samples:
        return self.study.draw(self.spec)


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
