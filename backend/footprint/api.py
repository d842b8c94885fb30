"""The Python door: fly(case) with a case dict or a validated Case."""

from footprint.cases import Case, parse_case
from footprint.core.trajectory import Trajectory, simulate


def fly(case: dict | Case) -> Trajectory:
    """Fly one trajectory. `case` follows the case contract (see footprint.cases.Case)."""
    return simulate(parse_case(case).to_spec())
