"""Results as JSON-ready records: plain values, and a trajectory's histories decimated for a map or a plot."""

import json
import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np
import orjson
from numpy.typing import NDArray

if TYPE_CHECKING:
    from footprint.core.trajectory import Trajectory

MAX_TRACK_POINTS = 500  # a stored ground track or flight
FLIGHT_KEYS = (
    "time_s",
    "latitude_deg",
    "longitude_deg",
    "altitude_ft",
    "velocity_fps",
    "alpha_deg",
    "bank_deg",
    "downrange_nmi",
    "crossrange_nmi",
    "temperature_R",
)  # a flight's stored histories (with heating)


def plain(value: Any) -> Any:
    """JSON-ready: numpy scalars and arrays to Python, tuples to lists, NaN and infinities to None."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [plain(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


_JSON_OPTIONS = orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS


def json_bytes(value: Any, indent: int | None = None) -> bytes:
    """RFC 8259 JSON of `value` as plain() would make it (NaN and infinities as null, as the service writes them),
    compact or indented by 2: what the CLI prints and writes, and the service's trajectory answer, GeoJSON and job
    events. orjson walks the value in C, floats in their shortest round-trip digits as json.dumps writes them, numpy
    scalars and C-contiguous numeric arrays from their memory (plain() first, over a summary's 25 values, was most of
    the JSON's cost); anything else it does not know goes through plain(), or as its float or its text."""
    if indent not in (None, 2):
        raise ValueError(f"indent={indent!r}: 2 or None")
    return orjson.dumps(value, default=_json_other, option=_JSON_OPTIONS | (orjson.OPT_INDENT_2 if indent else 0))


def _json_other(o: Any) -> Any:
    if isinstance(o, np.ndarray):  # strided, or of a dtype orjson does not write
        return plain(o)
    return plain(float(o)) if hasattr(o, "__float__") else str(o)


def strict_json(value: Any, indent: int | None = None) -> str:
    """json_bytes as text."""
    return json_bytes(value, indent).decode()


def decimated(n: int, max_points: int) -> NDArray[np.int_]:
    """At most max_points indices of n samples, evenly spread, keeping the first and the last."""
    if n <= max_points:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, max_points).round().astype(int))


def flown(
    traj: "Trajectory",
    keys: Iterable[str] = ("time_s", "latitude_deg", "longitude_deg"),
    max_points: int = MAX_TRACK_POINTS,
) -> dict[str, Any]:
    """A trajectory's summary and its histories of `keys` (those it has), decimated to max_points."""
    keep = decimated(len(traj.history["time_s"]), max_points)
    return {"summary": plain(traj.summary), **{k: plain(traj.history[k][keep]) for k in keys if k in traj.history}}


# a spreadsheet runs a cell that starts so as a formula (OWASP, "CSV Injection"): user text is kept text by a quote
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def csv_cell(value: Any) -> Any:
    """A CSV cell: None empty; a float in full (repr) precision, so a table read back gives the same numbers; a dict
    as sorted JSON; text a spreadsheet would run as a formula behind an apostrophe."""
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dict):
        return json.dumps(value, sort_keys=True)
    if isinstance(value, str) and value.startswith(FORMULA_START):
        return "'" + value
    return value
