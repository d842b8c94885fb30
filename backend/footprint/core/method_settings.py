"""The footprint methods' settings: one frozen record per method, whose defaults are the only ones (the request
contracts take theirs from here). core.footprint_methods.footprint(spec, settings) flies the method a record names.
"""

from dataclasses import dataclass
from typing import Literal

from footprint.core.optimize import TTOL_TEMPERATURE_R

MinRange = Literal["zero_lift", "cl_max"]
BANK0_DEG = tuple(float(b) for b in range(0, 151, 15))  # Section II.6 a: phi0 stepped 0-150 deg


@dataclass(frozen=True)
class SingleParameter:
    """Section II.6 a-d: phi_B = K zeta, K = phi0 / 90 deg; the shortest flight by `min_range`."""

    bank0_deg: tuple[float, ...] = BANK0_DEG
    limit_deg: float | None = None
    min_range: MinRange | None = "zero_lift"
    mirror: bool = True
    contours_fps: tuple[float, ...] = ()  # Appendix C's iso-velocity contours


@dataclass(frozen=True)
class ConstantBank:
    """Fig. 14: constant bank for the whole flight."""

    bank_deg: tuple[float, ...] = (0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0)
    min_range: MinRange | None = "zero_lift"
    mirror: bool = True
    contours_fps: tuple[float, ...] = ()


@dataclass(frozen=True)
class Staged(ConstantBank):
    """Fig. 14: constant bank until the heading has changed turn_deg, then wings level."""

    turn_deg: float = 90.0


@dataclass(frozen=True)
class TwoParameter:
    """Figs. 5-7: phi_B = K (zeta - sigma_f), limited; one set per K, sigma_f varied along it."""

    bank_gain: tuple[float, ...] = (0.5, 0.67, 1.0)
    sigma_f_deg: tuple[float, ...] = tuple(float(s) for s in range(90, -46, -15))
    limit_deg: float = 75.0
    mirror: bool = True
    contours_fps: tuple[float, ...] = ()


@dataclass(frozen=True)
class ConstantAltitude:
    """Fig. 19 / Appendix C data set 2: hold the pull-out altitude; turns of turn_deg, or `steps` equal parts of the
    widest one."""

    turn_deg: tuple[float, ...] | None = None
    steps: int = 6
    mirror: bool = True
    contours_fps: tuple[float, ...] = ()


@dataclass(frozen=True)
class TemperatureLimited:
    """Single-parameter settings with alpha raised just enough to hold the radiation-equilibrium temperature to
    limit_R (core.constrained)."""

    limit_R: float
    tolerance_R: float = TTOL_TEMPERATURE_R  # TTOL of Section II.4
    bank0_deg: tuple[float, ...] = BANK0_DEG
    mirror: bool = False  # a study's default is to mirror (contracts.footprint)


@dataclass(frozen=True)
class Collocation:
    """The true optimal boundary by direct collocation (core.collocation_footprint)."""

    points_per_half: int = 11
    limit_R: float | None = None  # the radiation-equilibrium temperature held along the path
    max_load_factor: float | None = None  # g
    mirror: bool = True
    fine: bool = False  # the tables' narrow corners too (collocation.SMOOTHING_STAGES): ~3x the time
    intervals: int = 100  # mesh intervals
    alpha_bounds_deg: tuple[float, float] | None = None  # None: the tables' own range
    bank_bounds_deg: tuple[float, float] = (-180.0, 180.0)


MethodSettings = SingleParameter | ConstantBank | TwoParameter | ConstantAltitude | TemperatureLimited | Collocation
