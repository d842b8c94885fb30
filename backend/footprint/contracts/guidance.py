"""The guided bank law of a case: `"bank": {"law": "guided", "target": {...}, "terminal": {...}, ...settings}`.

The numerical predictor-corrector of footprint.core.guidance flies the bank; the case's alpha law and bank start
are kept. Every default is the core record's (core.guidance.Guidance).
"""

import dataclasses
import math
from typing import Annotated, Any, Literal

from pydantic import ValidationInfo

from footprint.contracts.doors import synchronous
from footprint.contracts.fields import Range, Strict
from footprint.core.guidance import Guidance


def _default(name: str) -> Any:
    return next(f.default for f in dataclasses.fields(Guidance) if f.name == name)


class GuidedTarget(Strict):
    latitude_deg: Annotated[float, Range(-90, 90, "deg")]
    longitude_deg: Annotated[float, Range(-180, 180, "deg")]


class GuidedTerminal(Strict):
    """Where guidance hands over (the Shuttle's TAEM interface by default): the flight ends at this energy."""

    altitude_ft: Annotated[float, Range(0, 1_000_000, "ft")] = _default("terminal_altitude_ft")
    velocity_fps: Annotated[float, Range(100, 30_000, "ft/s")] = _default("terminal_velocity_fps")


Magnitude = Annotated[float, Range(0, 180, "deg")]


class BankGuided(Strict):
    """Entry guidance in the loop: bank magnitude linear in energy, corrected each cycle on the predicted range;
    bank reversals in a heading-error corridor; path limits as a bank bound (core/guidance.py)."""

    law: Literal["guided"]
    target: GuidedTarget
    terminal: GuidedTerminal = GuidedTerminal()
    cycle_s: Annotated[float, Range(0.5, 120, "s")] = _default("cycle_s")
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
    bank_rate_deg_s: Annotated[float, Range(0.1, 1000, "deg/s")] | None = _default("bank_rate_deg_s")  # None: unlimited
    bank_acceleration_deg_s2: Annotated[float, Range(0.1, 10_000, "deg/s^2")] | None = _default(
        "bank_acceleration_deg_s2"
    )
    predictor_rtol: Annotated[float, Range(1e-12, 1e-3)] = _default("predictor_rtol")
    filter_gain: Annotated[float, Range(0, 1)] = _default("filter_gain")
    max_heat_rate_btu_ft2_s: Annotated[float, Range(0.1, 10_000, "Btu/(ft^2 s)")] | None = None
    max_temperature_R: Annotated[float, Range(100, 10_000, "degR")] | None = None
    max_load_factor: Annotated[float, Range(0.1, 100, "g")] | None = None
    max_dynamic_pressure_psf: Annotated[float, Range(1, 100_000, "lb/ft^2")] | None = None
    limit_damping: Annotated[float, Range(0, 10)] = _default("limit_damping")
    reach_nmi: Annotated[float, Range(0.001, 10_000, "nmi")] = _default("reach_nmi")

    def controls(self) -> dict[str, Any]:
        return {"bank_law": "zero"}  # the guidance flies the bank (core.guidance.guided_controls)

    def limits(self) -> list[str]:
        """The path limits given."""
        names = ("max_heat_rate_btu_ft2_s", "max_temperature_R", "max_load_factor", "max_dynamic_pressure_psf")
        return [n for n in names if getattr(self, n) is not None]

    def to_guidance(self) -> Guidance:
        settings = self.model_dump(exclude={"law", "target", "terminal"})
        for name in ("bank_rate_deg_s", "bank_acceleration_deg_s2"):
            settings[name] = math.inf if settings[name] is None else settings[name]
        return Guidance(
            target_latitude_deg=self.target.latitude_deg,
            target_longitude_deg=self.target.longitude_deg,
            terminal_altitude_ft=self.terminal.altitude_ft,
            terminal_velocity_fps=self.terminal.velocity_fps,
            **settings,
        )


def check_guided_study(bank: Any, info: ValidationInfo, what: str) -> None:
    """A study that flies a guided case (`what`: "guided dispersion"...): run as a job, its case's bank law the
    guided one; else one line naming the field."""
    if synchronous(info):
        raise ValueError(f"a {what} is run as a job; submit it with POST /api/jobs")
    if not isinstance(bank, BankGuided):
        raise ValueError(f"case.bank.law: a {what} flies the 'guided' law, not {bank.law!r}")
