"""POST /api/trajectories: one trajectory, flown synchronously (in the threadpool, off the event loop)."""

from typing import Any

from fastapi import APIRouter, Body, Request
from pydantic import ValidationError

from footprint.contracts.case import parse_case
from footprint.core.errors import InputError
from footprint.core.trajectory import simulate
from footprint.service.errors import invalid
from footprint.service.jobs.studies import resolve_vehicles
from footprint.service.jobs.tasks import decimated, plain
from footprint.service.routers.vehicles import stored_vehicle_lookup

router = APIRouter(tags=["trajectories"])
MAX_HISTORY_ROWS = 2_000


@router.post("/trajectories")
def fly(request: Request, case: dict[str, Any] = Body(..., description="a case (footprint.contracts.case.Case)")) -> dict:
    """Fly one case: its summary and its time histories (at most 2,000 rows)."""
    case = resolve_vehicles(case, lookup=stored_vehicle_lookup(request))
    try:
        spec = parse_case(case).to_spec()
    except (ValidationError, InputError) as exc:
        raise invalid(exc) from None
    traj = simulate(spec)
    keep = decimated(len(traj.history["time_s"]), MAX_HISTORY_ROWS)
    return {"summary": plain(traj.summary), "history": {k: plain(v[keep]) for k, v in traj.history.items()}}
