"""The footprint study contract: {"case": CASE, "method": ..., method parameters..., "mirror": true}.

One pydantic model per method (discriminated on "method"); `to_settings()` gives the core's settings record of the
method (footprint.core.method_settings, whose defaults these take). The case's own bank law is replaced by the
method's.
"""

from collections.abc import Callable
from dataclasses import fields, replace
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal

from pydantic import Field, TypeAdapter, ValidationInfo, model_validator

from footprint.contracts import stored_form
from footprint.contracts.case import MAX_STEP_RANGE_S, AlphaBound, Case, check_bounds
from footprint.contracts.doors import IN_A_SYNCHRONOUS_REQUEST, door_limit, synchronous, validated
from footprint.contracts.fields import Range, Strict
from footprint.contracts.records import flown, plain
from footprint.contracts.work import OnProgress, Stored, Work
from footprint.core.method_settings import (
    Collocation,
    ConstantAltitude,
    ConstantBank,
    MethodSettings,
    MinRange,
    SingleParameter,
    Staged,
    TemperatureLimited,
    TwoParameter,
)

if TYPE_CHECKING:
    from footprint.core.footprints import Footprint, FootprintPoint
    from footprint.core.trajectory import FlightSpec

BankDeg = Annotated[float, Range(-180, 180, "deg")]
MAX_POINTS = 10_000  # boundary points of one footprint (parameter settings x sides) from the CLI or Python
MAX_POINTS_HTTP = 200  # over HTTP, where the workers are shared
MAX_POINTS_SYNC = 100  # flown in the API process itself (a reach or an exact transform): about a second
# the shortest integrator.max_step_s of a study flown there: 100 flights of an exact transform of the reach example's
# study took 0.9 s at the default 50 s, 1.2 s at 2 s, 1.7 s at 1 s, 2.8 s at 0.5 s, 12 s at 0.1 s (~100 s at 0.01 s:
# each flight the integrator's 200,000 steps; 2 shared cores, load 14)
MIN_STEP_SYNC_S = 1.0


# each method as a name says it (a result's default name; the page's job form says the same)
METHOD_WORDS = {
    "single_parameter": "single parameter",
    "constant_bank": "constant bank",
    "staged": "staged bank",
    "two_parameter": "two parameter",
    "constant_altitude": "constant altitude",
    "temperature_limited": "temperature limited",
    "collocation": "true optimal (collocation)",
}


class _Study(Strict):
    case: Case
    mirror: bool = True
    contours_fps: list[Annotated[float, Range(100, 40_000, "ft/s")]] = Field(
        default=[], max_length=20
    )  # iso-velocity points
    SETTINGS: ClassVar[str]  # the field whose values (one trajectory set each) make the footprint's points
    CORE: ClassVar[type]  # the core's settings record of the method
    if TYPE_CHECKING:  # each method's model declares its own: the discriminator, a Literal of the method's name
        method: str

    def to_settings(self) -> MethodSettings:
        """The core's settings of the method: the fields the record has (a list as a tuple)."""
        values = {f.name: getattr(self, f.name) for f in fields(self.CORE) if f.name in type(self).model_fields}
        settings: MethodSettings = self.CORE(**{k: tuple(v) if isinstance(v, list) else v for k, v in values.items()})
        return settings

    def settings(self) -> tuple[str, int]:
        """(the field that sets them, how many parameter settings the study flies on each side)."""
        return self.SETTINGS, len(getattr(self, self.SETTINGS))

    @model_validator(mode="after")
    def _points(self, info: ValidationInfo) -> "_Study":
        limit, where = door_limit(info, MAX_POINTS, MAX_POINTS_HTTP, MAX_POINTS_SYNC)
        (field, n), sides = self.settings(), 2 if self.mirror else 1
        if n * sides > limit:
            raise ValueError(
                f"{field}: {n} settings x {sides} sides = {n * sides} footprint points is "
                f"outside the allowed range 1 to {limit}{where}"
            )
        return self

    @model_validator(mode="after")
    def _flights(self, info: ValidationInfo) -> "_Study":
        """The case's flights as the method flies them: not guided; steps not too short for the API process."""
        if self.case.bank.law == "guided":  # its guidance would fly every point to the target
            raise ValueError(
                "case.bank.law: 'guided' is not flown by a footprint study (its method replaces the case's bank law, "
                "but a guided case would fly every point to its target); give another law, or trace the guided "
                "vehicle's footprint as a guided_footprint"
            )
        step = self.case.integrator.max_step_s
        if synchronous(info) and step < MIN_STEP_SYNC_S:
            raise ValueError(
                f"case.integrator.max_step_s: {step:g} is outside the allowed range {MIN_STEP_SYNC_S:g} to "
                f"{MAX_STEP_RANGE_S[1]:g} s{IN_A_SYNCHRONOUS_REQUEST}"
            )
        return self

    def default_name(self) -> str:
        """The footprint's name unless one is given: vehicle, method in words and entry (Case.named)."""
        return self.case.named(METHOD_WORDS[self.method])


class SingleParameterStudy(_Study):
    """Section II.6 a-d: phi_B = K zeta, K = phi0 / 90 deg."""

    method: Literal["single_parameter"]
    SETTINGS: ClassVar[str] = "bank0_deg"
    CORE: ClassVar[type] = SingleParameter
    bank0_deg: list[Annotated[float, Range(0, 180, "deg")]] = Field(
        default=list(SingleParameter.bank0_deg), min_length=1, max_length=181
    )
    limit_deg: Annotated[float, Range(0, 180, "deg")] | None = SingleParameter.limit_deg
    min_range: MinRange | None = SingleParameter.min_range


class ConstantBankStudy(_Study):
    """Fig. 14: constant bank for the whole flight."""

    if TYPE_CHECKING:  # a StagedStudy is a constant-bank study too, discriminated by its own method
        method: Literal["constant_bank", "staged"]
    else:
        method: Literal["constant_bank"]
    SETTINGS: ClassVar[str] = "bank_deg"
    CORE: ClassVar[type] = ConstantBank
    bank_deg: list[BankDeg] = Field(default=list(ConstantBank.bank_deg), min_length=1, max_length=181)
    min_range: MinRange | None = ConstantBank.min_range


class StagedStudy(ConstantBankStudy):
    """Fig. 14: constant bank until the heading has changed turn_deg, then wings level."""

    method: Literal["staged"]
    CORE: ClassVar[type] = Staged
    turn_deg: Annotated[float, Range(0, 179, "deg")] = Staged.turn_deg  # a heading change within (-180, 180]


class TwoParameterStudy(_Study):
    """Figs. 5-7: phi_B = K (zeta - sigma_f), limited; one set per K."""

    method: Literal["two_parameter"]
    CORE: ClassVar[type] = TwoParameter
    bank_gain: list[Annotated[float, Range(0, 10)]] = Field(
        default=list(TwoParameter.bank_gain), min_length=1, max_length=20
    )  # K, deg/deg
    sigma_f_deg: list[Annotated[float, Range(-180, 180, "deg")]] = Field(
        default=list(TwoParameter.sigma_f_deg), min_length=1, max_length=181
    )
    limit_deg: Annotated[float, Range(0, 180, "deg")] = TwoParameter.limit_deg

    def settings(self) -> tuple[str, int]:
        return "sigma_f_deg", len(self.bank_gain) * len(self.sigma_f_deg)


class ConstantAltitudeStudy(_Study):
    """Fig. 19 / Appendix C data set 2: bank to hold the pull-out altitude until turn_deg, then wings level."""

    method: Literal["constant_altitude"]
    CORE: ClassVar[type] = ConstantAltitude
    turn_deg: list[Annotated[float, Range(0, 179, "deg")]] | None = (
        None if ConstantAltitude.turn_deg is None else list(ConstantAltitude.turn_deg)
    )
    steps: int = Field(default=ConstantAltitude.steps, ge=1, le=60)

    def settings(self) -> tuple[str, int]:  # the turns, or the count of steps when none are listed
        return ("steps", self.steps) if self.turn_deg is None else ("turn_deg", len(self.turn_deg))


class TemperatureLimitedStudy(_Study):
    """Beyond the report: single-parameter bank settings, alpha raised above 16,000 ft/s just enough that the
    radiation-equilibrium temperature stays within limit_R (footprint.core.constrained); needs case.heating."""

    method: Literal["temperature_limited"]
    SETTINGS: ClassVar[str] = "bank0_deg"
    CORE: ClassVar[type] = TemperatureLimited
    limit_R: Annotated[float, Range(500, 10_000, "degR")]
    tolerance_R: Annotated[float, Range(0, 100, "degR")] = TemperatureLimited.tolerance_R  # TTOL, Section II.4
    bank0_deg: list[Annotated[float, Range(0, 180, "deg")]] = Field(
        default=list(TemperatureLimited.bank0_deg), min_length=1, max_length=181
    )

    @model_validator(mode="after")
    def _heating(self) -> "TemperatureLimitedStudy":
        if self.case.heating is None:
            raise ValueError("case.heating: a temperature-limited footprint needs a heating model")
        if self.contours_fps:
            raise ValueError("contours_fps: not available with method 'temperature_limited'")
        return self


class CollocationStudy(_Study):
    """Beyond the report (issue 12): the true reachable boundary, cross-range maximized by direct collocation at
    points_per_half down-ranges between the maximum and minimum down-range (footprint.core.collocation_footprint);
    limit_R holds the radiation-equilibrium temperature along the path (needs case.heating), max_load_factor
    the load; alpha_bounds_deg and bank_bounds_deg bound the controls (bank both ways alike: (-b, b))."""

    method: Literal["collocation"]
    CORE: ClassVar[type] = Collocation
    points_per_half: int = Field(default=Collocation.points_per_half, ge=3, le=40)
    limit_R: Annotated[float, Range(500, 10_000, "degR")] | None = Collocation.limit_R
    # without a load limit the nearest points ride the stop altitude
    max_load_factor: Annotated[float, Range(1, 50, "g")] | None = Collocation.max_load_factor
    fine: bool = Collocation.fine  # the tables' narrow corners too: the re-flight comes closer, at ~3x the time
    intervals: int = Field(default=Collocation.intervals, ge=20, le=400)  # collocation mesh intervals
    # default: the vehicle's valid alpha range; a polynomial's lift may turn negative there and the optimum fly
    # upside down (Betts' shuttle below 7.08 deg: its points say so, ControlSetting.inverted_s)
    alpha_bounds_deg: tuple[AlphaBound, AlphaBound] | None = Collocation.alpha_bounds_deg
    bank_bounds_deg: tuple[BankDeg, BankDeg] = Collocation.bank_bounds_deg

    def settings(self) -> tuple[str, int]:
        return "points_per_half", self.points_per_half + 1

    @model_validator(mode="after")
    def _checks(self, info: ValidationInfo) -> "CollocationStudy":
        if synchronous(info):  # a minute of NLP solves is a job, not a request the API process answers itself
            raise ValueError(
                "method: 'collocation' is solved as a job, not in a synchronous request; submit it with POST /api/jobs"
            )
        if self.limit_R is not None and self.case.heating is None:
            raise ValueError("case.heating: a temperature limit needs a heating model")
        if self.contours_fps:
            raise ValueError("contours_fps: not available with method 'collocation'")
        if self.case.stop.altitude_ft is None:
            raise ValueError("case.stop.altitude_ft: a collocation footprint ends at a stop altitude; give one")
        check_bounds(self.alpha_bounds_deg, "alpha_bounds_deg")
        lo, hi = self.bank_bounds_deg
        if not 0.0 < hi == -lo:  # each half is the other's mirror image in bank
            raise ValueError(
                f"bank_bounds_deg: a footprint banks both ways alike: give (-b, b) with b > 0, not {lo:g}, {hi:g}"
            )
        return self


FootprintStudy = Annotated[
    SingleParameterStudy
    | ConstantBankStudy
    | StagedStudy
    | TwoParameterStudy
    | ConstantAltitudeStudy
    | TemperatureLimitedStudy
    | CollocationStudy,
    Field(discriminator="method"),
]

REQUEST = FootprintStudy  # the kind's request type (the OpenAPI document declares it)
ADAPTER: TypeAdapter[_Study] = TypeAdapter(REQUEST)  # validates to one of the method models


def parse_request(data: Any, ctx: dict[str, Any] | None = None) -> _Study:
    study: _Study = validated(ADAPTER, data, _Study, ctx)
    return study


def fly(
    study: _Study,
    part: Any = None,
    on_progress: OnProgress | None = None,
    stop_asked: Callable[[], bool] | None = None,
) -> "Footprint":
    """Fly the study's footprint (footprint.core.footprints.Footprint); on_progress(fraction, note) where the
    method reports (the collocation's IPOPT iterations), stop_asked() before each flight (True stops: Stopped)."""
    from footprint.core.footprint_methods import footprint

    spec = replace(study.case.to_spec(), stop_asked=stop_asked)
    return footprint(spec, study.to_settings(), on_progress=on_progress)


POINT_FIELDS = (
    "downrange_nmi",
    "crossrange_nmi",
    "flight_time_s",
    "latitude_deg",
    "longitude_deg",
    "heading_deg",
    "side",
    "parameter",
    "stop_reason",
    "mirrored",
)  # a stored footprint point


def ground_track(spec: "FlightSpec") -> dict[str, Any]:
    """The flight flown with zero bank (Section II.6's maximum down-range flight), decimated for the map."""
    from footprint.core.footprints import with_bank
    from footprint.core.trajectory import simulate

    return flown(simulate(with_bank(spec, "zero")))


def ground_track_at(study: dict[str, Any], reference: dict[str, Any]) -> list[dict[str, Any]]:
    """A stored study's zero-bank track flown from another entry point and heading on the rotating earth (a moved
    footprint's exact track, as a job stores it)."""
    from footprint.core.rotation import at_geometry
    from footprint.core.sphere import Reference

    dst = Reference(reference["latitude_deg"], reference["longitude_deg"], reference["heading_deg"])
    track = ground_track(at_geometry(parse_request(study).case.to_spec(), dst, rotating=True))
    return [
        {"latitude_deg": a, "longitude_deg": o, "time_s": t}
        for a, o, t in zip(track["latitude_deg"], track["longitude_deg"], track["time_s"])
    ]


def record(
    fp: "Footprint",
    *,
    vehicle: str,
    entry: dict[str, Any],
    study: dict[str, Any],
    track: dict[str, Any] | None,
    name: str,
) -> dict[str, Any]:
    """A flown footprint as the row data the job store writes (summary, points, interior, ground track); `entry`: the
    case's altitude_ft, velocity_fps and gamma_deg; `study`: its study as stored (plain data)."""
    return {
        "name": name,
        "vehicle": vehicle,
        "method": fp.method,
        "study": study,
        "entry": {**{k: float(fp.entry[k]) for k in ("latitude_deg", "longitude_deg", "heading_deg")}, **entry},
        "area_nmi2": float(fp.area_nmi2),
        "max_crossrange_nmi": float(fp.max_crossrange_nmi),
        "max_downrange_nmi": float(fp.max_downrange_nmi),
        "min_downrange_nmi": float(fp.min_downrange_nmi),
        "trajectories": int(fp.trajectories),
        "points": [_point(p) for p in fp.points],
        "interior": [_point(p) for p in fp.interior],
        "ground_track": track,
    }


def _point(p: "FootprintPoint") -> dict[str, Any]:
    d = p.to_dict()
    return {k: plain(d[k]) for k in POINT_FIELDS}


def store(study: _Study, fp: "Footprint", name: str | None) -> Stored:
    """A footprint job's rows: the footprint and its zero-bank ground track; its result, the broken limits."""
    e = study.case.entry
    entry = {"velocity_fps": e.velocity_fps, "gamma_deg": e.gamma_deg, "altitude_ft": e.altitude_ft}
    return Stored(
        result={"limits": fp.limits()},  # its flights that broke a vehicle limit, beside the stored footprint
        footprints=[
            record(
                fp,
                vehicle=study.case.vehicle.label(),
                entry=entry,
                study=stored_form(study),
                track=ground_track(study.case.to_spec()),
                name=name or study.default_name(),
            )
        ],
    )


WORK = Work(run_part=fly, store=store, default_name=_Study.default_name, part_unit="footprint")
