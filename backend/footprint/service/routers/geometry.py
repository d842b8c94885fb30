"""POST /api/transform: footprint.contracts.transform's request, at most 10,000 points over HTTP (the contract's
HTTP limit)."""

from typing import Any

from fastapi import APIRouter, Body, Request

from footprint import contracts
from footprint.core.errors import InputError
from footprint.service import deps
from footprint.service.errors import invalid
from footprint.service.schemas import TransformRead

router = APIRouter(tags=["geometry"])


def transform(request: Request, body: dict) -> dict:
    """The transform of a request body; 422 names the field."""
    req = deps.parse_body(request, "transform", body, synchronous=True)
    try:
        return contracts.module("transform").run(req)
    except InputError as exc:  # a place the numbers cannot make (an inclination the latitude cannot fly)
        raise invalid(exc) from None


@router.post("/transform", response_model=TransformRead, response_model_exclude_unset=True)
def transform_points(request: Request, body: dict[str, Any] = Body(...)) -> dict:
    """Move points to another node, inclination or deorbit point; mirror; earth rotation."""
    return transform(request, body)
