"""The functions Dask runs in the workers, one task per footprint, optimization or reach analysis. Each takes
and returns plain data (validated study dicts in, JSON-ready dicts out), so any worker can run it."""

import time
from dataclasses import asdict

from footprint import contracts
from footprint.contracts.records import FLIGHT_KEYS, flown, plain

PROGRESS_TOPIC = "footprint-progress"  # the Dask event topic of the tasks' progress (JobEngine subscribes)
PROGRESS_EVERY_S = 0.5  # a task's progress events at most this often
POINT_FIELDS = ("downrange_nmi", "crossrange_nmi", "flight_time_s", "latitude_deg", "longitude_deg", "heading_deg",
                "side", "parameter", "stop_reason", "mirrored")
WARM_CASE = {"vehicle": {"builtin": "lod-2.2"},
             "entry": {"altitude_ft": 364_800, "velocity_fps": 24_480, "gamma_deg": -2.0},
             "stop": {"altitude_ft": 250_000}}  # a short flight that loads every compiled kernel


def progress_reporter():
    """on_progress(fraction, note) for the core's long loops, sent as a Dask event of this task (its key), at
    most every PROGRESS_EVERY_S; None outside a Dask worker. Returns True once the task is cancelled (the engine's
    cancel and time limit cancel its future: the worker marks the running task), which stops the loop at its next
    report: the worker is free at once, not restarted (the engine's last resort). Its creation sends the task's
    first event, which tells the engine a worker has started it (the job is "running", its time limit counts)."""
    from distributed import get_worker

    try:
        worker = get_worker()
    except ValueError:
        return None
    key, last = worker.get_current_task(), [0.0]
    worker.log_event(PROGRESS_TOPIC, {"key": str(key), "progress": 0.0, "note": ""})

    def on_progress(fraction: float, note: str) -> bool:
        now = time.monotonic()
        if now - last[0] >= PROGRESS_EVERY_S:
            last[0] = now
            worker.log_event(PROGRESS_TOPIC, {"key": str(key), "progress": float(fraction), "note": note})
        task = worker.state.tasks.get(key)  # read in this thread, written by the worker's event loop: a plain lookup
        return task is None or task.state in ("cancelled", "released", "forgotten")
    return on_progress


def running_keys(dask_worker) -> list[str]:
    """The keys this worker's threads run now, cancelled ones included (client.run(running_keys): JobEngine.stop)."""
    return [str(task.key) for task in dask_worker.state.executing]


def warm_numba() -> float:
    """Fly one short trajectory so this process has loaded (or compiled) numba's cache; the seconds taken."""
    from footprint.api import fly

    t0 = time.perf_counter()
    fly(WARM_CASE)
    return time.perf_counter() - t0


def ground_track(spec) -> dict:
    """The case flown with zero bank (Section II.6's maximum down-range flight), decimated for the map."""
    from footprint.core.footprints import with_bank
    from footprint.core.trajectory import simulate

    return flown(simulate(with_bank(spec, "zero")))


def footprint_record(fp, study, study_dict: dict, track: dict, name: str) -> dict:
    """A flown footprint as the row data the store writes (summary, points, interior, ground track)."""
    entry = study.case.entry
    return {"name": name, "vehicle": study.case.vehicle.label(), "method": fp.method, "study": study_dict,
            "entry": {**{k: float(fp.entry[k]) for k in ("latitude_deg", "longitude_deg", "heading_deg")},
                      "velocity_fps": entry.velocity_fps, "gamma_deg": entry.gamma_deg,
                      "altitude_ft": entry.altitude_ft},
            "area_nmi2": float(fp.area_nmi2), "max_crossrange_nmi": float(fp.max_crossrange_nmi),
            "max_downrange_nmi": float(fp.max_downrange_nmi), "min_downrange_nmi": float(fp.min_downrange_nmi),
            "trajectories": int(fp.trajectories),
            "points": [_point(p) for p in fp.points], "interior": [_point(p) for p in fp.interior],
            "ground_track": track}


def _point(p) -> dict:
    d = asdict(p)
    return {k: plain(d[k]) for k in POINT_FIELDS}


def footprint_task(study_dict: dict, name: str) -> dict:
    """A footprint job: the footprint and its zero-bank ground track. Raises what the core raises."""
    study = contracts.parse("footprint", study_dict)
    fp = contracts.module("footprint").run(study, on_progress=progress_reporter())
    return footprint_record(fp, study, study_dict, ground_track(study.case.to_spec()), name)


def sweep_footprint_task(job: dict, name: str) -> dict:
    """One footprint of a sweep (footprint.contracts.sweep.fly_footprint) and its ground track; a footprint the core
    fails on comes back as {"key", "error"}."""
    from footprint.contracts.sweep import fly_footprint

    study = contracts.parse("footprint", job["study"])
    run = fly_footprint(job, study, on_progress=progress_reporter())  # a cancel stops it, no worker restarted
    if run.footprint is None:
        return {"key": list(job["key"]), "error": run.error}
    return footprint_record(run.footprint, study, job["study"], ground_track(study.case.to_spec()), name)


def optimize_task(study_dict: dict) -> dict:
    """An optimization job: the optimum, its parameters and the convergence history, and its flight (the
    integrator's; the ground track and the histories the page plots); a collocation that ends without an
    optimum fails the job with its one line (status and largest violation)."""
    from footprint.contracts.optimization import fly_optimum
    from footprint.core.collocation import NoOptimum, Result

    study = contracts.parse("optimize", study_dict)
    result = contracts.module("optimize").run(study, on_progress=progress_reporter())
    if isinstance(result, Result) and not result.ok:
        raise NoOptimum(result.one_line())
    return {**plain(result.to_dict()), "flight": flown(fly_optimum(study, result), FLIGHT_KEYS)}


def reach_task(request: dict) -> dict:
    """A reach job: footprint.contracts.reach's windows and per-site summary."""
    return plain(contracts.module("reach").run(contracts.parse("reach", request), on_progress=progress_reporter()))


def dispersion_task(study: dict, first: int, end: int):
    """A chunk of a dispersion job: samples first..end-1 flown (footprint.contracts.dispersion.fly_chunk), their
    landings (plain arrays, not JSON: the engine joins the chunks)."""
    from footprint.contracts.dispersion import fly_chunk

    return fly_chunk(study, first, end, on_progress=progress_reporter())


TASKS = {"optimize": optimize_task, "reach": reach_task}  # the single-task kinds (footprint, sweep, dispersion: engine._calls)
