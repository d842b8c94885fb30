"""POST /api/trajectories: one trajectory, flown synchronously (in the threadpool, off the event loop)."""

import numpy as np
from fastapi import APIRouter, Depends, Request
from fastapi.responses import Response
from numpy.typing import NDArray

from footprint.contracts.case import Case
from footprint.contracts.records import decimated, json_bytes
from footprint.service import deps
from footprint.service.errors import ApiRoute
from footprint.service.schemas import TrajectoryRead

router = APIRouter(tags=["trajectories"], route_class=ApiRoute)
MAX_HISTORY_ROWS = 2_000


@router.post("/trajectories", response_model=TrajectoryRead, dependencies=[Depends(deps.sync_door)])
def fly(request: Request, case: Case) -> Response:
    """Fly one case: its summary and its time histories (at most 2,000 rows)."""
    traj = deps.answer_now(request, "case", case)
    return Response(trajectory_json(traj.summary, traj.history), media_type="application/json")


def trajectory_json(summary: dict, history: dict[str, NDArray[np.float64]]) -> bytes:
    """TrajectoryRead's JSON (NaN and infinities as null), made in one step: the histories' float64 columns written
    straight from their memory (json_bytes), neither converted number by number nor validated again against the model
    they are built to (pydantic's serializer over lists took twice as long: issue 29's doors)."""
    n = len(history["time_s"])
    keep = slice(None) if n <= MAX_HISTORY_ROWS else decimated(n, MAX_HISTORY_ROWS)
    columns = {k: np.ascontiguousarray(v[keep], dtype=np.float64) for k, v in history.items()}
    return json_bytes({"summary": summary, "history": columns})
