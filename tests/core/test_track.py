"""A flight's track, taken for every row at once (issue 29 item 3: trajectory._track_terms, then numpy's atan2 over
the whole array): the geodetic latitude against Vermeille's closed form (J. Geodesy 76, 2002, pp. 451-454) and
against the per-row routine it replaced (frames.geodetic_from_ecef, Bowring's iteration), the longitude and heading
against frames' per-row routines, the ranges against sphere.downrange_crossrange_nmi of the latitudes and
longitudes; over a pole, across the antimeridian, past half-way round the earth and on a spherical earth."""

import copy
import math

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core.frames import flight_angles, geodetic_from_ecef
from footprint.core.integrate import R_VX, R_VY, R_VZ, R_X, R_Y, R_Z
from footprint.core.sphere import downrange_crossrange_nmi, wrap_longitude
from footprint.core.trajectory import _fly, simulate
from tests.authorities.report import example

TABLE2 = example("table2_lod22")
LOD189 = example("footprint_lod189")["case"]  # zero bank: 14,869 nmi, past half a circumference


def variant(base, entry=None, **changes):
    case = copy.deepcopy(base)
    case.update(changes)
    if entry:
        case["entry"].update(entry)
    return case


CASES = {
    "table2": TABLE2,
    "past half a circumference": LOD189,
    "over the north pole": variant(TABLE2, {"latitude_deg": 80.0, "heading_deg": 0.0}, bank={"law": "zero"}),
    "near the south pole, banked right": variant(
        TABLE2, {"latitude_deg": -84.0, "longitude_deg": -120.0, "heading_deg": 200.0}
    ),
    "across the antimeridian, westward": variant(
        TABLE2, {"latitude_deg": 30.0, "longitude_deg": -175.0, "heading_deg": 280.0}
    ),
    "spherical earth": variant(TABLE2, planet={"oblate": False}),
}
LATITUDE_TOL_DEG = 1e-12  # the brief's bound: the per-row routine reaches round-off in two iterations
HEADING_TOL_DEG = 1e-11  # round-off of atan2(east, north) on components of ~25,000 ft/s
RANGE_TOL_NMI = 1e-10  # round-off of 15,000-nmi ranges and their unwrapping (1 ulp of 15,000 nmi: 2e-12 nmi)


def vermeille_latitude_deg(x: float, y: float, z: float, a: float, b: float) -> float:
    """Geodetic latitude of an earth-fixed point on the ellipsoid of semi-axes a, b (Vermeille 2002, closed form:
    no iteration; valid outside the evolute, within about 44 km of the centre)."""
    e2 = 1.0 - (b / a) ** 2
    e4 = e2 * e2
    p = (x * x + y * y) / (a * a)
    q = (1.0 - e2) * z * z / (a * a)
    r = (p + q - e4) / 6.0
    s = e4 * p * q / (4.0 * r**3)
    t = (1.0 + s + math.sqrt(s * (2.0 + s))) ** (1.0 / 3.0)
    u = r * (1.0 + t + 1.0 / t)
    v = math.sqrt(u * u + e4 * q)
    w = e2 * (u + v - q) / (2.0 * v)
    k = math.sqrt(u + v + w * w) - w
    d = k * math.hypot(x, y) / (k + e2)
    return math.degrees(2.0 * math.atan2(z, d + math.hypot(d, z)))


def flown(case):
    spec = parse("case", case).to_spec()
    return spec, _fly(spec), simulate(spec)


@pytest.mark.parametrize("name", CASES)
def test_the_track_matches_the_per_row_routines_and_geographiclib(name):
    spec, flight, traj = flown(CASES[name])
    rows, p = flight.rows, spec.planet
    h = traj.history
    oblate = p.oblate
    lat_exact, lat_row, lon_row, heading_row = [], [], [], []
    for r in rows:
        x, y, z = r[R_X], r[R_Y], r[R_Z]
        if oblate:
            lat_exact.append(vermeille_latitude_deg(x, y, z, p.radius_ft, p.polar_radius_ft))
        else:  # the geocentric latitude
            lat_exact.append(math.degrees(math.atan2(z, math.hypot(x, y))))
        lat, lon, _ = geodetic_from_ecef(x, y, z, p.radius_ft, p.polar_radius_ft, oblate)
        lat_row.append(math.degrees(lat))
        lon_row.append(math.degrees(lon))
        heading_row.append(math.degrees(flight_angles(x, y, z, r[R_VX], r[R_VY], r[R_VZ])[2]))
    assert np.max(np.abs(h["latitude_deg"] - lat_row)) < LATITUDE_TOL_DEG
    assert np.max(np.abs(h["latitude_deg"] - lat_exact)) < LATITUDE_TOL_DEG
    assert np.max(np.abs(wrap_longitude(h["longitude_deg"] - np.array(lon_row)))) < LATITUDE_TOL_DEG
    assert np.all((0.0 <= h["heading_deg"]) & (h["heading_deg"] < 360.0))
    assert np.max(np.abs(wrap_longitude(h["heading_deg"] - np.array(heading_row)))) < HEADING_TOL_DEG
    e = spec.entry
    down, cross = downrange_crossrange_nmi(
        h["latitude_deg"], h["longitude_deg"], e.latitude_deg, e.longitude_deg, e.heading_deg, unwrap=True
    )
    assert np.max(np.abs(h["downrange_nmi"] - down)) < RANGE_TOL_NMI
    assert np.max(np.abs(h["crossrange_nmi"] - cross)) < RANGE_TOL_NMI


def test_the_tracks_cover_what_they_claim():
    """The cases above do go where they are named for: over a pole, across 180 deg, past half a circumference."""
    tracks = {name: simulate(parse("case", case).to_spec()).history for name, case in CASES.items()}
    assert tracks["over the north pole"]["latitude_deg"].max() > 89.0
    assert tracks["near the south pole, banked right"]["latitude_deg"].min() < -85.0
    lon = tracks["across the antimeridian, westward"]["longitude_deg"]
    assert lon.min() < -179.0 and lon.max() > 179.0
    assert tracks["past half a circumference"]["downrange_nmi"][-1] > math.pi * 3_440.0
