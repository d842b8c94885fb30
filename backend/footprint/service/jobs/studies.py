"""A job's study checked in the service before anything is queued: stored vehicles resolved, the contract's
parser for the kind, the core's vehicle checks, and the service's own limits. Errors name `study.<field>`."""

from typing import Callable

from pydantic import ValidationError

from footprint.core.errors import InputError
from footprint.contracts.optimization import parse_optimization
from footprint.contracts.reach import parse_reach
from footprint.service.errors import RequestInvalid, invalid
from footprint.contracts.footprint import parse_study
from footprint.contracts.sweep import check_vehicles, parse_sweep

KINDS = ("footprint", "optimize", "sweep", "reach")
MAX_FOOTPRINT_POINTS = 200  # one footprint study over HTTP (the contract allows more for the CLI)
MAX_SWEEP_FOOTPRINTS = 1_000  # one sweep job over HTTP (Appendix C data set 1 is 120)


def resolve_vehicles(data, *, lookup: Callable[[str], dict | None], path: str = ""):
    """A copy of `data` with every `{"stored": id}` vehicle (a "vehicle" value or a "vehicles" item) replaced
    by its stored definition. Raises RequestInvalid naming the field for an unknown id."""
    if isinstance(data, list):
        return [resolve_vehicles(v, lookup=lookup, path=f"{path}[{i}]") for i, v in enumerate(data)]
    if not isinstance(data, dict):
        return data
    out = {}
    for key, value in data.items():
        where = f"{path}.{key}" if path else key
        if key == "vehicle" and _is_stored(value):
            out[key] = _stored(value, lookup, where)
        elif key == "vehicles" and isinstance(value, list):
            out[key] = [_stored(v, lookup, f"{where}[{i}]") if _is_stored(v) else resolve_vehicles(v, lookup=lookup)
                        for i, v in enumerate(value)]
        else:
            out[key] = resolve_vehicles(value, lookup=lookup, path=where)
    return out


def _is_stored(value) -> bool:
    return isinstance(value, dict) and set(value) == {"stored"}


def _stored(value: dict, lookup, where: str) -> dict:
    definition = lookup(str(value["stored"]))
    if definition is None:
        raise RequestInvalid(f"{where}.stored: no stored vehicle {value['stored']!r} (GET /api/vehicles lists them)",
                             f"{where}.stored")
    return definition


def check_study(kind: str, study: dict) -> str | None:
    """Validate a job's study for its kind; RequestInvalid (422) names `study.<field>`. Returns the job's
    default name (a footprint job's: its vehicle, method and entry), computed once here, at creation."""
    try:
        return CHECKS[kind](study)
    except (ValidationError, InputError) as exc:
        raise invalid(exc, "study.") from None


def footprint_name(study) -> str:
    """A footprint study's default name: vehicle, method, entry speed and flight-path angle."""
    from footprint.contracts.sweep import vehicle_label

    e = study.case.entry
    return f"{vehicle_label(study.case.vehicle)} {study.method} {e.velocity_fps:g} fps {e.gamma_deg:g} deg"


def _check_footprint(study: dict) -> str:
    parsed = parse_study(study)
    check_points(parsed, "study.")
    _case_spec(parsed.case, "study.case.")
    return footprint_name(parsed)


def _check_optimize(study: dict) -> None:
    _case_spec(parse_optimization(study).case, "study.case.")


def _check_sweep(study: dict) -> None:
    sweep = parse_sweep(study)
    if sweep.size > MAX_SWEEP_FOOTPRINTS:
        raise RequestInvalid(f"study.vehicles: the sweep has {sweep.size} footprints; allowed over HTTP: 1 to "
                             f"{MAX_SWEEP_FOOTPRINTS}", "study.vehicles")
    check_points(parse_study(sweep.jobs()[0]["study"]), "study.")
    check_vehicles(sweep)


def _check_reach(study: dict) -> None:
    req = parse_reach(study)
    if req.footprint.study is not None:
        nested = parse_study(req.footprint.study)
        check_points(nested, "study.footprint.study.")
        _case_spec(nested.case, "study.footprint.study.case.")


CHECKS = {"footprint": _check_footprint, "optimize": _check_optimize, "sweep": _check_sweep,
          "reach": _check_reach}


def _case_spec(case, prefix: str) -> None:
    """Build the core's flight spec once here: the core's own checks (an inline vehicle's tables) answer 422."""
    try:
        case.to_spec()
    except InputError as exc:
        raise RequestInvalid(f"{prefix}{exc}", f"{prefix}{exc.field}") from None


def check_points(study, prefix: str) -> None:
    """At most MAX_FOOTPRINT_POINTS boundary points: parameter settings times the sides flown."""
    field, settings = _settings(study)
    sides = 2 if study.mirror else 1
    if settings * sides > MAX_FOOTPRINT_POINTS:
        raise RequestInvalid(f"{prefix}{field}: {settings} settings x {sides} sides = {settings * sides} footprint "
                             f"points is outside the allowed range 1 to {MAX_FOOTPRINT_POINTS}", f"{prefix}{field}")


def _settings(study) -> tuple[str, int]:
    if study.method in ("single_parameter", "temperature_limited"):
        return "bank0_deg", len(study.bank0_deg)
    if study.method == "collocation":
        return "points_per_half", study.points_per_half + 1
    if study.method in ("constant_bank", "staged"):
        return "bank_deg", len(study.bank_deg)
    if study.method == "two_parameter":
        return "sigma_f_deg", len(study.k) * len(study.sigma_f_deg)
    if study.turn_deg is not None:
        return "turn_deg", len(study.turn_deg)
    return "steps", study.steps
