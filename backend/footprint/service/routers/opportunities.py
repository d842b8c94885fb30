"""GET /api/jobs/{id}/opportunities and /api/jobs/{id}/opportunities/{index}: the files a planner hands on of a
succeeded opportunities job (issue 52): its calendar or CSV, and one opportunity's coast and entry as a CCSDS OEM or
as CZML."""

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Path, Query, Request, Response
from starlette.concurrency import run_in_threadpool

from footprint import contracts
from footprint.contracts import opportunities, opportunity_files
from footprint.core.errors import InputError
from footprint.service import deps
from footprint.service.db import queries as q
from footprint.service.errors import ApiRoute, NotFound
from footprint.service.schemas import StoredId

router = APIRouter(tags=["jobs"], route_class=ApiRoute)
MAX_INDEX = 1_000_000  # more than any answer holds (MAX_WORK_HTTP burn times x sites)


def _job(request: Request, job_id: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """The succeeded opportunities job's study (as stored) and answer, or 404 saying why not."""
    with deps.sessions(request).begin() as session:
        job = q.get_job(session, job_id=job_id)
        if job is None:
            raise NotFound(f"no job {job_id!r}")
        if job.kind != "opportunities":
            raise NotFound(f"job {job_id!r} is a {job.kind} job")
        if job.status != "succeeded":
            raise NotFound(f"job {job_id!r} is {job.status}: its opportunities are there once it has succeeded")
        return job.study, q.job_result(session, job_id=job_id)["opportunities"]


def _attachment(body: str, media_type: str, filename: str) -> Response:
    return Response(body, media_type=media_type, headers={"Content-Disposition": f'attachment; filename="{filename}"'})


@router.get(
    "/jobs/{job_id}/opportunities",
    response_class=Response,
    responses={200: {"content": {"text/calendar": {}, "text/csv": {}}}},
)
async def get_opportunities(
    job_id: StoredId, request: Request, format: Literal["ics", "csv"] = Query("ics")
) -> Response:
    """A succeeded opportunities job's calendar (RFC 5545: an event per opportunity that meets the rules, from the
    burn to the landing, its UID stable across re-plans) or its opportunities as CSV, in landing order."""
    _, answer = await run_in_threadpool(_job, request, job_id)
    if format == "csv":
        return _attachment(opportunities.opportunities_csv(answer), "text/csv", f"opportunities-{job_id}.csv")
    return _attachment(opportunities.opportunities_ics(answer), "text/calendar", f"opportunities-{job_id}.ics")


OEM_TYPES = {"oem": "text/plain", "oem-xml": "application/xml", "czml": "application/json"}


def _opportunity_file(request: Request, job_id: str, index: int, format: str) -> str:
    stored, answer = _job(request, job_id)
    try:
        opportunity_files.opportunity_at(answer, index)
    except InputError as exc:
        raise NotFound(f"job {job_id!r} has no opportunity {index}: {exc.message}") from exc
    study = contracts.parse("opportunities", stored)
    if format == "czml":
        return opportunity_files.opportunity_czml(study, answer, index)
    return opportunity_files.opportunity_oem(study, answer, index, "xml" if format == "oem-xml" else "kvn")


@router.get(
    "/jobs/{job_id}/opportunities/{index}",
    response_class=Response,
    responses={200: {"content": {media: {} for media in OEM_TYPES.values()}}},
)
async def get_opportunity_path(
    job_id: StoredId,
    request: Request,
    index: Annotated[int, Path(ge=0, le=MAX_INDEX, description="the opportunity's place in the answer (0: first)")],
    format: Literal["oem", "oem-xml", "czml"] = Query("oem"),
) -> Response:
    """One opportunity's coast (burn to entry interface, TEME) and entry (the study's case flown from there, GRC):
    a CCSDS OEM (KVN, or XML with `oem-xml`) or CZML for Cesium (earth-fixed positions, a path and a label); the
    opportunity by its index in the answer's `opportunities` (landing order)."""
    text = await run_in_threadpool(_opportunity_file, request, job_id, index, format)
    suffix = {"oem": "oem", "oem-xml": "oem.xml", "czml": "czml"}[format]
    return _attachment(text, OEM_TYPES[format], f"opportunity-{job_id}-{index}.{suffix}")
