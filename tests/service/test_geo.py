"""GeoJSON geometry near the antimeridian and over the poles: rings and lines cut there, in either direction,
nothing lost; a polar cap taken in along its pole; a ring that holds both poles a hole in the map."""

import numpy as np
import pytest

from footprint.core.outline import POLES, Outline, window_area
from footprint.pictures import geojson as geo


def ring(lat, lon):
    """The outline of a ring given open, the area on its left: closed by its first point, as many turns round the
    axis on as its longitudes make."""
    lat, lon = np.array(lat, float), np.array(lon, float)
    turns = round((lon[-1] + (lon[1] - lon[0]) - lon[0]) / 360.0) if abs(lon[-1] - lon[0]) > 180 else 0
    area, north, south = window_area(np.append(lat, lat[0]), np.append(lon, lon[0] + 360.0 * turns))
    return Outline(lat, lon, area, POLES[north, south])


def shoelace(ring) -> float:
    x, y = np.array(ring, float).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_a_ring_near_but_not_across_the_antimeridian_stays_one_polygon():
    geometry = geo.polygon(ring([0, 0, 10, 10], [170, 179.5, 179.5, 170]))
    assert geometry == {"type": "Polygon", "coordinates": [[[170, 0], [179.5, 0], [179.5, 10], [170, 10], [170, 0]]]}


def test_a_ring_across_the_antimeridian_is_cut_into_two_pieces():
    geometry = geo.polygon(ring([0, 0, 20, 20], [170, 190, 190, 170]))  # a 20-deg box centred on 180, anticlockwise
    assert geometry["type"] == "MultiPolygon"
    pieces = sorted((poly[0] for poly in geometry["coordinates"]), key=lambda r: r[0][0])
    assert [shoelace(r) for r in pieces] == pytest.approx([200.0, 200.0])  # 10 deg x 20 deg each
    assert {x for x, _ in pieces[0]} == {-180.0, -170.0} and {x for x, _ in pieces[1]} == {170.0, 180.0}


def test_a_polar_cap_is_cut_at_the_antimeridian_and_closed_along_its_pole():
    # a ring along 60 N from 30 E eastward once round: the cap on its left, above it
    o = ring([60.0] * 12, list(np.linspace(30.0, 360.0, 12, endpoint=False)))
    geometry = geo.polygon(o)
    assert o.pole == "north" and geometry["type"] == "Polygon"  # one piece from -180 to 180, along the pole
    (cap,) = geometry["coordinates"]
    assert min(x for x, _ in cap) == -180.0 and max(x for x, _ in cap) == 180.0
    assert [-180.0, 90.0] in cap and [180.0, 90.0] in cap
    assert shoelace(cap) == pytest.approx(360.0 * 30.0)  # the whole cap, once


def test_the_same_ring_run_westward_holds_the_rest_of_the_earth_and_the_south_pole():
    o = ring([60.0] * 12, list(np.linspace(390.0, 60.0, 12, endpoint=False)))
    geometry = geo.polygon(o)
    assert o.pole == "south" and geometry["type"] == "Polygon"
    (rest,) = geometry["coordinates"]
    assert [-180.0, -90.0] in rest and [180.0, -90.0] in rest
    assert shoelace(rest) == pytest.approx(360.0 * 150.0)


def test_a_clockwise_ring_is_a_hole_in_the_map_that_holds_both_poles():
    o = ring([0, 20, 20, 0], [-10, -10, 10, 10])
    geometry = geo.polygon(o)
    assert o.pole == "both" and geometry["type"] == "Polygon"
    world, hole = geometry["coordinates"]
    assert shoelace(world) == pytest.approx(360.0 * 180.0) and shoelace(hole) == pytest.approx(400.0)


@pytest.mark.parametrize(
    "lon, crossing_lat",
    [
        ([175.0, 178.0, -179.0, -176.0], 5.0),  # eastward: 180 lies 2 of the 3 deg from 178 to 181
        ([-176.0, -179.0, 178.0, 175.0], 4.0),  # westward: -180 lies 1 of the 3 deg from -179 to -182
    ],
)
def test_a_line_is_cut_where_it_crosses_either_way(lon, crossing_lat):
    lat = [0.0, 3.0, 6.0, 9.0]
    geometry = geo.line(lat, lon)
    assert geometry["type"] == "MultiLineString" and len(geometry["coordinates"]) == 2
    first, second = geometry["coordinates"]
    assert abs(first[-1][0]) == abs(second[0][0]) == 180.0 and first[-1][0] == -second[0][0]
    assert first[-1][1] == second[0][1] == pytest.approx(crossing_lat, abs=1e-12)
    assert [p for p in first[:-1] + second[1:]] == [[x, y] for x, y in zip(lon, lat)]
