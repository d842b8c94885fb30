"""A footprint point's control setting: what its flight's method set (the parameter of one of the report's bank
laws, Sections II.5-II.7, the shortest flight's law, or the collocation's down-range target), as a typed record.
Its stored form, the `parameter` of the service's rows, the CSV, the GeoJSON and the page, is the dict of the
fields that are set (`as_dict`; `of` reads it back)."""

from dataclasses import dataclass, fields
from typing import Any, Literal

MinRange = Literal["zero_lift", "cl_max"]


@dataclass(frozen=True)
class ControlSetting:
    bank0_deg: float | None = None  # single parameter: phi_B = K zeta with K = phi0 / 90 deg (Section II.6)
    bank_gain: float | None = None  # K, deg/deg (single and two parameter, Eqs. of Section II.6-II.7)
    sigma_f_deg: float | None = None  # two parameter: phi_B = K (zeta - sigma_f), Figs. 5-7
    bank_deg: float | None = None  # constant bank, Fig. 14
    turn_deg: float | None = None  # wings level after this heading change (staged, Fig. 14; constant altitude, Fig. 19)
    until: Literal["wings_level"] | None = None  # constant altitude's widest turn: banked until no lift is left
    min_range: MinRange | None = None  # the shortest flight: zero lift (Section II.6 d) or C_L max (Appendix C)
    alpha_floor_deg: float | None = None  # temperature limited: alpha's floor above 16,000 ft/s (core.constrained)
    downrange_target_nmi: float | None = None  # collocation: the down-range held (None: free, an end of the range)
    iterations: int | None = None  # collocation: IPOPT's iterations
    nlp_downrange_nmi: float | None = None  # collocation: the NLP's own landing
    nlp_crossrange_nmi: float | None = None
    agreement_deg: float | None = None  # collocation: the re-flight's largest departure from the NLP's landing
    inverted_s: float | None = None  # collocation: time its re-flight flew upside down at negative lift (None: none)

    @property
    def collocated(self) -> bool:
        """Set by a collocation (its controls are node tables, not a law's parameter)."""
        return self.iterations is not None

    def as_dict(self) -> dict[str, Any]:
        """The stored form: the fields that are set, in this order (a collocation's target also when free)."""
        keep = {"downrange_target_nmi"} if self.collocated else set()
        return {f.name: v for f in fields(self) if (v := getattr(self, f.name)) is not None or f.name in keep}

    @classmethod
    def of(cls, parameter: "ControlSetting | dict[str, Any]") -> "ControlSetting":
        """A setting from its stored form (a setting passes through)."""
        return parameter if isinstance(parameter, ControlSetting) else cls(**parameter)

    def key(self) -> tuple[tuple[str, Any], ...]:
        """What tells two settings of one study apart (the stored form's items, sorted)."""
        return tuple(sorted(self.as_dict().items()))

    def words(self) -> str:
        """The setting in words, for a terminal: 'initial bank 105°' (its K follows from phi0), 'K 0.5, σf 15°'."""
        if self.min_range is not None:
            return MIN_RANGE_WORDS[self.min_range]
        derived = {"bank_gain"} if self.bank0_deg is not None else set()
        named = [n for n in WORDS if getattr(self, n) is not None and n not in derived]
        return ", ".join(f"{WORDS[n][0]} {_shown(getattr(self, n))}{WORDS[n][1]}" for n in named)


WORDS = {  # name -> (word, unit), the settings a terminal or a popup names
    "bank0_deg": ("initial bank", "°"),
    "bank_gain": ("K", ""),
    "sigma_f_deg": ("σf", "°"),
    "bank_deg": ("bank", "°"),
    "turn_deg": ("wings level after a turn of", "°"),
    "alpha_floor_deg": ("α floor", "°"),
    "downrange_target_nmi": ("down-range held at", " nmi"),
    "agreement_deg": ("re-flown within", "°"),
    "iterations": ("IPOPT iterations", ""),
    "inverted_s": ("upside down at negative lift for", " s"),
}
MIN_RANGE_WORDS = {"zero_lift": "zero lift (shortest flight)", "cl_max": "C_L max, no bank (shortest flight)"}


def _shown(v: Any) -> str:
    if not isinstance(v, float):
        return str(v)
    return f"{v:,.0f}" if abs(v) >= 100 else f"{v:.3g}"
