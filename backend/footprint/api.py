"""The Python door: fly(case) and footprint(study), with dicts or validated models (footprint.contracts)."""

from footprint import contracts


def fly(case):
    """Fly one trajectory (footprint.core.trajectory.Trajectory). `case` follows the case contract
    (footprint.contracts.case.Case)."""
    return contracts.module("case").run(contracts.parse("case", case))


def footprint(study, on_progress=None):
    """A landing footprint (footprint.core.footprints.Footprint). `study` follows the study contract
    (footprint.contracts.footprint)."""
    return contracts.module("footprint").run(contracts.parse("footprint", study), on_progress)


def disperse(study, progress=None, **dask):
    """A dispersed footprint (footprint.core.monte_carlo.DispersedFootprint) and how it ran: `study` follows
    footprint.contracts.dispersion; in this process, or on Dask with client=, workers= or scheduler=."""
    return contracts.module("dispersion").run(study, progress, **dask)
