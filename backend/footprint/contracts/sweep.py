"""Footprint data base sweeps (AFWAL-TR-82-3036 Appendix C), one Dask task per footprint.

A sweep is a grid of footprints: every vehicle x every inertial entry velocity x every entry angle,
all sharing one base case and one footprint method (Appendix C data set 1: single-parameter bank at
(L/D)max with a C_L-max minimum-range point; data set 2: constant-altitude turns with iso-velocity
contours). The contract:

    {"name": "dataset1",
     "base": CASE without vehicle, bank and the swept entry fields,
     "method": "single_parameter" | "constant_altitude", plus that method's parameters (as in contracts/footprint.py),
     "vehicles": ["low-lod", {"builtin": "lod-2.6", "wing_loading_psf": 70}, ...],
     "entry_velocity_fps": [...], "entry_gamma_deg": [...], "velocity_frame": "inertial",
     "contours_fps": [...]}

`footprint.parallel.run("sweep", ...)` flies it, one part per footprint, on Dask (a LocalCluster or a scheduler
address; the same code path) or in this process. A footprint the core fails on becomes a row
with its error message; the rest of the sweep goes on. `SweepResult.write(folder)` writes the tidy
point table, the per-footprint summary and, when footprint.pictures.figures is there, the figures.

Each task also flies the footprint's zero-bank reference trajectory (the case's own alpha law, bank
held at zero), which gives the pull-out point of Figs. C-34 and C-35: every point that shares its
pull-out (all (L/D)max points when bank starts at pull-out) gets its pull-out down-range.
"""

import csv
import json
import os
import time
from collections.abc import Hashable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Annotated, Any, Literal, TypeVar

from pydantic import BeforeValidator, Field, TypeAdapter, ValidationError, ValidationInfo, create_model, model_validator

from footprint.contracts import parse
from footprint.contracts.bounds import FOOTPRINT_NAME_CHARS, fitted
from footprint.contracts.case import Case, EntryCase
from footprint.contracts.doors import door_limit, validated
from footprint.contracts.fields import Range, Strict, model_fields
from footprint.contracts.footprint import ConstantAltitudeStudy, SingleParameterStudy, ground_track, record
from footprint.contracts.footprint import fly as fly_study
from footprint.contracts.messages import error_line
from footprint.contracts.records import csv_cell
from footprint.contracts.vehicle import VehicleCase
from footprint.contracts.work import OnProgress, RunInfo, Stored, Work

MAX_FOOTPRINTS = 10_000  # one sweep; Appendix C data set 1 is 120
MAX_FOOTPRINTS_HTTP = 1_000  # one sweep job
SWEPT_ENTRY_FIELDS = ("velocity_fps", "gamma_deg", "velocity_frame")
UNFINISHED = ("max_steps", "step_underflow", "none")  # stop reasons of a flight the integrator gave up on


RunKey = tuple[str, float, float]  # a footprint of the sweep: (vehicle, entry_velocity_fps, entry_gamma_deg)
_H = TypeVar("_H", bound=Hashable)

# ---------------------------------------------------------------------------------------- contract
if TYPE_CHECKING:  # mypy cannot see the fields of create_model's classes (below): these name the ones the code reads

    class SweepEntry(Strict):
        altitude_ft: float

    class SweepBase(Strict):
        entry: SweepEntry

else:
    # The entry state shared by every footprint: the case's entry less what the sweep varies.
    SweepEntry = create_model("SweepEntry", __base__=Strict, **model_fields(EntryCase, exclude=SWEPT_ENTRY_FIELDS))

    # The base case: the case contract less the vehicle (the sweep's list), the bank law (the method's)
    # and the swept entry fields.
    SweepBase = create_model(
        "SweepBase", __base__=Strict, **model_fields(Case, exclude=("vehicle", "bank"), entry=(SweepEntry, ...))
    )


def _vehicle_ref(value: Any) -> Any:
    return {"builtin": value} if isinstance(value, str) else value


VehicleRef = Annotated[VehicleCase, BeforeValidator(_vehicle_ref)]


class _Sweep(Strict):
    name: str = Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")  # used in file names
    description: str = Field(default="", max_length=4000)
    base: SweepBase
    vehicles: list[VehicleRef] = Field(min_length=1, max_length=20)
    entry_velocity_fps: list[Annotated[float, Range(1_000, 40_000, "ft/s")]] = Field(min_length=1, max_length=100)
    entry_gamma_deg: list[Annotated[float, Range(-90, 10, "deg")]] = Field(min_length=1, max_length=100)
    velocity_frame: Literal["inertial", "relative"] = "inertial"
    contours_fps: list[Annotated[float, Range(100, 40_000, "ft/s")]] = Field(default=[], max_length=20)
    if TYPE_CHECKING:  # each method's sweep model has it (create_model, below): the study's discriminator
        method: str

    @model_validator(mode="after")
    def _grid(self, info: ValidationInfo) -> "_Sweep":
        labels = [v.label() for v in self.vehicles]
        if len(set(labels)) < len(labels):
            raise ValueError(
                f"vehicles: two vehicles share the label {_first_duplicate(labels)!r}; give each a distinct 'name'"
            )
        for what, values in (
            ("entry_velocity_fps", self.entry_velocity_fps),
            ("entry_gamma_deg", self.entry_gamma_deg),
            ("contours_fps", self.contours_fps),
        ):
            if len(set(values)) < len(values):
                raise ValueError(f"{what}: {_first_duplicate(values):g} is listed twice")
        limit, where = door_limit(info, MAX_FOOTPRINTS, MAX_FOOTPRINTS_HTTP)
        if self.size > limit:
            raise ValueError(
                f"vehicles: the sweep has {self.size} footprints (vehicles x entry_velocity_fps x "
                f"entry_gamma_deg); allowed{where}: 1 to {limit}"
            )
        try:  # every footprint flies the same settings: the first one's points bound them all
            parse("footprint", self.jobs()[0]["study"], info.context)
        except ValidationError as exc:
            raise ValueError(error_line(exc)) from None
        for v in self.entry_velocity_fps:  # every combination must be a valid case (the vehicle is irrelevant)
            for g in self.entry_gamma_deg:
                try:
                    Case.model_validate(self.case_dict(self.vehicles[0], v, g))
                except ValidationError as exc:
                    raise ValueError(f"entry_velocity_fps {v:g}, entry_gamma_deg {g:g}: {error_line(exc)}") from None
        return self

    # -- the footprints of the grid
    def method_params(self) -> dict[str, Any]:
        common = set(_Sweep.model_fields)
        return {k: v for k, v in self.model_dump().items() if k not in common and k != "method"}

    def case_dict(self, vehicle: VehicleCase, velocity_fps: float, gamma_deg: float) -> dict[str, Any]:
        base = self.base.model_dump()
        base["entry"] |= {"velocity_fps": velocity_fps, "gamma_deg": gamma_deg, "velocity_frame": self.velocity_frame}
        return {"vehicle": vehicle.definition(), **base}

    def jobs(self) -> list[dict[str, Any]]:
        """One job per footprint, in sweep order (vehicle, velocity, angle): plain data, small to ship."""
        return [
            {
                "key": (veh.label(), float(v), float(g)),
                "study": {
                    "case": self.case_dict(veh, v, g),
                    "method": self.method,
                    **self.method_params(),
                    "contours_fps": list(self.contours_fps),
                },
            }
            for veh in self.vehicles
            for v in self.entry_velocity_fps
            for g in self.entry_gamma_deg
        ]

    @property
    def size(self) -> int:
        return len(self.vehicles) * len(self.entry_velocity_fps) * len(self.entry_gamma_deg)


def _first_duplicate(values: Iterable[_H]) -> _H | None:
    seen = set()
    for v in values:
        if v in seen:
            return v
        seen.add(v)
    return None


# One sweep model per method: the shared fields plus that method's parameters from the study contract.
if TYPE_CHECKING:  # as mypy sees them: sweeps (the code reads the method's fields through model_dump)

    class SingleParameterSweep(_Sweep): ...

    class ConstantAltitudeSweep(_Sweep): ...

else:
    SingleParameterSweep = create_model(
        "SingleParameterSweep", __base__=_Sweep, **model_fields(SingleParameterStudy, exclude=("case",))
    )
    ConstantAltitudeSweep = create_model(
        "ConstantAltitudeSweep", __base__=_Sweep, **model_fields(ConstantAltitudeStudy, exclude=("case",))
    )
Sweep = Annotated[SingleParameterSweep | ConstantAltitudeSweep, Field(discriminator="method")]

REQUEST = Sweep  # the kind's request type (the OpenAPI document declares it)
ADAPTER: TypeAdapter[_Sweep] = TypeAdapter(REQUEST)  # validates to one of the method sweeps


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> _Sweep:
    """Validate a sweep (dict or model); its vehicles are built as they are parsed (an inline definition is checked
    by the core here, not in 40 tasks later). Raises pydantic's ValidationError (`error_line` makes it one line)."""
    sweep: _Sweep = validated(ADAPTER, data, _Sweep, ctx)
    return sweep


# ------------------------------------------------------------------------------------------ worker
@dataclass
class FootprintRun:
    """One part's outcome: the footprint (None if the core failed), its pull-out reference and ground track."""

    vehicle: str
    entry_velocity_fps: float
    entry_gamma_deg: float
    method: str
    study: dict[str, Any]  # the footprint's study, as stored
    footprint: Any = None  # footprint.core.footprints.Footprint
    # altitude_ft, downrange_nmi, velocity_fps, time_s of the footprint's first point
    pullout: dict[str, Any] | None = None
    # the zero-bank flight, decimated (footprint.contracts.footprint.ground_track)
    ground_track: dict[str, Any] | None = None
    trajectories: int = 0
    seconds: float = 0.0
    worker: str = ""
    error: str | None = None

    @property
    def key(self) -> RunKey:
        return self.vehicle, self.entry_velocity_fps, self.entry_gamma_deg


def fly_footprint(sweep: "_Sweep", job: dict[str, Any], on_progress: OnProgress | None = None) -> FootprintRun:
    """A part: one footprint of the sweep (`job`: one of sweep.jobs(); on_progress as the core's footprints take it:
    a True answer stops it). Never raises: a failure in the core comes back as a run with `error` set."""
    vehicle, velocity_fps, gamma_deg = job["key"]
    run = FootprintRun(
        vehicle=vehicle,
        entry_velocity_fps=velocity_fps,
        entry_gamma_deg=gamma_deg,
        method=job["study"]["method"],
        study=job["study"],
        worker=f"pid {os.getpid()}",
    )
    t0 = time.perf_counter()
    try:
        study = parse("footprint", job["study"])
        run.footprint = fly_study(study, on_progress=on_progress)
        first = run.footprint.points[0]  # the straight, wings-level flight: the footprint's pull-out
        run.pullout = {
            k: getattr(first, f"pullout_{k}") for k in ("altitude_ft", "downrange_nmi", "velocity_fps", "time_s")
        }
        run.trajectories = run.footprint.trajectories
        run.ground_track = ground_track(study.case.to_spec())
    except Exception as exc:  # noqa: BLE001 -- any failure of one footprint is that footprint's row
        run.footprint, run.error = None, f"{type(exc).__name__}: {exc}"
    run.seconds = time.perf_counter() - t0
    return run


def combine(sweep: "_Sweep", runs: list[FootprintRun], info: RunInfo) -> "SweepResult":
    return SweepResult(
        sweep=sweep,
        runs={run.key: run for run in runs},
        tasks=info.tasks,
        workers=info.workers,
        seconds=info.seconds,
        startup_seconds=info.startup_seconds,
        warm_seconds=info.warm_seconds,
    )


def store(sweep: "_Sweep", result: "SweepResult", name: str | None) -> Stored:
    """A sweep job's rows: each footprint flown (named for the sweep, its vehicle and entry), and the sweep's
    summary with the errors of those that failed."""
    flown_runs = [r for r in result.runs.values() if r.footprint is not None]
    errors = [
        {
            "vehicle": r.vehicle,
            "entry_velocity_fps": r.entry_velocity_fps,
            "entry_gamma_deg": r.entry_gamma_deg,
            "error": r.error,
        }
        for r in result.runs.values()
        if r.footprint is None
    ]
    footprints = [
        record(
            r.footprint,
            vehicle=r.vehicle,
            study=r.study,
            track=r.ground_track,
            entry={
                "velocity_fps": r.entry_velocity_fps,
                "gamma_deg": r.entry_gamma_deg,
                "altitude_ft": sweep.base.entry.altitude_ft,
            },
            name=fitted(
                f"{sweep.name} {r.vehicle}",
                f"{r.entry_velocity_fps:g} fps {r.entry_gamma_deg:g} deg",
                FOOTPRINT_NAME_CHARS,
            ),
        )
        for r in flown_runs
    ]
    return Stored(
        result={"sweep": {"name": sweep.name, "footprints": len(flown_runs), "errors": errors}}, footprints=footprints
    )


# ------------------------------------------------------------------------------------------ result
POINT_COLUMNS = (
    "sweep",
    "vehicle",
    "entry_velocity_fps",
    "entry_gamma_deg",
    "method",
    "point",
    "on_boundary",
    "parameter",
    "side",
    "velocity_contour_fps",
    "downrange_nmi",
    "crossrange_nmi",
    "flight_time_s",
    "altitude_ft",
    "latitude_deg",
    "longitude_deg",
    "pullout_altitude_ft",
    "pullout_downrange_nmi",
    "turn_deg",
    "stop_reason",
    "mirrored",
    "error",
)
SUMMARY_COLUMNS = (
    "sweep",
    "vehicle",
    "entry_velocity_fps",
    "entry_gamma_deg",
    "method",
    "points",
    "max_crossrange_nmi",
    "max_downrange_nmi",
    "min_downrange_nmi",
    "area_nmi2",
    "pullout_altitude_ft",
    "pullout_downrange_nmi",
    "pullout_velocity_fps",
    "skip_outs",
    "unfinished",
    "trajectories",
    "seconds",
    "worker",
    "error",
)


@dataclass
class SweepResult:
    sweep: _Sweep
    runs: dict[RunKey, FootprintRun]  # (vehicle, entry_velocity_fps, entry_gamma_deg) -> run, in sweep order
    tasks: int  # Dask tasks submitted (one per footprint)
    workers: int
    seconds: float  # first submission to last result
    startup_seconds: float = 0.0  # starting (or connecting to) the cluster
    warm_seconds: float = 0.0  # the numba warm-up flight in this process
    figures_note: str = field(default="", init=False)

    @property
    def footprints(self) -> dict[RunKey, Any]:
        """(vehicle, entry_velocity_fps, entry_gamma_deg) -> Footprint, for the footprints that were flown."""
        return {k: r.footprint for k, r in self.runs.items() if r.footprint is not None}

    @property
    def errors(self) -> dict[RunKey, str]:
        return {k: r.error for k, r in self.runs.items() if r.error is not None}

    @property
    def trajectories(self) -> int:
        return sum(r.trajectories for r in self.runs.values())

    def point_rows(self) -> list[dict[str, Any]]:
        """One row per footprint point: the boundary in order (`point` = its index), then any flown point
        inside it (`on_boundary` False: a minimum-range point that steep banks beat); each preceded by its
        iso-velocity crossings (`velocity_contour_fps` set). A failed footprint is one row with its error."""
        rows: list[dict[str, Any]] = []
        for run in self.runs.values():
            key: dict[str, Any] = {
                "sweep": self.sweep.name,
                "vehicle": run.vehicle,
                "entry_velocity_fps": run.entry_velocity_fps,
                "entry_gamma_deg": run.entry_gamma_deg,
                "method": run.method,
            }
            if run.footprint is None:
                rows.append(key | {"error": run.error})
                continue
            fp = run.footprint
            boundary = [(i, True, p) for i, p in enumerate(fp.points)]
            interior = [(None, False, p) for p in getattr(fp, "interior", ())]
            for i, on_boundary, p in boundary + interior:
                common = key | {
                    "point": i,
                    "on_boundary": on_boundary,
                    "parameter": json.dumps(p.parameter.as_dict(), sort_keys=True),
                    "side": p.side,
                    "pullout_altitude_ft": p.pullout_altitude_ft,
                    "pullout_downrange_nmi": p.pullout_downrange_nmi,
                    "turn_deg": p.turn_deg,
                    "mirrored": p.mirrored,
                }
                for c in p.contours:
                    rows.append(
                        common
                        | {
                            "velocity_contour_fps": c["velocity_fps"],
                            **{
                                k: c[k]
                                for k in (
                                    "downrange_nmi",
                                    "crossrange_nmi",
                                    "flight_time_s",
                                    "altitude_ft",
                                    "latitude_deg",
                                    "longitude_deg",
                                )
                            },
                        }
                    )
                rows.append(
                    common
                    | {
                        "downrange_nmi": p.downrange_nmi,
                        "crossrange_nmi": p.crossrange_nmi,
                        "flight_time_s": p.flight_time_s,
                        "altitude_ft": p.final_altitude_ft,
                        "latitude_deg": p.latitude_deg,
                        "longitude_deg": p.longitude_deg,
                        "stop_reason": p.stop_reason,
                    }
                )
        return rows

    def summary_rows(self) -> list[dict[str, Any]]:
        rows: list[dict[str, Any]] = []
        for run in self.runs.values():
            fp, po = run.footprint, run.pullout or {}
            row: dict[str, Any] = {
                "sweep": self.sweep.name,
                "vehicle": run.vehicle,
                "entry_velocity_fps": run.entry_velocity_fps,
                "entry_gamma_deg": run.entry_gamma_deg,
                "method": run.method,
                "pullout_altitude_ft": po.get("altitude_ft"),
                "pullout_downrange_nmi": po.get("downrange_nmi"),
                "pullout_velocity_fps": po.get("velocity_fps"),
                "trajectories": run.trajectories,
                "seconds": round(run.seconds, 4),
                "worker": run.worker,
                "error": run.error,
            }
            if fp is not None:
                flown = list(fp.points) + list(getattr(fp, "interior", ()))
                row |= {
                    "points": len(fp.points),
                    "max_crossrange_nmi": fp.max_crossrange_nmi,
                    "max_downrange_nmi": fp.max_downrange_nmi,
                    "min_downrange_nmi": fp.min_downrange_nmi,
                    "area_nmi2": fp.area_nmi2,
                    "skip_outs": sum(p.stop_reason == "skip_out" for p in flown),
                    "unfinished": sum(p.stop_reason in UNFINISHED for p in flown),
                }
            rows.append(row)
        return rows

    def write(self, folder: str | os.PathLike[str], figures: bool = True) -> list[Path]:
        """points.csv, summary.csv and sweep.json in `folder`; figures/ too when footprint.pictures.figures exists."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        written = [
            _write_csv(folder / "points.csv", POINT_COLUMNS, self.point_rows()),
            _write_csv(folder / "summary.csv", SUMMARY_COLUMNS, self.summary_rows()),
        ]
        (folder / "sweep.json").write_text(json.dumps(self.sweep.model_dump(), indent=1))
        written.append(folder / "sweep.json")
        if figures:
            written += self.write_figures(folder / "figures")
        return written

    def write_figures(self, folder: str | os.PathLike[str]) -> list[Path]:
        """Per vehicle and entry velocity, the footprints over entry angle; per vehicle, the pull-out carpet;
        per footprint with iso-velocity contours, the contours. Skipped (see `figures_note`) while
        footprint.pictures.figures is not there."""
        fig = _figures_module()
        if isinstance(fig, str):
            self.figures_note = fig
            return []
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        written, name = [], self.sweep.name
        by_vehicle: dict[str, dict[float, dict[str, Any]]] = {}
        for (veh, v, g), fp in self.footprints.items():
            by_vehicle.setdefault(veh, {}).setdefault(v, {})[f"gamma {g:g} deg"] = fp
        for veh, by_velocity in by_vehicle.items():
            for v, family in by_velocity.items():
                path = folder / f"{_file_part(veh)}_V{v:.0f}_footprints.png"
                fig.save(
                    fig.footprints_figure(family, f"{name}: {veh}, V = {v:,.0f} ft/s ({self.sweep.velocity_frame})"),
                    path,
                )
                written.append(path)
            rows = [r for r in self.summary_rows() if r["vehicle"] == veh and r["pullout_altitude_ft"] is not None]
            if rows:
                path = folder / f"{_file_part(veh)}_pullout_carpet.png"
                fig.save(fig.pullout_carpet_figure(rows, f"{name}: {veh}, pull-out altitude and down-range"), path)
                written.append(path)
        if self.sweep.contours_fps:
            for (veh, v, g), fp in self.footprints.items():
                path = folder / f"{_file_part(veh)}_V{v:.0f}_g{g:g}_contours.png"
                fig.save(fig.contours_figure(fp, f"{name}: {veh}, V = {v:,.0f} ft/s, gamma = {g:g} deg"), path)
                written.append(path)
        return written


def _figures_module() -> ModuleType | str:
    """footprint.pictures.figures, or a note saying why there are no figures."""
    import importlib
    import warnings

    try:
        fig = importlib.import_module("footprint.pictures.figures")
    except ModuleNotFoundError as exc:
        if exc.name != "footprint.pictures.figures":
            warnings.warn(f"figures skipped: {exc}", stacklevel=3)
            return f"figures skipped: {exc}"
        return "figures skipped: footprint.pictures.figures is not installed"
    missing = [
        f for f in ("footprints_figure", "contours_figure", "pullout_carpet_figure", "save") if not hasattr(fig, f)
    ]
    if missing:
        return f"figures skipped: footprint.pictures.figures has no {', '.join(missing)}"
    return fig


def _file_part(text: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in text)


def _write_csv(path: Path, columns: Sequence[str], rows: Iterable[dict[str, Any]]) -> Path:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, restval="", extrasaction="raise")
        w.writeheader()
        for row in rows:
            w.writerow({k: csv_cell(v) for k, v in row.items()})
    return path


WORK = Work(split=_Sweep.jobs, run_part=fly_footprint, combine=combine, store=store, part_unit="footprint")
