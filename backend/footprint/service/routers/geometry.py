"""POST /api/transform: footprint.contracts.transform's transform contract, at most 10,000 points over HTTP."""

from typing import Any

from fastapi import APIRouter, Body, Request
from pydantic import ValidationError

from footprint.core.errors import InputError
from footprint.contracts.transform import run_transform
from footprint.service.errors import RequestInvalid, invalid
from footprint.service.jobs.studies import check_points, resolve_vehicles
from footprint.service.routers.vehicles import stored_vehicle_lookup

router = APIRouter(tags=["geometry"])
MAX_TRANSFORM_POINTS = 10_000  # over HTTP (the contract allows 1,000,000 from the CLI)


def transform(request_body: dict) -> dict:
    """run_transform with the service's limits; 422 names the field."""
    points = request_body.get("points", [])
    if isinstance(points, list) and len(points) > MAX_TRANSFORM_POINTS:
        raise RequestInvalid(f"points: {len(points)} points is outside the allowed range 1 to "
                             f"{MAX_TRANSFORM_POINTS:,} over HTTP", "points")
    try:
        if isinstance(request_body.get("study"), dict):
            from footprint.contracts.footprint import parse_study

            check_points(parse_study(request_body["study"]), "study.")
        return run_transform(request_body)
    except (ValidationError, InputError) as exc:
        raise invalid(exc) from None


@router.post("/transform")
def transform_points(request: Request, body: dict[str, Any] = Body(..., description="footprint.contracts.transform request")):
    """Move points to another node, inclination or deorbit point; mirror; earth rotation."""
    return transform(resolve_vehicles(body, lookup=stored_vehicle_lookup(request)))
