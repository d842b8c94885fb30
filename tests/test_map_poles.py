"""Footprints that hold none, one or both poles on the cylindrical map (issue 25 items 1 and 2).

The L/D 1.89 footprint (examples/footprint_lod189.json: the Table 2 entry, mirrored) reaches 14,869 nmi, past half
way round, and 2,024 nmi across: moved onto a polar orbit it holds both poles, onto a 60 deg one the north pole. Two
routes to "inside": the reach test on the sphere (core.reach.placement_margins, the even-odd rule in the chart about
the moved entry, every branch of the down-range), and the even-odd rule in longitude and latitude on the service's
GeoJSON polygon (what a cylindrical map fills). They must agree at every sample point more than 40 nmi off the
boundary, for every node, inclination and step, with the earth's rotation left out and with the report's shift
(Section IV.3)."""

import json
from pathlib import Path

import numpy as np
import pytest
from matplotlib.path import Path as PlanePath

from footprint import api, parallel
from footprint.core.reach import placement_margins
from footprint.core.sphere import Reference
from footprint.pictures import geojson

ROOT = Path(__file__).resolve().parents[1]
CLEAR_NMI = 40.0  # off the boundary by more than this: a drawn edge may differ from the chart's by a pixel
GRID = np.array([(a, b) for a in np.arange(-88.0, 90.0, 4.0) for b in np.arange(-177.0, 180.0, 6.0)])


@pytest.fixture(scope="module")
def flown():
    fp = api.footprint(json.loads((ROOT / "examples" / "footprint_lod189.json").read_text()))
    points = [
        {
            "latitude_deg": p.latitude_deg,
            "longitude_deg": p.longitude_deg,
            "flight_time_s": p.flight_time_s,
            "downrange_nmi": p.downrange_nmi,
        }
        for p in fp.points
    ]
    return fp.entry, points


def moved(flown, node_deg, inclination_deg, step_nmi, rotation):
    """The service's transform of the boundary (POST /api/footprints/{id}/transform's points): the reference, the
    moved ranges and the outline."""
    entry, points = flown
    result = parallel.run(
        "transform",
        {
            "from": entry,
            "to": {"node_longitude_deg": node_deg, "inclination_deg": inclination_deg, "argument_of_latitude_deg": 0.0},
            "step_downrange_nmi": step_nmi,
            "earth_rotation": rotation,
            "points": points,
        },
    )
    r = result["reference"]
    reference = Reference(r["latitude_deg"], r["longitude_deg"], r["heading_deg"])
    down, cross = [p["downrange_nmi"] for p in result["points"]], [p["crossrange_nmi"] for p in result["points"]]
    return reference, down, cross, geojson.area(result["points"], r)


def geojson_inside(geometry: dict, lat, lon) -> np.ndarray:
    """The even-odd rule on a GeoJSON Polygon or MultiPolygon (holes included), longitude and latitude planar."""
    polygons = [geometry["coordinates"]] if geometry["type"] == "Polygon" else geometry["coordinates"]
    xy = np.column_stack([lon, lat])
    inside = np.zeros(len(xy), bool)
    for rings in polygons:
        hit = np.zeros(len(xy), bool)
        for ring in rings:
            hit ^= PlanePath(np.asarray(ring, float)).contains_points(xy)
        inside |= hit
    return inside


def disagreements(flown, node_deg, inclination_deg, step_nmi, rotation, lat=GRID[:, 0], lon=GRID[:, 1]):
    reference, down, cross, o = moved(flown, node_deg, inclination_deg, step_nmi, rotation)
    margin, sphere = placement_margins(reference, down, cross, np.zeros(len(down)), lat, lon)
    drawn = geojson_inside(geojson.polygon(o), lat, lon)
    clear = np.abs(margin) > CLEAR_NMI
    return int(np.count_nonzero((drawn != sphere) & clear)), int(np.count_nonzero(sphere & clear)), o


POLES_LAT, POLES_LON = np.array([89.9, 89.9, -89.9, -89.9]), np.array([0.0, 180.0 - 1e-9, -90.0, 90.0])


def test_a_footprint_that_holds_both_poles_is_drawn_with_them_and_not_inverted(flown):
    """The issue's case: node -30 deg, inclination 90 deg, step 3,000 nmi. The outline said no pole and its polygon
    held (0, 0), outside the footprint, and left out (0, 150 E) and both poles, on the footprint's own track."""
    lat, lon = np.array([0.0, 0.0]), np.array([0.0, 150.0])
    reference, down, cross, o = moved(flown, -30.0, 90.0, 3_000.0, "none")
    assert o.pole == "both"
    drawn = geojson_inside(geojson.polygon(o), np.append(lat, POLES_LAT), np.append(lon, POLES_LON))
    assert drawn.tolist() == [False, True] + [True] * 4
    _, sphere = placement_margins(reference, down, cross, np.zeros(len(down)), lat, lon)
    assert sphere.tolist() == [False, True]  # the reach test agrees


def test_a_footprint_that_holds_one_pole_is_closed_along_its_own_edge_with_the_rotation_applied(flown):
    """The issue's case: node -170 deg, inclination 60 deg, step 0, the approximate rotation: the polygon held (10 N,
    58 E), (40 N, 55 E) and (60 N, 58 E), 2,100-3,100 nmi off the track, along a straight seam."""
    for rotation in ("approximate", "none"):
        bad, held, o = disagreements(flown, -170.0, 60.0, 0.0, rotation)
        assert o.pole == "north" and held > 100 and bad == 0, rotation
        drawn = geojson_inside(
            geojson.polygon(o), np.array([10.0, 40.0, 60.0, 89.9]), np.array([58.0, 55.0, 58.0, 0.0])
        )
        assert drawn.tolist() == [False, False, False, True], rotation


@pytest.mark.parametrize("rotation", ["none", "approximate"])
def test_every_node_inclination_and_step_is_drawn_as_the_sphere_holds_it(flown, rotation):
    """Every 30 deg of node, inclinations 0-180 deg by 15, steps to 20,000 nmi (nearly a circuit from the node)."""
    _sweep(flown, rotation, range(-180, 180, 30), range(0, 181, 15), (0.0, 3_000.0, 7_000.0, 12_000.0, 20_000.0))


def _sweep(flown, rotation, nodes, inclinations, steps):
    wrong, poles = [], set()
    for node in nodes:
        for inclination in inclinations:
            for step in steps:
                bad, held, o = disagreements(flown, node, inclination, step, rotation)
                poles.add(o.pole)
                assert held > 100  # the test sees the footprint's inside
                if bad:
                    wrong.append((node, inclination, step, o.pole, bad))
    assert not wrong, wrong
    assert poles == {None, "north", "south", "both"}  # every kind of footprint was met


def test_the_folium_map_fills_the_same_area(flown):
    """The standalone map (footprint map, GET /api/footprints/{id}/map) draws the moved footprint that holds both
    poles with the same area: its polygons on the main copy, even-odd, against the reach test."""
    import folium

    from footprint.pictures.folium_page import footprint_map

    entry, points = flown
    result = parallel.run(
        "transform",
        {
            "from": entry,
            "to": {"node_longitude_deg": -30.0, "inclination_deg": 90.0, "argument_of_latitude_deg": 0.0},
            "step_downrange_nmi": 3_000.0,
            "points": points,
        },
    )
    m = footprint_map({"name": "moved", "points": result["points"], "entry": result["reference"]})
    main = [
        [np.asarray(ring, float)[:, ::-1] for ring in child.locations]
        for child in m._children.values()
        if isinstance(child, folium.Polygon)
        and all(-180.0 <= lon <= 180.0 for ring in child.locations for _, lon in ring)
    ]
    drawn = geojson_inside(
        {"type": "MultiPolygon", "coordinates": [[r.tolist() for r in p] for p in main]}, GRID[:, 0], GRID[:, 1]
    )
    r = result["reference"]
    margin, sphere = placement_margins(
        Reference(r["latitude_deg"], r["longitude_deg"], r["heading_deg"]),
        [p["downrange_nmi"] for p in result["points"]],
        [p["crossrange_nmi"] for p in result["points"]],
        np.zeros(len(points)),
        GRID[:, 0],
        GRID[:, 1],
    )
    clear = np.abs(margin) > CLEAR_NMI
    assert sphere[clear].sum() > 100 and np.array_equal(drawn[clear], sphere[clear])
