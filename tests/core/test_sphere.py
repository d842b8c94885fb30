"""core.sphere's longitude conventions at their edges, unwrapping round trips, the half closed along the axis
and the initial great circle. Expected values are written out by hand (not the code's own outputs); the values
are multiples of 1/4 deg, so every sum is exact and equality is asserted exactly."""

import numpy as np
import pytest

from footprint.core.sphere import (
    Reference,
    close_half_along_axis,
    great_circle,
    unit_vectors,
    unwrap_longitude,
    wrap_longitude,
)

UNIT_VECTOR_TOL = 1e-15  # a few ulps of a coordinate of a unit vector


@pytest.mark.parametrize(
    "lon, expected",
    [
        (-180.0, -180.0),
        (180.0, -180.0),
        (540.0, -180.0),
        (-540.0, -180.0),  # [-180, 180): +180 becomes -180
        (0.0, 0.0),
        (179.75, 179.75),
        (-179.75, -179.75),
        (190.0, -170.0),
        (-190.0, 170.0),
        (359.0, -1.0),
        (720.25, 0.25),
        (-1080.5, -0.5),
    ],
)
def test_wrap_is_half_open_above_by_default(lon, expected):
    assert float(wrap_longitude(lon)) == expected


@pytest.mark.parametrize(
    "lon, expected",
    [
        (-180.0, 180.0),
        (180.0, 180.0),
        (540.0, 180.0),
        (-540.0, 180.0),  # (-180, 180]: -180 becomes +180
        (0.0, 0.0),
        (179.75, 179.75),
        (-179.75, -179.75),
        (190.0, -170.0),
        (-190.0, 170.0),
    ],
)
def test_wrap_closed_above_keeps_plus_180(lon, expected):
    assert float(wrap_longitude(lon, closed_above=True)) == expected


@pytest.mark.parametrize(
    "lon, center, expected, expected_closed_above",
    [
        (10.0, 360.0, 370.0, 370.0),
        (-170.0, 180.0, 190.0, 190.0),
        (0.0, 180.0, 0.0, 360.0),  # the window [0, 360) about 180, or (0, 360]
        (360.0, 180.0, 0.0, 360.0),
        (-90.0, -90.0, -90.0, -90.0),
        (90.0, -90.0, -270.0, 90.0),  # the window [-270, 90) about -90, or (-270, 90]
    ],
)
def test_wrap_about_a_centre(lon, center, expected, expected_closed_above):
    assert float(wrap_longitude(lon, center)) == expected
    assert float(wrap_longitude(lon, center, closed_above=True)) == expected_closed_above


def test_wrap_keeps_the_shape_of_an_array():
    lon = np.array([[-180.0, 180.0], [540.0, -540.0]])
    assert wrap_longitude(lon).tolist() == [[-180.0, -180.0], [-180.0, -180.0]]
    assert wrap_longitude(lon, closed_above=True).tolist() == [[180.0, 180.0], [180.0, 180.0]]


def test_unwrap_makes_a_path_across_the_antimeridian_continuous():
    assert unwrap_longitude([170.0, -170.0, -150.0]).tolist() == [170.0, 190.0, 210.0]  # the first as given
    assert unwrap_longitude([-170.0, 170.0, 150.0]).tolist() == [-170.0, -190.0, -210.0]
    assert unwrap_longitude([170.0, -170.0, -150.0], 0.0).tolist() == [170.0, 190.0, 210.0]
    assert unwrap_longitude([10.0, 20.0, -170.0], 360.0).tolist() == [370.0, 380.0, 550.0]  # first near 360
    assert unwrap_longitude([190.0, -170.0], 0.0).tolist() == [-170.0, -170.0]
    assert unwrap_longitude([], 0.0).tolist() == []


@pytest.mark.parametrize("reference_deg", [None, 0.0, 180.0, -400.0])
def test_unwrap_round_trips_through_wrap(reference_deg):
    rng = np.random.default_rng(14)
    steps = 0.25 * rng.integers(-679, 680, 400)  # steps of less than 170 deg, in quarter degrees
    path = -720.0 + np.cumsum(steps)  # a continuous path, many turns round
    given = wrap_longitude(path)  # what a caller holds: the path wrapped, with jumps of 360 deg
    edges = np.array([-180.0, 180.0, 540.0, -540.0, 179.75, -179.75])
    for lon in (given, edges):
        unwrapped = unwrap_longitude(lon, reference_deg)
        assert np.array_equal(wrap_longitude(unwrapped), wrap_longitude(lon))
        assert np.all(np.abs(np.diff(unwrapped)) <= 180.0)
    if reference_deg is not None:
        assert abs(unwrap_longitude(given, reference_deg)[0] - reference_deg) <= 180.0
    assert np.array_equal(np.diff(unwrap_longitude(given, reference_deg)), steps[1:])  # the path's own steps


def test_a_half_is_closed_along_the_axis_and_a_whole_boundary_is_not():
    left = [(500.0, 10.0, 1.0), (2000.0, 800.0, 2.0), (9000.0, 0.0, 3.0)]
    assert close_half_along_axis(left) == [(500.0, 0.0, 1.0)] + left + [(9000.0, 0.0, 3.0)]
    right = [(600.0, -10.0), (5000.0, -1500.0)]
    assert close_half_along_axis(right) == [(600.0, 0.0)] + right + [(5000.0, 0.0)]
    whole = [(500.0, 0.0), (2000.0, 800.0), (9000.0, 0.0), (2000.0, -800.0)]
    assert close_half_along_axis(whole) == whole


def test_unit_vectors_broadcast_and_the_initial_great_circle():
    np.testing.assert_allclose(
        unit_vectors(0.0, [0.0, 90.0, 180.0]), [[1, 0, 0], [0, 1, 0], [-1, 0, 0]], atol=UNIT_VECTOR_TOL
    )
    np.testing.assert_allclose(unit_vectors([90.0, -90.0], 0.0), [[0, 0, 1], [0, 0, -1]], atol=UNIT_VECTOR_TOL)
    # eastbound from (0, 0): the equator; northbound: the meridian of Greenwich
    np.testing.assert_allclose(
        great_circle(Reference(0.0, 0.0, 90.0), [0.0, 90.0, 180.0]),
        [[1, 0, 0], [0, 1, 0], [-1, 0, 0]],
        atol=UNIT_VECTOR_TOL,
    )
    np.testing.assert_allclose(
        great_circle(Reference(0.0, 0.0, 0.0), [90.0, -90.0]), [[0, 0, 1], [0, 0, -1]], atol=UNIT_VECTOR_TOL
    )
