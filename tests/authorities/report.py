"""The published numbers the tests, benchmarks and scripts compare against, read from data, never retyped.

    REPORT[key].value / .unit / .where / .quote   AFWAL-TR-82-3036 (afwal_tr_82_3036.json beside this file)
    example(name)                                 examples/<name>.json, parsed
    table2_entry(**changes), table2_stop()        the report's Table 2 entry and stop, from examples/table2_lod22.json
    betts(case)                                   Betts' published shuttle optimum (betts_shuttle_reentry.csv)

Standard library only: tests import it as tests.authorities.report; bench/ and scripts/ put the repository
root on sys.path first.
"""

import csv
import json
from pathlib import Path
from typing import Any, NamedTuple

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parents[1] / "examples"


class Number(NamedTuple):
    value: Any
    unit: str
    where: str
    quote: str


REPORT = {k: Number(**r) for k, r in json.loads((HERE / "afwal_tr_82_3036.json").read_text())["records"].items()}


def example(name: str) -> dict:
    """A fresh copy of examples/<name>.json (callers may change it)."""
    return json.loads((EXAMPLES / f"{name}.json").read_text())


def guided_spreads() -> dict:
    """The dispersions of issue 27's example (examples/disperse_guided_lod189.json): entry gamma and heading 0.05 deg,
    V 15 ft/s, density 5 % correlated over 30,000 ft, C_L and C_D 3 % truncated at 3 sigma."""
    data = example("disperse_guided_lod189")
    return {k: data[k] for k in ("entry", "vehicle", "density")}


def table2_entry(**changes) -> dict:
    """The report's Table 2 entry (364,800 ft, 24,480 ft/s relative, -2 deg, heading 90 at 0 N 0 E), as
    examples/table2_lod22.json flies it (whose vehicle, lod-2.2, is not part of Table 2), with `changes`."""
    return {**example("table2_lod22")["entry"], **changes}


def table2_stop() -> dict:
    """Table 2's stop: 50,000 ft."""
    return example("table2_lod22")["stop"]


def betts(case: str = "max_crossrange_no_heating_limit") -> dict:
    """Betts' published Space Shuttle optimum, a row of betts_shuttle_reentry.csv: final_latitude_deg, flight_time_s."""
    with open(HERE / "betts_shuttle_reentry.csv") as f:
        rows = {r.pop("case"): r for r in csv.DictReader(line for line in f if not line.startswith("#"))}
    return {k: float(v) for k, v in rows[case].items()}
