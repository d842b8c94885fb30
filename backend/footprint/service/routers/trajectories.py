"""POST /api/trajectories: one trajectory, flown synchronously (in the threadpool, off the event loop)."""

from fastapi import APIRouter, Depends, Request

from footprint.contracts.case import Case
from footprint.contracts.records import decimated, plain
from footprint.service import deps
from footprint.service.errors import ApiRoute
from footprint.service.schemas import TrajectoryRead

router = APIRouter(tags=["trajectories"], route_class=ApiRoute)
MAX_HISTORY_ROWS = 2_000


@router.post("/trajectories", response_model=TrajectoryRead, dependencies=[Depends(deps.sync_door)])
def fly(request: Request, case: Case) -> dict:
    """Fly one case: its summary and its time histories (at most 2,000 rows)."""
    traj = deps.answer_now(request, "case", case)
    keep = decimated(len(traj.history["time_s"]), MAX_HISTORY_ROWS)
    return {"summary": plain(traj.summary), "history": {k: plain(v[keep]) for k, v in traj.history.items()}}
