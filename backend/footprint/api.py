"""The Python door: fly(case), footprint(study), disperse(study), opportunities(study) and run(kind, request) for any
kind, with dicts or validated models (footprint.contracts), all through the one runner (footprint.parallel)."""

from footprint.parallel import run


def fly(case):
    """Fly one trajectory (footprint.core.trajectory.Trajectory). `case` follows the case contract
    (footprint.contracts.case.Case)."""
    return run("case", case)


def footprint(study, on_progress=None):
    """A landing footprint (footprint.core.footprints.Footprint). `study` follows the study contract
    (footprint.contracts.footprint)."""
    return run("footprint", study, on_progress=on_progress)


def disperse(study, progress=None, **dask):
    """A dispersed footprint (footprint.core.monte_carlo.DispersedFootprint) and how it ran: `study` follows
    footprint.contracts.dispersion; in this process, or on Dask with client=, workers= or scheduler=."""
    return run("dispersion", study, progress, **dask)


def opportunities(study, progress=None, **dask):
    """Landing opportunities in UTC from a TLE or a state vector (a dict: footprint.contracts.opportunities's answer):
    in this process, or on Dask with client=, workers= or scheduler=."""
    return run("opportunities", study, progress, **dask)


__all__ = ["disperse", "fly", "footprint", "opportunities", "run"]
