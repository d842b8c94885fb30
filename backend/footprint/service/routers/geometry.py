"""POST /api/transform: footprint.contracts.transform's request, at most 10,000 points over HTTP (the contract's
HTTP limit)."""

from typing import Any

from fastapi import APIRouter, Body, Request

from footprint.service import deps
from footprint.service.schemas import TransformRead

router = APIRouter(tags=["geometry"])


@router.post("/transform", response_model=TransformRead, response_model_exclude_unset=True)
def transform_points(request: Request, body: dict[str, Any] = Body(...)) -> dict:
    """Move points to another node, inclination or deorbit point; mirror; earth rotation."""
    return deps.answer_now(request, "transform", body)
