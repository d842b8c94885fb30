"""GET /api/jobs/{id}/dispersion: a succeeded dispersion job's result as GeoJSON or CSV."""

from typing import Literal

from fastapi import APIRouter, Query, Request, Response

from footprint.contracts import dispersion
from footprint.contracts.records import json_bytes
from footprint.pictures import geojson
from footprint.service import deps
from footprint.service.db import queries as q
from footprint.service.errors import ApiRoute, NotFound
from footprint.service.schemas import StoredId

router = APIRouter(tags=["jobs"], route_class=ApiRoute)


@router.get(
    "/jobs/{job_id}/dispersion",
    response_class=Response,
    responses={200: {"content": {"application/geo+json": {}, "text/csv": {}}}},
)
def get_dispersion(
    job_id: StoredId, request: Request, format: Literal["geojson", "csv"] = Query("geojson")
) -> Response:
    """A succeeded dispersion job's result for a GIS or a spreadsheet: GeoJSON of the nominal and confidence
    footprints, the 1 and 3 sigma ellipses, the entry and the sites with their probability; or CSV of the sites."""
    with deps.sessions(request).begin() as session:
        job = q.get_job(session, job_id=job_id)
        if job is None:
            raise NotFound(f"no job {job_id!r}")
        if job.kind != "dispersion" or job.status != "succeeded":
            raise NotFound(
                f"job {job_id!r} is a {job.kind} job"
                if job.kind != "dispersion"
                else f"job {job_id!r} is {job.status}: its dispersion is there once it has succeeded"
            )
        result = q.job_result(session, job_id=job_id)["dispersion"]
    if format == "csv":
        return Response(
            dispersion.sites_csv(result),
            media_type="text/csv",
            headers={"Content-Disposition": f'attachment; filename="dispersion-{job_id}-sites.csv"'},
        )
    return Response(json_bytes(geojson.dispersion_collection(result)), media_type="application/geo+json")
