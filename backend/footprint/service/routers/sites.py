"""Landing sites: CRUD and CSV upload; POST /api/reach (footprint.contracts.reach, synchronous) with the stored sites
when the request gives none."""

import csv
import io
from typing import Annotated

from fastapi import APIRouter, Depends, Path, Query, Request, Response
from pydantic import ValidationError
from starlette.concurrency import run_in_threadpool

from footprint.contracts.doors import enter
from footprint.contracts.messages import error_line
from footprint.contracts.reach import ReachRequest, Site
from footprint.contracts.records import plain
from footprint.service import deps
from footprint.service.db import queries as q
from footprint.service.db.models import MAX_INTEGER
from footprint.service.errors import ApiRoute, NotFound, RequestInvalid, UnsupportedMediaType
from footprint.service.schemas import ReachRead, SiteRead, SitesCreated, SitesDeleted

router = APIRouter(tags=["sites"], route_class=ApiRoute)
CSV_COLUMNS = ("name", "latitude_deg", "longitude_deg")
MAX_CSV_SITES = 10_000
SiteId = Annotated[int, Path(le=MAX_INTEGER)]  # the route's :int takes any digits; the column holds int4


def _read(row) -> dict:
    return {
        "id": row.id,
        "name": row.name,
        "latitude_deg": row.latitude_deg,
        "longitude_deg": row.longitude_deg,
        "last_reach": row.last_reach,
    }


def _site(row) -> dict:
    """A stored site as the reach contract takes it."""
    return {"name": row.name, "latitude_deg": row.latitude_deg, "longitude_deg": row.longitude_deg}


@router.get("/sites", response_model=list[SiteRead])
async def list_sites(request: Request) -> list[dict]:
    """Every stored landing site."""
    return await deps.read(request, lambda session: [_read(r) for r in q.list_sites(session)])


@router.post("/sites", response_model=SiteRead, status_code=201)
def create_site(site: Site, session: deps.Transaction) -> dict:
    """Store a landing site."""
    return _read(q.create_sites(session, sites=[site.model_dump()])[0])


@router.post(
    "/sites/csv",
    response_model=SitesCreated,
    status_code=201,
    responses={415: {}},
    openapi_extra={"requestBody": {"content": {"text/csv": {"schema": {"type": "string"}}}}},
)
async def upload_sites(request: Request) -> dict:
    """Store the sites of a text/csv body with the header name,latitude_deg,longitude_deg (all or none), by name: a
    stored site of the same name is moved to the row's place, not stored twice. Other types are refused (415): a
    text/plain POST is a "simple" request another site's page may send."""
    kind = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if kind != "text/csv":
        raise UnsupportedMediaType(f"body: the sites are a text/csv body (got {kind[:80] or 'none'!r})")
    sites = _parse_csv(await request.body())
    with deps.sessions(request).begin() as session:
        created, updated = q.upsert_sites(session, sites=sites)
    return {"created": created, "updated": updated}


def _parse_csv(body: bytes) -> list[dict]:
    try:
        text = body.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RequestInvalid(f"body: not UTF-8 text ({exc.reason} at byte {exc.start})", "body") from None
    reader = csv.DictReader(io.StringIO(text))
    if reader.fieldnames is None or set(CSV_COLUMNS) - {f.strip() for f in reader.fieldnames}:
        raise RequestInvalid(
            f"line 1: the header must name the columns {','.join(CSV_COLUMNS)} "
            f"(got {','.join(reader.fieldnames or [])!r})",
            "line 1",
        )
    sites = []
    for row in reader:
        line = reader.line_num
        try:
            values = {k.strip(): (v or "").strip() for k, v in row.items() if k is not None}
            sites.append(Site.model_validate({k: values.get(k) for k in CSV_COLUMNS}).model_dump())
        except ValidationError as exc:
            raise RequestInvalid(f"line {line}: {error_line(exc)}", f"line {line}") from None
        if len(sites) > MAX_CSV_SITES:
            raise RequestInvalid(f"line {line}: more than {MAX_CSV_SITES:,} sites in one upload", f"line {line}")
    if not sites:
        raise RequestInvalid("line 2: no sites below the header", "line 2")
    return sites


@router.delete("/sites", response_model=SitesDeleted)
def delete_sites(session: deps.Transaction) -> dict:
    """Delete every landing site (the page's "remove all")."""
    return {"deleted": q.delete_sites(session)}


@router.get("/sites/{site_id:int}", response_model=SiteRead)
async def get_site(site_id: SiteId, request: Request) -> dict:
    """One landing site."""
    row = await deps.read(request, lambda session: q.get_site(session, site_id=site_id))
    if row is None:
        raise NotFound(f"no site {site_id}")
    return _read(row)


@router.put("/sites/{site_id:int}", response_model=SiteRead)
def update_site(site_id: SiteId, site: Site, session: deps.Transaction) -> dict:
    """Replace a landing site's name and place."""
    row = q.update_site(session, site_id=site_id, site=site.model_dump())
    if row is None:
        raise NotFound(f"no site {site_id}")
    return _read(row)


@router.delete("/sites/{site_id:int}", status_code=204)
def delete_site(site_id: SiteId, session: deps.Transaction) -> Response:
    """Delete a landing site."""
    if not q.delete_site(session, site_id=site_id):
        raise NotFound(f"no site {site_id}")
    return Response(status_code=204)


class StoredSites:
    """The stored landing sites, for a reach that names none (`used`: it named none, and got these)."""

    def __init__(self, rows: list) -> None:
        self.ids, self.sites, self.used = [r.id for r in rows], [_site(r) for r in rows], False

    def __call__(self) -> list[dict]:
        self.used = True
        return self.sites


async def reach_door(request: Request) -> StoredSites:
    """The synchronous door, with the stored sites for a reach that gives none (read off the event loop)."""

    def read() -> StoredSites:
        with deps.sessions(request).begin() as session:
            return StoredSites(q.list_sites(session))

    stored = await run_in_threadpool(read)
    enter(deps.body_context(request, synchronous=True, sites=stored))
    return stored


@router.post("/reach", response_model=ReachRead)
def reach(
    request: Request,
    body: ReachRequest,
    stored: Annotated[StoredSites, Depends(reach_door)],
    store_verdicts: bool = Query(
        False, description="keep each stored site's verdict with it (stored sites only: the request gives no sites)"
    ),
) -> dict:
    """Which sites the footprint reaches from which deorbit points (the stored sites when none are given); with
    store_verdicts, each stored site keeps its verdict (shown again after a reload)."""
    if store_verdicts and not stored.used:
        raise RequestInvalid(
            "store_verdicts: only for the stored sites (give no 'sites' in the body)", "store_verdicts"
        )
    result = plain(deps.answer_now(request, "reach", body))
    if store_verdicts:
        verdicts = {i: _verdict(s, body, result) for i, s in zip(stored.ids, result["sites"])}
        with deps.sessions(request).begin() as session:
            q.store_verdicts(session, verdicts=verdicts)
    return result


def _verdict(site: dict, req, result: dict) -> dict:
    """What a site keeps of a reach: its verdict, and of what footprint and orbit."""
    return {k: site[k] for k in ("reachable", "windows", "first_deorbit_time_s", "best_margin_nmi")} | {
        "footprint": req.description or "footprint",
        "orbit": {k: result["orbit"][k] for k in ("inclination_deg", "node_longitude_deg")},
        "checked_at": q.iso(q.utc_now()),
    }
