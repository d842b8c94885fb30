"""The case contract (one trajectory): pydantic models shared by the Python API, the CLI and the REST API.

Each model converts itself into the core's plain types (`to_spec`). Every quantity names its unit;
every number is bounded, and a value out of range is reported as "field: value is outside ...".
"""

from collections.abc import Sequence
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import (
    BaseModel,
    Field,
    PrivateAttr,
    TypeAdapter,
    model_validator,
)

from footprint.contracts.bounds import JOB_NAME_CHARS, fitted
from footprint.contracts.doors import validated
from footprint.contracts.fields import Range, Settled, Strict, by_shape, shape_tag
from footprint.contracts.guidance import BankGuided
from footprint.contracts.vehicle import VehicleCase
from footprint.contracts.work import OnProgress, Work, stop_question
from footprint.core import constants as c
from footprint.core.aero import ALPHA_LIMIT_DEG
from footprint.core.controls import pack_controls
from footprint.core.dynamics import energy_height_ft
from footprint.core.guidance import Guidance
from footprint.core.heating import EMISSIVITY_DEFAULT, REFERENCE_RADIUS_FT, CorrelationHeating, ReferenceHeating
from footprint.core.limits import Limits
from footprint.core.trajectory import Entry, FlightSpec, Planet, Stop, Trajectory


# ------------------------------------------------------------------------------------------ planet
class AtmosphereCase(Settled):  # the default of every case that leaves it out
    model: Literal["ardc1959", "us1976", "exponential"] = "ardc1959"
    rho0_slug_ft3: Annotated[float, Range(1e-12, 1.0, "slug/ft^3")] = 0.0027
    scale_height_ft: Annotated[float, Range(1_000, 1_000_000, "ft")] = 23_800.0
    temperature_R: Annotated[float, Range(50, 10_000, "degR")] | None = None


class PlanetCase(Settled):  # the default of every case that leaves it out
    rotating: bool = True
    oblate: bool = True
    atmosphere: AtmosphereCase = AtmosphereCase()
    radius_ft: Annotated[float, Range(1e5, 1e9, "ft")] = c.RADIUS_EQUATORIAL_FT
    polar_radius_ft: Annotated[float, Range(1e5, 1e9, "ft")] | None = None
    mu_ft3_s2: Annotated[float, Range(1e10, 1e22, "ft^3/s^2")] = c.MU_EARTH_FT3_S2
    rotation_rate_deg_s: Annotated[float, Range(-0.1, 0.1, "deg/s")] = c.OMEGA_EARTH_DEG_S
    j: Annotated[float, Range(-0.1, 0.1)] = c.J_ZONAL
    h: Annotated[float, Range(-0.1, 0.1)] = c.H_ZONAL
    k: Annotated[float, Range(-0.1, 0.1)] = c.K_ZONAL

    @model_validator(mode="after")
    def _polar(self) -> "PlanetCase":
        if self.polar_radius_ft is not None and not 0.9 * self.radius_ft <= self.polar_radius_ft <= self.radius_ft:
            raise ValueError(f"polar_radius_ft {self.polar_radius_ft:g} must lie between 0.9 and 1 times radius_ft")
        return self

    def to_planet(self) -> Planet:
        polar = self.polar_radius_ft
        if polar is None:  # scale the default flattening to the given equatorial radius
            polar = self.radius_ft * c.RADIUS_POLAR_FT / c.RADIUS_EQUATORIAL_FT
        a = self.atmosphere
        return Planet(
            rotating=self.rotating,
            oblate=self.oblate,
            radius_ft=self.radius_ft,
            polar_radius_ft=polar,
            mu_ft3_s2=self.mu_ft3_s2,
            rotation_rate_deg_s=self.rotation_rate_deg_s,
            j=self.j,
            h=self.h,
            k=self.k,
            atmosphere=a.model,
            rho0_slug_ft3=a.rho0_slug_ft3,
            scale_height_ft=a.scale_height_ft,
            temperature_R=a.temperature_R,
        )


# ------------------------------------------------------------------------------------------- entry
SENSIBLE_ATMOSPHERE_FT = 295_000.0  # Section II.7: "the beginning of the sensible atmosphere, 295K ft"


class EntryCase(Strict):
    altitude_ft: Annotated[float, Range(1_000, 3_000_000, "ft")]
    velocity_fps: Annotated[float, Range(1_000, 40_000, "ft/s")]
    velocity_frame: Literal["relative", "inertial"] = "relative"
    gamma_deg: Annotated[float, Range(-90, 10, "deg")]
    heading_deg: Annotated[float, Range(-360, 360, "deg")] = 90.0
    latitude_deg: Annotated[float, Range(-90, 90, "deg")] = 0.0
    longitude_deg: Annotated[float, Range(-360, 360, "deg")] = 0.0

    @model_validator(mode="after")
    def _enters(self) -> "EntryCase":
        if self.gamma_deg > 0 and self.altitude_ft > SENSIBLE_ATMOSPHERE_FT:
            raise ValueError(
                f"gamma_deg {self.gamma_deg:g} > 0 above {SENSIBLE_ATMOSPHERE_FT:,.0f} ft climbs away "
                "with no atmosphere to enter; allowed: gamma_deg <= 0 there"
            )
        return self

    def to_entry(self) -> Entry:
        return Entry(
            altitude_ft=self.altitude_ft,
            velocity_fps=self.velocity_fps,
            gamma_deg=self.gamma_deg,
            heading_deg=self.heading_deg,
            latitude_deg=self.latitude_deg,
            longitude_deg=self.longitude_deg,
            velocity_frame=self.velocity_frame,
        )


# ---------------------------------------------------------------------------------------- controls
Bank = Annotated[float, Range(-180, 180, "deg")]


class _BankLaw(Strict):
    """A bank law: `controls()`, its part of the control array's settings (core.controls.pack_controls)."""

    law: str

    def controls(self) -> dict[str, Any]:
        return {"bank_law": self.law}


class _AlphaLaw(Strict):
    """An angle-of-attack law: `controls()`, its part of the control array's settings."""

    law: str

    def controls(self) -> dict[str, Any]:
        return {"alpha_law": self.law}


class BankZero(_BankLaw):
    law: Literal["zero"]


class BankConstant(_BankLaw):
    law: Literal["constant"]
    bank_deg: Bank

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"bank_deg": self.bank_deg}


class BankStaged(_BankLaw):
    law: Literal["staged"]
    bank_deg: Bank
    turn_deg: Annotated[float, Range(0, 179, "deg")] = 90.0  # a heading change measured within (-180, 180]

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"bank_deg": self.bank_deg, "turn_deg": self.turn_deg}


class BankTwoParameter(_BankLaw):
    """Section II.6, Figs. 5-7: phi_B = K (zeta - sigma_f), K the bank gain (deg of bank per deg of heading)."""

    law: Literal["two_parameter"]
    bank_gain: Annotated[float, Range(-10, 10)]
    sigma_f_deg: Annotated[float, Range(-180, 180, "deg")] = 0.0
    limit_deg: Annotated[float, Range(0, 180, "deg")] | None = 75.0
    variable: Literal["zeta", "heading"] = "zeta"

    def controls(self) -> dict[str, Any]:
        return super().controls() | {
            "bank_gain": abs(self.bank_gain),
            "mirror": self.bank_gain < 0,
            "bank_limit_deg": self.limit_deg,
            "bank_variable": self.variable,
            "sigma_f_deg": self.sigma_f_deg,
        }


class BankSingleParameter(_BankLaw):
    """Section II.6 a-d: phi_B = K zeta, K the bank gain (negative: the right-hand law)."""

    law: Literal["single_parameter"]
    bank_gain: Annotated[float, Range(-10, 10)]
    limit_deg: Annotated[float, Range(0, 180, "deg")] | None = None
    variable: Literal["zeta", "heading"] = "zeta"

    def controls(self) -> dict[str, Any]:
        return super().controls() | {
            "bank_gain": abs(self.bank_gain),
            "mirror": self.bank_gain < 0,
            "bank_limit_deg": self.limit_deg,
            "bank_variable": self.variable,
        }


# a collocation optimum re-flown as tables carries one node per mesh point, a guided flight's bank one per actuator step
TABLE_MAX_NODES = 8_192
# the control tables' abscissae, one unit each (cases and optimization studies)
HeadingNode = Annotated[float, Range(-180, 180, "deg")]
TimeNode = Annotated[float, Range(0, 100_000, "s")]
VelocityNode = Annotated[float, Range(0, 40_000, "ft/s")]
EnergyNode = Annotated[float, Range(0, 1e8, "ft")]  # energy height h + V^2/(2 g0)


class BankTable(_BankLaw):
    """Bank (deg) tabulated against ONE abscissa, linear between nodes, held at the ends: the heading laws'
    steering angle (heading_deg with variable zeta or heading, Section II.5 Fig. 2), or time, velocity or energy."""

    law: Literal["table"]
    bank_deg: list[Bank] = Field(min_length=2, max_length=TABLE_MAX_NODES)
    heading_deg: list[HeadingNode] | None = Field(default=None, min_length=2, max_length=TABLE_MAX_NODES)
    time_s: list[TimeNode] | None = Field(default=None, min_length=2, max_length=TABLE_MAX_NODES)
    velocity_fps: list[VelocityNode] | None = Field(default=None, min_length=2, max_length=TABLE_MAX_NODES)
    energy_ft: list[EnergyNode] | None = Field(default=None, min_length=2, max_length=TABLE_MAX_NODES)
    side: Literal["left", "right"] = "left"
    variable: Literal["zeta", "heading"] = "zeta"  # what heading_deg means

    @model_validator(mode="after")
    def _table(self) -> "BankTable":
        name, x = table_abscissa(self, ("heading_deg", "time_s", "velocity_fps", "energy_ft"))
        _check_table(x, self.bank_deg, name, "bank_deg")
        return self

    def abscissa(self) -> tuple[str, list[float]]:
        """(bank_variable of pack_controls, nodes)."""
        name, x = table_abscissa(self, ("heading_deg", "time_s", "velocity_fps", "energy_ft"))
        return (self.variable if name == "heading_deg" else name.rsplit("_", 1)[0]), x

    def controls(self) -> dict[str, Any]:
        variable, x = self.abscissa()
        return super().controls() | {
            "bank_table": (x, self.bank_deg),
            "mirror": self.side == "right",
            "bank_variable": variable,
        }


def table_abscissa(table: BaseModel, names: tuple[str, ...], default: tuple[Any, Any] | None = None) -> tuple[Any, Any]:
    """(name, nodes) of the one abscissa field of `table` that is given; `default` when none is (else an error)."""
    given = [n for n in names if getattr(table, n) is not None]
    if not given and default is not None:
        return default
    if len(given) != 1:
        raise ValueError(
            f"give {'exactly' if default is None else 'at most'} one of {', '.join(names)} as the table's abscissa"
        )
    return given[0], getattr(table, given[0])


class BankZeroLift(_BankLaw):
    law: Literal["zero_lift"]


class BankConstantAltitude(_BankLaw):
    law: Literal["constant_altitude"]
    turn_deg: Annotated[float, Range(0, 179, "deg")] = 90.0  # a heading change measured within (-180, 180]
    side: Literal["left", "right"] = "left"

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"turn_deg": self.turn_deg, "side": 1.0 if self.side == "left" else -1.0}


BankCase = Annotated[
    BankZero
    | BankConstant
    | BankStaged
    | BankTwoParameter
    | BankSingleParameter
    | BankTable
    | BankZeroLift
    | BankConstantAltitude
    | BankGuided,
    Field(discriminator="law"),
]

Alpha = Annotated[float, Range(-30, 90, "deg")]
AlphaBound = Annotated[float, Range(-ALPHA_LIMIT_DEG, ALPHA_LIMIT_DEG, "deg")]  # an optimizer's alpha bound


class AlphaMaxLD(_AlphaLaw):
    law: Literal["max_ld"]


class AlphaCLMax(_AlphaLaw):
    law: Literal["cl_max"]


class AlphaConstant(_AlphaLaw):
    law: Literal["constant"]
    alpha_deg: Alpha

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"alpha_deg": self.alpha_deg}


class AlphaTable(_AlphaLaw):
    law: Literal["table"]
    alpha_deg: list[Alpha] = Field(min_length=2, max_length=TABLE_MAX_NODES)
    velocity_fps: list[VelocityNode] | None = None
    time_s: list[TimeNode] | None = None
    energy_ft: list[EnergyNode] | None = None  # energy height h + V^2/(2 g0)

    @model_validator(mode="after")
    def _table(self) -> "AlphaTable":
        name, x = table_abscissa(self, ("velocity_fps", "time_s", "energy_ft"))
        _check_table(x, self.alpha_deg, name, "alpha_deg")
        return self

    def abscissa(self) -> tuple[str, list[float]]:
        """(alpha_table_abscissa of pack_controls, nodes)."""
        name, x = table_abscissa(self, ("velocity_fps", "time_s", "energy_ft"))
        return name.rsplit("_", 1)[0], x

    def controls(self) -> dict[str, Any]:
        abscissa, x = self.abscissa()
        return super().controls() | {"alpha_table": (x, self.alpha_deg), "alpha_table_abscissa": abscissa}


class AlphaLevelFlight(_AlphaLaw):
    law: Literal["level_flight"]
    before_pullout: Literal["max_ld", "cl_max"] = "max_ld"

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"alpha_before": self.before_pullout}


class AlphaGammaHold(_AlphaLaw):
    law: Literal["gamma_hold"]
    gamma_deg: Annotated[float, Range(-10, 10, "deg")]
    before_pullout: Literal["max_ld", "cl_max"] = "max_ld"

    def controls(self) -> dict[str, Any]:
        return super().controls() | {"gamma_deg": self.gamma_deg, "alpha_before": self.before_pullout}


AlphaCase = Annotated[
    AlphaMaxLD | AlphaCLMax | AlphaConstant | AlphaTable | AlphaLevelFlight | AlphaGammaHold, Field(discriminator="law")
]


def _check_table(x: Sequence[float], y: Sequence[float], xname: str, yname: str) -> None:
    if len(x) != len(y):
        raise ValueError(f"{xname} and {yname} must have the same length ({len(x)} vs {len(y)})")
    check_increasing(x, xname)


def check_increasing(x: Sequence[float], name: str) -> None:
    if any(b <= a for a, b in zip(x, x[1:])):
        raise ValueError(f"{name} must be strictly increasing")


def check_bounds(bounds: tuple[float, float] | None, name: str) -> None:
    """A (lower, upper) pair, if given, with the lower bound below the upper."""
    if bounds is not None and bounds[0] >= bounds[1]:
        raise ValueError(f"{name}: lower bound {bounds[0]:g} is not below the upper bound {bounds[1]:g}")


class BankStartAltitude(Strict):
    altitude_ft: Annotated[float, Range(1_000, 3_000_000, "ft")]


BankStart = Annotated[
    Annotated[Literal["pullout", "entry"], shape_tag("string")] | Annotated[BankStartAltitude, shape_tag("object")],
    by_shape("string", "object"),
]


class StopCase(Settled):  # the default of every case that leaves it out
    altitude_ft: Annotated[float, Range(0, 3_000_000, "ft")] | None = 50_000.0
    velocity_fps: Annotated[float, Range(0, 40_000, "ft/s")] | None = None
    time_s: Annotated[float, Range(1, 100_000, "s")] | None = None
    energy_ft: Annotated[float, Range(0, 1e8, "ft")] | None = None  # h + V^2/(2 g0): a guided flight's terminal energy
    max_altitude_ft: Annotated[float, Range(10_000, 100_000_000, "ft")] = 10_000_000.0  # see trajectory.Stop


# ----------------------------------------------------------------------------------------- heating
class HeatingReference(Strict):
    """AFWAL-TR-82-3036 Section III: Fay-Riddell h_F&R times Table 1's h/h_F&R(alpha), eqs. (5)-(7)."""

    model: Literal["reference"]
    reference_radius_ft: Annotated[float, Range(0.01, 100, "ft")] = REFERENCE_RADIUS_FT  # calibrated to 2,670 degR
    emissivity: Annotated[float, Range(0.01, 1)] = EMISSIVITY_DEFAULT
    # 0: radiation-equilibrium temperature, eq. (7); > 0: a thin skin's lagging temperature (core/heating.py)
    skin_heat_capacity_btu_ft2_R: Annotated[float, Range(0, 100, "Btu/(ft^2 degR)")] = 0.0

    def to_model(self) -> ReferenceHeating:
        return ReferenceHeating(
            reference_radius_ft=self.reference_radius_ft,
            emissivity=self.emissivity,
            skin_heat_capacity_btu_ft2_R=self.skin_heat_capacity_btu_ft2_R,
        )


class HeatingCorrelation(Strict):
    """q_btu_ft2_s = coefficient * rho_slug_ft3^density_exponent * V_fps^velocity_exponent * f(alpha_deg)."""

    model: Literal["correlation"]
    coefficient: Annotated[float, Range(0, 1e12)]  # Btu/(ft^2 s) for rho in slug/ft^3 and V in ft/s
    density_exponent: Annotated[float, Range(0, 2)] = 0.5
    velocity_exponent: Annotated[float, Range(0, 10)] = 3.0
    alpha_polynomial_deg: list[Annotated[float, Range(-1e6, 1e6)]] = Field(default=[1.0], min_length=1, max_length=8)
    emissivity: Annotated[float, Range(0.01, 1)] | None = (
        None  # with it, eq. (7) gives a radiation-equilibrium temperature
    )

    def to_model(self) -> CorrelationHeating:
        return CorrelationHeating(
            coefficient=self.coefficient,
            density_exponent=self.density_exponent,
            velocity_exponent=self.velocity_exponent,
            alpha_polynomial=tuple(self.alpha_polynomial_deg),
            emissivity=self.emissivity,
        )


HeatingCase = Annotated[HeatingReference | HeatingCorrelation, Field(discriminator="model")]


MAX_STEP_RANGE_S = (0.01, 1_000.0)


class IntegratorCase(Settled):  # the default of every case that leaves it out
    rtol: Annotated[float, Range(1e-13, 1e-4)] = 1e-9
    max_step_s: Annotated[float, Range(*MAX_STEP_RANGE_S, "s")] = 50.0
    # Dormand-Prince 5(4) or 8(5,3) (core.integrate): the same landing to 0.001 nmi; DOP853 takes fewer right-hand
    # sides on a smooth flight (Table 2) and more where the model has kinks (a dispersed density profile, L/D 1.89)
    method: Literal["dopri5", "dop853"] = "dopri5"


class Case(Strict):
    """One trajectory: vehicle, planet, entry state, alpha and bank laws, phase rule, stop conditions."""

    vehicle: VehicleCase
    planet: PlanetCase = PlanetCase()
    entry: EntryCase
    alpha: AlphaCase = AlphaMaxLD(law="max_ld")
    bank: BankCase = BankZero(law="zero")
    bank_start: BankStart = "pullout"
    stop: StopCase = StopCase()
    integrator: IntegratorCase = IntegratorCase()
    heating: HeatingCase | None = None

    def named(self, method_words: str) -> str:
        """A result of this case named for what it is, in a job name's bound: vehicle, method in words and entry, as
        "lod-1.89 · single parameter · 364.8 kft 24,480 ft/s -2°" (issue 53 item 3: "footprint a5dde2ec" said
        nothing); a long vehicle name is cut, the rest kept whole."""
        e = self.entry
        entry = f"{e.altitude_ft / 1000:g} kft {e.velocity_fps:,.0f} ft/s {e.gamma_deg:g}°"
        return fitted(self.vehicle.label(), f"· {method_words} · {entry}", JOB_NAME_CHARS)

    @model_validator(mode="after")
    def _consistent(self) -> "Case":
        s, e = self.stop, self.entry
        if s.altitude_ft is None and s.velocity_fps is None and s.time_s is None and s.energy_ft is None:
            raise ValueError("stop: give at least one of altitude_ft, velocity_fps, time_s, energy_ft")
        if s.altitude_ft is not None and s.altitude_ft >= e.altitude_ft:
            raise ValueError(f"stop.altitude_ft {s.altitude_ft:g} must be below entry.altitude_ft {e.altitude_ft:g}")
        if s.max_altitude_ft <= e.altitude_ft:
            raise ValueError(
                f"stop.max_altitude_ft {s.max_altitude_ft:g} must be above entry.altitude_ft {e.altitude_ft:g}"
            )
        if self.bank.law == "constant_altitude" and self.alpha.law != "max_ld":
            raise ValueError("bank law 'constant_altitude' flies alpha at (L/D)max: alpha.law must be 'max_ld'")
        if isinstance(self.bank, BankGuided):
            self._guided(self.bank)
        return self

    def _guided(self, bank: BankGuided) -> None:
        e, t = self.entry, bank.terminal
        if energy_height_ft(t.altitude_ft, t.velocity_fps, c.G0_FT_S2) >= energy_height_ft(
            e.altitude_ft, e.velocity_fps, c.G0_FT_S2
        ):
            raise ValueError("bank.terminal: its energy h + V^2/(2 g0) must be below the entry's")
        if bank.min_bank_deg > bank.max_bank_deg:
            raise ValueError(f"bank.min_bank_deg {bank.min_bank_deg:g} must not exceed bank.max_bank_deg")
        heat = self.heating
        for name in ("max_heat_rate_btu_ft2_s", "max_temperature_R"):
            if getattr(bank, name) is not None and heat is None:
                raise ValueError(f"bank.{name} needs a heating model: give heating")
        if bank.max_temperature_R is not None and isinstance(heat, HeatingCorrelation) and heat.emissivity is None:
            raise ValueError("bank.max_temperature_R needs heating.emissivity (the temperature of eq. 7)")

    _spec: FlightSpec | None = PrivateAttr(default=None)

    def to_spec(self) -> FlightSpec:
        """The core's flight spec, built once per parsed case (the footprint and its ground track share it)."""
        if self._spec is None:
            self._spec = self._build_spec()
        return self._spec

    def _build_spec(self) -> FlightSpec:
        vehicle = self.vehicle.to_vehicle()
        return FlightSpec(
            vehicle=vehicle,
            planet=self.planet.to_planet(),
            entry=self.entry.to_entry(),
            ctrl=self.controls(),
            stop=self._stop(),
            rtol=self.integrator.rtol,
            max_step_s=self.integrator.max_step_s,
            integrator_method=self.integrator.method,
            heating=None if self.heating is None else self.heating.to_model(),
            guidance=self._guidance(self.bank, vehicle.limits) if isinstance(self.bank, BankGuided) else None,
        )

    def _guidance(self, bank: BankGuided, vehicle: Limits) -> Guidance:
        """The guided law's settings, holding the vehicle's limits unless the bank changes or lifts them."""
        heat = self.heating
        emissive = heat is not None and not (isinstance(heat, HeatingCorrelation) and heat.emissivity is None)
        return bank.to_guidance(bank.path_limits(vehicle, heat_rate=heat is not None, temperature=emissive))

    def _stop(self) -> Stop:
        s = self.stop
        return Stop(
            altitude_ft=s.altitude_ft,
            velocity_fps=s.velocity_fps,
            time_s=s.time_s,
            skip_altitude_ft=s.max_altitude_ft,
            energy_ft=s.energy_ft,
        )

    def controls(self) -> NDArray[np.float64]:
        kw = self.bank.controls() | self.alpha.controls()
        start = self.bank_start
        if isinstance(start, BankStartAltitude):
            kw.update(bank_start="altitude", bank_start_altitude_ft=start.altitude_ft)
        else:
            kw["bank_start"] = start
        ctrl: NDArray[np.float64] = pack_controls(**kw)
        return ctrl


REQUEST = Case  # the kind's request type (the OpenAPI document declares it)
ADAPTER = TypeAdapter(REQUEST)


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> Case:
    case: Case = validated(ADAPTER, data, Case, ctx)
    return case


def fly(case: Case, part: Any = None, on_progress: OnProgress | None = None) -> Trajectory:
    """Fly the case: footprint.core.trajectory.Trajectory (summary and histories); on_progress is asked before the
    flight and each guidance prediction (True stops it: errors.Stopped)."""
    from dataclasses import replace

    from footprint.core.trajectory import simulate

    return simulate(replace(case.to_spec(), stop_asked=stop_question(on_progress, "flying")))


WORK = Work(run_part=fly, part_unit="flight")  # answered at once, never a job
