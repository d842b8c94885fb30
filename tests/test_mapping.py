"""The transform contract (footprint.contracts.transform, `footprint transform`) and the world maps
(footprint.pictures.maps)."""

import csv
import json
import math
import subprocess
import sys
from functools import partial

import numpy as np
import pytest

from footprint import parallel
from footprint.contracts.transform import TransformRequest
from footprint.core.constants import OMEGA_EARTH_DEG_S
from footprint.core.sphere import Reference
from footprint.pictures import maps as M
from tests.authorities.report import table2_entry, table2_stop

run_transform = partial(parallel.run, "transform")


EAST = {"latitude_deg": 0.0, "longitude_deg": 0.0, "heading_deg": 90.0}
# the L/D 1.89 footprint's left half, non-rotating (front, left side, back): lat, lon deg, flight time s
HALF = [
    (0.0, 120.17, 2818.0),
    (13.18, 115.44, 2753.0),
    (26.98, 90.97, 2412.0),
    (29.88, 58.77, 1944.0),
    (23.79, 30.77, 1464.0),
    (10.02, 18.99, 1008.0),
    (0.0, 16.26, 266.0),
]
POINTS = [{"latitude_deg": a, "longitude_deg": b, "flight_time_s": t} for a, b, t in HALF]
SMALL_STUDY = {
    "case": {"vehicle": {"builtin": "lod-1.89"}, "entry": table2_entry(), "stop": table2_stop()},
    "method": "single_parameter",
    "bank0_deg": [0, 60],
    "min_range": None,
    "mirror": False,
}
ANGLE_DEG = 1e-9  # the moves are closed forms: a few ulps


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "footprint.cli", *map(str, args)], capture_output=True, text=True, timeout=300
    )


def request(**kw):
    return {"points": POINTS, "from": EAST, "to": EAST} | kw


def write(tmp_path, data):
    path = tmp_path / "transform.json"
    path.write_text(json.dumps(data) if not isinstance(data, str) else data)
    return path


# ------------------------------------------------------------------------------------------ the CLI
def test_cli_re_nodes_a_footprint_and_writes_csv(tmp_path):
    out = tmp_path / "moved.csv"
    r = run("transform", write(tmp_path, request(to=EAST | {"longitude_deg": -75.0})), "--csv", out)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert len(result["points"]) == len(HALF)
    for (lat, lon, t), p in zip(HALF, result["points"]):  # a new node on the equator: every longitude -75 deg
        assert p["latitude_deg"] == pytest.approx(lat, abs=ANGLE_DEG)
        assert p["longitude_deg"] == pytest.approx(lon - 75.0, abs=ANGLE_DEG)
        assert p["flight_time_s"] == t and p["mirrored"] is False
    assert result["reference"] == pytest.approx(
        {"latitude_deg": 0.0, "longitude_deg": -75.0, "heading_deg": 90.0, "inclination_deg": 0.0}
    )
    rows = list(csv.DictReader(out.open()))
    assert list(rows[0]) == [
        "latitude_deg",
        "longitude_deg",
        "flight_time_s",
        "downrange_nmi",
        "crossrange_nmi",
        "mirrored",
    ]
    assert float(rows[3]["longitude_deg"]) == pytest.approx(HALF[3][1] - 75.0, abs=ANGLE_DEG)


@pytest.mark.parametrize(
    "data, field, words",
    [
        (request(points=[{"latitude_deg": 95, "longitude_deg": 0}]), "points.0.latitude_deg", "-90 to 90 deg"),
        (request(step_downrange_nmi=1e6), "step_downrange_nmi", "-250,000 to 250,000 nmi"),
        (
            request(points=[{"latitude_deg": 1, "longitude_deg": 2}], earth_rotation="approximate"),
            "points.0.flight_time_s",
            "required for every point",
        ),
        (
            request(points=[{"latitude_deg": 1, "longitude_deg": 2, "flight_time_s": -5}]),
            "points.0.flight_time_s",
            "0 to 100,000 s",
        ),
        (request(earth_rotation="exact"), "study", "required with earth_rotation 'exact'"),
        (request(earth_rotation="full"), "earth_rotation", "'none', 'approximate' or 'exact'"),
        (request(to=EAST | {"inclination_deg": 30}), "heading_deg", "exactly one of"),
        (
            request(to={"latitude_deg": 70, "longitude_deg": 0, "inclination_deg": 30}),
            "to.inclination_deg",
            "never reaches latitude 70",
        ),
        (
            request(to={"latitude_deg": 0, "longitude_deg": 0, "inclination_deg": 200}),
            "to.inclination_deg",
            "0 to 180 deg",
        ),
        (request(study=SMALL_STUDY), "study", "only used with earth_rotation 'exact'"),
        (
            request(earth_rotation="exact", study=SMALL_STUDY | {"bank0_deg": [400]}),
            "study.bank0_deg.0",
            "0 to 180 deg",
        ),
        (
            request(earth_rotation="exact", study={"case": SMALL_STUDY["case"], "method": "collocation"}),
            "study.method",
            "submit a footprint job",
        ),
        (request(points=[]), "points", "at least one point"),
        ({"points": POINTS, "to": EAST}, "from", "required"),
        (request(speed=3), "speed", "not permitted"),
        ('{"points": [', "transform.json", "not valid JSON"),
    ],
)
def test_cli_bad_input_gets_one_line_naming_the_field_and_exit_2(tmp_path, data, field, words):
    r = run("transform", write(tmp_path, data))
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr
    assert field in lines[0] and words in lines[0], lines[0]


# ------------------------------------------------------------------------------------- the contract
def test_json_round_trip_of_the_request_and_back_to_the_points():
    """The request survives JSON both ways; the response fed back (from and to swapped, the step undone)
    gives the original points."""
    req = TransformRequest.model_validate(
        request(
            to={"latitude_deg": 10.0, "longitude_deg": -40.0, "inclination_deg": 51.6, "ascending": False},
            step_downrange_nmi=1_234.5,
            mirror=True,
        )
    )
    again = TransformRequest.model_validate(json.loads(req.model_dump_json(by_alias=True, exclude_unset=True)))
    assert again == req
    out = json.loads(json.dumps(run_transform(req)))
    assert len(out["points"]) == 2 * len(HALF) - 2  # the two axis points have no mirror image
    ref = out["reference"]
    assert ref["inclination_deg"] == pytest.approx(51.6, abs=1e-9)
    dst = {k: ref[k] for k in ("latitude_deg", "longitude_deg", "heading_deg")}  # the stepped initial point
    back = run_transform(
        {
            "points": [{k: p[k] for k in ("latitude_deg", "longitude_deg", "flight_time_s")} for p in out["points"]],
            "from": dst,
            "to": EAST,
        }
    )
    for p, (lat, lon, _) in zip(back["points"], HALF):
        assert p["latitude_deg"] == pytest.approx(lat, abs=ANGLE_DEG)
        assert (p["longitude_deg"] - lon + 180) % 360 - 180 == pytest.approx(0.0, abs=ANGLE_DEG)
    for p, q in zip(out["points"], back["points"]):  # ranges about the destination are the flown ones
        assert p["crossrange_nmi"] == pytest.approx(q["crossrange_nmi"], abs=1e-6)


def test_mirror_adds_the_other_half_in_reverse_and_negates_cross_range():
    out = run_transform(request(mirror=True))
    pts = out["points"]
    left, right = pts[: len(HALF)], pts[len(HALF) :]
    assert all(not p["mirrored"] for p in left) and all(p["mirrored"] for p in right)
    for p, q in zip(left[1:-1][::-1], right):
        assert q["crossrange_nmi"] == pytest.approx(-p["crossrange_nmi"], abs=1e-9)
        assert q["downrange_nmi"] == pytest.approx(p["downrange_nmi"], abs=1e-9)
        assert q["latitude_deg"] == pytest.approx(-p["latitude_deg"], abs=1e-12)
        assert q["flight_time_s"] == p["flight_time_s"]


def test_approximate_rotation_shifts_each_point_west_by_omega_t():
    plain = run_transform(request(to=EAST | {"heading_deg": 30.0}))
    shifted = run_transform(request(to=EAST | {"heading_deg": 30.0}, earth_rotation="approximate"))
    for p, q, (_, _, t) in zip(plain["points"], shifted["points"], HALF):
        assert q["latitude_deg"] == p["latitude_deg"]
        dlon = (q["longitude_deg"] - p["longitude_deg"] + 180) % 360 - 180
        assert dlon == pytest.approx(-OMEGA_EARTH_DEG_S * t, abs=1e-9)


def test_inclination_gives_the_node_heading_90_minus_i():
    a = run_transform(request(to={"latitude_deg": 0, "longitude_deg": 0, "inclination_deg": 60}))
    b = run_transform(request(to=EAST | {"heading_deg": 30.0}))
    assert a["reference"]["heading_deg"] == pytest.approx(30.0, abs=1e-12)
    for p, q in zip(a["points"], b["points"]):
        assert p["latitude_deg"] == pytest.approx(q["latitude_deg"], abs=ANGLE_DEG)


def test_exact_flies_the_study_again_from_the_destination_on_the_rotating_earth():
    out = run_transform(
        {
            "from": EAST,
            "to": EAST | {"heading_deg": -90.0},
            "step_downrange_nmi": 600.0,
            "earth_rotation": "exact",
            "study": SMALL_STUDY,
        }
    )
    ref = out["reference"]
    assert ref["latitude_deg"] == pytest.approx(0.0, abs=1e-9)
    assert ref["longitude_deg"] == pytest.approx(-600.0 / (math.pi / 180 * 3440.069), abs=1e-3)
    assert ref["heading_deg"] == pytest.approx(-90.0, abs=1e-9)
    assert [p["parameter"]["bank0_deg"] for p in out["points"]] == [0.0, 60.0]
    front = out["points"][0]
    assert front["latitude_deg"] == pytest.approx(0.0, abs=0.05)  # along the equator, westward
    assert front["longitude_deg"] < ref["longitude_deg"] - 60.0
    assert front["flight_time_s"] > 1_000.0


# ---------------------------------------------------------------------------------------------- maps
def test_cylindrical_lines_are_cut_at_the_date_line_and_reach_both_edges():
    v = M.densify([10.0, 20.0], [170.0, -170.0])
    x, y = M.Cylindrical().lines(v)
    cut = np.flatnonzero(np.isnan(x))
    assert len(cut) == 1
    assert x[cut[0] - 1] == 180.0 and x[cut[0] + 1] == -180.0
    assert y[cut[0] - 1] == y[cut[0] + 1]
    assert np.all(np.abs(np.diff(x[: cut[0]])) < 1.0) and np.all(np.abs(np.diff(x[cut[0] + 1 :])) < 1.0)


def test_orthographic_hides_the_far_hemisphere_and_ends_lines_on_the_limb():
    ortho = M.Orthographic(0.0, 0.0)
    x, y = ortho.lines(M.densify(np.zeros(3), [0.0, 120.0, 179.0]))  # along the equator over the limb at 90 E
    finite = ~np.isnan(x)
    assert np.all(x[finite] ** 2 + y[finite] ** 2 <= 1.0 + 1e-12)
    assert np.nanmax(x) == pytest.approx(1.0, abs=1e-12)  # the last visible sample is on the limb
    assert not ortho.visible(0.0, 120.0) and ortho.visible(0.0, 80.0)


def test_footprint_center_is_on_the_axis_of_a_symmetric_footprint():
    lat = np.array([p[0] for p in HALF] + [-p[0] for p in HALF[1:-1][::-1]])
    lon = np.array([p[1] for p in HALF] + [p[1] for p in HALF[1:-1][::-1]])
    c_lat, c_lon = M.footprint_center(lat, lon)
    assert c_lat == pytest.approx(0.0, abs=1e-9) and 40.0 < c_lon < 90.0


def test_map_figure_draws_footprint_initial_point_track_and_shade():
    lat = np.array([p[0] for p in HALF] + [-p[0] for p in HALF[1:-1][::-1]])
    lon = np.array([p[1] for p in HALF] + [p[1] for p in HALF[1:-1][::-1]])
    ref = Reference(0.0, 0.0, 90.0)
    layer = M.footprint_layer(lat, lon, reference=ref, shade=True, label="L/D 1.89")
    for projection in ("cylindrical", "orthographic"):
        fig = M.map_figure([layer], projection=projection)
        ax = fig.axes[0]
        gids = [a.get_gid() for a in ax.get_children()]
        assert {"footprint", "initial_point", "ground_track", "shade"} <= set(gids)
        shade = next(a for a in ax.get_children() if a.get_gid() == "shade").get_array()
        share = float((shade[..., 3] > 0).mean())
        assert 0.01 < share < 0.5  # the footprint covers part of the map, not none or all of it


def test_a_moved_point_keeps_its_flown_down_range_past_half_way_round():
    """Issue 13 defect 2: a point flown 18,108 nmi came back as -3,507 (folded into +-pi R'). A move is a
    rotation of the sphere, so the ranges about the moved (and stepped) reference are the flown ones."""
    from footprint.core.sphere import MEAN_RADIUS_NMI, latlon_from_ranges

    down, cross = np.array([18_108.0, 14_869.0, 6_000.0]), np.array([0.0, 850.0, -1_900.0])
    lat, lon = latlon_from_ranges(down, cross, 0.0, 0.0, 90.0)
    points = [
        {"latitude_deg": float(a), "longitude_deg": float(b), "flight_time_s": 3_000.0, "downrange_nmi": float(d)}
        for a, b, d in zip(lat, lon, down)
    ]
    polar = {"latitude_deg": 0.0, "longitude_deg": -60.0, "inclination_deg": 90.0}
    out = run_transform({"points": points, "from": EAST, "to": polar, "step_downrange_nmi": 2_500.0, "mirror": True})
    moved = out["points"]
    # the images of the two points off the axis follow, in reverse order; the one on the axis has none
    assert [p["downrange_nmi"] for p in moved] == pytest.approx(list(down) + list(down[:0:-1]), abs=1e-6)
    assert [p["crossrange_nmi"] for p in moved] == pytest.approx(list(cross) + list(-cross[:0:-1]), abs=1e-6)
    # the approximate earth rotation shifts each point by a few hundred nmi: still on the flown turn
    shifted = run_transform({"points": points, "from": EAST, "to": polar, "earth_rotation": "approximate"})["points"]
    assert all(abs(p["downrange_nmi"] - d) < 800.0 for p, d in zip(shifted, down))
    # without the flown down-range the answer is the chart's, within +-pi R' (as documented)
    folded = run_transform(
        {"points": [{k: p[k] for k in ("latitude_deg", "longitude_deg")} for p in points], "from": EAST, "to": polar}
    )["points"]
    assert folded[0]["downrange_nmi"] == pytest.approx(18_108.0 - 2.0 * math.pi * MEAN_RADIUS_NMI, abs=1e-6)


def test_a_place_may_be_an_orbit_point():
    """Issue 13 item 9: "to" as node longitude, inclination and argument of latitude (the map's controls),
    without the page's arithmetic; by hand: the ascending node heads 90 - i, and u is an arc of R' along it."""
    from footprint.core.sphere import MEAN_RADIUS_NMI

    by_orbit = run_transform(
        request(
            to={"node_longitude_deg": -60.0, "inclination_deg": 51.6, "argument_of_latitude_deg": 30.0},
            step_downrange_nmi=500.0,
        )
    )
    by_hand = run_transform(
        request(
            to={"latitude_deg": 0.0, "longitude_deg": -60.0, "heading_deg": 90.0 - 51.6},
            step_downrange_nmi=500.0 + math.radians(30.0) * MEAN_RADIUS_NMI,
        )
    )
    for a, b in zip(by_orbit["points"], by_hand["points"]):
        assert a["latitude_deg"] == pytest.approx(b["latitude_deg"], abs=ANGLE_DEG)
        assert a["longitude_deg"] == pytest.approx(b["longitude_deg"], abs=ANGLE_DEG)
    # u = 90 deg on a 51.6 deg orbit is its northernmost point, heading east
    top = run_transform(
        request(to={"node_longitude_deg": 0.0, "inclination_deg": 51.6, "argument_of_latitude_deg": 90.0})
    )
    assert top["reference"]["latitude_deg"] == pytest.approx(51.6, abs=ANGLE_DEG)
    assert top["reference"]["heading_deg"] == pytest.approx(90.0, abs=ANGLE_DEG)
    with pytest.raises(ValueError, match="missing argument_of_latitude_deg"):
        TransformRequest.model_validate(request(to={"node_longitude_deg": 0.0, "inclination_deg": 51.6}))
