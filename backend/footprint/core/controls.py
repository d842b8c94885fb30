"""Bank-angle and angle-of-attack laws (AFWAL-TR-82-3036 Sections II.5-II.7, III, Appendix C).

Conventions: bank is positive to the left, so a positive bank turns an eastbound entry toward north and
gives positive cross-range. Laws that steer on the heading use zeta, the remaining heading change: the
angle, clockwise, from the cross-range axis (the local horizontal direction toward the left pole of the
initial great circle) to the horizontal velocity. For an equatorial eastbound entry zeta equals the
heading sigma (Section II.6: "for other inclinations zeta must be substituted for sigma").
A right-hand (mirrored) law evaluates the same rule on 180 deg - zeta and negates the bank.

The laws live in a flat float64 array `ctrl` (layout below) so the compiled integrator takes one argument.
"""

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core._jit import njit

# --- bank laws ---
BANK_ZERO = 0
BANK_CONSTANT = 1
BANK_STAGED = 2
BANK_TWO_PARAMETER = 3
BANK_SINGLE_PARAMETER = 4
BANK_TABLE = 5
BANK_ZERO_LIFT = 6
BANK_CONSTANT_ALTITUDE = 7
BANK_LAWS = {
    "zero": BANK_ZERO,
    "constant": BANK_CONSTANT,
    "staged": BANK_STAGED,
    "two_parameter": BANK_TWO_PARAMETER,
    "single_parameter": BANK_SINGLE_PARAMETER,
    "table": BANK_TABLE,
    "zero_lift": BANK_ZERO_LIFT,
    "constant_altitude": BANK_CONSTANT_ALTITUDE,
}
# --- angle-of-attack laws ---
ALPHA_MAX_LD = 0
ALPHA_CL_MAX = 1
ALPHA_CONSTANT = 2
ALPHA_TABLE_VELOCITY = 3
ALPHA_TABLE_TIME = 4
ALPHA_LEVEL_FLIGHT = 5
ALPHA_GAMMA_HOLD = 6
ALPHA_MAX_LD_FLOOR = 7  # (L/D)max, never below a floor table vs velocity (the temperature-limited law)
ALPHA_TABLE_ENERGY = 8  # table vs energy height h + V^2/(2 g0), ft
ALPHA_LAWS = {
    "max_ld": ALPHA_MAX_LD,
    "cl_max": ALPHA_CL_MAX,
    "constant": ALPHA_CONSTANT,
    "table": ALPHA_TABLE_VELOCITY,  # or ALPHA_TABLE_TIME / ALPHA_TABLE_ENERGY, by the table's abscissa
    "level_flight": ALPHA_LEVEL_FLIGHT,
    "gamma_hold": ALPHA_GAMMA_HOLD,
    "max_ld_floor": ALPHA_MAX_LD_FLOOR,
}
ALPHA_TABLE_BY_ABSCISSA = {"velocity": ALPHA_TABLE_VELOCITY, "time": ALPHA_TABLE_TIME, "energy": ALPHA_TABLE_ENERGY}
# --- what the heading laws and the bank table are tabulated against (C_BANK_VAR) ---
VAR_ZETA = 0  # remaining heading change, deg (Section II.6)
VAR_HEADING = 1  # heading sigma, deg
VAR_TIME = 2  # s from entry (bank table only)
VAR_VELOCITY = 3  # earth-relative speed, ft/s (bank table only)
VAR_ENERGY = 4  # energy height h + V^2/(2 g0), ft (bank table only)
BANK_VARIABLES = {
    "zeta": VAR_ZETA,
    "heading": VAR_HEADING,
    "time": VAR_TIME,
    "velocity": VAR_VELOCITY,
    "energy": VAR_ENERGY,
}
# --- when the bank law takes over (before it the bank is zero) ---
START_ENTRY = 0
START_PULLOUT = 1
START_ALTITUDE = 2
BANK_STARTS = {"entry": START_ENTRY, "pullout": START_PULLOUT, "altitude": START_ALTITUDE}

# --- ctrl array layout (one quantity per slot, its unit in the name) ---
C_BANK_LAW = 0
C_BANK_DEG = 1  # deg, bank of the constant and staged laws
C_BANK_GAIN = 2  # K, deg of bank per deg of steering angle (two- and single-parameter laws)
C_SIDE = 3  # +1 left, -1 right: where a constant-altitude turn banks
C_BANK_LIMIT = 4  # deg; NO_LIMIT when none
C_SIGMA_F = 5  # deg, two-parameter final heading
C_TURN = 6  # deg, staged / constant-altitude heading change
C_BANK_VAR = 7  # one of BANK_VARIABLES
C_MIRROR = 8  # 1: right-hand version of the law
C_START = 9
C_START_ALT = 10  # ft
C_ALPHA_LAW = 11
C_ALPHA_DEG = 12  # deg, alpha of the constant law
C_GAMMA_DEG = 13  # deg, flight-path angle the gamma_hold law holds after pull-out
C_ALPHA_BEFORE = 14  # law before pull-out for level_flight / gamma_hold: ALPHA_MAX_LD or ALPHA_CL_MAX
C_BANK_TABLE = 15  # offset of (n, x[n], y[n]) or -1
C_ALPHA_TABLE = 16
C_TAU = 17  # s, time constant of the flight-path and altitude holds
C_SIZE = 18
NO_LIMIT = 1.0e9
LEFT, RIGHT = 1.0, -1.0  # C_SIDE values


def pack_controls(
    *,
    bank_law: str,
    bank_deg: float = 0.0,
    bank_gain: float = 0.0,
    side: float = LEFT,
    bank_limit_deg: float | None = None,
    sigma_f_deg: float = 0.0,
    turn_deg: float = 90.0,
    bank_variable: str = "zeta",
    mirror: bool = False,
    bank_start: str = "pullout",
    bank_start_altitude_ft: float = 0.0,
    alpha_law: str = "max_ld",
    alpha_deg: float = 0.0,
    gamma_deg: float = 0.0,
    alpha_before: str = "max_ld",
    bank_table: tuple[ArrayLike, ArrayLike] | None = None,
    alpha_table: tuple[ArrayLike, ArrayLike] | None = None,
    alpha_table_abscissa: str = "velocity",
    hold_time_constant_s: float = 10.0,
) -> NDArray[np.float64]:
    """Build the ctrl array from plain values (validated by the caller)."""
    arguments = locals()  # each slot has one writer, _slot_value, shared with replace_controls
    slots = [0.0] * C_SIZE  # filled as plain floats, made an array once
    for name, slot in SLOTS.items():
        slots[slot] = _slot_value(name, arguments[name])
    slots[C_ALPHA_LAW] = _alpha_code(alpha_law, alpha_table_abscissa)
    parts: list[NDArray[np.float64]] = []
    offset = C_SIZE
    for slot, table in ((C_BANK_TABLE, bank_table), (C_ALPHA_TABLE, alpha_table)):
        if table is None:
            slots[slot] = -1.0
            continue
        x, y = (np.asarray(v, dtype=np.float64) for v in table)
        slots[slot] = float(offset)
        parts.append(np.concatenate(([len(x)], x, y)))
        offset += 1 + 2 * len(x)
    ctrl = np.array(slots)
    return np.concatenate([ctrl, *parts]) if parts else ctrl


SLOTS = {  # pack_controls' scalar arguments -> their slot (the laws' codes, the tables' offsets aside)
    "bank_law": C_BANK_LAW,
    "bank_deg": C_BANK_DEG,
    "bank_gain": C_BANK_GAIN,
    "side": C_SIDE,
    "bank_limit_deg": C_BANK_LIMIT,
    "sigma_f_deg": C_SIGMA_F,
    "turn_deg": C_TURN,
    "bank_variable": C_BANK_VAR,
    "mirror": C_MIRROR,
    "bank_start": C_START,
    "bank_start_altitude_ft": C_START_ALT,
    "alpha_deg": C_ALPHA_DEG,
    "gamma_deg": C_GAMMA_DEG,
    "alpha_before": C_ALPHA_BEFORE,
    "hold_time_constant_s": C_TAU,
}
_CODES = {"bank_law": BANK_LAWS, "bank_variable": BANK_VARIABLES, "bank_start": BANK_STARTS, "alpha_before": ALPHA_LAWS}
_TABLES = {"bank_table", "alpha_table"}
_ALPHA = {"alpha_law", "alpha_table_abscissa"}


def _slot_value(name: str, value: Any) -> float:  # value: a code's name, a number, a flag or None, by name
    """An argument of pack_controls as its slot holds it."""
    if name in _CODES:
        return float(_CODES[name][value])
    if name == "bank_limit_deg":
        return NO_LIMIT if value is None else float(value)
    if name == "mirror":
        return 1.0 if value else 0.0
    return float(value)


def _alpha_code(law: str, abscissa: str) -> float:
    return float(ALPHA_TABLE_BY_ABSCISSA[abscissa] if law == "table" else ALPHA_LAWS[law])


def _name_of(names: dict[str, int], code: float) -> str:
    return next(n for n, c in names.items() if c == int(code))


def alpha_law_name(code: float) -> tuple[str, str]:
    """(alpha_law, alpha_table_abscissa) of pack_controls for an alpha-law code."""
    abscissa = {c: a for a, c in ALPHA_TABLE_BY_ABSCISSA.items()}.get(int(code))
    return ("table", abscissa) if abscissa is not None else (_name_of(ALPHA_LAWS, code), "velocity")


def _table(ctrl: NDArray[np.float64], slot: int) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    if ctrl[slot] < 0:
        return None
    o = int(ctrl[slot])
    n = int(ctrl[o])
    return ctrl[o + 1 : o + 1 + n].copy(), ctrl[o + 1 + n : o + 1 + 2 * n].copy()


def unpack_controls(ctrl: NDArray[np.float64]) -> dict[str, Any]:
    """The keyword arguments of pack_controls that rebuild ctrl (its inverse)."""
    alpha_law, abscissa = alpha_law_name(ctrl[C_ALPHA_LAW])
    return {
        "bank_law": _name_of(BANK_LAWS, ctrl[C_BANK_LAW]),
        "bank_deg": float(ctrl[C_BANK_DEG]),
        "bank_gain": float(ctrl[C_BANK_GAIN]),
        "side": float(ctrl[C_SIDE]),
        "bank_limit_deg": None if ctrl[C_BANK_LIMIT] == NO_LIMIT else float(ctrl[C_BANK_LIMIT]),
        "sigma_f_deg": float(ctrl[C_SIGMA_F]),
        "turn_deg": float(ctrl[C_TURN]),
        "bank_variable": _name_of(BANK_VARIABLES, ctrl[C_BANK_VAR]),
        "mirror": ctrl[C_MIRROR] != 0.0,
        "bank_start": _name_of(BANK_STARTS, ctrl[C_START]),
        "bank_start_altitude_ft": float(ctrl[C_START_ALT]),
        "alpha_law": alpha_law,
        "alpha_deg": float(ctrl[C_ALPHA_DEG]),
        "gamma_deg": float(ctrl[C_GAMMA_DEG]),
        "alpha_before": _name_of(ALPHA_LAWS, ctrl[C_ALPHA_BEFORE]),
        "bank_table": _table(ctrl, C_BANK_TABLE),
        "alpha_table": _table(ctrl, C_ALPHA_TABLE),
        "alpha_table_abscissa": abscissa,
        "hold_time_constant_s": float(ctrl[C_TAU]),
    }


def replace_controls(ctrl: NDArray[np.float64], **changes: Any) -> NDArray[np.float64]:
    """ctrl with some of pack_controls' arguments changed, the rest kept: the changed slots written into a copy (a
    footprint's every flight changes a law's parameter); a new table packs the array again."""
    unknown = changes.keys() - SLOTS.keys() - _TABLES - _ALPHA
    if unknown:
        raise TypeError(f"replace_controls: no control {', '.join(sorted(unknown))}")
    if changes.keys() & _TABLES:
        return pack_controls(**(unpack_controls(ctrl) | changes))
    out = ctrl.copy()
    for name in changes.keys() & SLOTS.keys():
        out[SLOTS[name]] = _slot_value(name, changes[name])
    if changes.keys() & _ALPHA:
        law, abscissa = alpha_law_name(ctrl[C_ALPHA_LAW])
        out[C_ALPHA_LAW] = _alpha_code(changes.get("alpha_law", law), changes.get("alpha_table_abscissa", abscissa))
    return out


# The variants the footprint, optimization and heating methods fly, all through replace_controls.
def replace_bank_law(
    ctrl: NDArray[np.float64],
    law: str,
    *,
    bank_deg: float = 0.0,
    bank_gain: float = 0.0,
    limit_deg: float | None = None,
    sigma_f_deg: float = 0.0,
    turn_deg: float = 90.0,
    right: bool = False,
) -> NDArray[np.float64]:
    """ctrl with its bank law replaced, steering on zeta (the procedure for any inclination, Section II.6); the
    alpha law, the bank start and the tables kept. right: the right-hand version of the law (a negative bank
    for the constant and staged laws, a turn to the right for constant altitude, the mirrored rule otherwise)."""
    signed = law in ("constant", "staged")
    return replace_controls(
        ctrl,
        bank_law=law,
        bank_deg=-bank_deg if right and signed else bank_deg,
        bank_gain=bank_gain,
        side=RIGHT if right and law == "constant_altitude" else LEFT,
        bank_limit_deg=limit_deg,
        sigma_f_deg=sigma_f_deg,
        turn_deg=turn_deg,
        bank_variable="zeta",
        mirror=right and not signed and law != "constant_altitude",
    )


def replace_alpha_law(ctrl: NDArray[np.float64], law: str) -> NDArray[np.float64]:
    """ctrl with its angle-of-attack law replaced (a law without a table), the rest kept."""
    return replace_controls(ctrl, alpha_law=law)


def replace_bank_table(
    ctrl: NDArray[np.float64], bank_deg: ArrayLike, nodes: ArrayLike, variable: str = "zeta"
) -> NDArray[np.float64]:
    """ctrl flying bank = linear interpolation in (variable, bank) (Section II.5, Fig. 2: in zeta), nodes in the
    unit of BANK_VARIABLES[variable], held at the table's ends, no limit, left-hand; the rest kept."""
    return replace_controls(
        ctrl, bank_law="table", bank_limit_deg=None, bank_variable=variable, mirror=False, bank_table=(nodes, bank_deg)
    )


def replace_alpha_table(
    ctrl: NDArray[np.float64], alpha_deg: ArrayLike, nodes: ArrayLike, law: int = ALPHA_TABLE_VELOCITY
) -> NDArray[np.float64]:
    """ctrl flying alpha = linear interpolation in (node, alpha), held at the table's ends, over the whole flight:
    nodes are velocities in ft/s (ALPHA_TABLE_VELOCITY, and ALPHA_MAX_LD_FLOOR: (L/D)max, never below the
    table), times in s (ALPHA_TABLE_TIME) or energy heights in ft (ALPHA_TABLE_ENERGY); the rest kept."""
    x = np.asarray(nodes, dtype=float)
    a = np.asarray(alpha_deg, dtype=float)
    if x.shape != a.shape or np.any(np.diff(x) <= 0.0):
        raise ValueError(f"alpha table: {len(x)} nodes (must ascend) for {len(a)} angles")
    alpha_law, abscissa = alpha_law_name(law)
    return replace_controls(ctrl, alpha_law=alpha_law, alpha_table=(x, a), alpha_table_abscissa=abscissa)


@njit(allocates=False)
def table_interp(ctrl: NDArray[np.float64], offset: float, x: float) -> float:
    """Linear interpolation in a (n, x[n], y[n]) table of ctrl, held at the ends."""
    o = int(offset)
    n = int(ctrl[o])
    xs = o + 1
    ys = o + 1 + n
    y: float  # each return a typed value (numpy types an array's item as Any)
    if x <= ctrl[xs]:
        y = ctrl[ys]
        return y
    if x >= ctrl[xs + n - 1]:
        y = ctrl[ys + n - 1]
        return y
    lo, hi = 0, n - 1  # bisection for the interval [i, i + 1] with x[i] < x <= x[i + 1]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ctrl[xs + mid] < x:
            lo = mid
        else:
            hi = mid
    i = lo
    w = (x - ctrl[xs + i]) / (ctrl[xs + i + 1] - ctrl[xs + i])
    y = ctrl[ys + i] + w * (ctrl[ys + i + 1] - ctrl[ys + i])
    return y


@njit
def wrap_deg(a: float) -> float:
    """Angle wrapped to (-180, 180] (core.sphere.wrap_longitude with closed_above=True; this one stays a numba kernel
    because the compiled integrator calls it)."""
    return a - 360.0 * math.ceil((a - 180.0) / 360.0)


@njit(allocates=False)
def steering_angle_deg(ctrl: NDArray[np.float64], zeta_deg: float, heading_deg: float) -> float:
    """The angle the heading laws steer on, in the law's own (left-hand) sense (the heading for a bank table
    against time, velocity or energy: the staged and constant-altitude turns still measure their turn on it)."""
    a = zeta_deg if ctrl[C_BANK_VAR] == VAR_ZETA else heading_deg
    if ctrl[C_MIRROR] != 0.0:
        a = 180.0 - a
    return wrap_deg(a)


@njit(allocates=False)
def bank_abscissa(
    ctrl: NDArray[np.float64], steer_deg: float, time_s: float, velocity_fps: float, energy_ft: float
) -> float:
    """The value the bank table is read at: the steering angle, or time, velocity or energy (not mirrored)."""
    var = ctrl[C_BANK_VAR]
    if var == VAR_TIME:
        return time_s
    if var == VAR_VELOCITY:
        return velocity_fps
    if var == VAR_ENERGY:
        return energy_ft
    return steer_deg


@njit(allocates=False)
def bank_from_law(
    ctrl: NDArray[np.float64], mode_active: float, mode_done: float, angle_deg: float, table_x: float = math.nan
) -> float:
    """Bank angle (deg) of the laws that depend on the steering angle only (and of the bank table, read at
    table_x when it is tabulated against time, velocity or energy).

    BANK_CONSTANT_ALTITUDE and BANK_ZERO_LIFT are resolved by the dynamics (they need the forces).
    """
    if mode_active == 0.0:
        return 0.0
    law = int(ctrl[C_BANK_LAW])
    bank: float  # a typed value (numpy types an array's item as Any)
    if law == BANK_CONSTANT:
        bank = ctrl[C_BANK_DEG]
    elif law == BANK_STAGED:
        bank = 0.0 if mode_done != 0.0 else ctrl[C_BANK_DEG]  # Section I / Fig. 14: constant until the turn, then zero
    elif law == BANK_TWO_PARAMETER:
        bank = ctrl[C_BANK_GAIN] * (angle_deg - ctrl[C_SIGMA_F])  # Section II.5, phi_B = K (sigma - sigma_f), Fig. 5
    elif law == BANK_SINGLE_PARAMETER:
        bank = ctrl[C_BANK_GAIN] * angle_deg  # Section II.5-II.6, phi_B = K sigma (K zeta), Fig. 8
    elif law == BANK_TABLE:
        x = angle_deg if ctrl[C_BANK_VAR] <= VAR_HEADING else table_x
        bank = table_interp(ctrl, ctrl[C_BANK_TABLE], x)  # Section II.5, Fig. 2: linear in heading (or time...)
    else:
        bank = 0.0
    limit = min(ctrl[C_BANK_LIMIT], 180.0)  # past 180 deg the wings roll on through inverted: no law means that
    if bank > limit:
        bank = limit
    elif bank < -limit:
        bank = -limit
    if ctrl[C_MIRROR] != 0.0 and (law == BANK_TWO_PARAMETER or law == BANK_SINGLE_PARAMETER or law == BANK_TABLE):
        bank = -bank
    return bank
