"""GeoJSON for a footprint: its outline's area (core.outline: the chart's edges sampled, cut at the antimeridian into
pieces that each lie within -180..180 deg, RFC 7946 section 3.1.9, a pole taken in when the footprint holds it),
coordinates to 1e-6 deg (RFC 7946 section 11.2)."""

import numpy as np

from footprint.core.outline import Outline, outline
from footprint.core.sphere import Reference, unwrap_longitude, wrap_longitude

ANTIMERIDIAN_DEG = 180.0
DIGITS = 6  # decimals of a coordinate: 0.1 m


def area(points: list[dict], entry: dict) -> Outline:
    """The outline of a footprint's boundary points (their flown down-range and cross-range about the entry)."""
    return outline(
        [p["downrange_nmi"] for p in points],
        [p["crossrange_nmi"] for p in points],
        Reference(entry["latitude_deg"], entry["longitude_deg"], entry["heading_deg"]),
    )


def polygon(o: Outline) -> dict:
    """The outline's area (its pieces within -180..180 deg, core.outline) as a Polygon, or a MultiPolygon."""
    pieces = [[[[round(float(x), DIGITS), round(float(y), DIGITS)] for x, y in ring] for ring in p] for p in o.area]
    if len(pieces) == 1:
        return {"type": "Polygon", "coordinates": pieces[0]}
    return {"type": "MultiPolygon", "coordinates": pieces}


def line(lat_deg, lon_deg) -> dict:
    """A LineString, or a MultiLineString cut where it crosses the antimeridian."""
    lon, lat = unwrap_longitude(lon_deg), np.asarray(lat_deg, float)
    pieces, current, window = [], [], None
    for i in range(len(lon)):
        k = int(np.floor((lon[i] + ANTIMERIDIAN_DEG) / 360.0))
        if window is not None and k != window:  # close this piece and open the next on the crossing
            edge = ANTIMERIDIAN_DEG + 360.0 * min(k, window)
            t = (edge - lon[i - 1]) / (lon[i] - lon[i - 1])
            cross_lat = float(lat[i - 1] + t * (lat[i] - lat[i - 1]))
            current.append([edge - 360.0 * window, cross_lat])
            pieces.append(current)
            current = [[edge - 360.0 * k, cross_lat]]
        window = k
        current.append([float(lon[i] - 360.0 * k), float(lat[i])])
    pieces.append(current)
    pieces = [[[round(x, DIGITS), round(y, DIGITS)] for x, y in piece] for piece in pieces]
    if len(pieces) == 1:
        return {"type": "LineString", "coordinates": pieces[0]}
    return {"type": "MultiLineString", "coordinates": pieces}


def _point(p: dict) -> dict:
    return {
        "type": "Point",
        "coordinates": [round(float(wrap_longitude(p["longitude_deg"])), DIGITS), round(p["latitude_deg"], DIGITS)],
    }


def feature_collection(item: dict, outline_: Outline | None = None) -> dict:
    """The footprint (a stored footprint's JSON view, or a moved one) as GeoJSON features: boundary (its outline,
    where already made), entry, track, points."""
    pts, track, entry = item["points"], item["ground_track"], item["entry"]
    features = [
        {
            "type": "Feature",
            "geometry": polygon(outline_ or area(pts, entry)),
            "properties": {
                "kind": "footprint",
                "id": item["id"],
                "name": item["name"],
                "vehicle": item["vehicle"],
                "method": item["method"],
                "area_nmi2": item["area_nmi2"],
                "max_crossrange_nmi": item["max_crossrange_nmi"],
                "max_downrange_nmi": item["max_downrange_nmi"],
            },
        },
        {"type": "Feature", "geometry": _point(entry), "properties": {"kind": "entry", **entry}},
    ]
    if len(track) >= 2:
        features.append(
            {
                "type": "Feature",
                "geometry": line([t["latitude_deg"] for t in track], [t["longitude_deg"] for t in track]),
                "properties": {"kind": "ground_track", "flight_time_s": track[-1]["time_s"]},
            }
        )
    features += [
        {"type": "Feature", "geometry": _point(p), "properties": {"kind": "point", "index": i, **p}}
        for i, p in enumerate(pts)
    ]
    return {"type": "FeatureCollection", "features": features}


def _ring(shape: dict, entry: dict) -> Outline:
    """A dispersion's or a guided footprint's ring as its outline: the service's own where the result has one, else
    made from its ranges (an ellipse: closed, its first point repeated last)."""
    if "area" in shape.get("outline", {}):  # a result stored before issue 25 has no area: made again below
        return Outline.from_dict(shape["outline"])
    down, cross = shape["downrange_nmi"], shape["crossrange_nmi"]
    if down[0] == down[-1] and cross[0] == cross[-1]:
        down, cross = down[:-1], cross[:-1]
    return outline(down, cross, Reference(entry["latitude_deg"], entry["longitude_deg"], entry["heading_deg"]))


def dispersion_collection(result: dict) -> dict:
    """A dispersion's result (contracts.dispersion.to_dict) as GeoJSON features: the nominal footprint, each
    confidence footprint (one feature per piece), each flight's 1 and 3 sigma ellipses, the entry and each site
    with its probability. The landing clouds stay in the JSON (up to 10^5 points a flight)."""
    entry, samples = result["entry"], result["samples"]
    features = [
        {
            "type": "Feature",
            "geometry": polygon(_ring(result["nominal_boundary"], entry)),
            "properties": {"kind": "nominal_footprint", "samples": samples},
        },
        {"type": "Feature", "geometry": _point(entry), "properties": {"kind": "entry", **entry}},
    ]
    for c in result["confidence"]:
        features += [
            {
                "type": "Feature",
                "geometry": polygon(_ring(ring, entry)),
                "properties": {
                    "kind": "confidence_footprint",
                    "level": c["level"],
                    "piece": i,
                    "area_nmi2": ring["area_nmi2"],
                    "samples": samples,
                },
            }
            for i, ring in enumerate(c["rings"])
        ]
    for f in result["flights"]:
        about = {
            k: f[k] for k in ("parameter", "side", "landed", "mean_downrange_nmi", "mean_crossrange_nmi") if k in f
        }
        features += [
            {
                "type": "Feature",
                "geometry": polygon(_ring(shape, entry)),
                "properties": {"kind": "ellipse", "sigma": float(sigma), **about},
            }
            for sigma, shape in f.get("ellipses", {}).items()
        ]
    features += [
        {"type": "Feature", "geometry": _point(s), "properties": {"kind": "site", "samples": samples, **s}}
        for s in result["sites"]
    ]
    return {"type": "FeatureCollection", "features": features}


def guided_dispersion_collection(result: dict) -> dict:
    """A guided dispersion's result (contracts.guided_dispersion.to_dict) as GeoJSON features: the target with each
    mode's probability of ending within each radius of the interface circle, the circles bounding each band about it
    (interface range +- R), the nominal guided track, and
    each mode's 3-sigma landing ellipse. The landing clouds stay in the JSON."""
    t, entry = result["target"], result["entry"]
    within = {mode: result[mode]["within"] for mode in ("guided", "open_loop") if mode in result}
    features = [
        {"type": "Feature", "geometry": _point(entry), "properties": {"kind": "entry", **entry}},
        {"type": "Feature", "geometry": _point(t), "properties": {"kind": "target", **t, "within": within}},
        {
            "type": "Feature",
            "geometry": line(result["nominal_flight"]["latitude_deg"], result["nominal_flight"]["longitude_deg"]),
            "properties": {"kind": "nominal_guided_track", "miss_nmi": result["nominal"]["guidance"]["miss_nmi"]},
        },
    ]
    interface = t.get("interface_range_nmi", 0.0)  # within R of the interface circle: between its two circles
    for radius in result["radii_nmi"]:
        for side, about in (("outer", interface + radius), ("inner", interface - radius)):
            if about <= 0.0:
                continue
            lat, lon = circle(t["latitude_deg"], t["longitude_deg"], about)
            props = {"kind": "miss_circle", "radius_nmi": radius, "interface_range_nmi": interface, "side": side}
            features.append({"type": "Feature", "geometry": line(lat, lon), "properties": props})
    for mode in within:
        e = result[mode].get("landing", {}).get("ellipse_3sigma")
        if e is not None:
            features.append(
                {
                    "type": "Feature",
                    "geometry": line(e["latitude_deg"], e["longitude_deg"]),
                    "properties": {"kind": "ellipse", "mode": mode, "sigma": 3.0},
                }  # fmt: skip
            )
    return {"type": "FeatureCollection", "features": features}


GUIDED_FOOTPRINT_RINGS = ("optimal", "report", "nominal_guided", "guided")  # outermost first


def guided_footprint_collection(result: dict) -> dict:
    """A guided footprint (contracts.guided_footprint) as GeoJSON features: each ring (the true optimal and the
    report's footprints, the undispersed guided one and the guided one under dispersion) as a polygon with its area,
    the guided ring's properties holding the margins, and the entry."""
    entry = result["entry"]
    features = [{"type": "Feature", "geometry": _point(entry), "properties": {"kind": "entry", **entry}}]
    for name in GUIDED_FOOTPRINT_RINGS:
        ring = result.get(name)
        if ring is None:
            continue
        props = {"kind": f"{name}_footprint", "area_nmi2": ring["area_nmi2"]}
        if name == "guided":
            props |= {k: v for k, v in result.items() if k.startswith("margin_to_")} | {"settings": result["settings"]}
        features.append({"type": "Feature", "geometry": polygon(_ring(ring, entry)), "properties": props})
    return {"type": "FeatureCollection", "features": features}


def circle(lat_deg: float, lon_deg: float, radius_nmi: float, points: int = 73) -> tuple[np.ndarray, np.ndarray]:
    """A small circle of radius_nmi (on R') about a point: latitudes and longitudes, closed."""
    from footprint.core.sphere import MEAN_RADIUS_NMI, latlon_from_ranges

    t = np.linspace(0.0, 2.0 * np.pi, points)
    a = radius_nmi / MEAN_RADIUS_NMI  # the circle's angular radius, as down/cross-range about a local frame
    return latlon_from_ranges(
        MEAN_RADIUS_NMI * np.arctan2(np.sin(a) * np.cos(t), np.cos(a)),
        MEAN_RADIUS_NMI * np.arcsin(np.sin(a) * np.sin(t)),
        lat_deg, lon_deg, 0.0,
    )  # fmt: skip


def opportunities_collection(result: dict) -> dict:
    """Landing opportunities (contracts.opportunities) as GeoJSON features: the ground track of each revolution,
    and per opportunity its burn point, deorbit coast arc, entry point, footprint flown from that entry and site."""
    track = result["ground_track"]
    features = []
    revs = np.asarray(track["revolution"])
    for rev in np.unique(revs):
        at = revs == rev
        geometry = line(np.asarray(track["latitude_deg"])[at], np.asarray(track["longitude_deg"])[at])
        features.append(
            {"type": "Feature", "geometry": geometry, "properties": {"kind": "ground_track", "revolution": int(rev)}}
        )
    sites = result["sites"]
    for o in result["opportunities"]:
        about = {  # an answer stored before issue 52 lacks the revolution number, the margins by axis, the flag
            k: o.get(k)
            for k in (
                "site_name", "revolution", "revolution_number", "burn_utc", "entry_utc", "landing_utc", "margin_nmi",
                "downrange_margin_nmi", "crossrange_margin_nmi", "meets_rules", "burn_window_clipped",
            )
        }  # fmt: skip
        arc = np.asarray(o["coast_track"])
        burn_point = {"latitude_deg": arc[0, 0], "longitude_deg": arc[0, 1]}
        burn_alt = o.get("burn_altitude_ft")
        features += [
            {
                "type": "Feature",
                "geometry": _point(burn_point),
                "properties": {"kind": "burn", "delta_v_fps": o["delta_v_fps"], "altitude_ft": burn_alt, **about},
            },
            {"type": "Feature", "geometry": line(arc[:, 0], arc[:, 1]), "properties": {"kind": "coast", **about}},
            {"type": "Feature", "geometry": _point(o["entry"]), "properties": {"kind": "entry", **o["entry"], **about}},
            {
                "type": "Feature",
                "geometry": polygon(_ring(o["footprint_ring"], o["entry"])),
                "properties": {"kind": "footprint", **about},
            },
        ]
    for s in sites:
        features.append({"type": "Feature", "geometry": _point(s), "properties": {"kind": "site", **s}})
    return {"type": "FeatureCollection", "features": features}
