"""Vehicles: the built-ins (Appendix B) and stored custom vehicles."""

import threading

from fastapi import APIRouter, Request, Response
from starlette.concurrency import run_in_threadpool

from footprint.contracts.vehicle import VehicleLimits, user_vehicle
from footprint.core.aero import (
    SUMMARY_ALTITUDE_FT,
    SUMMARY_MACH,
    alpha_cl_max_deg,
    builtin_vehicle,
    builtin_vehicle_ids,
    coefficients,
    ld_max,
    vehicle_summaries,
)
from footprint.service import deps, read_cache
from footprint.service.db import queries as q
from footprint.service.errors import ApiRoute, Conflict, NotFound
from footprint.service.schemas import VehicleCreate, VehicleDetail, VehicleItem

router = APIRouter(tags=["vehicles"], route_class=ApiRoute)
AERO_MACH = (2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0, 15.0, 20.0, 25.0, 30.0)  # the aero summary's Mach numbers


class BuiltinSummaries:
    """The built-in vehicles' list items and aero summaries: computed once (at service start-up, see
    app.lifespan), under a lock so concurrent first requests wait for that one computation."""

    def __init__(self):
        self._lock = threading.Lock()
        self.value: tuple[dict[str, dict], dict[str, dict]] | None = None  # (items by id, aero by id)

    def get(self) -> tuple[dict[str, dict], dict[str, dict]]:
        value = self.value
        if value is None:
            with self._lock:
                if self.value is None:
                    self.value = self._compute()
                value = self.value
        return value

    def clear(self) -> None:
        with self._lock:
            self.value = None

    @staticmethod
    def _compute() -> tuple[dict[str, dict], dict[str, dict]]:
        items = {
            r["id"]: {
                "id": r["id"],
                "builtin": True,
                "description": r["name"] + (f" ({r['note']})" if r["note"] else ""),
                "wing_loading_psf": r["wing_loading_psf"],
                "ld_max": r["ld_max_m20_200kft"],
                "alpha_ld_max_deg": r["alpha_ld_max_deg"],
                "reported_ld_max": r["reported_ld_max"],
                "limits": VehicleLimits().model_dump(),  # a built-in's are the defaults
            }
            for r in vehicle_summaries()
        }
        return items, {vid: _aero(builtin_vehicle(vid)) for vid in items}


BUILTINS = BuiltinSummaries()


def warm_builtins() -> None:
    """Compute the built-in summaries now (the service's start-up)."""
    BUILTINS.get()


def _builtins() -> dict[str, dict]:
    return BUILTINS.get()[0]


def _custom_vehicle(definition: dict):
    """The core's vehicle of a stored definition (inline tables packed once per process: contracts.vehicle)."""
    return user_vehicle(definition)


def _finite(x: float) -> float | None:
    return x if x == x and abs(x) != float("inf") else None


def _summary(vehicle) -> dict:
    """A vehicle's list item numbers: wing loading, (L/D)max and its alpha at Mach 20, 200,000 ft."""
    ld, alpha = ld_max(vehicle, SUMMARY_MACH, SUMMARY_ALTITUDE_FT)
    return {
        "wing_loading_psf": vehicle.wing_loading_psf,
        "ld_max": _finite(round(ld, 4)),
        "alpha_ld_max_deg": _finite(round(alpha, 2)),
    }


def _custom_item(row) -> dict:
    """A stored vehicle's list item from its stored summary (one stored before it had one is summarized now)."""
    summary = row.summary or _summary(_custom_vehicle(row.definition))
    item = {"id": row.id, "builtin": False, "description": row.description, **summary, "reported_ld_max": None}
    return item | {"limits": _limits(row.definition)}


def _limits(definition: dict) -> dict[str, float | None]:
    """A stored definition's limits (read from it: nothing packed); "limits": null lifts them all."""
    given = definition.get("limits", {})
    lifted = dict.fromkeys(VehicleLimits.model_fields)
    return lifted if given is None else VehicleLimits.model_validate(given).model_dump()


def _aero(vehicle) -> dict:
    rows = {"ld_max": [], "alpha_ld_max_deg": [], "cl_max": []}
    for mach in AERO_MACH:
        ld, alpha = ld_max(vehicle, mach, SUMMARY_ALTITUDE_FT)
        cl_max, _ = coefficients(
            vehicle.blob, mach, float(alpha_cl_max_deg(vehicle.blob, mach, SUMMARY_ALTITUDE_FT)), SUMMARY_ALTITUDE_FT
        )
        rows["ld_max"].append(_finite(round(ld, 4)))
        rows["alpha_ld_max_deg"].append(_finite(round(alpha, 2)))
        rows["cl_max"].append(_finite(round(float(cl_max), 4)))
    return {"altitude_ft": SUMMARY_ALTITUDE_FT, "mach": list(AERO_MACH), **rows}


@router.get("/vehicles", response_model=list[VehicleItem], responses=read_cache.NOT_MODIFIED)
async def list_vehicles(request: Request) -> Response:
    """Built-in vehicles, then the stored custom ones (with an ETag: If-None-Match answers 304 while none changed)."""

    def build(session):
        items = list(_builtins().values()) + [_custom_item(r) for r in q.list_vehicles(session)]
        return read_cache.as_json(list[VehicleItem], items)

    return await deps.cached(request, ("list",), "vehicles", build)


@router.get("/vehicles/{vehicle_id}", response_model=VehicleDetail)
async def get_vehicle(vehicle_id: str, request: Request) -> dict:
    """One vehicle with its aero summary at 200,000 ft."""
    items, aero = BUILTINS.get()  # computed at start-up (app.lifespan)
    if vehicle_id in items:
        return items[vehicle_id] | {"definition": None, "aero": aero[vehicle_id]}
    row = await deps.read(request, lambda session: q.get_vehicle(session, vehicle_id=vehicle_id))
    if row is None:
        raise NotFound(f"no vehicle {vehicle_id!r}")
    return await run_in_threadpool(
        lambda: _custom_item(row) | {"definition": row.definition, "aero": _aero(_custom_vehicle(row.definition))}
    )


@router.post("/vehicles", response_model=VehicleDetail, status_code=201, responses={409: {}})
def create_vehicle(body: VehicleCreate, session: deps.Transaction) -> dict:
    """Store a custom vehicle (tables, polynomial or constant CL/CD, plus its wing loading)."""
    if body.id in builtin_vehicle_ids():
        raise Conflict(f"id: {body.id!r} is a built-in vehicle; choose another id")
    vehicle = body.vehicle.to_vehicle()  # packed once, as the body was read (contracts.vehicle: cached)
    definition = body.vehicle.definition()
    definition.setdefault("name", body.id)
    if q.get_vehicle(session, vehicle_id=body.id) is not None:
        raise Conflict(f"id: a vehicle {body.id!r} is stored already")
    row = q.create_vehicle(
        session, vehicle_id=body.id, description=body.description, definition=definition, summary=_summary(vehicle)
    )
    return _custom_item(row) | {"definition": definition, "aero": _aero(vehicle)}


@router.delete("/vehicles/{vehicle_id}", status_code=204, responses={409: {}})
def delete_vehicle(vehicle_id: str, session: deps.Transaction) -> Response:
    """Delete a custom vehicle (a built-in: 409)."""
    if vehicle_id in builtin_vehicle_ids():
        raise Conflict(f"{vehicle_id!r} is a built-in vehicle and cannot be deleted")
    if not q.delete_vehicle(session, vehicle_id=vehicle_id):
        raise NotFound(f"no vehicle {vehicle_id!r}")
    return Response(status_code=204)
