"""Which sites a footprint reaches from which deorbit points (core/reach.py)."""

import math

import numpy as np
import pytest

from footprint.core.constants import FT_PER_NMI, OMEGA_EARTH_DEG_S
from footprint.core.orbits import CircularOrbit, frames, position
from footprint.core.reach import margins, margins_reference, placement_margins, reach
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, latlon_from_ranges, unit_vectors

R_NMI = MEAN_RADIUS_NMI
# A small convex footprint about its reference: down-range, cross-range (nmi), flight time (s).
SMALL = np.array(
    [
        (1300.0, 0.0, 1900.0),
        (1250.0, 90.0, 1850.0),
        (1120.0, 150.0, 1700.0),
        (1000.0, 160.0, 1500.0),
        (900.0, 100.0, 1400.0),
        (860.0, 0.0, 1300.0),
        (900.0, -100.0, 1400.0),
        (1000.0, -160.0, 1500.0),
        (1120.0, -150.0, 1700.0),
        (1250.0, -90.0, 1850.0),
    ]
)
# A diamond on the initial great circle from 1,000 to 5,000 nmi.
DIAMOND = np.array([(5000.0, 0.0, 3000.0), (3000.0, 500.0, 2000.0), (1000.0, 0.0, 1000.0), (3000.0, -500.0, 2000.0)])
# The shape of the L/D 1.89 footprint (Table 2 entry, inertial speed, non-rotating earth), rounded: it
# reaches past half the circumference (pi R' = 10,807 nmi).
LOD189 = np.array(
    [
        (15202, 0, 4779),
        (14690, 852, 4652),
        (13366, 1459, 4326),
        (11418, 1880, 3852),
        (8999, 2138, 3275),
        (6337, 2227, 2649),
        (4044, 2118, 2105),
        (2645, 1778, 1730),
        (1908, 1279, 1445),
        (1554, 739, 1170),
        (1404, 20, 338),
        (1404, -20, 338),
        (1554, -739, 1169),
        (1908, -1279, 1445),
        (2645, -1778, 1730),
        (4044, -2118, 2105),
        (6337, -2227, 2649),
        (8999, -2138, 3275),
        (11418, -1880, 3852),
        (13366, -1459, 4326),
        (14690, -852, 4652),
    ],
    float,
)


def cols(poly):
    return poly[:, 0], poly[:, 1], poly[:, 2]


def assert_same_windows(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert (x.site, x.revolution, x.u_start_deg, x.u_end_deg, x.samples) == (
            y.site,
            y.revolution,
            y.u_start_deg,
            y.u_end_deg,
            y.samples,
        )
        assert x.max_margin_nmi == pytest.approx(y.max_margin_nmi, abs=1e-6)  # nmi, rounding
        assert (x.deorbit_time_start_s, x.deorbit_time_end_s) == pytest.approx(
            (y.deorbit_time_start_s, y.deorbit_time_end_s), abs=1e-6
        )


def test_a_site_at_a_footprint_point_is_on_the_boundary_and_a_nudge_decides():
    ref = Reference(latitude_deg=30.0, longitude_deg=-100.0, heading_deg=60.0)
    d, c, t = cols(SMALL)
    centre = np.array([d.mean(), c.mean()])
    for dv, cv in zip(d, c):
        toward = (centre - (dv, cv)) / np.hypot(*(centre - (dv, cv)))
        at = latlon_from_ranges(dv, cv, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
        m, inside = placement_margins(ref, d, c, t, *at)
        assert inside[0] and abs(m[0]) < 1e-6  # nmi: on the boundary counts as inside
        for nudge_nmi, expect in ((0.5, True), (-0.5, False)):
            dn, cn = np.array([dv, cv]) + nudge_nmi * toward
            m, inside = placement_margins(
                ref, d, c, t, *latlon_from_ranges(dn, cn, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
            )
            assert inside[0] == expect
            assert (m[0] > 0) == expect and 0.05 < abs(m[0]) <= 0.5 + 1e-6  # nmi, a nudge at a convex corner


def test_the_footprint_reaches_past_half_the_circumference():
    ref = Reference(0.0, 0.0, 90.0)  # east along the equator
    d, c, t = cols(LOD189)
    lon = np.array([120.0, -120.0, -30.0, 20.0, 179.0])  # -120 deg is 240 deg = 14,400 nmi down-range
    m, inside = placement_margins(ref, d, c, t, np.zeros_like(lon), lon)
    assert list(inside) == [True, True, False, False, True]
    arc_nmi = np.radians([120.0, 240.0, 330.0, 20.0, 179.0]) * R_NMI
    gap = 15202.0 - arc_nmi[1]  # short of the front vertex; the nearest edge runs to (14,690, 852)
    assert m[1] == pytest.approx(gap * 852.0 / math.hypot(512.0, 852.0), abs=1e-6)  # nmi
    assert m[3] == pytest.approx(arc_nmi[3] - 1404.0, abs=1.0)  # nmi, short of the back edge (negative)
    assert m[3] < 0.0


def test_a_site_on_the_ground_track_is_reached_over_the_analytic_u_window():
    """No earth rotation, no regression: the track is one great circle and a site on it at u_s is reached from
    u_s - 5,000/R' to u_s - 1,000/R' (radians): 116.73 to 183.35 deg, a width of 66.6 deg."""
    orbit = CircularOrbit(
        40.0, 100 * FT_PER_NMI, node_longitude_deg=25.0, rotation_rate_deg_s=0.0, nodal_regression=False
    )
    lat, lon = position(orbit, 1, 200.0)
    d, c, t = cols(DIAMOND)
    r = reach(d, c, t, [lat], [lon], orbit, [1, 2], u_step_deg=1.0, earth_rotation="none")
    first, last = 200.0 - math.degrees(5000.0 / R_NMI), 200.0 - math.degrees(1000.0 / R_NMI)
    assert (first, last) == pytest.approx((116.73, 183.35), abs=0.01)
    assert [(w.revolution, w.u_start_deg, w.u_end_deg) for w in r.windows] == [(1, 117.0, 183.0), (2, 117.0, 183.0)]
    w = r.windows[0]
    assert w.u_end_deg - w.u_start_deg == pytest.approx(math.degrees(4000.0 / R_NMI), abs=1.0)  # deg, one step
    assert w.samples == 67
    assert w.max_margin_nmi == pytest.approx(500.0 * 2000.0 / math.hypot(2000.0, 500.0), abs=5.0)  # centre
    assert w.deorbit_time_start_s == pytest.approx(117.0 / 360.0 * orbit.period_s)
    assert r.passes(0) == [[r.windows[0]], [r.windows[1]]]
    rotated_off = reach(d, c, 0 * t, [lat], [lon], orbit, [1, 2], earth_rotation="approximate")
    assert rotated_off.windows == r.windows  # zero flight times: nothing to shift


def test_a_window_across_the_node_is_one_pass():
    orbit = CircularOrbit(40.0, 100 * FT_PER_NMI, rotation_rate_deg_s=0.0, nodal_regression=False)
    lat, lon = position(orbit, 1, 30.0)  # reached from u = 30 - 83.3 to 30 - 16.7: across the node
    d, c, t = cols(DIAMOND)
    r = reach(d, c, t, [lat], [lon], orbit, [1, 2, 3], earth_rotation="none")
    got = [(w.revolution, w.u_start_deg, w.u_end_deg) for w in r.windows]
    assert got == [
        (1, 0.0, 13.0),
        (1, 307.0, 359.0),
        (2, 0.0, 13.0),
        (2, 307.0, 359.0),
        (3, 0.0, 13.0),
        (3, 307.0, 359.0),
    ]
    assert [len(p) for p in r.passes(0)] == [1, 2, 2, 1]
    cut = reach(d, c, t, [lat], [lon], orbit, [1, 2, 3], earth_rotation="none", time_span_s=1.5 * orbit.period_s)
    assert [(w.revolution, w.u_start_deg) for w in cut.windows] == [(1, 0.0), (1, 307.0), (2, 0.0)]
    assert np.isnan(cut.margin_nmi[2]).all() and not cut.inside[2].any()


def test_the_date_line_changes_nothing():
    """Sites at 179.9 E and 179.9 W, and the same geometry turned 40 deg east about the polar axis."""
    lats = np.array([10.0, 10.0, 35.0, 35.0, -20.0, -20.0, 51.0])
    lons = np.array([179.9, -179.9, 179.9, -179.9, 179.9, -179.9, -179.95])
    d, c, t = cols(LOD189)
    for rotation in ("none", "approximate"):
        near = CircularOrbit(51.6, 120 * FT_PER_NMI, node_longitude_deg=150.0)
        away = CircularOrbit(51.6, 120 * FT_PER_NMI, node_longitude_deg=-170.0)
        a = reach(d, c, t, lats, lons, near, range(1, 17), earth_rotation=rotation)
        b = reach(d, c, t, lats, (lons + 40.0 + 180.0) % 360.0 - 180.0, away, range(1, 17), earth_rotation=rotation)
        np.testing.assert_allclose(a.margin_nmi, b.margin_nmi, atol=1e-6)  # nmi
        assert_same_windows(a.windows, b.windows)
        assert len(a.windows) > 10
        for i in (0, 2, 4):  # 0.2 deg of longitude apart: near the boundary, margins within their distance
            near = np.abs(a.margin_nmi[..., i]) < 300.0
            gap = np.abs(a.margin_nmi[..., i] - a.margin_nmi[..., i + 1])[near]
            assert near.sum() > 20
            assert gap.max() <= 0.2 * 60.04 * math.cos(math.radians(lats[i])) * 1.01  # nmi, chart metric 1 %


def test_near_the_pole_a_polar_orbit_matches_the_same_geometry_on_the_equator():
    """Turn the earth -90 deg about the x axis, (x, y, z) -> (x, z, -y): the polar orbit with its node at 0
    becomes the equatorial orbit, and sites about the north pole become sites on the equator near 90 E."""
    polar = CircularOrbit(90.0, 100 * FT_PER_NMI, rotation_rate_deg_s=0.0, nodal_regression=False)
    equatorial = CircularOrbit(0.0, 100 * FT_PER_NMI, rotation_rate_deg_s=0.0, nodal_regression=False)
    lats = np.array([89.9, 89.9, 89.9, 89.99, 90.0, 88.0, 85.0])
    lons = np.array([0.0, 90.0, 180.0, -45.0, 0.0, 120.0, -100.0])
    v = unit_vectors(lats, lons)
    w = np.stack([v[:, 0], v[:, 2], -v[:, 1]], axis=-1)
    lat2, lon2 = np.degrees(np.arcsin(w[:, 2])), np.degrees(np.arctan2(w[:, 1], w[:, 0]))
    d, c, t = cols(SMALL * [2.0, 3.0, 1.0])
    a = reach(d, c, t, lats, lons, polar, [1], u_step_deg=0.5, earth_rotation="none")
    b = reach(d, c, t, lat2, lon2, equatorial, [1], u_step_deg=0.5, earth_rotation="none")
    np.testing.assert_allclose(a.margin_nmi, b.margin_nmi, atol=1e-6)  # nmi
    assert_same_windows(a.windows, b.windows)
    # the pole, 90 deg round from the node, is reached from u = 90 - 2,600/R' to 90 - 1,720/R' (radians)
    pole = [(x.u_start_deg, x.u_end_deg) for x in a.windows if x.site == 4]
    assert pole == [(47.0, 61.0)]
    assert (90.0 - math.degrees(2600.0 / R_NMI), 90.0 - math.degrees(1720.0 / R_NMI)) == pytest.approx(
        (46.70, 61.35), abs=0.01
    )


def test_margins_agree_with_great_circle_distances_to_a_dense_boundary():
    ref = Reference(latitude_deg=45.0, longitude_deg=10.0, heading_deg=30.0)
    d, c, t = cols(SMALL)
    rng = np.random.default_rng(3)
    sd = rng.uniform(600.0, 1600.0, 300)
    sc = rng.uniform(-450.0, 450.0, 300)
    slat, slon = latlon_from_ranges(sd, sc, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    m, inside = placement_margins(ref, d, c, t, slat, slon)
    s = np.linspace(0.0, 1.0, 400, endpoint=False)
    bd = np.concatenate([d0 + s * (d1 - d0) for d0, d1 in zip(d, np.roll(d, -1))])
    bc = np.concatenate([c0 + s * (c1 - c0) for c0, c1 in zip(c, np.roll(c, -1))])
    blat, blon = latlon_from_ranges(bd, bc, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    dots = np.clip(unit_vectors(slat, slon) @ unit_vectors(blat, blon).T, -1.0, 1.0)
    brute = np.arccos(dots).min(axis=1) * R_NMI
    near = brute < 300.0
    assert near.sum() > 150 and inside.sum() > 40
    np.testing.assert_array_less(np.abs(np.abs(m) - brute)[near], 0.5)  # nmi: 0.3 at 300 nmi, second order
    assert np.all((m > 0) == inside)


def test_earth_rotation_moves_the_windows_the_way_the_shift_says():
    """Eastward on the equator the footprint's points land omega_p t further west, so the deorbit point must
    be that much further east: later by omega_p t / (1 - omega_p T / 360 deg) in u. Westward, earlier."""
    d, c, t = cols(DIAMOND)
    for inclination, sense in ((0.0, 1.0), (180.0, -1.0)):
        orbit = CircularOrbit(inclination, 100 * FT_PER_NMI, nodal_regression=False)
        lat, lon = position(orbit, 1, 200.0)
        kw = dict(sites_lat=[lat], sites_lon=[lon], orbit=orbit, revolutions=[1], u_step_deg=0.25)
        none = reach(d, c, t, earth_rotation="none", **kw).windows
        shifted = reach(d, c, t, earth_rotation="approximate", **kw).windows
        assert len(none) == len(shifted) == 1
        ground_rate = 1.0 + sense * -OMEGA_EARTH_DEG_S * orbit.period_s / 360.0  # track deg per u deg, signed
        front = OMEGA_EARTH_DEG_S * 3000.0 / ground_rate  # the 5,000 nmi point, 3,000 s
        back = OMEGA_EARTH_DEG_S * 1000.0 / ground_rate  # the 1,000 nmi point, 1,000 s
        assert shifted[0].u_start_deg - none[0].u_start_deg == pytest.approx(sense * front, abs=0.5)
        assert shifted[0].u_end_deg - none[0].u_end_deg == pytest.approx(sense * back, abs=0.5)


def test_the_vectorized_kernel_matches_the_plain_python_loop():
    orbit = CircularOrbit(63.4, 150 * FT_PER_NMI, node_longitude_deg=-170.0)
    rng = np.random.default_rng(11)
    rev, u = rng.integers(1, 17, 40), rng.uniform(0.0, 360.0, 40)
    p0, d0, n, _ = frames(orbit, rev, u)
    lat, lon = rng.uniform(-89.0, 89.0, 25), rng.uniform(-180.0, 180.0, 25)
    for poly in (LOD189, SMALL):
        d, c, t = cols(poly)
        for shift in (0.0, OMEGA_EARTH_DEG_S):
            m, inside = margins(p0, d0, n, d, c, t, unit_vectors(lat, lon), shift)
            ref = margins_reference(list(zip(p0, d0, n)), d, c, t, list(zip(lat, lon)), shift)
            np.testing.assert_allclose(m, [[x[0] for x in row] for row in ref], atol=1e-8)  # nmi
            assert (inside == np.array([[x[1] for x in row] for row in ref])).all()
    assert inside.any() and not inside.all()


def test_chunks_do_not_change_the_answer():
    orbit = CircularOrbit(28.5, 100 * FT_PER_NMI)
    d, c, t = cols(LOD189)
    lat, lon = [28.5, -33.9, 51.5], [-80.6, 18.6, -0.1]
    a = reach(d, c, t, lat, lon, orbit, range(1, 4), u_step_deg=2.0)
    b = reach(d, c, t, lat, lon, orbit, range(1, 4), u_step_deg=2.0, chunk_elements=1)
    np.testing.assert_allclose(a.margin_nmi, b.margin_nmi, atol=1e-9)  # nmi: only the rounding of a matmul
    assert_same_windows(a.windows, b.windows)


def test_an_unknown_earth_rotation_is_refused():
    with pytest.raises(ValueError, match="earth_rotation"):
        reach(*cols(SMALL), [0.0], [0.0], CircularOrbit(28.5, 600_000.0), [1], earth_rotation="exact")


def test_progress_rises_over_the_placements_and_a_true_answer_stops():
    """A reach job reported nothing until it ended, and a cancel could not stop it but by restarting its worker."""
    from footprint.core.errors import Stopped

    orbit = CircularOrbit(28.5, 100 * FT_PER_NMI)
    d, c, t = cols(LOD189)
    reports = []
    full = reach(
        d,
        c,
        t,
        [28.5],
        [-80.6],
        orbit,
        range(1, 4),
        u_step_deg=2.0,
        chunk_elements=len(d) * 40,
        on_progress=lambda f, note: reports.append((f, note)) and False,
    )
    placements = 3 * 180
    assert [f for f, _ in reports] == [a / placements for a in range(0, placements, 40)]
    assert reports[1][1] == "placement 40 of 540"
    assert_same_windows(full.windows, reach(d, c, t, [28.5], [-80.6], orbit, range(1, 4), u_step_deg=2.0).windows)
    asked = []
    with pytest.raises(Stopped, match="stopped at placement 80 of 540"):
        reach(
            d,
            c,
            t,
            [28.5],
            [-80.6],
            orbit,
            range(1, 4),
            u_step_deg=2.0,
            chunk_elements=len(d) * 40,
            on_progress=lambda f, note: asked.append(f) or len(asked) == 3,
        )
