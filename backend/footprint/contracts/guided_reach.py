"""The guided reach contract: each landing site made the target of a guided case and flown in the same dispersed
samples (footprint.core.guided_reach), one part per site: P(within R) with its interval, the CEP and the nominal miss.

    {"case": CASE whose bank law is "guided" (its target is replaced by each site),
     "sites": [{"name", "latitude_deg", "longitude_deg"}, ...], "radius_nmi": 5, "samples": 100,
     "entry", "vehicle", "density" (as a dispersion study's), "seed", "design"}
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
from footprint.contracts.reach import Site
from footprint.contracts.records import plain
from footprint.contracts.work import OnProgress, PerStudy, RunInfo, Stored, Work
from footprint.core import dispersion as disp
from footprint.core import guided_reach as greach

MAX_FLIGHTS = 10_000_000  # sites x samples, from the CLI or Python
MAX_FLIGHTS_HTTP = 20_000  # ~40 ms each: ~7 min on the two workers of a small server


class GuidedReachStudy(DispersedInputs):
    description: str | None = Field(default=None, max_length=4_000)
    case: Case
    sites: list[Site] = Field(min_length=1, max_length=500)
    samples: int = Field(default=100, ge=1, le=100_000)
    radius_nmi: Annotated[float, Range(0.001, 10_000, "nmi")] = 5.0

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> GuidedReachStudy:
        check_guided_study(self.case.bank, info, "guided reach")
        flights, where = door_limit(info, MAX_FLIGHTS, MAX_FLIGHTS_HTTP)
        if len(self.sites) * self.samples > flights:
            raise ValueError(
                f"samples: {len(self.sites):,} sites x {self.samples:,} samples is outside the allowed range of "
                f"1 to {flights:,.0f} flights{where}"
            )
        return self

    def parts(self) -> list[int]:
        """One site each: its index."""
        return list(range(len(self.sites)))


REQUEST = GuidedReachStudy
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> GuidedReachStudy:
    study: GuidedReachStudy = validated(ADAPTER, data, GuidedReachStudy, ctx)
    return study


class Plan:
    """Once per process: the spec and the samples (the same for every site)."""

    def __init__(self, study: GuidedReachStudy) -> None:
        self.study = study
        self.spec = study.case.to_spec()

    @functools.cached_property
    def samples(self) -> disp.Samples:
        return self.study.draw(self.spec)


_plan = PerStudy(Plan)  # this process's plan of the study it flies (a study's parts share one draw)


def fly_site(study: GuidedReachStudy, index: int, on_progress: OnProgress | None = None) -> dict[str, Any]:
    plan, site = _plan(study), study.sites[index]
    return greach.site_reach(
        plan.spec, site.name, site.latitude_deg, site.longitude_deg, plan.samples, study.radius_nmi, on_progress
    )


def combine(study: GuidedReachStudy, sites: list[dict[str, Any]], info: RunInfo) -> dict[str, Any]:
    answer: dict[str, Any] = plain(
        {
            "sites": sites,
            "radius_nmi": study.radius_nmi,
            "samples": study.samples,
            "design": study.design,
            "seed": study.seed,
            "run": {"tasks": info.tasks, "workers": info.workers, "seconds": info.seconds},
        }
    )
    return answer


def store(study: GuidedReachStudy, answer: dict[str, Any], name: str | None) -> Stored:
    return Stored(result={"guided_reach": answer})


WORK = Work(split=GuidedReachStudy.parts, run_part=fly_site, combine=combine, store=store, part_unit="site")
