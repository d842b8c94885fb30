"""The `footprint` command, run as a user runs it: a new process, exit status, stdout and stderr."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.core.footprints import with_bank
from footprint.core.trajectory import simulate
from tests.authorities.report import REPORT

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
TABLE2 = json.loads((EXAMPLES / "table2_lod22.json").read_text())


def run(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "footprint.cli", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=300
    )


def write_case(tmp_path, case):
    path = tmp_path / "case.json"
    path.write_text(json.dumps(case) if isinstance(case, dict) else case)
    return path


def with_(section, **values):
    case = json.loads(json.dumps(TABLE2))
    case[section].update(values)
    return case


def test_fly_prints_the_summary_and_writes_the_history(tmp_path):
    out = tmp_path / "history.csv"
    r = run("fly", ROOT / "examples" / "table2_lod22.json", "--history", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    for key in (
        "downrange_nmi",
        "crossrange_nmi",
        "flight_time_s",
        "final_altitude_ft",
        "final_velocity_fps",
        "final_latitude_deg",
        "final_longitude_deg",
        "final_heading_deg",
        "pullout_altitude_ft",
        "pullout_time_s",
        "max_dynamic_pressure_psf",
        "max_temperature_R",
    ):
        assert key in summary
    assert summary["final_altitude_ft"] == pytest.approx(50_000.0, abs=1.0)
    lines = out.read_text().splitlines()
    assert lines[0].startswith("time_s,altitude_ft,velocity_fps")
    assert len(lines) == summary["steps"] + 2  # header, entry point, one row per step
    last = dict(zip(lines[0].split(","), map(float, lines[-1].split(","))))
    assert last["downrange_nmi"] == pytest.approx(summary["downrange_nmi"], rel=1e-9)


@pytest.mark.parametrize(
    "case, field, words",
    [
        (with_("vehicle", builtin="lod-9.9"), "vehicle", "lod-1.89"),
        (with_("entry", gamma_deg=2.0), "gamma_deg", "climbs"),
        (with_("entry", velocity_fps=45_000), "entry.velocity_fps", "1,000 to 40,000"),
        (with_("entry", velocity_fps=500), "entry.velocity_fps", "1,000 to 40,000"),
        (with_("entry", latitude_deg=95), "entry.latitude_deg", "-90 to 90"),
        (with_("bank", k="fast"), "bank.k", ""),
        (with_("stop", altitude_ft=-5), "stop.altitude_ft", "allowed range"),
        ({**TABLE2, "integrator": {"method": "rk4"}}, "integrator.method", "dop853"),
        ({**TABLE2, "planet": {"atmosphere": {"model": "mars"}}}, "planet.atmosphere.model", "ardc1959"),
        ({k: v for k, v in TABLE2.items() if k != "entry"}, "entry", "required"),
        ('{"vehicle": {"builtin": "lod-2.2"},', "case.json", "not valid JSON"),
        ("[1, 2]", "case.json", "JSON object"),
    ],
)
def test_a_bad_case_gets_one_line_naming_the_field_and_exit_2(tmp_path, case, field, words):
    r = run("fly", write_case(tmp_path, case))
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "Traceback" not in r.stderr
    assert lines[0].startswith("error: ") and field in lines[0] and words in lines[0], lines[0]


def test_a_missing_case_file_is_named(tmp_path):
    r = run("fly", tmp_path / "nope.json")
    assert r.returncode == 2 and "nope.json" in r.stderr and "Traceback" not in r.stderr


def test_vehicles_lists_the_appendix_b_vehicles_beside_the_report():
    r = run("vehicles", "--json")
    assert r.returncode == 0, r.stderr
    rows = {row["id"]: row for row in json.loads(r.stdout)}
    assert set(rows) >= {"lod-1.89", "lod-2.2", "lod-2.6", "low-lod", "high-lod"}
    # (L/D)max at Mach 20 / 200,000 ft against the report's names; the printed L/D 2.6 tables give 2.83
    for vid in ("lod-1.89", "lod-2.2"):
        assert rows[vid]["ld_max_m20_200kft"] == pytest.approx(REPORT[f"vehicle.{vid}.ld_max"].value, abs=0.03)
    assert rows["lod-2.6"]["ld_max_m20_200kft"] == pytest.approx(2.83, abs=0.03)
    for vid in ("lod-1.89", "lod-2.2"):
        assert rows[vid]["wing_loading_psf"] == REPORT[f"vehicle.{vid}.wing_loading_psf"].value
    table = run("vehicles")
    assert table.returncode == 0 and "lod-2.6" in table.stdout
    assert f"{REPORT['vehicle.lod-1.89.ld_max'].value}" in table.stdout


def test_footprint_prints_the_boundary_and_draws_it(tmp_path):
    study = json.loads((ROOT / "examples" / "footprint_lod189.json").read_text())
    study["bank0_deg"] = [0, 45, 90]
    study["case"]["planet"]["rotating"] = False  # the right half by reflection
    study["case"]["planet"]["oblate"] = False
    path = write_case(tmp_path, study)
    r = run("footprint", path, "--plot", tmp_path / "fp.png")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    sides = [p["side"] for p in out["points"]]
    assert sides == ["axis", "left", "left", "axis", "right", "right"]
    assert out["trajectories"] == 4 and [p["mirrored"] for p in out["points"]].count(True) == 2
    for p in out["points"]:
        assert {
            "downrange_nmi",
            "crossrange_nmi",
            "flight_time_s",
            "latitude_deg",
            "longitude_deg",
            "parameter",
        } <= set(p)
    left, right = out["points"][1], out["points"][5]
    assert right["crossrange_nmi"] == -left["crossrange_nmi"] and right["parameter"] == left["parameter"]
    assert out["area_nmi2"] > 0
    assert (tmp_path / "fp.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_bad_study_gets_one_line_naming_the_field(tmp_path):
    study = json.loads((ROOT / "examples" / "footprint_lod189.json").read_text())
    study["bank0_deg"] = [0, 200]
    r = run("footprint", write_case(tmp_path, study))
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert r.stderr.startswith("error: bank0_deg.1: 200 is outside the allowed range 0 to 180 deg")
    study["method"] = "spiral"
    r = run("footprint", write_case(tmp_path, study))
    assert r.returncode == 2 and "method" in r.stderr and "single_parameter" in r.stderr and "Traceback" not in r.stderr


def test_a_temperature_limited_footprint_keeps_every_flown_point_within_the_limit(tmp_path):
    """The simple heating-constrained method as a study: both halves flown on the rotating earth, each point's
    alpha floor searched for its own side; the settings that no floor can cool are left out."""
    study = json.loads((ROOT / "examples" / "footprint_lod189.json").read_text())
    study = {
        "case": {**study["case"], "heating": {"model": "reference"}},
        "method": "temperature_limited",
        "limit_R": REPORT["sec3.limit_R"].value,
        "bank0_deg": [0, 60, 90, 120],
    }
    r = run("footprint", write_case(tmp_path, study))
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    sides = [p["side"] for p in out["points"]]
    left = [p["parameter"]["bank0_deg"] for p in out["points"] if p["side"] == "left"]
    right = [p["parameter"]["bank0_deg"] for p in out["points"] if p["side"] == "right"]
    assert sides[0] == "axis" and out["points"][0]["parameter"]["bank0_deg"] == 0
    assert sorted(left) == sorted(right) and {60, 90} <= set(left) and 120 not in left  # 120 deg: too hot
    assert len(left) > 2  # the grid refined around its max cross-range setting
    assert all(12.5 <= p["parameter"]["alpha_floor_deg"] <= 40.0 for p in out["points"])
    assert out["trajectories"] > 5  # the floor searches are counted, not only the five flights drawn
    base = parse("case", study["case"]).to_spec()
    for p in out["points"]:  # fly each point again: its own bank law, side and alpha floor
        spec = with_bank(base, "single_parameter", bank_gain=p["parameter"]["bank_gain"], right=p["side"] == "right")
        s = simulate(C.with_alpha_floor(spec, p["parameter"]["alpha_floor_deg"])).summary
        assert s["max_temperature_R"] <= study["limit_R"] + 5.0  # degR: the limit plus the TTOL band
        assert s["downrange_nmi"] == pytest.approx(p["downrange_nmi"], abs=1e-3)  # nmi: the flight re-flown


def test_a_temperature_limited_footprint_needs_a_heating_model(tmp_path):
    study = json.loads((ROOT / "examples" / "footprint_lod189.json").read_text())
    study = {"case": study["case"], "method": "temperature_limited", "limit_R": 2_550}
    r = run("footprint", write_case(tmp_path, study))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "case.heating" in r.stderr, r.stderr


@pytest.mark.parametrize(
    "args, option",
    [
        (("fly", EXAMPLES / "table2_lod22.json", "--history", "{missing}/h.csv"), "--history"),
        (("footprint", EXAMPLES / "footprint_lod189.json", "--plot", "{missing}/f.png"), "--plot"),
        (("optimize", EXAMPLES / "optimize_betts_collocation.json", "--plot", "{missing}/o.png"), "--plot"),
        (("map", EXAMPLES / "footprint_lod189.json", "--out", "{missing}/m.html"), "--out"),
        (("disperse", EXAMPLES / "disperse_lod189.json", "--geojson", "{missing}/d.geojson"), "--geojson"),
        (("disperse", EXAMPLES / "disperse_lod189.json", "--csv", "{missing}/d.csv"), "--csv"),
    ],
)
def test_an_output_into_a_missing_folder_is_one_line_and_nothing_is_made(tmp_path, args, option):
    """Issue 13 item 10: --history printed a traceback and --plot made the folders a typo named."""
    missing = tmp_path / "no" / "such"
    r = run(*[str(a).format(missing=missing) for a in args])
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert r.stderr.strip() == f"error: {option}: the folder {missing} does not exist (create it first)"
    assert not (tmp_path / "no").exists()


@pytest.mark.parametrize(
    "study, line",
    [
        (
            {"method": "wiggle"},
            "error: method: 'wiggle' is not one of 'single_parameter', 'constant_bank', 'staged', "
            "'two_parameter', 'constant_altitude', 'temperature_limited', 'collocation'",
        ),
        (None, "error: method: missing (this looks like a case: a study holds it as 'case' and names its 'method')"),
    ],
)
def test_a_wrong_method_or_a_case_file_is_named_not_dumped(tmp_path, study, line):
    case = json.loads((EXAMPLES / "table2_lod22.json").read_text())
    path = tmp_path / "study.json"
    path.write_text(json.dumps(case if study is None else {"case": case} | study))
    r = run("footprint", path)
    assert r.returncode == 2 and r.stderr.strip() == line


def run_on_terminal(*args):
    """The command with its stdout on a pseudo-terminal, as a person runs it: (exit status, what it printed)."""
    import os
    import pty

    leader, follower = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "footprint.cli", *map(str, args)], stdout=follower, stderr=subprocess.PIPE, text=True
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 65536)
        except OSError:  # the command closed its end
            break
        if not data:
            break
        chunks.append(data)
    proc.wait(timeout=300)
    os.close(leader)
    text = b"".join(chunks).decode().replace("\r\n", "\n")
    return proc.returncode, re.sub(r"\x1b\[[0-9;]*m", "", text)  # the terminal's colour resets


def test_reach_and_optimize_print_a_summary_on_a_terminal_and_json_when_piped():
    """Issue 13 item 10: a person reads a few lines; a script (piped, or --json) gets the whole result."""
    code, text = run_on_terminal("reach", EXAMPLES / "reach_20_sites.json")
    assert code == 0 and text.startswith("orbit: inclination 28.5 deg, node -170 deg")
    piped = run("reach", EXAMPLES / "reach_20_sites.json")
    result = json.loads(piped.stdout)
    assert f"{len(result['windows'])} landing windows" in text
    for site in result["sites"][:3]:
        assert f"  {site['name']}: " in text
    assert len(text.splitlines()) <= len(result["sites"]) + 4 and "(the full result: --json)" in text
    code, text = run_on_terminal("reach", EXAMPLES / "reach_20_sites.json", "--json")
    again = json.loads(text)
    for r in (again, result):
        r["analysis"].pop("seconds")  # the run's own time
    assert again == result
    code, text = run_on_terminal("optimize", EXAMPLES / "optimize_betts_collocation.json")
    assert code == 0 and text.startswith("optimal: cross-range ") and "IPOPT iterations" in text
    assert "re-flown by the integrator within 0.00" in text and "upside down" not in text  # Betts' optimum: upright


def _unreadable_files(tmp_path):
    nested = tmp_path / "nested.json"
    nested.write_text('{"case": ' + "[" * 100_000 + "]" * 100_000 + "}")
    latin = tmp_path / "latin.json"
    latin.write_bytes('{"vehicle": {"builtin": "lod-2.2", "name": "caf\xe9"}}'.encode("latin-1"))
    return {"nested": (nested, "nested deeper than"), "latin": (latin, "not UTF-8")}


@pytest.mark.parametrize("which", ["nested", "latin"])
@pytest.mark.parametrize("command", ["fly", "footprint", "optimize", "sweep", "transform", "reach", "map"])
def test_a_file_json_cannot_read_is_one_line_and_exit_2(tmp_path, which, command):
    """Issue 15 item 10: a deeply nested file (RecursionError) and a file that is not UTF-8 printed tracebacks."""
    path, words = _unreadable_files(tmp_path)[which]
    r = run(command, path)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and words in lines[0], r.stderr
    assert "Traceback" not in r.stderr


def test_a_temperature_limit_no_setting_can_meet_is_one_line_and_exit_2(tmp_path):
    """Issue 15 item 10: a temperature-limited study whose limit cannot be met (22,000 ft/s at -3 deg, 2,550 degR)
    is the user's limit, named with its value: one line, exit 2."""
    study = {
        "case": {
            "vehicle": {"builtin": "lod-1.89"},
            "heating": {"model": "reference"},
            "entry": {"altitude_ft": 364_800, "velocity_fps": 22_000, "gamma_deg": -3},
            "stop": {"altitude_ft": 50_000},
        },
        "method": "temperature_limited",
        "limit_R": 2_550,
        "bank0_deg": [0, 60],
    }
    path = tmp_path / "hot.json"
    path.write_text(json.dumps(study))
    r = run("footprint", path)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].startswith("error: limit_R: 2550 degR cannot be met"), lines[0]


def test_disperse_prints_a_summary_on_a_terminal_and_the_job_result_when_piped(tmp_path):
    """Issue 16: `footprint disperse` answers what the Python door and the job kind answer, trajectories included."""
    from footprint import disperse

    study = {
        "footprint": json.loads((EXAMPLES / "footprint_lod189.json").read_text()) | {"bank0_deg": [0, 60]},
        "samples": 24,
        "seed": 3,
        "entry": {"gamma_deg": {"normal": {"std": 0.05}}},
        "histories": [7],
        "sites": [{"name": "Ascension", "latitude_deg": -7.95, "longitude_deg": -14.36}],
    }
    path = write_case(tmp_path, study)
    piped = run("disperse", path, "--workers", 0, "--geojson", tmp_path / "d.geojson", "--csv", tmp_path / "d.csv")
    assert piped.returncode == 0, piped.stderr
    got = json.loads(piped.stdout)
    kinds = [f["properties"]["kind"] for f in json.loads((tmp_path / "d.geojson").read_text())["features"]]
    assert kinds.count("ellipse") == 2 * len(got["flights"]) and kinds.count("site") == 1
    assert (
        (tmp_path / "d.csv")
        .read_text()
        .splitlines()[1]
        .startswith(f"Ascension,-7.95,-14.36,{got['sites'][0]['probability']},")
    )
    here, _ = disperse(study)
    flights = len(here.flights)  # the family: each setting and its mirror, counted by the core
    assert got["trajectories"] == 24 * flights == got["outcomes"]["flights"]
    assert [f["mean_downrange_nmi"] for f in got["flights"]] == [f["mean_downrange_nmi"] for f in here.flights]
    assert got["sites"][0]["probability"] == here.sites[0]["probability"]
    assert (got["design"], got["seed"], got["run"]["workers"]) == ("sobol", 3, 0)
    code, text = run_on_terminal("disperse", path, "--workers", 0)
    assert code == 0 and "\n  Ascension: probability 0.000 (95% interval 0.000-0.142); outside" in text, text
    assert f"24 samples (sobol, seed 3): {24 * flights:,} trajectories in " in text and " s in this process; " in text
    assert "\n  the flights of sample(s) 7 with their histories: in the JSON\n" in text
    assert [h["sample"] for h in got["histories"]] == [7] * flights


def test_run_prints_a_summary_on_a_terminal_and_json_when_piped_with_a_bar_that_starts_in_words():
    """Issue 53 item 12: `run reach` printed 3.1 MB of JSON on a terminal as when piped, and its bar began
    "0analysis [00:00, ?analysis/s]"."""
    request = EXAMPLES / "reach_20_sites.json"
    piped = run("run", "reach", request)
    assert piped.returncode == 0, piped.stderr
    result = json.loads(piped.stdout)["result"]["reach"]
    assert "0analysis" not in piped.stderr and "?analysis/s" not in piped.stderr, piped.stderr
    code, text = run_on_terminal("run", "reach", request)
    assert code == 0 and text.startswith("orbit: inclination 28.5 deg, node -170 deg"), text[:300]
    assert f"{sum(s['reachable'] for s in result['sites'])} of {len(result['sites'])} sites reached" in text
    assert len(text.splitlines()) <= len(result["sites"]) + 4 and "(the full result: --json)" in text
    code, text = run_on_terminal("run", "reach", request, "--json")
    again = json.loads(text)["result"]["reach"]
    for r in (again, result):
        r["analysis"].pop("seconds")  # the run's own time
    assert again == result
