"""Equations of motion (1)-(3) of AFWAL-TR-82-3036 in the earth-referenced frame, with the forces of
Appendix A: lift and drag in wind axes (A5-A9, coordinated turn, no side force, no thrust) and
gravity (A10).

State y = (x, y, z, vx, vy, vz): earth-fixed position (ft) and velocity relative to the earth (ft/s),
z toward the north pole. The planet rotates about z at omega (rad/s).

Parameters live in a flat float64 array `p` (layout below); the flight mode (which phase the control laws
are in) in a small float64 array `mode`, changed only at located events.
"""

import math

import numpy as np
from numpy.typing import NDArray

from footprint.core import aero as _aero
from footprint.core._jit import njit
from footprint.core.atmosphere import DENSITY_NODE_COUNT, atmosphere, density_factor
from footprint.core.controls import (
    ALPHA_CL_MAX,
    ALPHA_CONSTANT,
    ALPHA_GAMMA_HOLD,
    ALPHA_LEVEL_FLIGHT,
    ALPHA_MAX_LD_FLOOR,
    ALPHA_TABLE_ENERGY,
    ALPHA_TABLE_TIME,
    ALPHA_TABLE_VELOCITY,
    BANK_CONSTANT_ALTITUDE,
    BANK_ZERO_LIFT,
    C_ALPHA_BEFORE,
    C_ALPHA_DEG,
    C_ALPHA_LAW,
    C_ALPHA_TABLE,
    C_BANK_LAW,
    C_BANK_VAR,
    C_GAMMA_DEG,
    C_SIDE,
    C_TAU,
    VAR_ZETA,
    bank_abscissa,
    bank_from_law,
    steering_angle_deg,
    table_interp,
)
from footprint.core.frames import altitude_ft, horizon_basis
from footprint.core.gravity import gravity_ecef

# --- p layout ---
P_MU = 0  # ft^3/s^2
P_RE = 1  # ft, equatorial radius
P_RP = 2  # ft, polar radius
P_J = 3
P_H = 4
P_K = 5
P_OMEGA = 6  # rad/s
P_OBLATE = 7  # 1.0 oblate (App. A), 0.0 spherical mu/r^2
P_ATM = 8  # atmosphere model id
P_RHO0 = 9  # exponential atmosphere: slug/ft^3
P_SCALE_H = 10  # ft
P_ATM_T = 11  # degR
P_WS = 12  # wing loading, lb/ft^2
P_G0 = 13  # ft/s^2, turns weight into mass
P_POLE_X = 14  # unit vector to the left pole of the initial great circle (earth-fixed)
P_POLE_Y = 15
P_POLE_Z = 16
P_STOP_ALT = 17  # ft (NaN: none)
P_STOP_VEL = 18  # ft/s (NaN: none)
P_STOP_TIME = 19  # s
P_SKIP_ALT = 20  # ft, skip-out guard
P_RTOL = 21
P_MAX_STEP = 22  # s
P_STOP_ENERGY = 23  # ft, energy height h + V^2/(2 g0) (NaN: none): a guided flight's terminal energy
# dispersions of one Monte Carlo sample (trajectory.Dispersion); 1.0, 1.0, 0.0 fly the tables and the model as given
P_CL_MULTIPLIER = 24  # times the aero table's CL
P_CD_MULTIPLIER = 25  # times the aero table's CD
P_DENSITY_DISPERSED = 26  # 1.0: the model's density times 1 + delta(h) of the profile below; 0.0: as the model gives it
# atmosphere.density_profile: delta at atmosphere.DENSITY_NODES_FT and its spline's second derivatives, 2 x 41 slots
P_DENSITY_PROFILE = 27
P_INTEGRATOR = P_DENSITY_PROFILE + 2 * DENSITY_NODE_COUNT  # core.integrate's method, INTEGRATOR_* below
P_SIZE = P_INTEGRATOR + 1
INTEGRATOR_DOPRI5 = 0.0  # Dormand-Prince 5(4), the default
# Dormand-Prince 8(5,3), each step recorded at integrate.DOP853_ROWS_PER_STEP points. Not the default (issue 29 item 4):
# Table 2 in 2,677 right-hand sides against DOPRI5's 3,031 (summary path 0.93x), but the L/D 1.89 case 4,829 against
# 4,010: a high-order step across a kink (ARDC layer bases, aero table nodes) is rejected, retried up to it and
# regrown (a dispersed density profile, a polyline through its nodes until issue 29, cost it 1.4-1.8x DOPRI5's)
INTEGRATOR_DOP853 = 1.0
INTEGRATOR_IDS = {"dopri5": INTEGRATOR_DOPRI5, "dop853": INTEGRATOR_DOP853}  # contracts' integrator.method

# --- mode layout ---
M_BANK_ACTIVE = 0
M_BANK_DONE = 1
M_LATCHED = 2  # level-flight / gamma-hold alpha has reached (L/D)max: fly (L/D)max from here
M_PULLED_OUT = 3
M_REF_ANGLE = 4  # steering angle (deg) the turn so far is counted from: the bank law's start, then each step's
M_HOLD_ALT = 5  # ft, altitude at pull-out (held by the constant-altitude law)
M_PULLOUT_T = 6
M_PULLOUT_ALT = 7
M_TURN_DONE_DEG = 8  # heading change (steering angle) when a staged / constant-altitude turn ended
M_TURNED_DEG = 9  # the steering angle's change since the bank law's start, to M_REF_ANGLE, unwrapped step by step
M_SIZE = 10

# --- evaluate's outputs (a tuple: numba returns it without allocating) ---
EV_AX, EV_AY, EV_AZ = 0, 1, 2  # ft/s^2, d/dt of the earth-relative velocity in the earth-fixed frame
EV_ALPHA_DEG = 3
EV_BANK_DEG = 4
EV_MACH = 5
EV_Q_PSF = 6  # dynamic pressure, lb/ft^2
EV_CL = 7
EV_CD = 8
EV_ALTITUDE_FT = 9
EV_SPEED_FPS = 10  # earth-relative
EV_SIN_GAMMA = 11
EV_STEER_DEG = 12  # the angle the heading laws steer on (controls.steering_angle_deg)
EV_NEED_RATIO = 13  # lift needed over lift available (the holds, the constant-altitude turn; else 0)
EV_RHO_SLUG_FT3 = 14


@njit
def energy_height_ft(altitude_ft: float, speed_fps: float, g0_ft_s2: float) -> float:
    """Specific energy over g0, h + V^2/(2 g0) (ft): the energy abscissa of the control tables."""
    return altitude_ft + 0.5 * speed_fps * speed_fps / g0_ft_s2


@njit(allocates=False)
def holds_with_alpha(ctrl: NDArray[np.float64], mode: NDArray[np.float64]) -> bool:
    """True while alpha, not (L/D)max, flies the commanded path: level flight or gamma hold after pull-out
    (Section II.7), and the constant-altitude law after its turn (App. C data set 2: the straight flight
    after roll-out holds the altitude with alpha until (L/D)max is reached)."""
    if mode[M_PULLED_OUT] == 0.0:
        return False
    law = int(ctrl[C_ALPHA_LAW])
    if law == ALPHA_LEVEL_FLIGHT or law == ALPHA_GAMMA_HOLD:
        return True
    return int(ctrl[C_BANK_LAW]) == BANK_CONSTANT_ALTITUDE and mode[M_BANK_DONE] != 0.0


@njit(allocates=False)
def _zeta_deg(ux: float, uy: float, uz: float, hx: float, hy: float, hz: float, p: NDArray[np.float64]) -> float:
    """Remaining heading change (deg) of the horizontal velocity h at the unit position u: the angle, clockwise seen
    from above, from the left pole of the initial great circle projected on the local horizontal plane to h."""
    px, py, pz = p[P_POLE_X], p[P_POLE_Y], p[P_POLE_Z]
    pu = px * ux + py * uy + pz * uz
    cx, cy, cz = px - pu * ux, py - pu * uy, pz - pu * uz
    # the direction 90 deg clockwise of c seen from above: c x up
    dx, dy, dz = cy * uz - cz * uy, cz * ux - cx * uz, cx * uy - cy * ux
    return math.degrees(math.atan2(hx * dx + hy * dy + hz * dz, hx * cx + hy * cy + hz * cz))


@njit(allocates=False)
def steering_angles(
    x: float, y: float, z: float, vx: float, vy: float, vz: float, p: NDArray[np.float64]
) -> tuple[float, float]:
    """(zeta, heading) in degrees: remaining heading change and azimuth of the horizontal velocity."""
    ux, uy, uz, nx, ny, nz, ex, ey, ez = horizon_basis(x, y, z)
    vu = vx * ux + vy * uy + vz * uz
    hx, hy, hz = vx - vu * ux, vy - vu * uy, vz - vu * uz
    heading = math.degrees(math.atan2(hx * ex + hy * ey + hz * ez, hx * nx + hy * ny + hz * nz))
    return _zeta_deg(ux, uy, uz, hx, hy, hz, p), heading


@njit(allocates=False)
def _steer_deg(
    ux: float,
    uy: float,
    uz: float,
    vx: float,
    vy: float,
    vz: float,
    p: NDArray[np.float64],
    ctrl: NDArray[np.float64],
) -> float:
    """steering_angle_deg of steering_angles at the unit position u (the right-hand side has it), computing only
    the angle the law steers on."""
    vu = vx * ux + vy * uy + vz * uz
    hx, hy, hz = vx - vu * ux, vy - vu * uy, vz - vu * uz
    if ctrl[C_BANK_VAR] == VAR_ZETA:
        return steering_angle_deg(ctrl, _zeta_deg(ux, uy, uz, hx, hy, hz, p), math.nan)
    _, _, _, nx, ny, nz, ex, ey, ez = horizon_basis(ux, uy, uz)
    heading = math.degrees(math.atan2(hx * ex + hy * ey + hz * ez, hx * nx + hy * ny + hz * nz))
    return steering_angle_deg(ctrl, math.nan, heading)


@njit(allocates=False)
def flown_coefficients(
    aero: NDArray[np.float64], p: NDArray[np.float64], mach: float, alpha_deg: float, altitude_ft: float
) -> tuple[float, float]:
    """(CL, CD) of the vehicle flown: the aero table's times the dispersion multipliers (exactly 1.0 undispersed).
    Multiplying the whole curves leaves the alphas of (L/D)max, CL max and zero lift those of the tables."""
    cl, cd = _aero.coefficients(aero, mach, alpha_deg, altitude_ft)
    return cl * p[P_CL_MULTIPLIER], cd * p[P_CD_MULTIPLIER]


@njit(allocates=False)
def evaluate(
    t: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
) -> tuple[float, ...]:
    """Accelerations and every derived quantity at one state, in the slots EV_* above."""
    x, y, z, vx, vy, vz = s[0], s[1], s[2], s[3], s[4], s[5]
    omega = p[P_OMEGA]
    alt = altitude_ft(x, y, z, p[P_RE], p[P_RP], p[P_OBLATE] != 0.0)
    rho, _, _, sound = atmosphere(int(p[P_ATM]), alt, p[P_RHO0], p[P_SCALE_H], p[P_ATM_T])
    if p[P_DENSITY_DISPERSED] != 0.0:
        rho *= density_factor(p, P_DENSITY_PROFILE, alt)
    r = math.sqrt(x * x + y * y + z * z)
    v = math.sqrt(vx * vx + vy * vy + vz * vz)
    mach = v / sound
    q = 0.5 * rho * v * v  # dynamic pressure on the earth-relative speed (the air turns with the earth)
    ivr = 1.0 / r
    ux, uy, uz = x * ivr, y * ivr, z * ivr
    # non-aerodynamic accelerations: gravity (A10) and, from eqs. (1)-(2), Coriolis and centrifugal terms
    # gravity from the position itself (sharing r and the unit vector moved it by round-off, and the widest
    # constant-altitude turn of data set 2 at 25,800 ft/s, a knife edge, from 179 to 65 deg)
    gx, gy, gz = gravity_ecef(x, y, z, p[P_MU], p[P_RE], p[P_J], p[P_H], p[P_K], p[P_OBLATE] != 0.0)
    a0x = gx + 2.0 * omega * vy + omega * omega * x
    a0y = gy - 2.0 * omega * vx + omega * omega * y
    a0z = gz
    # wind axes: v_hat; left = r_hat x v_hat; lift_up = v_hat x left (in the vertical plane, above v)
    iv = 1.0 / v
    wx, wy, wz = vx * iv, vy * iv, vz * iv
    sin_gamma = ux * wx + uy * wy + uz * wz
    lx, ly, lz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
    ln = math.sqrt(lx * lx + ly * ly + lz * lz)
    if ln < 1e-12:  # vertical flight: any horizontal direction will do
        lx, ly, lz, ln = 0.0, 0.0, 1.0, 1.0
    iln = 1.0 / ln
    lx, ly, lz = lx * iln, ly * iln, lz * iln
    upx, upy, upz = wy * lz - wz * ly, wz * lx - wx * lz, wx * ly - wy * lx
    lift_per_cl = q * p[P_G0] / p[P_WS]  # L/m = CL q S / m = CL q g0 / (W/S)
    vert_needed = 0.0
    if int(ctrl[C_BANK_LAW]) == BANK_CONSTANT_ALTITUDE or holds_with_alpha(ctrl, mode):
        # vertical lift per unit mass that holds the commanded flight-path rate:
        # V dgamma/dt = a . up + V^2 cos(gamma) / r   (derived from sin(gamma) = v.r_hat / V)
        cos_gamma = math.sqrt(max(0.0, 1.0 - sin_gamma * sin_gamma))
        tau = ctrl[C_TAU]
        gamma = math.asin(sin_gamma)
        gamma_cmd = 0.0
        if int(ctrl[C_ALPHA_LAW]) == ALPHA_GAMMA_HOLD:
            gamma_cmd = math.radians(ctrl[C_GAMMA_DEG])
        if int(ctrl[C_BANK_LAW]) == BANK_CONSTANT_ALTITUDE:
            gamma_cmd = -(alt - mode[M_HOLD_ALT]) / (v * tau)  # Appendix C data set 2: hold the pull-out altitude
        vert_needed = v * (gamma_cmd - gamma) / tau - v * v * cos_gamma * ivr - (a0x * upx + a0y * upy + a0z * upz)

    steer = _steer_deg(ux, uy, uz, vx, vy, vz, p, ctrl)
    bank_law = int(ctrl[C_BANK_LAW])
    alpha_law = int(ctrl[C_ALPHA_LAW])
    pulled_out = mode[M_PULLED_OUT] != 0.0
    need_ratio = 0.0
    # --- angle of attack (Sections II.5, II.7; Appendix C) ---
    if bank_law == BANK_ZERO_LIFT:
        alpha = _aero.alpha_zero_lift_deg(aero, mach, alt)  # Section II.6 d: minimum down-range at zero lift
    elif alpha_law == ALPHA_CL_MAX:
        alpha = _aero.alpha_cl_max_deg(aero, mach, alt)
    elif alpha_law == ALPHA_CONSTANT:
        alpha = ctrl[C_ALPHA_DEG]
    elif alpha_law == ALPHA_TABLE_VELOCITY:
        alpha = table_interp(ctrl, ctrl[C_ALPHA_TABLE], v)
    elif alpha_law == ALPHA_TABLE_TIME:
        alpha = table_interp(ctrl, ctrl[C_ALPHA_TABLE], t)
    elif alpha_law == ALPHA_TABLE_ENERGY:
        alpha = table_interp(ctrl, ctrl[C_ALPHA_TABLE], energy_height_ft(alt, v, p[P_G0]))
    elif alpha_law == ALPHA_MAX_LD_FLOOR:  # heating-limited footprints (constrained.py): raised where hot
        alpha = max(_aero.alpha_max_ld_deg(aero, mach, alt), table_interp(ctrl, ctrl[C_ALPHA_TABLE], v))
    elif (alpha_law == ALPHA_LEVEL_FLIGHT or alpha_law == ALPHA_GAMMA_HOLD) and not pulled_out:
        if int(ctrl[C_ALPHA_BEFORE]) == ALPHA_CL_MAX:
            alpha = _aero.alpha_cl_max_deg(aero, mach, alt)
        else:
            alpha = _aero.alpha_max_ld_deg(aero, mach, alt)
    else:
        alpha = _aero.alpha_max_ld_deg(aero, mach, alt)
    # --- bank ---
    if bank_law == BANK_CONSTANT_ALTITUDE:
        cl_star, _ = flown_coefficients(aero, p, mach, alpha, alt)
        available = cl_star * lift_per_cl
        need_ratio = vert_needed / available if available > 0.0 else 2.0
        bank = 0.0
        if mode[M_BANK_ACTIVE] != 0.0 and mode[M_BANK_DONE] == 0.0 and need_ratio < 1.0:
            bank = math.degrees(math.acos(max(need_ratio, 0.0))) * ctrl[C_SIDE]
    else:
        table_x = bank_abscissa(ctrl, steer, t, v, energy_height_ft(alt, v, p[P_G0]))
        bank = bank_from_law(ctrl, mode[M_BANK_ACTIVE], mode[M_BANK_DONE], steer, table_x)
    if holds_with_alpha(ctrl, mode):
        # Section II.7: reduce lift so that lift plus centrifugal force balance weight, until (L/D)max
        cl_star, _ = flown_coefficients(aero, p, mach, alpha, alt)
        cos_bank = math.cos(math.radians(bank))
        cl_needed = vert_needed / (lift_per_cl * cos_bank) if lift_per_cl * cos_bank > 0.0 else cl_star
        need_ratio = cl_needed / cl_star if cl_star > 0.0 else 2.0
        if mode[M_LATCHED] == 0.0 and cl_needed < cl_star:
            alpha = _aero.alpha_for_cl_deg(aero, cl_needed / p[P_CL_MULTIPLIER], mach, alt, aero[1], alpha)
    cl, cd = flown_coefficients(aero, p, mach, alpha, alt)
    if bank_law == BANK_ZERO_LIFT:
        cl = 0.0
    # --- forces: App. A eqs. (A5)-(A9), lift along cos(bank) up + sin(bank) left, drag along -v ---
    lift = cl * lift_per_cl
    drag = cd * lift_per_cl
    cb, sb = math.cos(math.radians(bank)), math.sin(math.radians(bank))
    ax = a0x + lift * (cb * upx + sb * lx) - drag * wx
    ay = a0y + lift * (cb * upy + sb * ly) - drag * wy
    az = a0z + lift * (cb * upz + sb * lz) - drag * wz
    return (ax, ay, az, alpha, bank, mach, q, cl, cd, alt, v, sin_gamma, steer, need_ratio, rho)


@njit(allocates=False)
def rhs(
    t: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    """ds/dt into `out`: eqs. (1)-(3)."""
    res = evaluate(t, s, p, aero, ctrl, mode)
    out[0] = s[3]
    out[1] = s[4]
    out[2] = s[5]
    out[3] = res[EV_AX]
    out[4] = res[EV_AY]
    out[5] = res[EV_AZ]
