"""Every footprint method by its settings' type, and footprint(spec, settings): the one table the CLI, the Python
API, the service and the data-base sweeps look a study's method up in. It sits above the modules that implement
the methods (footprints: Sections II.5-II.7; constrained: the temperature-limited footprint; collocation_footprint:
the true optimal boundary), which build on footprints, so none of them imports another in a circle."""

from collections.abc import Callable

from footprint.core.constrained import temperature_limited_footprint
from footprint.core.footprints import (
    Family,
    Footprint,
    constant_altitude,
    constant_bank,
    constant_bank_family,
    single_parameter,
    single_parameter_family,
    staged,
    two_parameter,
)
from footprint.core.method_settings import (
    Collocation,
    ConstantAltitude,
    ConstantBank,
    MethodSettings,
    SingleParameter,
    Staged,
    TemperatureLimited,
    TwoParameter,
)
from footprint.core.trajectory import FlightSpec

METHODS: dict[type, Callable[..., Footprint]] = {
    SingleParameter: single_parameter,
    ConstantBank: constant_bank,
    Staged: staged,
    TwoParameter: two_parameter,
    ConstantAltitude: constant_altitude,
}


# the methods whose control settings are fixed laws, as families [(parameter, make(spec, right) -> spec, on_axis)]
# (the others search or optimize each point's controls for the spec they fly: a dispersed world would change them)
FAMILIES: dict[type, Callable[..., Family]] = {
    SingleParameter: single_parameter_family,
    ConstantBank: constant_bank_family,
    Staged: constant_bank_family,
}


def control_family(settings: MethodSettings) -> tuple[Family, bool]:
    """(the family of control settings a method flies with these settings, whether it flies both halves)."""
    return FAMILIES[type(settings)](settings), settings.mirror


def footprint(
    spec: FlightSpec, settings: MethodSettings, on_progress: Callable[[float, str], bool | None] | None = None
) -> Footprint:
    """The footprint of `spec` by the method `settings` name; on_progress(fraction, note) where the method is long
    enough to report (the collocation's IPOPT iterations)."""
    if isinstance(settings, TemperatureLimited):
        return temperature_limited_footprint(spec, settings).footprint
    if isinstance(settings, Collocation):  # the true optimal boundary (CasADi, slow to import): loaded when asked for
        from footprint.core.collocation_footprint import collocation_footprint

        return collocation_footprint(spec, settings, on_progress=on_progress)
    return METHODS[type(settings)](spec, settings)
