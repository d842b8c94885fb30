"""The guided footprint contract: the targets a guided case's vehicle reaches within R nmi in at least p of the
dispersed samples (footprint.core.guided_footprint), one part per ray, beside the outer footprints of the same vehicle
flown to the same end: the report's (Sec. II.6, single parameter) and the true optimal one (collocation), one part.

    {"case": CASE whose bank law is "guided" (its target is replaced along each ray),
     "rays": 24, "samples": 300, "radius_nmi": 5, "probability": 0.99, "optimal": true,
     "entry", "vehicle", "density" (as a dispersion study's), "seed", "design"}
"""

from __future__ import annotations

import functools
import math
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
from footprint.core import guided_footprint as gfp

MAX_SAMPLES = 100_000
MAX_SAMPLES_HTTP = 1_000  # 24 rays x ~5 candidates x 1,000 guided flights: about an hour on two workers
OUTER = "outer"  # the part that flies the outer footprints


class GuidedFootprintStudy(DispersedInputs):
    description: str | None = Field(default=None, max_length=4_000)
    case: Case
    samples: int = Field(default=gfp.GuidedFootprintSettings.samples, ge=1, le=MAX_SAMPLES)
    rays: int = Field(default=gfp.GuidedFootprintSettings.rays, ge=4, le=360)
    radius_nmi: Annotated[float, Range(0.001, 10_000, "nmi")] = gfp.GuidedFootprintSettings.radius_nmi
    probability: Annotated[float, Range(0.01, 1.0)] = gfp.GuidedFootprintSettings.probability
    optimal: bool = True  # the true optimal footprint too (collocation, ~1-3 min of one worker)

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> GuidedFootprintStudy:
        check_guided_study(self.case.bank, info, "guided footprint")
        samples, where = door_limit(info, MAX_SAMPLES, MAX_SAMPLES_HTTP)
        if self.samples > samples:
            raise ValueError(f"samples: {self.samples:,} is outside the allowed range 1 to {samples:,.0f}{where}")
        fewest, p = gfp.fewest_samples(self.probability), self.probability
        if fewest is None:
            raise ValueError("probability: 1 cannot be shown with 95 % confidence by any number of samples; give < 1")
        if self.samples < fewest:
            raise ValueError(
                f"samples: {self.samples:,} cannot show P >= {p:g} with 95 % confidence; give {fewest:,} or more"
            )
        return self

    def criterion(self) -> str:
        """What a guided boundary point means, in words."""
        misses = gfp.allowed_misses(self.samples, self.probability)
        return (
            f"reached within {self.radius_nmi:g} nmi: P >= {self.probability:g} with {100 * gfp.CONFIDENCE:g} % "
            f"confidence (one-sided Clopper-Pearson lower bound): at most {misses:,} of "
            f"{self.samples:,} samples missing"
        )

    def settings(self) -> gfp.GuidedFootprintSettings:
        return gfp.GuidedFootprintSettings(self.rays, self.samples, self.radius_nmi, self.probability)

    def parts(self) -> list[float | str]:
        """The outer footprints first (the longest part), then one ray each: its angle (rad) from down-range."""
        return [OUTER, *(2.0 * math.pi * k / self.rays for k in range(self.rays))]


REQUEST = GuidedFootprintStudy
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> GuidedFootprintStudy:
    study: GuidedFootprintStudy = validated(ADAPTER, data, GuidedFootprintStudy, ctx)
    return study


class Plan:
    """Once per process: the spec, the rays' frame (undispersed flights on the axis), the samples."""

    def __init__(self, study: GuidedFootprintStudy) -> None:
        self.study = study
        self.spec = study.case.to_spec()

    @functools.cached_property
    def frame(self) -> gfp.Frame:
        return gfp.frame(self.spec, self.study.radius_nmi)

    @functools.cached_property
    def samples(self) -> disp.Samples:
        return self.study.draw(self.spec)


_plan = PerStudy(Plan)  # this process's plan of the study it flies (a study's parts share one draw)


def run_part(study: GuidedFootprintStudy, part: float | str, on_progress: OnProgress | None = None) -> dict[str, Any]:
    plan = _plan(study)
    if part == OUTER:
        return gfp.outer_footprints(plan.spec, study.optimal, on_progress)
    assert isinstance(part, float)
    ray = gfp.trace_ray(plan.spec, plan.frame, part, plan.samples, study.settings(), on_progress)
    return ray | {"frame": plan.frame._asdict()}


def combine(study: GuidedFootprintStudy, outputs: list[dict[str, Any]], info: RunInfo) -> dict[str, Any]:
    """The guided and undispersed guided boundaries, the outer footprints, each ray's reach in all of them, and the
    guidance's margin to each outer footprint (nmi^2 and percent of its area)."""
    spec = _plan(study).spec
    outer, rays = outputs[0], outputs[1:]
    f = gfp.Frame(**rays[0].pop("frame"))
    for r in rays[1:]:
        r.pop("frame")
    guided = gfp.boundary(spec, rays, "guided")
    answer: dict[str, Any] = {
        "frame": f._asdict(),
        # the guided rings are of targets, each reached at its interface this far before it; the outer ones of ends
        "interface_range_nmi": spec.guidance.interface_range_nmi if spec.guidance is not None else 0.0,
        "settings": study.settings().__dict__,
        "criterion": study.criterion(),
        "guided": guided,
        "nominal_guided": gfp.boundary(spec, rays, "nominal"),
        "flights": sum(r["flights"] for r in rays),
        "run": {"tasks": info.tasks, "workers": info.workers, "seconds": info.seconds},
        "entry": {
            "latitude_deg": spec.entry.latitude_deg,
            "longitude_deg": spec.entry.longitude_deg,
            "heading_deg": spec.entry.heading_deg,
        },
    }
    for name, fp in outer.items():
        answer[name] = fp
        if fp is None:
            continue
        ring = list(zip(fp["downrange_nmi"], fp["crossrange_nmi"]))
        for r in rays:
            r[f"s_{name}"] = gfp.reach_on_ray(ring, f, math.radians(r["angle_deg"]))
        margin = fp["area_nmi2"] - guided["area_nmi2"]
        answer[f"margin_to_{name}"] = {
            "area_nmi2": margin,
            "percent": 100.0 * margin / fp["area_nmi2"],
            "inside_at_every_ray": all(r[f"s_{name}"] is None or r["s_guided"] <= r[f"s_{name}"] for r in rays),
        }
    answer["rays"] = sorted(rays, key=lambda r: r["angle_deg"])
    result: dict[str, Any] = plain(answer)
    return result


def store(study: GuidedFootprintStudy, answer: dict[str, Any], name: str | None) -> Stored:
    return Stored(result={"guided_footprint": answer})


WORK = Work(split=GuidedFootprintStudy.parts, run_part=run_part, combine=combine, store=store, part_unit="ray")
