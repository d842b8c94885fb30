"""GET /api/health: database, cluster, version. GET /api/config: what the map page needs to know."""

from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse

import footprint
from footprint.service import deps
from footprint.service.errors import ApiRoute
from footprint.service.jobs.engine import one_line
from footprint.service.schemas import Health, PageConfig

router = APIRouter(tags=["health"], route_class=ApiRoute)


@router.get("/health", response_model=Health, responses={503: {"model": Health, "description": "degraded or starting"}})
async def health(request: Request) -> JSONResponse:
    """The service's state: "ok" (200) when the database answers, the Dask scheduler answers and no worker is missing;
    else "degraded" (503, so that a deployment's health check sees it) with what is wrong. The scheduler's address
    only to a caller with the bearer token (so never when FOOTPRINT_API_TOKEN is unset). Nothing read on the event
    loop: the database answered when the cached reads' shared revision read, begun after this request came, did
    (read_cache.SharedRead); the cluster's state is the job engine's last look (ClusterLink.recent_status), at most
    half a second old while the scheduler answers. While the service starts: "starting" (503) at once, with the
    step under way (`starting`), before the database and the cluster are looked at."""
    if (step := request.app.state.starting) is not None:
        body = {"status": "starting", "version": footprint.__version__, "starting": step, "database": {}, "cluster": {}}
        return JSONResponse(body, status_code=503)
    try:
        await request.app.state.revisions.current()
        database = {"ok": True, "dialect": request.app.state.dialect}
    except Exception as exc:  # noqa: BLE001 -- health reports, never raises
        database = {"ok": False, "dialect": request.app.state.dialect, "error": one_line(exc)}
    cluster = deps.engine(request).recent_status()
    if not deps.has_token(request):  # the internal address is the operator's, not every caller's
        cluster.pop("scheduler", None)
    ok = database["ok"] and cluster["ok"]
    body = {
        "status": "ok" if ok else "degraded",
        "version": footprint.__version__,
        "database": database,
        "cluster": cluster,
    }
    return JSONResponse(body, status_code=200 if ok else 503)


@router.get("/config", response_model=PageConfig)
async def config(request: Request) -> dict:
    """The page's configuration: the optional online tile layer (FOOTPRINT_TILE_URL), the version."""
    return {"tile_url": request.app.state.settings.tile_url or None, "version": footprint.__version__}
