"""Stored footprints: list, get as JSON, GeoJSON or CSV, delete, transform."""

import csv
import io
from typing import Literal

from fastapi import APIRouter, Query, Request, Response
from fastapi.responses import HTMLResponse

from footprint.contracts.footprint import POINT_FIELDS, ground_track_at
from footprint.contracts.records import csv_cell, json_bytes
from footprint.core.errors import InputError
from footprint.core.rotation import shift_error_nmi
from footprint.pictures import geojson
from footprint.service import deps, read_cache
from footprint.service.db import queries as q
from footprint.service.db.models import MAX_INTEGER
from footprint.service.errors import ApiRoute, NotFound, Unavailable
from footprint.service.schemas import (
    FootprintList,
    FootprintRead,
    FootprintRename,
    FootprintSummary,
    FootprintTransform,
    FootprintTransformRead,
    StoredId,
)

router = APIRouter(tags=["footprints"], route_class=ApiRoute)
CSV_COLUMNS = ("index", *POINT_FIELDS)


def _summary(fp) -> dict:
    return {
        "id": fp.id,
        "name": fp.name,
        "job_id": fp.job_id,
        "vehicle": fp.vehicle,
        "method": fp.method,
        "entry": {k: getattr(fp, f"entry_{k}") for k in q.ENTRY_FIELDS},
        **{k: getattr(fp, k) for k in q.SUMMARY_FIELDS},
        "created_at": q.iso(fp.created_at),
    }


def _point(p) -> dict:
    return {k: getattr(p, k) for k in q.POINT_FIELDS}


def _full(request: Request, footprint_id: str) -> tuple[dict, dict]:
    """(the footprint's JSON view, its study)."""
    with deps.sessions(request).begin() as session:
        return _stored(session, footprint_id)


def _stored(session, footprint_id: str) -> tuple[dict, dict]:
    fp = q.get_footprint(session, footprint_id=footprint_id)
    if fp is None:
        raise NotFound(f"no footprint {footprint_id!r}")
    track = q.ground_track(session, footprint_id=footprint_id)
    item = _summary(fp) | {
        "points": [_point(p) for p in q.footprint_points(session, footprint_id=footprint_id, interior=False)],
        "interior": [_point(p) for p in q.footprint_points(session, footprint_id=footprint_id, interior=True)],
        "ground_track": []
        if track is None
        else [
            {"latitude_deg": a, "longitude_deg": o, "time_s": t}
            for a, o, t in zip(track.latitude_deg, track.longitude_deg, track.time_s)
        ],
    }
    return item, fp.study


@router.get("/footprints", response_model=FootprintList, responses=read_cache.NOT_MODIFIED)
async def list_footprints(
    request: Request,
    job_id: StoredId | None = None,
    limit: int = Query(50, ge=1, le=500),
    offset: int = Query(0, ge=0, le=MAX_INTEGER),
) -> Response:
    """Stored footprints, newest first (with an ETag: If-None-Match answers 304 while none changed)."""

    def build(session):
        rows, total = q.list_footprints(session, job_id=job_id, limit=limit, offset=offset)
        return read_cache.as_json(FootprintList, {"items": [_summary(r) for r in rows], "total": total})

    return await deps.cached(request, ("list", job_id, limit, offset), "footprints", build)


@router.get(
    "/footprints/{footprint_id}",
    response_model=FootprintRead,
    responses={200: {"content": {"application/geo+json": {}, "text/csv": {}}}, **read_cache.NOT_MODIFIED},
)
async def get_footprint(
    footprint_id: StoredId, request: Request, format: Literal["json", "geojson", "csv"] = Query("json")
) -> Response:
    """A footprint with its boundary (closed), interior points and ground track; or GeoJSON, or CSV (with an ETag:
    If-None-Match answers 304 while it is unchanged)."""

    def build(session):
        item, _ = _stored(session, footprint_id)
        if format == "geojson":
            return read_cache.serialized(json_bytes(geojson.feature_collection(item)), "application/geo+json")
        if format == "csv":
            return read_cache.serialized(
                _csv(item["points"]).encode(),
                "text/csv",
                {"Content-Disposition": f'attachment; filename="footprint-{footprint_id}.csv"'},
            )
        return read_cache.as_json(
            FootprintRead, item | {"outline": geojson.area(item["points"], item["entry"]).to_dict()}
        )

    return await deps.cached(request, ("item", footprint_id, format), "footprints", build)


def _csv(points: list[dict]) -> str:
    out = io.StringIO()
    w = csv.writer(out)
    w.writerow(CSV_COLUMNS)
    for i, p in enumerate(points):
        w.writerow([i] + [csv_cell(p[c]) for c in CSV_COLUMNS[1:]])
    return out.getvalue()


@router.get("/footprints/{footprint_id}/map", response_class=HTMLResponse, responses={503: {}})
def footprint_map(footprint_id: StoredId, request: Request) -> HTMLResponse:
    """A standalone folium map of the footprint that works offline (footprint.pictures.folium_page)."""
    from footprint.pictures.folium_page import footprint_map_html, map_policy

    item, _ = _full(request, footprint_id)
    try:
        html = footprint_map_html(item, title=item["name"])
        # folium's inline scripts, allowed by hash (the page policy allows no inline script)
        return HTMLResponse(html, headers={"Content-Security-Policy": map_policy(html)})
    except InputError as exc:  # the page's npm packages are not installed: the server's state, not the request's
        raise Unavailable(exc.message) from None


@router.patch("/footprints/{footprint_id}", response_model=FootprintSummary)
def rename_footprint(footprint_id: StoredId, body: FootprintRename, session: deps.Transaction) -> dict:
    """Rename a footprint; a name another footprint has gets a number, as a job's default names do."""
    fp = q.rename_footprint(session, footprint_id=footprint_id, name=body.name.strip())
    if fp is None:
        raise NotFound(f"no footprint {footprint_id!r}")
    return _summary(fp)


@router.delete("/footprints/{footprint_id}", status_code=204)
def delete_footprint(footprint_id: StoredId, session: deps.Transaction) -> Response:
    """Delete a footprint with its points and ground track."""
    if not q.delete_footprint(session, footprint_id=footprint_id):
        raise NotFound(f"no footprint {footprint_id!r}")
    return Response(status_code=204)


@router.post(
    "/footprints/{footprint_id}/transform", response_model=FootprintTransformRead, response_model_exclude_unset=True
)
def transform_footprint(footprint_id: StoredId, request: Request, body: FootprintTransform) -> dict:
    """Move the footprint's boundary (and its ground track) from its entry to another place (Section IV); the
    moved boundary's outline and GeoJSON geometry; with "exact", the track flown again and how far the report's
    approximate shift lies from the exact points."""
    body = body.model_dump(mode="json", by_alias=True, exclude_unset=True)
    item, study = _full(request, footprint_id)
    origin = {k: item["entry"][k] for k in ("latitude_deg", "longitude_deg", "heading_deg")}
    common = {"from": origin, **body}
    exact = body.get("earth_rotation") == "exact"
    points = [
        {
            "latitude_deg": p["latitude_deg"],
            "longitude_deg": p["longitude_deg"],
            "flight_time_s": p["flight_time_s"],
            "downrange_nmi": p["downrange_nmi"],
        }
        for p in item["points"]
    ]
    result = deps.answer_now(request, "transform", common | ({"study": study} if exact else {"points": points}))
    boundary = [p for p in result["points"] if p.get("on_boundary", True)]
    area = geojson.area(boundary, result["reference"])
    result["outline"] = area.to_dict()
    if exact:
        result["ground_track"] = ground_track_at(study, result["reference"])
        shifted = deps.answer_now(request, "transform", common | {"points": points, "earth_rotation": "approximate"})
        result["approximate_error_nmi"] = shift_error_nmi(item["points"], shifted["points"], boundary)
    elif item["ground_track"]:
        track = [
            {"latitude_deg": t["latitude_deg"], "longitude_deg": t["longitude_deg"], "flight_time_s": t["time_s"]}
            for t in item["ground_track"]
        ]
        moved = deps.answer_now(request, "transform", common | {"points": track, "mirror": False})
        result["ground_track"] = [
            {"latitude_deg": p["latitude_deg"], "longitude_deg": p["longitude_deg"], "time_s": p.get("flight_time_s")}
            for p in moved["points"]
        ]
    moved_item = item | {
        "points": boundary,
        "ground_track": result.get("ground_track", []),
        "entry": item["entry"] | result["reference"],
    }
    result["geojson"] = geojson.feature_collection(moved_item, area)  # the same GeoJSON as the stored footprint's
    return result
