"""GET /api/health: database, cluster, version. GET /api/config: what the map page needs to know."""

from fastapi import APIRouter, Request
from starlette.concurrency import run_in_threadpool

import footprint
from footprint.service import deps
from footprint.service.errors import ApiRoute
from footprint.service.jobs.engine import one_line
from footprint.service.schemas import Health, PageConfig

router = APIRouter(tags=["health"], route_class=ApiRoute)


@router.get("/health", response_model=Health)
async def health(request: Request) -> dict:
    """The service's state: database reachable, cluster up, version (the scheduler's address only to a caller with the
    bearer token, so never when FOOTPRINT_API_TOKEN is unset). The database answered when the cached reads' shared
    revision read, begun after this request came, did (read_cache.SharedRead: no query of its own, none on the event
    loop); the scheduler is asked in the background (ClusterLink.recent_status), or in the thread pool before its
    first answer."""
    try:
        await request.app.state.revisions.current()
        database = {"ok": True, "dialect": request.app.state.dialect}
    except Exception as exc:  # noqa: BLE001 -- health reports, never raises
        database = {"ok": False, "dialect": request.app.state.dialect, "error": one_line(exc)}
    jobs = deps.engine(request)
    cluster = jobs.recent_status() or await run_in_threadpool(jobs.status)
    if not deps.has_token(request):  # the internal address is the operator's, not every caller's
        cluster.pop("scheduler", None)
    status = "ok" if database["ok"] and cluster["ok"] else "degraded"
    return {"status": status, "version": footprint.__version__, "database": database, "cluster": cluster}


@router.get("/config", response_model=PageConfig)
async def config(request: Request) -> dict:
    """The page's configuration: the optional online tile layer (FOOTPRINT_TILE_URL), the version."""
    return {"tile_url": request.app.state.settings.tile_url or None, "version": footprint.__version__}
