"""POST /api/trajectories: one trajectory, flown synchronously (in the threadpool, off the event loop)."""

from typing import Any

from fastapi import APIRouter, Body, Request

from footprint.contracts.records import decimated, plain
from footprint.service import deps
from footprint.service.schemas import TrajectoryRead

router = APIRouter(tags=["trajectories"])
MAX_HISTORY_ROWS = 2_000


@router.post("/trajectories", response_model=TrajectoryRead)
def fly(request: Request, case: dict[str, Any] = Body(...)) -> dict:
    """Fly one case: its summary and its time histories (at most 2,000 rows)."""
    traj = deps.answer_now(request, "case", case)
    keep = decimated(len(traj.history["time_s"]), MAX_HISTORY_ROWS)
    return {"summary": plain(traj.summary), "history": {k: plain(v[keep]) for k, v in traj.history.items()}}
