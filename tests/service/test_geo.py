"""GeoJSON geometry near the antimeridian and over the poles: rings and lines cut there, in either direction,
nothing lost; a polar cap closed along its pole."""

import numpy as np
import pytest

from footprint.core.outline import Outline
from footprint.pictures import geojson as geo


def ring(lat, lon, pole=None):
    return Outline(np.array(lat, float), np.array(lon, float), pole)


def shoelace(ring) -> float:
    x, y = np.array(ring, float).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_a_ring_near_but_not_across_the_antimeridian_stays_one_polygon():
    geometry = geo.polygon(ring([0, 10, 10, 0], [170, 170, 179.5, 179.5]))
    assert geometry == {"type": "Polygon",
                        "coordinates": [[[170, 0], [170, 10], [179.5, 10], [179.5, 0], [170, 0]]]}


def test_a_ring_across_the_antimeridian_is_cut_into_two_pieces():
    geometry = geo.polygon(ring([0, 0, 20, 20], [170, 190, 190, 170]))  # a 20-deg box centred on 180
    assert geometry["type"] == "MultiPolygon"
    pieces = sorted((poly[0] for poly in geometry["coordinates"]), key=lambda r: r[0][0])
    assert [shoelace(r) for r in pieces] == pytest.approx([200.0, 200.0])  # 10 deg x 20 deg each
    assert {x for x, _ in pieces[0]} == {-180.0, -170.0} and {x for x, _ in pieces[1]} == {170.0, 180.0}


def test_a_polar_cap_is_cut_at_the_antimeridian_and_closed_along_the_pole():
    # a cap above 60 N drawn from 30 E once round to 390 E, closed along the pole
    lon = list(np.linspace(30.0, 390.0, 13)) + [390.0, 30.0]
    geometry = geo.polygon(ring([60.0] * 13 + [90.0, 90.0], lon, "north"))
    assert geometry["type"] == "MultiPolygon"
    pieces = [poly[0] for poly in geometry["coordinates"]]
    assert all(-180.0 <= x <= 180.0 for r in pieces for x, _ in r)
    assert all(any(y == 90.0 for _, y in r) for r in pieces)  # each piece reaches the pole
    assert sum(shoelace(r) for r in pieces) == pytest.approx(360.0 * 30.0)  # the whole cap, once


@pytest.mark.parametrize("lon, crossing_lat", [
    ([175.0, 178.0, -179.0, -176.0], 5.0),  # eastward: 180 lies 2 of the 3 deg from 178 to 181
    ([-176.0, -179.0, 178.0, 175.0], 4.0),  # westward: -180 lies 1 of the 3 deg from -179 to -182
])
def test_a_line_is_cut_where_it_crosses_either_way(lon, crossing_lat):
    lat = [0.0, 3.0, 6.0, 9.0]
    geometry = geo.line(lat, lon)
    assert geometry["type"] == "MultiLineString" and len(geometry["coordinates"]) == 2
    first, second = geometry["coordinates"]
    assert abs(first[-1][0]) == abs(second[0][0]) == 180.0 and first[-1][0] == -second[0][0]
    assert first[-1][1] == second[0][1] == pytest.approx(crossing_lat, abs=1e-12)
    assert [p for p in first[:-1] + second[1:]] == [[x, y] for x, y in zip(lon, lat)]
