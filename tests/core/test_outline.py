"""A footprint's outline on the map (core.outline, issue 13 defect 1) against the chart it is drawn from.

Two routes to "inside": the even-odd rule in the (down-range, cross-range) chart about the entry (reach's,
where the footprint's edges are straight and the poles need no care), and the even-odd rule in latitude and
longitude on the outline (what a cylindrical map fills, every copy 360 deg apart). They must agree everywhere
off the boundary, for footprints over either pole, across the antimeridian and past half-way round."""

import numpy as np
import pytest
from matplotlib.path import Path as PlanePath

from footprint.core.outline import outline
from footprint.core.reach import placement_margins
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference

HALF_ROUND_NMI = np.pi * MEAN_RADIUS_NMI


def oval(far_nmi, half_width_nmi, near_nmi=300.0, n=41):
    """A footprint-like boundary: from near_nmi to far_nmi down-range, half_width_nmi across at its widest."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    mid, half = 0.5 * (far_nmi + near_nmi), 0.5 * (far_nmi - near_nmi)
    return mid + half * np.cos(t), half_width_nmi * np.sin(t)


def planar_inside(o, lat, lon):
    """The even-odd rule in longitude and latitude on the outline's area (its one copy of the map, -180..180)."""
    xy = np.column_stack([(np.asarray(lon, float) + 180.0) % 360.0 - 180.0, lat])
    inside = np.zeros(len(xy), bool)
    for polygon in o.area:
        hit = np.zeros(len(xy), bool)
        for ring in polygon:
            hit ^= PlanePath(ring).contains_points(xy)
        inside |= hit
    return inside


GLOBE = np.array([(la, lo) for la in np.arange(-89.0, 90.0, 2.0) for lo in np.arange(-179.0, 180.0, 3.0)])
CASES = {
    "north over the pole": (Reference(40.0, 10.0, 0.0), oval(6_000.0, 1_500.0), "north"),
    "south over the pole": (Reference(-40.0, -100.0, 180.0), oval(6_000.0, 1_500.0), "south"),
    "north-east across the antimeridian": (Reference(28.5, 150.0, 60.0), oval(10_000.0, 1_700.0), None),
    "L/D 1.89 past half-way round": (Reference(0.0, 0.0, 90.0), oval(15_300.0, 2_100.0, 580.0), None),
    "polar orbit past half-way round": (Reference(-10.0, -60.0, 0.0), oval(15_300.0, 2_100.0, 580.0), "north"),
}


@pytest.mark.parametrize("name", CASES)
def test_the_map_fills_what_the_chart_holds(name):
    reference, (down, cross), pole = CASES[name]
    o = outline(down, cross, reference)
    assert o.pole == pole
    assert np.all(np.abs(np.diff(o.longitude_deg)) <= 180.0)  # the line: continuous on the cylindrical map
    assert all(-180.0 <= ring[:, 0].min() and ring[:, 0].max() <= 180.0 for p in o.area for ring in p)
    margin, chart = placement_margins(reference, down, cross, np.zeros(len(down)), GLOBE[:, 0], GLOBE[:, 1])
    clear = np.abs(margin) > 40.0  # nmi: off the boundary, where the drawn edge may differ by a pixel
    plane = planar_inside(o, GLOBE[:, 0], GLOBE[:, 1])
    assert chart[clear].sum() > 30  # the test sees the footprint's inside
    np.testing.assert_array_equal(plane[clear], chart[clear])


def test_the_polar_cap_is_inside_and_the_far_hemisphere_is_not():
    reference, (down, cross), _ = CASES["north over the pole"]
    o = outline(down, cross, reference)
    # across the pole from the entry (its meridian + 180 deg) and beside it, against the other hemisphere
    lat, lon = np.array([89.5, 85.0, 80.0, -60.0, 20.0]), np.array([-170.0, 100.0, 190.0 - 360.0, 10.0, 100.0])
    assert planar_inside(o, lat, lon).tolist() == [True, True, True, False, False]
    _, chart = placement_margins(reference, down, cross, np.zeros(len(down)), lat, lon)
    assert chart.tolist() == [True, True, True, False, False]  # reach agrees (core: issue 13 "Must show")


def test_an_outline_keeps_the_boundary_points_and_follows_the_chart_edges():
    reference, (down, cross), _ = CASES["north-east across the antimeridian"]
    o = outline(down, cross, reference, max_edge_nmi=50.0)
    from footprint.core.sphere import downrange_crossrange_nmi

    d, c = downrange_crossrange_nmi(
        o.latitude_deg,
        o.longitude_deg,
        reference.latitude_deg,
        reference.longitude_deg,
        reference.heading_deg,
        unwrap=True,
    )
    assert len(o.latitude_deg) > 5 * len(down)
    # every sample lies on a chart edge: its distance to the polygon's edges is round-off
    ring = np.column_stack([np.append(down, down[0]), np.append(cross, cross[0])])
    a, b = ring[:-1], ring[1:]
    p = np.column_stack([d, c])[:, None, :]
    t = np.clip(np.sum((p - a) * (b - a), axis=2) / np.sum((b - a) ** 2, axis=1), 0.0, 1.0)
    gap = np.min(np.linalg.norm(p - (a + t[..., None] * (b - a)), axis=2), axis=1)
    assert gap.max() < 1e-6
