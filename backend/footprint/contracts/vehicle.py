"""The vehicle contract: a built-in vehicle (Appendix B, with an optional wing-loading change), an inline aero
definition, or (over HTTP) a vehicle stored in the service. Its shape and bounds are checked here, once; the core
packs what passed (footprint.core.aero.vehicle_from_definition) and refuses only what the numbers show: a drag
nowhere positive, a polynomial past the force range within its alpha range, tables whose alpha ranges do not
overlap."""

import functools
import json
from dataclasses import replace
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, ConfigDict, Field, ValidationInfo, model_validator

from footprint.contracts.bounds import VEHICLE_ID_CHARS, VEHICLE_NAME_CHARS
from footprint.contracts.doors import context_of
from footprint.contracts.fields import Range, Settled, Strict
from footprint.core.aero import (
    ALPHA_LIMIT_DEG,
    MAX_AXIS_NODES,
    MAX_FORCE_COEFFICIENT,
    MAX_POLY_TERMS,
    WING_LOADING_RANGE_PSF,
    Vehicle,
    builtin_vehicle,
    vehicle_from_definition,
)
from footprint.core.errors import InputError
from footprint.core.limits import NO_LIMITS, Limits


def _positive(v: float) -> float:
    if not v > 0.0:
        raise ValueError(f"{v:g} must be > 0")
    return v


def _increasing(values: list[float]) -> list[float]:
    if any(b <= a for a, b in zip(values, values[1:])):
        raise ValueError(f"{values} must be strictly increasing")
    return values


Finite = Annotated[float, Field(allow_inf_nan=False)]
Coefficient = Annotated[Finite, Range(-MAX_FORCE_COEFFICIENT, MAX_FORCE_COEFFICIENT)]  # |C| of Appendix B: < 3


AXIS = Field(min_length=1, max_length=MAX_AXIS_NODES)  # a table's axis: its nodes, strictly increasing
MachAxis = Annotated[list[Annotated[Finite, Range(0.0, 100.0)]], AXIS, AfterValidator(_increasing)]
AlphaAxis = Annotated[
    list[Annotated[Finite, Range(-ALPHA_LIMIT_DEG, ALPHA_LIMIT_DEG, "deg")]], AXIS, AfterValidator(_increasing)
]
AltitudeAxis = Annotated[list[Annotated[Finite, Range(-1.0e5, 1.0e7, "ft")]], AXIS, AfterValidator(_increasing)]


class AeroConstant(Strict):
    cl: Coefficient
    cd: Annotated[Coefficient, AfterValidator(_positive)]


class AeroPolynomial(Strict):
    """C_L and C_D as polynomials in alpha (deg), lowest power first, flown within alpha_range_deg (0-60 deg)."""

    cl: list[Finite] = Field(min_length=1, max_length=MAX_POLY_TERMS)
    cd: list[Finite] = Field(min_length=1, max_length=MAX_POLY_TERMS)
    alpha_range_deg: tuple[Finite, Finite] | None = None

    @model_validator(mode="after")
    def _range(self) -> "AeroPolynomial":
        if self.alpha_range_deg is not None:
            lo, hi = self.alpha_range_deg
            if not -ALPHA_LIMIT_DEG <= lo < hi <= ALPHA_LIMIT_DEG:
                raise ValueError(f"alpha_range_deg: {[lo, hi]} must satisfy -90 <= lo < hi <= 90 deg")
        return self


class AeroTable(Strict):
    """One coefficient over (Mach, alpha, altitude); an axis it does not depend on has one node."""

    mach: MachAxis
    alpha_deg: AlphaAxis
    altitude_ft: AltitudeAxis
    values: list[list[list[Coefficient]]]  # [mach][alpha][altitude]

    @model_validator(mode="after")
    def _shape(self) -> "AeroTable":
        shape, got = (len(self.mach), len(self.alpha_deg), len(self.altitude_ft)), _shape_of(self.values)
        if got != shape:
            raise ValueError(f"values: shape {got or 'ragged'}; must be [mach][alpha][altitude] of shape {shape}")
        return self


def _shape_of(values: list[list[list[float]]]) -> tuple[int, ...] | None:
    """A nested list's shape (None: ragged)."""
    rows, cols = {len(r) for r in values}, {len(c) for r in values for c in r}
    return None if len(rows) > 1 or len(cols) > 1 else (len(values), *rows, *cols)


class AeroTables(Strict):
    form: Literal["lift_drag", "normal_axial"]  # (C_L, C_D) or (C_N, C_A), body axes
    first: AeroTable
    second: AeroTable


class Aero(Strict):
    """Exactly one of the three forms."""

    constant: AeroConstant | None = None
    polynomial: AeroPolynomial | None = None
    tables: AeroTables | None = None

    @model_validator(mode="after")
    def _one(self) -> "Aero":
        given = [k for k in ("constant", "polynomial", "tables") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(f"keys {given}: give exactly one of 'constant', 'polynomial', 'tables'")
        return self


_GLIDER = Limits()  # core.limits: each default's source


class VehicleLimits(Settled):
    """The limits each flight's summary checks (core.limits): a crewed glider's unless changed; null lifts one."""

    load_factor_g: Annotated[float, Range(0.1, 100, "g")] | None = _GLIDER.load_factor_g
    dynamic_pressure_psf: Annotated[float, Range(1, 100_000, "lb/ft^2")] | None = _GLIDER.dynamic_pressure_psf
    heat_rate_btu_ft2_s: Annotated[float, Range(0.1, 10_000, "Btu/(ft^2 s)")] | None = _GLIDER.heat_rate_btu_ft2_s
    temperature_R: Annotated[float, Range(100, 10_000, "degR")] | None = _GLIDER.temperature_R

    def to_limits(self) -> Limits:
        return Limits(**self.model_dump())


class VehicleCase(Strict):
    """A built-in vehicle (with an optional wing-loading change), an inline aero definition, or (over HTTP) a vehicle
    stored in the service, {"stored": id}."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"anyOf": [{"required": ["builtin"]}, {"required": ["aero"]}, {"required": ["stored"]}]},
    )
    stored: str | None = Field(default=None, max_length=VEHICLE_ID_CHARS)  # replaced by its definition as it is parsed
    builtin: str | None = None
    name: str | None = Field(default=None, max_length=VEHICLE_NAME_CHARS)  # a footprint's `vehicle`
    wing_loading_psf: Annotated[float, Range(*WING_LOADING_RANGE_PSF, "lb/ft^2")] | None = None
    weight_lb: Annotated[float, Range(1, 1e7, "lb")] | None = None
    reference_area_ft2: Annotated[float, Range(0.01, 1e5, "ft^2")] | None = None
    aero: Aero | None = None
    limits: VehicleLimits | None = VehicleLimits()  # null: no limits at all

    @model_validator(mode="before")
    @classmethod
    def _stored(cls, data: Any, info: ValidationInfo) -> Any:
        if not isinstance(data, dict) or "stored" not in data:
            return data
        if set(data) != {"stored"}:
            raise ValueError("stored: a stored vehicle is given by its id alone")
        lookup = context_of(info).get("vehicles")
        if lookup is None:
            raise ValueError(
                "stored: stored vehicles live in the service (POST /api/vehicles); give 'builtin' or 'aero' here"
            )
        definition = lookup(str(data["stored"]))
        if definition is None:
            raise ValueError(f"stored: no stored vehicle {data['stored']!r} (GET /api/vehicles lists them)")
        return definition

    @model_validator(mode="after")
    def _one_source(self) -> "VehicleCase":
        if self.builtin is None and self.aero is None:
            raise ValueError("aero: missing: give 'builtin' (a built-in vehicle id) or 'aero' with a wing loading")
        if self.builtin is not None and self.aero is not None:
            raise ValueError("aero: give either 'builtin' (a built-in vehicle id) or 'aero', not both")
        if self.wing_loading_psf is not None and (self.weight_lb is not None or self.reference_area_ft2 is not None):
            raise ValueError("wing_loading_psf: give wing_loading_psf or weight_lb and reference_area_ft2, not both")
        if (self.weight_lb is None) != (self.reference_area_ft2 is None):
            missing = "reference_area_ft2" if self.reference_area_ft2 is None else "weight_lb"
            raise ValueError(f"{missing}: give weight_lb and reference_area_ft2 together, or wing_loading_psf")
        ws, lo, hi = self.loading_psf(), *WING_LOADING_RANGE_PSF
        if self.aero is not None and ws is None:
            raise ValueError("wing_loading_psf: missing: give wing_loading_psf or weight_lb and reference_area_ft2")
        if ws is not None and not lo <= ws <= hi:
            raise ValueError(f"weight_lb: wing loading {ws:g} psf is outside the allowed range {lo:g} to {hi:g} psf")
        try:  # what only the numbers show: the core packs the vehicle here, once (cached)
            self.to_vehicle()
        except InputError as exc:
            below = exc.field.removeprefix("vehicle").lstrip(".")
            raise ValueError(f"{below}: {exc.message}" if below else exc.message) from None
        return self

    def definition(self) -> dict[str, Any]:
        """As plain data: what was given (None left out) and the limits always, a lifted one as null (left out, it
        would come back as its default)."""
        out = self.model_dump(exclude_none=True)
        return out | {"limits": None if self.limits is None else self.limits.model_dump()}

    def loading_psf(self) -> float | None:
        """The wing loading asked for: given, or weight over reference area (None: the built-in's own)."""
        if self.weight_lb is not None and self.reference_area_ft2 is not None:
            return self.weight_lb / self.reference_area_ft2
        return self.wing_loading_psf

    def to_vehicle(self) -> Vehicle:
        ws = self.loading_psf()
        limits = NO_LIMITS if self.limits is None else self.limits.to_limits()
        if self.builtin is not None:
            v = builtin_vehicle(self.builtin)
            return replace(v, limits=limits) if ws is None else replace(v, wing_loading_psf=ws, limits=limits)
        assert self.aero is not None and ws is not None  # _one_source: an inline vehicle has both
        v = _inline_vehicle(self.aero.model_dump_json(exclude_none=True), ws, self.name or "custom vehicle")
        return replace(v, limits=limits)

    def label(self) -> str:
        """The vehicle's name in tables and keys: its `name`, else the built-in id with any wing-loading change."""
        if self.name:
            return self.name
        if self.builtin is None:
            return "inline"
        ws = self.loading_psf()
        return self.builtin if ws is None else f"{self.builtin}@{ws:g}psf"


def user_vehicle(definition: dict[str, Any]) -> Vehicle:
    """The core's vehicle of a definition, as a case's `vehicle` gives it (pydantic's ValidationError names the
    field)."""
    return VehicleCase.model_validate(definition).to_vehicle()


@functools.lru_cache(maxsize=32)
def _inline_vehicle(aero_json: str, wing_loading_psf: float, name: str) -> Vehicle:
    """An inline aero definition packed once per process (packing its tables takes up to a second; a sweep's
    footprints share one)."""
    return vehicle_from_definition(json.loads(aero_json), wing_loading_psf, name, field="vehicle")
