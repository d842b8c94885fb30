"""The guided bank law of a case: `"bank": {"law": "guided", "target": {...}, "terminal": {...}, ...settings}`.

The numerical predictor-corrector of footprint.core.guidance flies the bank; the case's alpha law and bank start
are kept. Every default is the core record's (core.guidance.Guidance).
"""

import dataclasses
import math
from typing import Annotated, Any, Literal

from pydantic import ValidationInfo, model_validator

from footprint.contracts.doors import synchronous
from footprint.contracts.fields import Range, Strict
from footprint.core.guidance import Guidance
from footprint.core.limits import Limits


def _default(name: str) -> Any:
    return next(f.default for f in dataclasses.fields(Guidance) if f.name == name)


class GuidedTarget(Strict):
    latitude_deg: Annotated[float, Range(-90, 90, "deg")]
    longitude_deg: Annotated[float, Range(-180, 180, "deg")]


class GuidedTerminal(Strict):
    """Where guidance hands over, the terminal-area interface (the Shuttle's TAEM interface by default): the flight
    ends at the energy of altitude_ft and velocity_fps, aimed at the circle of range_nmi about the site, headed at
    it; each value has a tolerance (the range's is the bank law's reach_nmi). Sources, choices: core.guidance."""

    altitude_ft: Annotated[float, Range(0, 1_000_000, "ft")] = _default("terminal_altitude_ft")
    velocity_fps: Annotated[float, Range(100, 30_000, "ft/s")] = _default("terminal_velocity_fps")
    range_nmi: Annotated[float, Range(0, 1_000, "nmi")] = _default("interface_range_nmi")
    altitude_tolerance_ft: Annotated[float, Range(0, 1_000_000, "ft")] = _default("interface_altitude_tolerance_ft")
    velocity_tolerance_fps: Annotated[float, Range(0, 30_000, "ft/s")] = _default("interface_velocity_tolerance_fps")
    heading_tolerance_deg: Annotated[float, Range(0, 180, "deg")] = _default("interface_heading_tolerance_deg")


Magnitude = Annotated[float, Range(0, 180, "deg")]
MIN_CYCLE_S, MAX_CYCLE_S = 0.5, 120.0
MIN_PREDICTOR_RTOL, MAX_PREDICTOR_RTOL = 1e-12, 1e-3

# A guided flight's work over the defaults' (5 s cycles, predictor_rtol 3e-5), in right-hand sides, measured with
# `footprint fly` on examples/fly_guided_lod189.json (5,000/600 nmi: 154,792 right-hand sides, 0.062 s, 2 shared
# cores, load 2; the HTTP answer 0.63 s):
#   cycle_s          0.5 s: 8.2x, 1 s: 4.1x, 2 s: 2.2x, 10 s: 0.58x (3,801, 1,915, 979, 259 cycles; 430 at 5 s)
#   predictor_rtol   1e-12: 21.9x, 1e-10: 10.3x, 1e-8: 4.4x, 1e-6: 1.7x, 1e-4: 0.93x, 1e-3: 1.06x
#   both             0.5 s and 1e-12: 194x (12.5 s; 89 s over HTTP in the issue), 2 s and 1e-10: 23.7x,
#                    1 s and 1e-8: 19.2x
#   iterations 20    1.0x (1.1x with tolerance_nmi 0.001): the corrector stops at the first prediction that does not
#                    improve the miss, 1.4 to 3.3 predictions a cycle whatever the iterations
# modelled from above: (5 s / cycle_s) x max(1, (3e-5 / predictor_rtol)^0.18)
RTOL_WORK_EXPONENT = 0.18
SYNC_WORK = 25.0  # the most a synchronous request may ask, in the defaults' work: ~1.6 s of flight on this machine


GUIDANCE_LIMITS = {  # a guided case's path limit -> the vehicle's (core.limits)
    "max_load_factor": "load_factor_g",
    "max_dynamic_pressure_psf": "dynamic_pressure_psf",
    "max_heat_rate_btu_ft2_s": "heat_rate_btu_ft2_s",
    "max_temperature_R": "temperature_R",
}


class BankGuided(Strict):
    """Entry guidance in the loop: bank magnitude linear in energy, corrected each cycle on the predicted range;
    bank reversals in a heading-error corridor; path limits as a bank bound (core/guidance.py): the vehicle's unless
    given here (a number changes one, null lifts it)."""

    law: Literal["guided"]
    target: GuidedTarget
    terminal: GuidedTerminal = GuidedTerminal()
    cycle_s: Annotated[float, Range(MIN_CYCLE_S, MAX_CYCLE_S, "s")] = _default("cycle_s")
    max_prediction_interval_s: Annotated[float, Range(MIN_CYCLE_S, 600, "s")] = _default("max_prediction_interval_s")
    initial_bank_deg: Magnitude = _default("initial_bank_deg")
    final_bank_deg: Magnitude = _default("final_bank_deg")
    min_bank_deg: Magnitude = _default("min_bank_deg")
    max_bank_deg: Magnitude = _default("max_bank_deg")
    iterations: Annotated[int, Range(0, 20)] = _default("iterations")
    tolerance_nmi: Annotated[float, Range(0.001, 1000, "nmi")] = _default("tolerance_nmi")
    tolerance_fraction: Annotated[float, Range(0, 0.1)] = _default("tolerance_fraction")
    corridor_entry_deg: Annotated[float, Range(0.1, 90, "deg")] = _default("corridor_entry_deg")
    corridor_terminal_deg: Annotated[float, Range(0.1, 90, "deg")] = _default("corridor_terminal_deg")
    lateral_freeze_nmi: Annotated[float, Range(0, 10_000, "nmi")] = _default("lateral_freeze_nmi")
    min_reversal_interval_s: Annotated[float, Range(0, 10_000, "s")] = _default("min_reversal_interval_s")
    final_reversal_window_s: Annotated[float, Range(0, 10_000, "s")] = _default("final_reversal_window_s")
    reversal_inhibit_s: Annotated[float, Range(0, 10_000, "s")] = _default("reversal_inhibit_s")
    bank_rate_deg_s: Annotated[float, Range(0.1, 1000, "deg/s")] | None = _default("bank_rate_deg_s")  # None: unlimited
    bank_acceleration_deg_s2: Annotated[float, Range(0.1, 10_000, "deg/s^2")] | None = _default(
        "bank_acceleration_deg_s2"
    )
    predictor_rtol: Annotated[float, Range(MIN_PREDICTOR_RTOL, MAX_PREDICTOR_RTOL)] = _default("predictor_rtol")
    filter_gain: Annotated[float, Range(0, 1)] = _default("filter_gain")
    # path limits: unset, the vehicle's (path_limits); a number changes it, null lifts it
    max_heat_rate_btu_ft2_s: Annotated[float, Range(0.1, 10_000, "Btu/(ft^2 s)")] | None = None
    max_temperature_R: Annotated[float, Range(100, 10_000, "degR")] | None = None
    max_load_factor: Annotated[float, Range(0.1, 100, "g")] | None = None
    max_dynamic_pressure_psf: Annotated[float, Range(1, 100_000, "lb/ft^2")] | None = None
    limit_damping: Annotated[float, Range(0, 10)] = _default("limit_damping")
    reach_nmi: Annotated[float, Range(0.001, 10_000, "nmi")] = _default("reach_nmi")

    @model_validator(mode="after")
    def _synchronous_work(self, info: ValidationInfo) -> "BankGuided":
        if synchronous(info):
            check_synchronous_work(self.cycle_s, self.predictor_rtol)
        return self

    def controls(self) -> dict[str, Any]:
        return {"bank_law": "zero"}  # the guidance flies the bank (core.guidance.guided_controls)

    def path_limits(self, vehicle: Limits, heat_rate: bool, temperature: bool) -> dict[str, float | None]:
        """The limits the guidance holds (issue 50): each as given (null: lifted), unset the vehicle's; an unset heat
        rate or temperature only where the case evaluates it (heat_rate, temperature: a heating model, with the
        emissivity of eq. 7 for the temperature), else none (the summary lists the vehicle's as unchecked)."""
        evaluated = {"heat_rate_btu_ft2_s": heat_rate, "temperature_R": temperature}
        out = {}
        for setting, name in GUIDANCE_LIMITS.items():
            if setting in self.model_fields_set:
                out[setting] = getattr(self, setting)
            else:
                out[setting] = vehicle.value(name) if evaluated.get(name, True) else None
        return out

    def to_guidance(self, limits: dict[str, float | None] | None = None) -> Guidance:
        """The core's settings, with the path limits held (path_limits; None: only those given)."""
        settings = self.model_dump(exclude={"law", "target", "terminal"}) | (limits or {})
        for name in ("bank_rate_deg_s", "bank_acceleration_deg_s2"):
            settings[name] = math.inf if settings[name] is None else settings[name]
        return Guidance(
            target_latitude_deg=self.target.latitude_deg,
            target_longitude_deg=self.target.longitude_deg,
            terminal_altitude_ft=self.terminal.altitude_ft,
            terminal_velocity_fps=self.terminal.velocity_fps,
            interface_range_nmi=self.terminal.range_nmi,
            interface_altitude_tolerance_ft=self.terminal.altitude_tolerance_ft,
            interface_velocity_tolerance_fps=self.terminal.velocity_tolerance_fps,
            interface_heading_tolerance_deg=self.terminal.heading_tolerance_deg,
            **settings,
        )


def check_guided_study(bank: Any, info: ValidationInfo, what: str) -> None:
    """A study that flies a guided case (`what`: "guided dispersion"...): run as a job, its case's bank law the
    guided one; else one line naming the field."""
    if synchronous(info):
        raise ValueError(f"a {what} is run as a job; submit it with POST /api/jobs")
    if not isinstance(bank, BankGuided):
        raise ValueError(f"case.bank.law: a {what} flies the 'guided' law, not {bank.law!r}")


def work_factors(cycle_s: float, predictor_rtol: float) -> tuple[float, float]:
    """(the cycles', the predictor's) factor of a guided flight's work over the defaults' (the model above)."""
    cycles = _default("cycle_s") / cycle_s
    return cycles, max(1.0, (_default("predictor_rtol") / predictor_rtol) ** RTOL_WORK_EXPONENT)


def check_synchronous_work(cycle_s: float, predictor_rtol: float) -> None:
    """A guided flight the API process may fly itself: at most SYNC_WORK times the defaults' work; else one line
    naming the setting that asks more of the two, and its range with the other as given."""
    cycles, predictor = work_factors(cycle_s, predictor_rtol)
    if cycles * predictor <= SYNC_WORK:
        return
    if predictor >= cycles:
        least = _default("predictor_rtol") / (SYNC_WORK / cycles) ** (1.0 / RTOL_WORK_EXPONENT)
        said = f"predictor_rtol: {predictor_rtol:g} with cycle_s {cycle_s:g} s"
        allowed = f"{_up(least):g} to {MAX_PREDICTOR_RTOL:g} with this cycle_s"
    else:
        said = f"cycle_s: {cycle_s:g} s with predictor_rtol {predictor_rtol:g}"
        allowed = f"{_up(_default('cycle_s') * predictor / SYNC_WORK):g} to {MAX_CYCLE_S:g} s with this predictor_rtol"
    raise ValueError(
        f"{said} is about {cycles * predictor:.3g} times the work of the default settings, past the {SYNC_WORK:g} "
        f"times a synchronous request may ask: allowed {allowed}; or fly it with the CLI (footprint fly) or the "
        "Python API (footprint.fly)"
    )


def _up(x: float) -> float:
    """x rounded up to two significant digits (a bound said so still passes)."""
    scale = 10.0 ** (math.floor(math.log10(x)) - 1)
    return math.ceil(x / scale) * scale
