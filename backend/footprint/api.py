"""The Python door: fly(case) and footprint(study), with dicts or validated models."""

from footprint.cases import Case, parse_case
from footprint.core.footprints import Footprint
from footprint.core.footprint_methods import footprint as _footprint
from footprint.core.trajectory import Trajectory, simulate
from footprint.studies import parse_study


def fly(case: dict | Case) -> Trajectory:
    """Fly one trajectory. `case` follows the case contract (see footprint.cases.Case)."""
    return simulate(parse_case(case).to_spec())


def footprint(study) -> Footprint:
    """A landing footprint. `study` follows the study contract (see footprint.studies)."""
    study = parse_study(study)
    return _footprint(study.case.to_spec(), study.method, **study.to_params())
