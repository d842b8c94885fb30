"""Every command that reads a JSON file, fed near-misses of the repository's examples (fields dropped, wrong types,
huge, negative and non-finite numbers, NUL and other control characters, unicode, long strings, deep nesting,
unknown keys) and bytes that are not UTF-8 or not JSON: it answers with exit status 0, or 2 and ONE line on stderr,
never a traceback (issue 15).

In-process (fast) through click's CliRunner and the console script's entry point, footprint.cli:main, which also
turns an InputError from deeper in the core into one line. A request that parses stops where its command would
start the work (`Parsed`), so that nothing flies for minutes; a transform's moves (milliseconds) run for real, and
a map is drawn without its Leaflet and Natural Earth files (what is tested is the map's reading of its footprint).
The same examples on every run, a bounded number of them: ~15 s in all.
"""

import copy
import json
import sys
from pathlib import Path
from unittest import mock

import pytest
from click.testing import CliRunner  # typer's subclass of it takes only a Typer app, not the entry point
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from footprint import cli
from tests.test_foliummap import FOOTPRINT as MAP_FOOTPRINT  # as `footprint footprint` prints one, across 180 deg

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
BY_PREFIX = {
    "fly": "table2_",
    "footprint": "footprint_",
    "optimize": "optimize_",
    "sweep": "sweep_",
    "transform": "transform_",
    "reach": "reach_",
    "disperse": "disperse_",
}  # a command's examples
ALL_EXAMPLES = {p.name: json.loads(p.read_text()) for p in sorted(EXAMPLES.glob("*.json"))}
TABLE2 = ALL_EXAMPLES["table2_lod22.json"]


def inline_tables_case() -> dict:
    """Table 2's case with its vehicle given inline: the built-in L/D 1.89 vehicle's aerodynamic tables."""
    from footprint.core.aero import DATA_DIR

    builtin = json.loads((DATA_DIR / "lod-1.89.json").read_text())
    vehicle = {"name": "inline lod-1.89", "wing_loading_psf": builtin["wing_loading_psf"], "aero": builtin["aero"]}
    return TABLE2 | {"vehicle": vehicle}


def bases(command: str) -> list[dict]:
    """The documents a command's near-misses start from: its examples (a case also from each study's case, and one
    with aerodynamic tables inline)."""
    if command == "map":
        return [MAP_FOOTPRINT]
    own = [d for name, d in ALL_EXAMPLES.items() if name.startswith(BY_PREFIX[command])]
    if command == "fly":
        own += [d["case"] for d in ALL_EXAMPLES.values() if isinstance(d.get("case"), dict)] + [inline_tables_case()]
    return own


COMMANDS = (*BY_PREFIX, "map")
EXAMPLES_PER_COMMAND = 250  # 1-3 s for each command (~14 s for the module); the same examples every run
RAW_EXAMPLES = 350  # over all the commands


# ------------------------------------------------------------------------------- what the documents hold
# written into the JSON text after json.dumps (which cannot write them, or not without deep recursion in the test)
HUGE_INT, DEEP, NEAR_LIMIT, LONG, LONG_KEY = "@@huge-int@@", "@@deep@@", "@@near-limit@@", "@@long@@", "@@long-key@@"
TEXT = {
    HUGE_INT: "9" * 5_000,  # past Python's 4,300 digits of int() from text: json.loads raises ValueError
    LONG: json.dumps("x" * 100_000),
    LONG_KEY: json.dumps("k" * 10_000),
    DEEP: "[" * 50_000 + "]" * 50_000,  # past the JSON reader's recursion limit
    NEAR_LIMIT: '{"x": ' * 900 + "1" + "}" * 900,
}  # just within it (pydantic's own limit is lower)
STRANGE_TEXT = [
    "",
    " ",
    "\x00",
    "a\x00b",
    "\n",
    "a\nb",
    "\r\n",
    "\t",
    "\u2028",
    "\x1b[31mred",
    "\ud800",
    "\ufeff",
    "NaN",
    "Infinity",
    "-1e999",
    "1e308",
    "0x10",
    "true",
    "null",
    "{}",
    "[]",
    "lod-1.89",
    "lod-2.2",
    "single_parameter",
    "collocation",
    "constant",
    "table",
    "zero",
    "max_ld",
    "exact",
    "approximate",
    "🚀" * 3,
    "é" * 40,
    LONG,
    "%s%n{0}",
    "../../etc/passwd",
    HUGE_INT,
    DEEP,
    NEAR_LIMIT,
]
STRANGE_NUMBERS = [
    0,
    -0.0,
    -1,
    1,
    2,
    0.5,
    -180,
    180.0001,
    1e-300,
    5e-324,
    1e308,
    -1e308,
    2**31,
    2**63,
    -(2**63) - 1,
    10**400,
    float("nan"),
    float("inf"),
    float("-inf"),
]
scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.sampled_from(STRANGE_NUMBERS),
    st.integers(),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(STRANGE_TEXT),
    st.text(max_size=12),
)
keys = st.one_of(
    st.sampled_from(
        [
            "",
            "x",
            "law",
            "method",
            "case",
            "vehicle",
            "\x00",
            "a\nb",
            "\u2028",
            "é" * 90,
            LONG_KEY,
            "__class__",
            "from",
            "to",
        ]
    ),
    st.text(max_size=8),
)
values = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(keys, inner, max_size=4)),
    max_leaves=12,
)


def paths(doc, here=()) -> list[tuple]:
    """Every place in a JSON document down to depth 8: the root, each member of an object, each item of an array
    (no deeper: an earlier mutation may have nested it hundreds deep)."""
    out = [here]
    if len(here) >= 8:
        return out
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += paths(v, here + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            out += paths(v, here + (i,))
    return out


def get(doc, path):
    for step in path:
        doc = doc[step]
    return doc


def nested(value, depth: int, as_list: bool):
    for _ in range(depth):
        value = [value] if as_list else {"x": value}
    return value


@st.composite
def mutation(draw, doc):
    """doc with one place changed: dropped, replaced by a strange value, given an unknown key, wrapped, nested
    deep, emptied, or its array grown."""
    path = draw(st.sampled_from(paths(doc)))
    target = get(doc, path)
    ops = (
        ["replace", "wrap", "nest"]
        + (["drop"] if path else [])
        + (["unknown key", "empty"] if isinstance(target, (dict, list)) else [])
    )
    ops += ["grow"] if isinstance(target, list) and target else []
    op = draw(st.sampled_from(ops))
    if op == "replace":
        new = draw(values)
    elif op == "wrap":
        new = draw(st.sampled_from([[target], {"value": target}, [target, target], str(target)[:200]]))
    elif op == "nest":
        new = nested(target, draw(st.sampled_from([2, 30, 300])), draw(st.booleans()))
    elif op == "unknown key" and isinstance(target, dict):
        new = {**target, draw(keys): draw(values)}
    elif op == "unknown key":
        new = target + [draw(values)]
    elif op == "empty":
        new = type(target)()
    elif op == "grow":  # to ~2,000 items (a list grown twice must not reach millions)
        new = target * max(2, draw(st.sampled_from([2, 50, 2_000])) // len(target))
    if not path:
        return new
    parent = get(doc, path[:-1])
    if op == "drop":
        del parent[path[-1]]
    else:
        parent[path[-1]] = new
    return doc


@st.composite
def near_misses(draw, command):
    """A command's example, or now and then another command's, changed in one to three places."""
    pool = bases(command) if draw(st.integers(0, 9)) else list(ALL_EXAMPLES.values())
    doc = copy.deepcopy(draw(st.sampled_from(pool)))
    for _ in range(draw(st.integers(1, 3))):
        doc = draw(mutation(doc))
    return doc


def json_bytes(doc, ensure_ascii: bool) -> bytes:
    text = json.dumps(doc, ensure_ascii=ensure_ascii)
    for marker, replacement in TEXT.items():
        text = text.replace(json.dumps(marker), replacement)
    return text.encode("utf-8", "surrogatepass")  # a lone surrogate, unescaped: not UTF-8


@st.composite
def raw_files(draw):
    """Bytes that are not a request: an example cut short, bytes spliced in (invalid UTF-8 among them), another
    encoding, a byte-order mark, arbitrary binary."""
    text = json.dumps(draw(st.sampled_from(list(ALL_EXAMPLES.values())))).encode()
    how = draw(st.sampled_from(["cut", "splice", "utf-16", "utf-8-sig", "latin-1", "binary", "empty", "scalar"]))
    if how == "cut":
        return text[: draw(st.integers(0, len(text) - 1))]
    if how == "splice":
        at = draw(st.integers(0, len(text)))
        junk = draw(
            st.one_of(
                st.binary(min_size=1, max_size=8),
                st.sampled_from([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\x00", b"\x80\x80", b"}", b","]),
            )
        )
        return text[:at] + junk + text[at:]
    if how == "utf-16":
        return text.decode().encode("utf-16")
    if how == "utf-8-sig":
        return text.decode().encode("utf-8-sig")
    if how == "latin-1":
        return text.decode().replace('"', '"\u00e9', 1).encode("latin-1")
    if how == "binary":
        return draw(st.binary(max_size=64))
    if how == "empty":
        return draw(st.sampled_from([b"", b" ", b"\n", b"\x00"]))
    return draw(st.sampled_from([b"null", b"1", b"NaN", b"-Infinity", b'"case"', b"[]", b"[{}]", b"true"]))


# ---------------------------------------------------------------------------------------- the commands
class Parsed(Exception):
    """A request that parsed reached the work of its command (stubbed: the fuzz flies nothing)."""


def _parsed(*args, **kwargs):
    raise Parsed()


@pytest.fixture(scope="module")
def quick_commands():
    """The commands with their work stubbed out (see the module docstring)."""
    from footprint import parallel
    from footprint.pictures import folium_page

    run = parallel.run

    def parsed_only(kind, request, *args, **kwargs):  # a plain transform is quick: the rest stops once parsed
        if kind == "transform" and request.earth_rotation != "exact":
            return run(kind, request)
        raise Parsed()

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(parallel, "run", parsed_only)
        mp.setattr(parallel, "dask_client", _parsed)  # a valid sweep would start a LocalCluster first
        mp.setattr(folium_page, "leaflet_assets", lambda: ("", ""))
        mp.setattr(folium_page, "countries_geojson", lambda: {"type": "FeatureCollection", "features": []})
        yield


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


class Main:
    """The console script (footprint.cli:main) as CliRunner invokes a click command."""

    name = "footprint"

    def main(self, args, prog_name=None, **extra):
        with mock.patch.object(sys, "argv", ["footprint", *args]):
            cli.main()


def invoke(command: str, content: bytes, folder: Path):
    path = folder / "request.json"
    path.write_bytes(content)
    extra = ["-o", str(folder / "map.html")] if command == "map" else []
    return CliRunner().invoke(Main(), [command, str(path), *extra])


def assert_one_line_or_success(result, command: str, content: bytes) -> str:
    """'parsed', 'ok' or 'error'; anything else (a traceback, several lines, another status) fails."""
    shown = content[:600]
    if isinstance(result.exception, Parsed):
        return "parsed"
    assert result.exception is None or isinstance(result.exception, SystemExit), (
        f"{command} raised {type(result.exception).__name__}: {result.exception!r} on {shown!r}"
    )
    assert result.exit_code in (0, 2), f"{command}: exit {result.exit_code} on {shown!r}\n{result.output}"
    assert "Traceback" not in result.output, result.output
    if result.exit_code == 0:
        return "ok"
    lines = result.stderr.splitlines()  # str.splitlines: \n, \r, \v, \f, \x1c-\x1e, \x85, \u2028, \u2029
    assert len(lines) == 1 and lines[0].startswith("error: "), f"{command} on {shown!r}:\n{result.stderr!r}"
    assert result.stdout == "", result.stdout
    return "error"


def bounded_fuzz(max_examples: int):
    """The same examples on every run, a bounded number of them (the default suite stays fast)."""
    return settings(
        max_examples=max_examples,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.function_scoped_fixture],
    )


@pytest.mark.parametrize("command", COMMANDS)
@bounded_fuzz(EXAMPLES_PER_COMMAND)
@given(data=st.data())
def test_a_near_miss_of_an_example_gets_exit_0_or_one_line_and_exit_2(quick_commands, folder, command, data):
    doc = data.draw(near_misses(command), label="document")
    content = json_bytes(doc, ensure_ascii=data.draw(st.booleans(), label="ensure_ascii"))
    outcome = assert_one_line_or_success(invoke(command, content, folder), command, content)
    event(outcome)  # how many parsed: pytest --hypothesis-show-statistics


@pytest.mark.parametrize("command", COMMANDS)
@bounded_fuzz(RAW_EXAMPLES // len(COMMANDS))
@given(content=raw_files())
def test_bytes_that_are_not_a_json_object_get_one_line_and_exit_2(quick_commands, folder, command, content):
    result = invoke(command, content, folder)
    outcome = assert_one_line_or_success(result, command, content)
    if not json_object(content):  # (a byte spliced in may leave JSON: a key "}case", a number 4500)
        assert outcome == "error" and str(folder / "request.json") in result.stderr, result.stderr  # names the file


def json_object(content: bytes) -> bool:
    try:
        return isinstance(json.loads(content.decode("utf-8")), dict)
    except (UnicodeDecodeError, ValueError, RecursionError):
        return False


@pytest.mark.parametrize("command", COMMANDS)
def test_the_examples_themselves_parse(quick_commands, folder, command):
    """The fuzz starts from requests that are valid (so that its near misses are near)."""
    for doc in bases(command):
        content = json_bytes(doc, ensure_ascii=True)
        assert assert_one_line_or_success(invoke(command, content, folder), command, content) in ("parsed", "ok")


# --------------------------------------------------------------------- what the fuzz found, kept as examples
STUDY = ALL_EXAMPLES["footprint_lod189.json"]


def changed(doc: dict, where: str, value) -> dict:
    """A copy of doc with the value at a dotted path ("points.0.latitude_deg") replaced."""
    doc = copy.deepcopy(doc)
    *path, last = [int(p) if p.isdigit() else p for p in where.split(".")]
    get(doc, path)[last] = value
    return doc


SHUTTLE_CASE = ALL_EXAMPLES["optimize_betts_shuttle.json"]["case"]  # an inline vehicle (polynomial aero)


@pytest.mark.parametrize(
    "command, doc, line",
    [
        # a key with a line break (or another character that does not print) was echoed as it is: two lines
        ("fly", {**TABLE2, "a\nb": 1}, r"error: a\nb: Extra inputs are not permitted (got 1)"),
        ("footprint", {**STUDY, "\x1e": None}, r"error: \x1e: Extra inputs are not permitted (got None)"),
        (
            "fly",
            {**TABLE2, "vehicle": {"builtin": "lod-2.2", "x\u2028y\x00": 1}},
            r"error: vehicle.x\u2028y\x00: Extra inputs are not permitted (got 1)",
        ),
        # map read its file unchecked: a null latitude reached folium (ValueError: Location values cannot contain
        # NaNs), a word float(), a list html.escape (AttributeError): tracebacks
        (
            "map",
            changed(MAP_FOOTPRINT, "points.0.latitude_deg", None),
            "error: points.0.latitude_deg: Input should be a valid number (got None)",
        ),
        (
            "map",
            changed(MAP_FOOTPRINT, "points.1.longitude_deg", "east"),
            "error: points.1.longitude_deg: Input should be a valid number, unable to parse string as a number "
            "(got 'east')",
        ),
        (
            "map",
            changed(MAP_FOOTPRINT, "entry.heading_deg", float("nan")),
            "error: entry.heading_deg: nan is outside the allowed range -360 to 360 deg",
        ),
        (
            "map",
            changed(MAP_FOOTPRINT, "name", ["a", "list"]),
            "error: name: Input should be a valid string (got ['a', 'list'])",
        ),
        # an inline vehicle's coefficient of 401 digits: math.isfinite(int) raised OverflowError in core.aero (now
        # refused by the vehicle contract, which names the field as every other)
        (
            "fly",
            changed(SHUTTLE_CASE, "vehicle.aero.polynomial.cl.0", 10**400),
            f"error: vehicle.aero.polynomial.cl.0: Input should be a valid number (got {'1' + '0' * 76}...)",
        ),
    ],
)
def test_a_bad_key_or_value_found_by_the_fuzz_gets_one_line(quick_commands, folder, command, doc, line):
    result = invoke(command, json_bytes(doc, ensure_ascii=True), folder)
    assert (result.exit_code, result.stderr) == (2, line + "\n")


def test_an_integer_of_5000_digits_gets_one_line(quick_commands, folder):
    """json.loads raises a plain ValueError (Python's limit on the digits of int() from text), not JSONDecodeError."""
    result = invoke("sweep", b'{"name": ' + b"9" * 5_000 + b"}", folder)
    assert (result.exit_code, result.stderr) == (
        2,
        f"error: {folder / 'request.json'}: not a request: a number with more than 4,300 digits\n",
    )
