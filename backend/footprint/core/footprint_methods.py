"""Every footprint method by name, and footprint(spec, method, ...): the one table the CLI, the Python API,
the service and the data-base sweeps look a study's method up in. It sits above the modules that implement
the methods (footprints: Sections II.5-II.7; constrained: the temperature-limited footprint; collocation_footprint:
the true optimal boundary), which build on footprints, so none of them imports another in a circle."""

from collections.abc import Callable

from footprint.core.constrained import temperature_limited_footprint
from footprint.core.footprints import (
    Footprint,
    constant_altitude,
    constant_bank,
    constant_bank_family,
    single_parameter,
    single_parameter_family,
    staged,
    two_parameter,
)
from footprint.core.trajectory import FlightSpec

METHODS: dict[str, Callable[..., Footprint]] = {
    "single_parameter": single_parameter,
    "constant_bank": constant_bank,
    "staged": staged,
    "two_parameter": two_parameter,
    "constant_altitude": constant_altitude,
}


# the methods whose control settings are fixed laws, as families [(parameter, make(spec, right) -> spec, on_axis)]
# (the others search or optimize each point's controls for the spec they fly: a dispersed world would change them)
FAMILIES: dict[str, Callable[..., list]] = {
    "single_parameter": single_parameter_family,
    "constant_bank": constant_bank_family,
    "staged": lambda **params: constant_bank_family(staged=True, **params),
}


def control_family(method: str, **params) -> tuple[list, bool]:
    """(the family of control settings `method` flies with these parameters, whether it flies both halves)."""
    params = dict(params)
    mirror = params.pop("mirror", True)
    params.pop("contours_fps", None)
    return FAMILIES[method](**params), mirror


def footprint(spec: FlightSpec, method: str, on_progress=None, **params) -> Footprint:
    """The footprint of `spec` by `method`; on_progress(fraction, note) where the method is long enough to
    report (the collocation's IPOPT iterations)."""
    if method == "temperature_limited":
        return temperature_limited_footprint(spec, **params).footprint
    if method == "collocation":  # the true optimal boundary (CasADi, slow to import): loaded when asked for
        from footprint.core.collocation_footprint import collocation_footprint

        return collocation_footprint(spec, on_progress=on_progress, **params)
    return METHODS[method](spec, **params)
