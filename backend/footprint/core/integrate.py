"""Adaptive Dormand-Prince 5(4) integration of the equations of motion with located events.

Hairer, Norsett & Wanner, Solving ODEs I (2nd ed.), Table 5.2 (coefficients) and the DOPRI5 code's
continuous extension (dense output of order 4), used to locate events. The step control is the usual
error-per-step rule with the error scaled by rtol times a characteristic size of each component
(the planet radius for positions, the entry speed for velocities), so it is not fooled by components
that cross zero.

Events (a function of state and mode crossing from negative to non-negative) change the control mode
or stop the flight. Nothing here raises: a flight ends with a stop code.
"""

import math

import numpy as np
from numpy.typing import NDArray

from footprint.core._jit import njit
from footprint.core.controls import (
    BANK_CONSTANT_ALTITUDE,
    BANK_STAGED,
    C_BANK_LAW,
    C_START,
    C_START_ALT,
    C_TURN,
    START_ALTITUDE,
    START_PULLOUT,
    wrap_deg,
)
from footprint.core.dynamics import (
    EV_ALPHA_DEG,
    EV_ALTITUDE_FT,
    EV_AX,
    EV_AY,
    EV_AZ,
    EV_BANK_DEG,
    EV_CD,
    EV_CL,
    EV_MACH,
    EV_NEED_RATIO,
    EV_Q_PSF,
    EV_SIN_GAMMA,
    EV_SPEED_FPS,
    EV_STEER_DEG,
    M_BANK_ACTIVE,
    M_BANK_DONE,
    M_HOLD_ALT,
    M_LATCHED,
    M_PULLED_OUT,
    M_PULLOUT_ALT,
    M_PULLOUT_T,
    M_REF_ANGLE,
    M_TURN_DONE_DEG,
    P_G0,
    P_MAX_STEP,
    P_RE,
    P_RTOL,
    P_SKIP_ALT,
    P_STOP_ALT,
    P_STOP_ENERGY,
    P_STOP_TIME,
    P_STOP_VEL,
    energy_height_ft,
    evaluate,
    holds_with_alpha,
)

# events
E_PULLOUT = 0
E_BANK_START = 1
E_TURN_DONE = 2
E_ALPHA_LATCH = 3
E_STOP_ALTITUDE = 4
E_STOP_VELOCITY = 5
E_STOP_TIME = 6
E_SKIP_OUT = 7
E_STOP_ENERGY = 8
N_EVENTS = 9

# stop codes
STOP_NONE = 0
STOP_ALTITUDE = 1
STOP_VELOCITY = 2
STOP_TIME = 3
STOP_SKIP_OUT = 4
STOP_MAX_STEPS = 5
STOP_STEP_UNDERFLOW = 6
STOP_ENERGY = 7
STOP_REASONS = ("none", "altitude", "velocity", "time", "skip_out", "max_steps", "step_underflow", "energy")

# recorded columns
R_T, R_X, R_Y, R_Z, R_VX, R_VY, R_VZ = 0, 1, 2, 3, 4, 5, 6
R_ALPHA, R_BANK, R_MACH, R_Q, R_CL, R_CD, R_ALT, R_V, R_SIN_GAMMA = 7, 8, 9, 10, 11, 12, 13, 14, 15
N_COLS = 16

# Dormand-Prince 5(4) tableau (Hairer et al., Table 5.2)
C2, C3, C4, C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = 9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0
A71, A73, A74, A75, A76 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
E1, E3, E4, E5, E6, E7 = 71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0
# dense output (DOPRI5 contd5)
D1, D3, D4 = -12715105075.0 / 11282082432.0, 87487479700.0 / 32700410799.0, -10690763975.0 / 1880347072.0
D5, D6, D7 = 701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0


@njit(allocates=False)
def _derivative(
    t: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    out: NDArray[np.float64],
) -> tuple[float, ...]:
    res = evaluate(t, s, p, aero, ctrl, mode)
    out[0], out[1], out[2] = s[3], s[4], s[5]
    out[3], out[4], out[5] = res[EV_AX], res[EV_AY], res[EV_AZ]
    return res


@njit(allocates=False)
def _event_values(
    t: float,
    s: NDArray[np.float64],
    res: tuple[float, ...],
    p: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    g: NDArray[np.float64],
) -> None:
    """Event functions; NaN where an event cannot happen in the present mode."""
    for i in range(N_EVENTS):
        g[i] = np.nan
    alt, v, sin_gamma = res[EV_ALTITUDE_FT], res[EV_SPEED_FPS], res[EV_SIN_GAMMA]
    steer, need_ratio = res[EV_STEER_DEG], res[EV_NEED_RATIO]
    if mode[M_PULLED_OUT] == 0.0:
        g[E_PULLOUT] = sin_gamma  # first gamma = 0 (Section II.2)
    if mode[M_BANK_ACTIVE] == 0.0 and int(ctrl[C_START]) == START_ALTITUDE:
        g[E_BANK_START] = ctrl[C_START_ALT] - alt
    law = int(ctrl[C_BANK_LAW])
    if (
        (law == BANK_STAGED or law == BANK_CONSTANT_ALTITUDE)
        and mode[M_BANK_ACTIVE] != 0.0
        and mode[M_BANK_DONE] == 0.0
    ):
        g[E_TURN_DONE] = abs(wrap_deg(steer - mode[M_REF_ANGLE])) - ctrl[C_TURN]
        if law == BANK_CONSTANT_ALTITUDE:
            # App. C data set 2: the turn also ends when the wings come level (no lift left to turn with)
            g[E_TURN_DONE] = max(g[E_TURN_DONE], need_ratio - 1.0)
    if holds_with_alpha(ctrl, mode) and mode[M_LATCHED] == 0.0:
        g[E_ALPHA_LATCH] = need_ratio - 1.0
    if not math.isnan(p[P_STOP_ALT]):
        g[E_STOP_ALTITUDE] = p[P_STOP_ALT] - alt
    if not math.isnan(p[P_STOP_VEL]):
        g[E_STOP_VELOCITY] = p[P_STOP_VEL] - v
    g[E_STOP_TIME] = t - p[P_STOP_TIME]
    g[E_SKIP_OUT] = alt - p[P_SKIP_ALT]
    if not math.isnan(p[P_STOP_ENERGY]):
        g[E_STOP_ENERGY] = p[P_STOP_ENERGY] - energy_height_ft(alt, v, p[P_G0])


@njit(allocates=False)
def _apply_event(
    event: int, t: float, res: tuple[float, ...], ctrl: NDArray[np.float64], mode: NDArray[np.float64]
) -> int:
    """Change the mode for a located event; return the stop code (STOP_NONE to go on)."""
    if event == E_PULLOUT:
        mode[M_PULLED_OUT] = 1.0
        mode[M_PULLOUT_T] = t
        mode[M_PULLOUT_ALT] = res[EV_ALTITUDE_FT]
        mode[M_HOLD_ALT] = res[EV_ALTITUDE_FT]
        if mode[M_BANK_ACTIVE] == 0.0 and int(ctrl[C_START]) == START_PULLOUT:
            mode[M_BANK_ACTIVE] = 1.0
            mode[M_REF_ANGLE] = res[EV_STEER_DEG]
    elif event == E_BANK_START:
        mode[M_BANK_ACTIVE] = 1.0
        mode[M_REF_ANGLE] = res[EV_STEER_DEG]
    elif event == E_TURN_DONE:
        mode[M_BANK_DONE] = 1.0
        mode[M_TURN_DONE_DEG] = abs(wrap_deg(res[EV_STEER_DEG] - mode[M_REF_ANGLE]))
    elif event == E_ALPHA_LATCH:
        mode[M_LATCHED] = 1.0
    elif event == E_STOP_ALTITUDE:
        return STOP_ALTITUDE
    elif event == E_STOP_VELOCITY:
        return STOP_VELOCITY
    elif event == E_STOP_TIME:
        return STOP_TIME
    elif event == E_SKIP_OUT:
        return STOP_SKIP_OUT
    elif event == E_STOP_ENERGY:
        return STOP_ENERGY
    return STOP_NONE


@njit(allocates=False)
def _dense(
    theta: float,
    y0: NDArray[np.float64],
    r2: NDArray[np.float64],
    r3: NDArray[np.float64],
    r4: NDArray[np.float64],
    r5: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    """DOPRI5 continuous extension at theta in [0, 1] of the last step."""
    t1 = 1.0 - theta
    for i in range(6):
        out[i] = y0[i] + theta * (r2[i] + t1 * (r3[i] + theta * (r4[i] + t1 * r5[i])))


@njit
def _record(
    rows: NDArray[np.float64], n: int, t: float, s: NDArray[np.float64], res: tuple[float, ...]
) -> NDArray[np.float64]:
    if n == rows.shape[0]:
        bigger = np.empty((2 * n, N_COLS))
        bigger[:n] = rows
        rows = bigger
    rows[n, R_T] = t
    for i in range(6):
        rows[n, R_X + i] = s[i]
    rows[n, R_ALPHA] = res[EV_ALPHA_DEG]
    rows[n, R_BANK] = res[EV_BANK_DEG]
    rows[n, R_MACH] = res[EV_MACH]
    rows[n, R_Q] = res[EV_Q_PSF]
    rows[n, R_CL] = res[EV_CL]
    rows[n, R_CD] = res[EV_CD]
    rows[n, R_ALT] = res[EV_ALTITUDE_FT]
    rows[n, R_V] = res[EV_SPEED_FPS]
    rows[n, R_SIN_GAMMA] = res[EV_SIN_GAMMA]
    return rows


@njit
def integrate(
    s0: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    max_steps: int,
    t0: float = 0.0,
) -> tuple[NDArray[np.float64], int, int]:
    """Fly from s0 at t0 (s) until a stop event. Returns (rows[:n], stop_code, n_rhs)."""
    rtol = p[P_RTOL]
    h_max = p[P_MAX_STEP]
    v0 = math.sqrt(s0[3] ** 2 + s0[4] ** 2 + s0[5] ** 2)
    scale = np.empty(6)
    for i in range(3):
        scale[i] = rtol * p[P_RE]
        scale[3 + i] = rtol * max(v0, 1000.0)
    k1, k2, k3, k4 = np.empty(6), np.empty(6), np.empty(6), np.empty(6)
    k5, k6, k7 = np.empty(6), np.empty(6), np.empty(6)
    ys, y1, ye = np.empty(6), np.empty(6), np.empty(6)
    r2, r3, r4, r5 = np.empty(6), np.empty(6), np.empty(6), np.empty(6)
    g0, g1, gt = np.empty(N_EVENTS), np.empty(N_EVENTS), np.empty(N_EVENTS)

    t = t0
    s = s0.copy()
    rows = np.empty((1024, N_COLS))
    res = _derivative(t, s, p, aero, ctrl, mode, k1)
    rows = _record(rows, 0, t, s, res)
    n = 1
    n_rhs = 1
    _event_values(t, s, res, p, ctrl, mode, g0)
    h = min(1.0, h_max)
    stop = STOP_NONE
    steps = 0
    while stop == STOP_NONE:
        steps += 1
        if steps > max_steps:
            stop = STOP_MAX_STEPS
            break
        if h < 1e-9:
            stop = STOP_STEP_UNDERFLOW
            break
        if t + h > p[P_STOP_TIME] > t:  # end the step on the stop time: no interpolated state at a guidance cycle
            h = p[P_STOP_TIME] - t
        for i in range(6):
            ys[i] = s[i] + h * A21 * k1[i]
        _derivative(t + C2 * h, ys, p, aero, ctrl, mode, k2)
        for i in range(6):
            ys[i] = s[i] + h * (A31 * k1[i] + A32 * k2[i])
        _derivative(t + C3 * h, ys, p, aero, ctrl, mode, k3)
        for i in range(6):
            ys[i] = s[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
        _derivative(t + C4 * h, ys, p, aero, ctrl, mode, k4)
        for i in range(6):
            ys[i] = s[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
        _derivative(t + C5 * h, ys, p, aero, ctrl, mode, k5)
        for i in range(6):
            ys[i] = s[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i])
        _derivative(t + h, ys, p, aero, ctrl, mode, k6)
        for i in range(6):
            y1[i] = s[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i])
        res1 = _derivative(t + h, y1, p, aero, ctrl, mode, k7)
        n_rhs += 6
        err = 0.0
        for i in range(6):
            e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i])
            err += (e / scale[i]) ** 2
        err = math.sqrt(err / 6.0)
        if not (err <= 1.0):  # also catches NaN
            h *= max(0.2, 0.9 * err**-0.2) if err == err else 0.2
            continue

        _event_values(t + h, y1, res1, p, ctrl, mode, g1)
        first = -1
        theta_first = 2.0
        for i in range(N_EVENTS):
            if g0[i] < 0.0 and g1[i] >= 0.0:  # NaN compares false: inactive events never fire
                if first == -1:  # dense-output coefficients, built once per step
                    for j in range(6):
                        r2[j] = y1[j] - s[j]
                        r3[j] = h * k1[j] - r2[j]
                        r4[j] = r2[j] - h * k7[j] - r3[j]
                        r5[j] = h * (D1 * k1[j] + D3 * k3[j] + D4 * k4[j] + D5 * k5[j] + D6 * k6[j] + D7 * k7[j])
                # Illinois regula falsi on [0, 1] for g_i(theta); the stop time's is exact (g linear in time)
                a, b, ga, gb = 0.0, 1.0, g0[i], g1[i]
                side = 0
                if i == E_STOP_TIME:
                    b = min(max((p[P_STOP_TIME] - t) / h, 0.0), 1.0)
                for _ in range(60 if i != E_STOP_TIME else 0):
                    c = (a * gb - b * ga) / (gb - ga)
                    _dense(c, s, r2, r3, r4, r5, ye)
                    rc = evaluate(t + c * h, ye, p, aero, ctrl, mode)
                    _event_values(t + c * h, ye, rc, p, ctrl, mode, gt)
                    n_rhs += 1
                    gc = gt[i]
                    if gc >= 0.0:
                        b, gb = c, gc
                        if side == 1:
                            ga *= 0.5
                        side = 1
                    else:
                        a, ga = c, gc
                        if side == -1:
                            gb *= 0.5
                        side = -1
                    if (b - a) * h < 1e-7:
                        break
                if b < theta_first:
                    theta_first = b
                    first = i
        if first >= 0:
            te = t + theta_first * h
            _dense(theta_first, s, r2, r3, r4, r5, ye)
            rese = evaluate(te, ye, p, aero, ctrl, mode)
            stop = _apply_event(first, te, rese, ctrl, mode)
            for j in range(6):
                s[j] = ye[j]
            t = te
            res = _derivative(t, s, p, aero, ctrl, mode, k1)  # the mode may have changed the forces
            n_rhs += 1
            rows = _record(rows, n, t, s, res)
            n += 1
            _event_values(t, s, res, p, ctrl, mode, g0)
            continue

        t += h
        for j in range(6):
            s[j] = y1[j]
            k1[j] = k7[j]
        for j in range(N_EVENTS):
            g0[j] = g1[j]
        rows = _record(rows, n, t, s, res1)
        n += 1
        h = min(h * min(5.0, max(0.2, 0.9 * err**-0.2)), h_max) if err > 0.0 else min(5.0 * h, h_max)
    return rows[:n], stop, n_rhs
