"""POST /api/transform: footprint.contracts.transform's request, at most 10,000 points over HTTP (the contract's
HTTP limit)."""

from fastapi import APIRouter, Depends, Request

from footprint.contracts.transform import TransformRequest
from footprint.service import deps
from footprint.service.errors import ApiRoute
from footprint.service.schemas import TransformRead

router = APIRouter(tags=["geometry"], route_class=ApiRoute)


@router.post(
    "/transform",
    response_model=TransformRead,
    response_model_exclude_unset=True,
    dependencies=[Depends(deps.sync_door)],
)
def transform_points(request: Request, body: TransformRequest) -> dict:
    """Move points to another node, inclination or deorbit point; mirror; earth rotation."""
    return deps.answer_now(request, "transform", body)
