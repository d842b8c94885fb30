"""Adaptive explicit Runge-Kutta integration of the equations of motion with located events.

Two embedded pairs, chosen per flight by p[P_INTEGRATOR] (a case's integrator.method):
- DOPRI5 (the default): Dormand-Prince 5(4) (Hairer, Norsett & Wanner, Solving ODEs I, 2nd ed., Table 5.2) with
  the DOPRI5 code's continuous extension of order 4, 6 right-hand sides a step;
- DOP853 (dynamics.INTEGRATOR_DOP853): Dormand & Prince's 8(5,3) pair with its continuous extension of order 7
  (ibid., Sec. II.10, and Hairer's dop853.f), 12 right-hand sides a step; a rejected step across a kink of the
  right-hand side is retried up to the kink (_kink_fraction); each step recorded at DOP853_ROWS_PER_STEP points.
The step control is the usual error-per-step rule with the error scaled by rtol times a characteristic size of each
component (the planet radius for positions, the entry speed for velocities), so it is not fooled by components
that cross zero.

Events (a function of state and mode crossing from negative to non-negative) change the control mode
or stop the flight; they are located on the continuous extension. Nothing here raises: a flight ends with a stop
code.
"""

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from footprint.core import aero as _aero
from footprint.core._jit import njit
from footprint.core.atmosphere import density_kink_between_ft, kink_between_ft
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
    INTEGRATOR_DOP853,
    M_BANK_ACTIVE,
    M_BANK_DONE,
    M_HOLD_ALT,
    M_LATCHED,
    M_PULLED_OUT,
    M_PULLOUT_ALT,
    M_PULLOUT_T,
    M_REF_ANGLE,
    M_TURN_DONE_DEG,
    M_TURNED_DEG,
    P_ATM,
    P_DENSITY_DISPERSED,
    P_DENSITY_PROFILE,
    P_G0,
    P_INTEGRATOR,
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
STOP_ASKED = 8  # a loop's asks_stop said stop (core._jit): a guided flight raises errors.Stopped on it
STOP_REASONS = ("none", "altitude", "velocity", "time", "skip_out", "max_steps", "step_underflow", "energy", "stopped")

# recorded columns
R_T, R_X, R_Y, R_Z, R_VX, R_VY, R_VZ = 0, 1, 2, 3, 4, 5, 6
R_ALPHA, R_BANK, R_MACH, R_Q, R_CL, R_CD, R_ALT, R_V, R_SIN_GAMMA = 7, 8, 9, 10, 11, 12, 13, 14, 15
R_INTERIOR = 16  # 1.0: a row inside a DOP853 step (DOP853_ROWS_PER_STEP); 0.0: a step's end or an event
N_COLS = 17

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

# DOP853 (Hairer, Norsett & Wanner, Solving ODEs I, 2nd ed., Sec. II.10): the coefficients of Hairer's dop853.f
# (unige.ch/~hairer/software.html), as scipy.integrate's DOP853 also carries them. Stages 0-11 make the step,
# stage 12 is f(t + h, y1) (the next step's first), stages 13-15 only the continuous extension (order 7).
DOP853_STAGES = 12
DOP853_STAGES_DENSE = 16
DOP853_DENSE_ROWS = 4  # rows of D; the interpolant has 3 more, from y0, y1, f(t) and f(t + h)
DOP853_C: NDArray[np.float64] = np.array(
    [
        0.0,
        0.05260015195876773,
        0.0789002279381516,
        0.1183503419072274,
        0.2816496580927726,
        0.3333333333333333,
        0.25,
        0.3076923076923077,
        0.6512820512820513,
        0.6,
        0.8571428571428571,
        1.0,
        1.0,
        0.1,
        0.2,
        0.7777777777777778,
    ]
)
_DOP853_A_ROWS: dict[int, dict[int, float]] = {
    1: {0: 5.26001519587677318785587544488e-2},
    2: {0: 1.97250569845378994544595329183e-2, 1: 5.91751709536136983633785987549e-2},
    3: {0: 2.95875854768068491816892993775e-2, 2: 8.87627564304205475450678981324e-2},
    4: {
        0: 2.41365134159266685502369798665e-1,
        2: -8.84549479328286085344864962717e-1,
        3: 9.24834003261792003115737966543e-1,
    },
    5: {
        0: 3.7037037037037037037037037037e-2,
        3: 1.70828608729473871279604482173e-1,
        4: 1.25467687566822425016691814123e-1,
    },
    6: {
        0: 3.7109375e-2,
        3: 1.70252211019544039314978060272e-1,
        4: 6.02165389804559606850219397283e-2,
        5: -1.7578125e-2,
    },
    7: {
        0: 3.70920001185047927108779319836e-2,
        3: 1.70383925712239993810214054705e-1,
        4: 1.07262030446373284651809199168e-1,
        5: -1.53194377486244017527936158236e-2,
        6: 8.27378916381402288758473766002e-3,
    },
    8: {
        0: 6.24110958716075717114429577812e-1,
        3: -3.36089262944694129406857109825,
        4: -8.68219346841726006818189891453e-1,
        5: 2.75920996994467083049415600797e1,
        6: 2.01540675504778934086186788979e1,
        7: -4.34898841810699588477366255144e1,
    },
    9: {
        0: 4.77662536438264365890433908527e-1,
        3: -2.48811461997166764192642586468,
        4: -5.90290826836842996371446475743e-1,
        5: 2.12300514481811942347288949897e1,
        6: 1.52792336328824235832596922938e1,
        7: -3.32882109689848629194453265587e1,
        8: -2.03312017085086261358222928593e-2,
    },
    10: {
        0: -9.3714243008598732571704021658e-1,
        3: 5.18637242884406370830023853209,
        4: 1.09143734899672957818500254654,
        5: -8.14978701074692612513997267357,
        6: -1.85200656599969598641566180701e1,
        7: 2.27394870993505042818970056734e1,
        8: 2.49360555267965238987089396762,
        9: -3.0467644718982195003823669022,
    },
    11: {
        0: 2.27331014751653820792359768449,
        3: -1.05344954667372501984066689879e1,
        4: -2.00087205822486249909675718444,
        5: -1.79589318631187989172765950534e1,
        6: 2.79488845294199600508499808837e1,
        7: -2.85899827713502369474065508674,
        8: -8.87285693353062954433549289258,
        9: 1.23605671757943030647266201528e1,
        10: 6.43392746015763530355970484046e-1,
    },
    12: {  # the weights b of the 8th-order solution
        0: 5.42937341165687622380535766363e-2,
        5: 4.45031289275240888144113950566,
        6: 1.89151789931450038304281599044,
        7: -5.8012039600105847814672114227,
        8: 3.1116436695781989440891606237e-1,
        9: -1.52160949662516078556178806805e-1,
        10: 2.01365400804030348374776537501e-1,
        11: 4.47106157277725905176885569043e-2,
    },
    13: {
        0: 5.61675022830479523392909219681e-2,
        6: 2.53500210216624811088794765333e-1,
        7: -2.46239037470802489917441475441e-1,
        8: -1.24191423263816360469010140626e-1,
        9: 1.5329179827876569731206322685e-1,
        10: 8.20105229563468988491666602057e-3,
        11: 7.56789766054569976138603589584e-3,
        12: -8.298e-3,
    },
    14: {
        0: 3.18346481635021405060768473261e-2,
        5: 2.83009096723667755288322961402e-2,
        6: 5.35419883074385676223797384372e-2,
        7: -5.49237485713909884646569340306e-2,
        10: -1.08347328697249322858509316994e-4,
        11: 3.82571090835658412954920192323e-4,
        12: -3.40465008687404560802977114492e-4,
        13: 1.41312443674632500278074618366e-1,
    },
    15: {
        0: -4.28896301583791923408573538692e-1,
        5: -4.69762141536116384314449447206,
        6: 7.68342119606259904184240953878,
        7: 4.06898981839711007970213554331,
        8: 3.56727187455281109270669543021e-1,
        12: -1.39902416515901462129418009734e-3,
        13: 2.9475147891527723389556272149,
        14: -9.15095847217987001081870187138,
    },
}
# the 5th- and 3rd-order error estimates (dop853.f's ER and BHH; E3 = b - bhh), on stages 0-11
_DOP853_E5: dict[int, float] = {
    0: 0.1312004499419488073250102996e-1,
    5: -0.1225156446376204440720569753e1,
    6: -0.4957589496572501915214079952,
    7: 0.1664377182454986536961530415e1,
    8: -0.3503288487499736816886487290,
    9: 0.3341791187130174790297318841,
    10: 0.8192320648511571246570742613e-1,
    11: -0.2235530786388629525884427845e-1,
}
_DOP853_BHH: dict[int, float] = {
    0: 0.244094488188976377952755905512,
    8: 0.733846688281611857341361741547,
    11: 0.220588235294117647058823529412e-1,
}
# the continuous extension's rows 4-7 (dop853.f's D4j-D7j), on stages 0-15
_DOP853_D_ROWS: tuple[dict[int, float], ...] = (
    {
        0: -0.84289382761090128651353491142e1,
        5: 0.56671495351937776962531783590,
        6: -0.30689499459498916912797304727e1,
        7: 0.23846676565120698287728149680e1,
        8: 0.21170345824450282767155149946e1,
        9: -0.87139158377797299206789907490,
        10: 0.22404374302607882758541771650e1,
        11: 0.63157877876946881815570249290,
        12: -0.88990336451333310820698117400e-1,
        13: 0.18148505520854727256656404962e2,
        14: -0.91946323924783554000451984436e1,
        15: -0.44360363875948939664310572000e1,
    },
    {
        0: 0.10427508642579134603413151009e2,
        5: 0.24228349177525818288430175319e3,
        6: 0.16520045171727028198505394887e3,
        7: -0.37454675472269020279518312152e3,
        8: -0.22113666853125306036270938578e2,
        9: 0.77334326684722638389603898808e1,
        10: -0.30674084731089398182061213626e2,
        11: -0.93321305264302278729567221706e1,
        12: 0.15697238121770843886131091075e2,
        13: -0.31139403219565177677282850411e2,
        14: -0.93529243588444783865713862664e1,
        15: 0.35816841486394083752465898540e2,
    },
    {
        0: 0.19985053242002433820987653617e2,
        5: -0.38703730874935176555105901742e3,
        6: -0.18917813819516756882830838328e3,
        7: 0.52780815920542364900561016686e3,
        8: -0.11573902539959630126141871134e2,
        9: 0.68812326946963000169666922661e1,
        10: -0.10006050966910838403183860980e1,
        11: 0.77771377980534432092869265740,
        12: -0.27782057523535084065932004339e1,
        13: -0.60196695231264120758267380846e2,
        14: 0.84320405506677161018159903784e2,
        15: 0.11992291136182789328035130030e2,
    },
    {
        0: -0.25693933462703749003312586129e2,
        5: -0.15418974869023643374053993627e3,
        6: -0.23152937917604549567536039109e3,
        7: 0.35763911791061412378285349910e3,
        8: 0.93405324183624310003907691704e2,
        9: -0.37458323136451633156875139351e2,
        10: 0.10409964950896230045147246184e3,
        11: 0.29840293426660503123344363579e2,
        12: -0.43533456590011143754432175058e2,
        13: 0.96324553959188282948394950600e2,
        14: -0.39177261675615439165231486172e2,
        15: -0.14972683625798562581422125276e3,
    },
)


def _dense_table(rows: Sequence[dict[int, float]], columns: int) -> NDArray[np.float64]:
    table = np.zeros((len(rows), columns))
    for i, row in enumerate(rows):
        for j, value in row.items():
            table[i, j] = value
    return table


DOP853_A = _dense_table([_DOP853_A_ROWS.get(i, {}) for i in range(DOP853_STAGES_DENSE)], DOP853_STAGES_DENSE)
DOP853_E5 = _dense_table([_DOP853_E5], DOP853_STAGES)[0]
DOP853_E3 = DOP853_A[DOP853_STAGES, :DOP853_STAGES] - _dense_table([_DOP853_BHH], DOP853_STAGES)[0]
DOP853_D = _dense_table(_DOP853_D_ROWS, DOP853_STAGES_DENSE)
# Where the step size is capped by the flight's max_step_s (above the atmosphere; an orbit flown for hours), the error
# is far below the tolerance and a DOP853 step buys nothing that a DOPRI5 step of the same length (half the
# right-hand sides) does not: a step whose error would allow DOPRI5_CAPPED_STEP times max_step_s or more is
# followed by DOPRI5 steps, each with its own error control, until one would not (both end in f(t + h, y1)).
DOPRI5_CAPPED_STEP = 2.0
# a rejected DOP853 step that crosses a kink of the right-hand side is retried up to the kink (_kink_fraction) when
# that shortens it to less than KINK_MAX_FRACTION of itself, and to no less than KINK_MIN_STEP_S
KINK_MAX_FRACTION = 0.98
KINK_MIN_STEP_S = 1e-3
# A DOP853 step is about three DOPRI5 steps long: it is recorded at DOP853_ROWS_PER_STEP evenly spaced points (its end
# and the points inside), so that the histories keep the density DOPRI5's had, and trajectory._summary reads the maxima
# (parabola through the largest row) and the heat load (Simpson's 3/8 rule a step) off them within ~1e-5 of a converged
# flight's (core.sampled). An interior row of an accepted step is
# the quintic Hermite interpolant through the step's ends (state and acceleration at both, no right-hand side more:
# error of order h^6 in position, h^5 in velocity, far below what the rows are read for); of a step cut at an event,
# the continuous extension of order 7 that located it. Each interior row costs one evaluate (its alpha, q, Mach...).
DOP853_ROWS_PER_STEP = 3


def _hermite_weights(rows_per_step: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Weights of (x0, h v0, h^2 a0, h^2 a1, h v1, x1) in the quintic Hermite interpolant at theta = j / rows_per_step
    (j = 1 .. rows_per_step - 1), and in h times its derivative (the velocity)."""
    theta = np.arange(1, rows_per_step) / rows_per_step
    t2, t3, t4, t5 = theta**2, theta**3, theta**4, theta**5
    value = np.stack(
        [
            1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5,
            theta - 6.0 * t3 + 8.0 * t4 - 3.0 * t5,
            0.5 * t2 - 1.5 * t3 + 1.5 * t4 - 0.5 * t5,
            0.5 * t3 - t4 + 0.5 * t5,
            -4.0 * t3 + 7.0 * t4 - 3.0 * t5,
            10.0 * t3 - 15.0 * t4 + 6.0 * t5,
        ],
        axis=1,
    )
    slope = np.stack(
        [
            -30.0 * t2 + 60.0 * t3 - 30.0 * t4,
            1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4,
            theta - 4.5 * t2 + 6.0 * t3 - 2.5 * t4,
            1.5 * t2 - 4.0 * t3 + 2.5 * t4,
            -12.0 * t2 + 28.0 * t3 - 15.0 * t4,
            30.0 * t2 - 60.0 * t3 + 30.0 * t4,
        ],
        axis=1,
    )
    return value, slope


HERMITE_VALUE, HERMITE_SLOPE = _hermite_weights(DOP853_ROWS_PER_STEP)


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
        g[E_TURN_DONE] = abs(_turned_deg(steer, mode)) - ctrl[C_TURN]
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
def _turned_deg(steer: float, mode: NDArray[np.float64]) -> float:
    """The steering angle's change since the bank law's start, unwrapped: the turn counted to the last step's start
    and the change since (less than 180 deg within a step). A turn measured by the wrapped difference from its start
    alone passed 179 deg unseen when a step went from under 179 to past 181 deg (|wrap| only exceeds 179 between)."""
    turned: float = mode[M_TURNED_DEG] + wrap_deg(steer - mode[M_REF_ANGLE])  # typed: numpy's item is Any
    return turned


@njit(allocates=False)
def _advance_turn(steer: float, mode: NDArray[np.float64]) -> None:
    """Count the turn to a step's end (or an event): its reference becomes the steering angle there."""
    if mode[M_BANK_ACTIVE] != 0.0 and mode[M_BANK_DONE] == 0.0:
        mode[M_TURNED_DEG] = _turned_deg(steer, mode)
        mode[M_REF_ANGLE] = steer


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
            mode[M_REF_ANGLE], mode[M_TURNED_DEG] = res[EV_STEER_DEG], 0.0
    elif event == E_BANK_START:
        mode[M_BANK_ACTIVE] = 1.0
        mode[M_REF_ANGLE], mode[M_TURNED_DEG] = res[EV_STEER_DEG], 0.0
    elif event == E_TURN_DONE:
        mode[M_BANK_DONE] = 1.0
        mode[M_TURN_DONE_DEG] = abs(_turned_deg(res[EV_STEER_DEG], mode))
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
def _stage(
    t: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    k: NDArray[np.float64],
    row: int,
) -> tuple[float, ...]:
    """ds/dt at (t, s) into k[row]; returns evaluate's outputs."""
    res = evaluate(t, s, p, aero, ctrl, mode)
    k[row, 0], k[row, 1], k[row, 2] = s[3], s[4], s[5]
    k[row, 3], k[row, 4], k[row, 5] = res[EV_AX], res[EV_AY], res[EV_AZ]
    return res


@njit(allocates=False)
def _dopri5_step(
    t: float,
    h: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    k: NDArray[np.float64],
    ys: NDArray[np.float64],
    y1: NDArray[np.float64],
    scale: NDArray[np.float64],
) -> tuple[float, tuple[float, ...]]:
    """One DOPRI5 step from (t, s) with k[0] = f(t, s): y1, k[1..6], (rms scaled error, evaluate at y1)."""
    for i in range(6):
        ys[i] = s[i] + h * A21 * k[0, i]
    _stage(t + C2 * h, ys, p, aero, ctrl, mode, k, 1)
    for i in range(6):
        ys[i] = s[i] + h * (A31 * k[0, i] + A32 * k[1, i])
    _stage(t + C3 * h, ys, p, aero, ctrl, mode, k, 2)
    for i in range(6):
        ys[i] = s[i] + h * (A41 * k[0, i] + A42 * k[1, i] + A43 * k[2, i])
    _stage(t + C4 * h, ys, p, aero, ctrl, mode, k, 3)
    for i in range(6):
        ys[i] = s[i] + h * (A51 * k[0, i] + A52 * k[1, i] + A53 * k[2, i] + A54 * k[3, i])
    _stage(t + C5 * h, ys, p, aero, ctrl, mode, k, 4)
    for i in range(6):
        ys[i] = s[i] + h * (A61 * k[0, i] + A62 * k[1, i] + A63 * k[2, i] + A64 * k[3, i] + A65 * k[4, i])
    _stage(t + h, ys, p, aero, ctrl, mode, k, 5)
    for i in range(6):
        y1[i] = s[i] + h * (A71 * k[0, i] + A73 * k[2, i] + A74 * k[3, i] + A75 * k[4, i] + A76 * k[5, i])
    res1 = _stage(t + h, y1, p, aero, ctrl, mode, k, 6)
    err = 0.0
    for i in range(6):
        e = h * (E1 * k[0, i] + E3 * k[2, i] + E4 * k[3, i] + E5 * k[4, i] + E6 * k[5, i] + E7 * k[6, i])
        err += (e / scale[i]) ** 2
    return math.sqrt(err / 6.0), res1


@njit(allocates=False)
def _dop853_step(
    t: float,
    h: float,
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    k: NDArray[np.float64],
    ys: NDArray[np.float64],
    y1: NDArray[np.float64],
    scale: NDArray[np.float64],
) -> tuple[float, tuple[float, ...]]:
    """Stages 2-12 of one DOP853 step from (t, s) with k[0] = f(t, s): y1, k[1..11], and (dop853.f's scaled error,
    its 5th- and 3rd-order estimates combined; evaluate at the last stage, at t + h). f(t + h, y1) is left to the
    caller, for accepted steps only."""
    # the stages written out, their coefficients constants to the compiler (a loop over the table costs 10 %)
    for i in range(6):
        ys[i] = s[i] + h * (DOP853_A[1, 0] * k[0, i])
    _stage(t + DOP853_C[1] * h, ys, p, aero, ctrl, mode, k, 1)
    for i in range(6):
        ys[i] = s[i] + h * (DOP853_A[2, 0] * k[0, i] + DOP853_A[2, 1] * k[1, i])
    _stage(t + DOP853_C[2] * h, ys, p, aero, ctrl, mode, k, 2)
    for i in range(6):
        ys[i] = s[i] + h * (DOP853_A[3, 0] * k[0, i] + DOP853_A[3, 2] * k[2, i])
    _stage(t + DOP853_C[3] * h, ys, p, aero, ctrl, mode, k, 3)
    for i in range(6):
        ys[i] = s[i] + h * (DOP853_A[4, 0] * k[0, i] + DOP853_A[4, 2] * k[2, i] + DOP853_A[4, 3] * k[3, i])
    _stage(t + DOP853_C[4] * h, ys, p, aero, ctrl, mode, k, 4)
    for i in range(6):
        ys[i] = s[i] + h * (DOP853_A[5, 0] * k[0, i] + DOP853_A[5, 3] * k[3, i] + DOP853_A[5, 4] * k[4, i])
    _stage(t + DOP853_C[5] * h, ys, p, aero, ctrl, mode, k, 5)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[6, 0] * k[0, i] + DOP853_A[6, 3] * k[3, i] + DOP853_A[6, 4] * k[4, i] + DOP853_A[6, 5] * k[5, i]
        )
    _stage(t + DOP853_C[6] * h, ys, p, aero, ctrl, mode, k, 6)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[7, 0] * k[0, i]
            + DOP853_A[7, 3] * k[3, i]
            + DOP853_A[7, 4] * k[4, i]
            + DOP853_A[7, 5] * k[5, i]
            + DOP853_A[7, 6] * k[6, i]
        )
    _stage(t + DOP853_C[7] * h, ys, p, aero, ctrl, mode, k, 7)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[8, 0] * k[0, i]
            + DOP853_A[8, 3] * k[3, i]
            + DOP853_A[8, 4] * k[4, i]
            + DOP853_A[8, 5] * k[5, i]
            + DOP853_A[8, 6] * k[6, i]
            + DOP853_A[8, 7] * k[7, i]
        )
    _stage(t + DOP853_C[8] * h, ys, p, aero, ctrl, mode, k, 8)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[9, 0] * k[0, i]
            + DOP853_A[9, 3] * k[3, i]
            + DOP853_A[9, 4] * k[4, i]
            + DOP853_A[9, 5] * k[5, i]
            + DOP853_A[9, 6] * k[6, i]
            + DOP853_A[9, 7] * k[7, i]
            + DOP853_A[9, 8] * k[8, i]
        )
    _stage(t + DOP853_C[9] * h, ys, p, aero, ctrl, mode, k, 9)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[10, 0] * k[0, i]
            + DOP853_A[10, 3] * k[3, i]
            + DOP853_A[10, 4] * k[4, i]
            + DOP853_A[10, 5] * k[5, i]
            + DOP853_A[10, 6] * k[6, i]
            + DOP853_A[10, 7] * k[7, i]
            + DOP853_A[10, 8] * k[8, i]
            + DOP853_A[10, 9] * k[9, i]
        )
    _stage(t + DOP853_C[10] * h, ys, p, aero, ctrl, mode, k, 10)
    for i in range(6):
        ys[i] = s[i] + h * (
            DOP853_A[11, 0] * k[0, i]
            + DOP853_A[11, 3] * k[3, i]
            + DOP853_A[11, 4] * k[4, i]
            + DOP853_A[11, 5] * k[5, i]
            + DOP853_A[11, 6] * k[6, i]
            + DOP853_A[11, 7] * k[7, i]
            + DOP853_A[11, 8] * k[8, i]
            + DOP853_A[11, 9] * k[9, i]
            + DOP853_A[11, 10] * k[10, i]
        )
    res_end = _stage(t + h, ys, p, aero, ctrl, mode, k, 11)
    err5 = 0.0
    err3 = 0.0
    for i in range(6):
        y1[i] = s[i] + h * (
            DOP853_A[12, 0] * k[0, i]
            + DOP853_A[12, 5] * k[5, i]
            + DOP853_A[12, 6] * k[6, i]
            + DOP853_A[12, 7] * k[7, i]
            + DOP853_A[12, 8] * k[8, i]
            + DOP853_A[12, 9] * k[9, i]
            + DOP853_A[12, 10] * k[10, i]
            + DOP853_A[12, 11] * k[11, i]
        )
        err5 += (
            (
                DOP853_E5[0] * k[0, i]
                + DOP853_E5[5] * k[5, i]
                + DOP853_E5[6] * k[6, i]
                + DOP853_E5[7] * k[7, i]
                + DOP853_E5[8] * k[8, i]
                + DOP853_E5[9] * k[9, i]
                + DOP853_E5[10] * k[10, i]
                + DOP853_E5[11] * k[11, i]
            )
            / scale[i]
        ) ** 2
        err3 += (
            (
                DOP853_E3[0] * k[0, i]
                + DOP853_E3[5] * k[5, i]
                + DOP853_E3[6] * k[6, i]
                + DOP853_E3[7] * k[7, i]
                + DOP853_E3[8] * k[8, i]
                + DOP853_E3[9] * k[9, i]
                + DOP853_E3[10] * k[10, i]
                + DOP853_E3[11] * k[11, i]
            )
            / scale[i]
        ) ** 2
    deno = err5 + 0.01 * err3
    if not deno > 0.0:
        return (0.0 if deno == 0.0 else math.nan), res_end
    return abs(h) * err5 / math.sqrt(6.0 * deno), res_end


@njit(allocates=False)
def _altitude_fraction(alt0: float, alt1: float, rate0: float, rate1: float, target: float) -> float:
    """theta in [0, 1] where the cubic Hermite altitude through (alt0, rate0) at 0 and (alt1, rate1) at 1 reaches
    target (rates in ft per unit theta): Newton's method from the straight line's crossing."""
    theta = (target - alt0) / (alt1 - alt0)
    for _ in range(4):
        t2 = theta * theta
        t3 = t2 * theta
        value = (
            (2.0 * t3 - 3.0 * t2 + 1.0) * alt0
            + (t3 - 2.0 * t2 + theta) * rate0
            + (-2.0 * t3 + 3.0 * t2) * alt1
            + (t3 - t2) * rate1
        )
        slope = (
            (6.0 * t2 - 6.0 * theta) * (alt0 - alt1)
            + (3.0 * t2 - 4.0 * theta + 1.0) * rate0
            + (3.0 * t2 - 2.0 * theta) * rate1
        )
        if not slope != 0.0:
            break
        theta = min(max(theta - (value - target) / slope, 0.0), 1.0)
    return theta


@njit(allocates=False)
def _kink_fraction(
    res0: tuple[float, ...], res1: tuple[float, ...], h: float, p: NDArray[np.float64], aero: NDArray[np.float64]
) -> float:
    """Where in a step (theta in (0, 1), 2.0 if nowhere) the flight first crosses an altitude or Mach number at
    which the right-hand side has a kink (atmosphere layer bases, dispersed-density nodes, aero table and grid
    nodes; atmosphere.kink_between_ft, aero.kink_between). res0, res1: evaluate at the step's ends. A step across
    a kink has an error of order h^2 whatever the method's order: ending the rejected step there, and starting the
    next one there, replaces the string of ever shorter rejected steps that the error control would otherwise try.
    """
    alt0, alt1 = res0[EV_ALTITUDE_FT], res1[EV_ALTITUDE_FT]
    rate0 = h * res0[EV_SPEED_FPS] * res0[EV_SIN_GAMMA]  # d(altitude)/d(theta), to the oblateness
    rate1 = h * res1[EV_SPEED_FPS] * res1[EV_SIN_GAMMA]
    first = 2.0
    for z in (
        kink_between_ft(int(p[P_ATM]), alt0, alt1),
        density_kink_between_ft(p, P_DENSITY_PROFILE, alt0, alt1) if p[P_DENSITY_DISPERSED] != 0.0 else math.nan,
        _aero.kink_between(aero, 2, alt0, alt1),
    ):
        if not math.isnan(z):
            first = min(first, _altitude_fraction(alt0, alt1, rate0, rate1, z))
    mach0, mach1 = res0[EV_MACH], res1[EV_MACH]
    m = _aero.kink_between(aero, 0, mach0, mach1)
    if not math.isnan(m):
        first = min(first, (m - mach0) / (mach1 - mach0))
    return first


@njit(allocates=False)
def _dense_coefficients(
    dop853: bool,
    t: float,
    h: float,
    s: NDArray[np.float64],
    y1: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    k: NDArray[np.float64],
    ys: NDArray[np.float64],
    f: NDArray[np.float64],
) -> int:
    """The continuous extension of the step just taken (k holds its stages, the last f(t + h, y1)) into f;
    returns the number of its rows. DOP853: three more stages, an interpolant of order 7 (dop853.f's CONTD8);
    DOPRI5: order 4 (dopri5.f's CONTD5). Either is evaluated by _dense."""
    if not dop853:
        for j in range(6):
            f[0, j] = y1[j] - s[j]
            f[1, j] = h * k[0, j] - f[0, j]
            f[2, j] = f[0, j] - h * k[6, j] - f[1, j]
            f[3, j] = h * (D1 * k[0, j] + D3 * k[2, j] + D4 * k[3, j] + D5 * k[4, j] + D6 * k[5, j] + D7 * k[6, j])
        return 4
    for st in range(DOP853_STAGES + 1, DOP853_STAGES_DENSE):
        for i in range(6):
            acc = 0.0
            for j in range(st):
                acc += DOP853_A[st, j] * k[j, i]
            ys[i] = s[i] + h * acc
        _stage(t + DOP853_C[st] * h, ys, p, aero, ctrl, mode, k, st)
    last = DOP853_STAGES  # f(t + h, y1)
    for i in range(6):
        dy = y1[i] - s[i]
        f[0, i] = dy
        f[1, i] = h * k[0, i] - dy
        f[2, i] = 2.0 * dy - h * (k[last, i] + k[0, i])
        for m in range(DOP853_DENSE_ROWS):
            acc = 0.0
            for j in range(DOP853_STAGES_DENSE):
                acc += DOP853_D[m, j] * k[j, i]
            f[3 + m, i] = h * acc
    return 3 + DOP853_DENSE_ROWS


@njit(allocates=False)
def _dense(theta: float, y0: NDArray[np.float64], f: NDArray[np.float64], rows: int, out: NDArray[np.float64]) -> None:
    """The continuous extension at theta in [0, 1] of the last step: y0 + theta (f0 + (1 - theta) (f1 + theta (f2
    + ...))), the nested form of dopri5.f's CONTD5 and dop853.f's CONTD8."""
    t1 = 1.0 - theta
    for i in range(6):
        acc = 0.0
        for m in range(rows - 1, -1, -1):
            acc = (acc + f[m, i]) * (theta if m % 2 == 0 else t1)
        out[i] = y0[i] + acc


@njit
def _record(
    rows: NDArray[np.float64], n: int, t: float, s: NDArray[np.float64], res: tuple[float, ...], interior: float = 0.0
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
    rows[n, R_INTERIOR] = interior
    return rows


@njit
def _record_interior(
    rows: NDArray[np.float64],
    n: int,
    t: float,
    h: float,
    s: NDArray[np.float64],
    y1: NDArray[np.float64],
    k: NDArray[np.float64],
    last: int,
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    mode: NDArray[np.float64],
    ye: NDArray[np.float64],
) -> tuple[NDArray[np.float64], int]:
    """The rows inside the accepted step from (t, s) to (t + h, y1), k[0] and k[last] the derivatives at its ends:
    the quintic Hermite interpolant at theta = j / DOP853_ROWS_PER_STEP (HERMITE_VALUE, HERMITE_SLOPE)."""
    for j in range(DOP853_ROWS_PER_STEP - 1):
        w, d = HERMITE_VALUE[j], HERMITE_SLOPE[j]
        for i in range(3):
            x0, x1, v0, v1 = s[i], y1[i], s[3 + i], y1[3 + i]
            a0, a1 = h * k[0, 3 + i], h * k[last, 3 + i]
            ye[i] = w[0] * x0 + h * (w[1] * v0 + w[2] * a0 + w[3] * a1 + w[4] * v1) + w[5] * x1
            ye[3 + i] = (d[0] * (x0 - x1)) / h + d[1] * v0 + d[2] * a0 + d[3] * a1 + d[4] * v1
        te = t + (j + 1) * h / DOP853_ROWS_PER_STEP
        rows = _record(rows, n, te, ye, evaluate(te, ye, p, aero, ctrl, mode), 1.0)
        n += 1
    return rows, n


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
    dop853 = p[P_INTEGRATOR] == INTEGRATOR_DOP853
    use853 = dop853  # this step's method: DOP853 when chosen, unless capped by h_max (DOPRI5_CAPPED_STEP)
    rtol = p[P_RTOL]
    h_max = p[P_MAX_STEP]
    v0 = math.sqrt(s0[3] ** 2 + s0[4] ** 2 + s0[5] ** 2)
    scale = np.empty(6)
    for i in range(3):
        scale[i] = rtol * p[P_RE]
        scale[3 + i] = rtol * max(v0, 1000.0)
    k = np.empty((DOP853_STAGES_DENSE, 6))  # the stages of a step (DOPRI5 uses the first 7)
    f = np.empty((3 + DOP853_DENSE_ROWS, 6))  # the continuous extension of a step with an event
    ys, y1, ye = np.empty(6), np.empty(6), np.empty(6)
    g0, g1, gt = np.empty(N_EVENTS), np.empty(N_EVENTS), np.empty(N_EVENTS)

    t = t0
    s = s0.copy()
    rows = np.empty((1024, N_COLS))
    res = _stage(t, s, p, aero, ctrl, mode, k, 0)
    res0 = res  # evaluate at the start of the step
    rows = _record(rows, 0, t, s, res)
    n = 1
    n_rhs = 1
    _event_values(t, s, res, p, ctrl, mode, g0)
    h = min(1.0, h_max)
    stop = STOP_NONE
    steps = 0
    rejected = False
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
        if use853:
            err, res_end = _dop853_step(t, h, s, p, aero, ctrl, mode, k, ys, y1, scale)
            n_rhs += DOP853_STAGES - 1
            if not (err <= 1.0):  # also catches NaN
                theta = _kink_fraction(res0, res_end, h, p, aero) if err == err else 2.0
                if theta < KINK_MAX_FRACTION and theta * h >= KINK_MIN_STEP_S:
                    h *= theta
                else:
                    h *= max(1.0 / 3.0, 0.9 * err**-0.125) if err == err else 1.0 / 3.0
                rejected = True
                continue
            res1 = _stage(t + h, y1, p, aero, ctrl, mode, k, DOP853_STAGES)  # first stage of the next step
            n_rhs += 1
        else:
            err, res1 = _dopri5_step(t, h, s, p, aero, ctrl, mode, k, ys, y1, scale)
            n_rhs += 6
            if not (err <= 1.0):  # also catches NaN
                h *= max(0.2, 0.9 * err**-0.2) if err == err else 0.2
                use853 = dop853
                continue

        _event_values(t + h, y1, res1, p, ctrl, mode, g1)
        first = -1
        theta_first = 2.0
        n_dense = 0
        for i in range(N_EVENTS):
            if g0[i] < 0.0 and g1[i] >= 0.0:  # NaN compares false: inactive events never fire
                if n_dense == 0:  # the continuous extension, built once per step
                    n_dense = _dense_coefficients(use853, t, h, s, y1, p, aero, ctrl, mode, k, ys, f)
                    if use853:
                        n_rhs += DOP853_STAGES_DENSE - DOP853_STAGES - 1
                # Illinois regula falsi on [0, 1] for g_i(theta); the stop time's is exact (g linear in time)
                a, b, ga, gb = 0.0, 1.0, g0[i], g1[i]
                side = 0
                if i == E_STOP_TIME:
                    b = min(max((p[P_STOP_TIME] - t) / h, 0.0), 1.0)
                for _ in range(60 if i != E_STOP_TIME else 0):
                    c = (a * gb - b * ga) / (gb - ga)
                    _dense(c, s, f, n_dense, ye)
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
            if use853 and theta_first > 0.0:  # the rows inside the step up to the event, on its continuous extension
                for j in range(1, DOP853_ROWS_PER_STEP):
                    theta = theta_first * j / DOP853_ROWS_PER_STEP
                    _dense(theta, s, f, n_dense, ys)
                    rows = _record(rows, n, t + theta * h, ys, evaluate(t + theta * h, ys, p, aero, ctrl, mode), 1.0)
                    n += 1
                n_rhs += DOP853_ROWS_PER_STEP - 1
            _dense(theta_first, s, f, n_dense, ye)
            rese = evaluate(te, ye, p, aero, ctrl, mode)
            _advance_turn(rese[EV_STEER_DEG], mode)
            stop = _apply_event(first, te, rese, ctrl, mode)
            for j in range(6):
                s[j] = ye[j]
            t = te
            res = _stage(t, s, p, aero, ctrl, mode, k, 0)  # the mode may have changed the forces
            res0 = res
            n_rhs += 1
            rows = _record(rows, n, t, s, res)
            n += 1
            _event_values(t, s, res, p, ctrl, mode, g0)
            rejected = False
            continue

        last = DOP853_STAGES if use853 else 6  # the row of k that holds f(t + h, y1)
        if use853:
            rows, n = _record_interior(rows, n, t, h, s, y1, k, last, p, aero, ctrl, mode, ye)
            n_rhs += DOP853_ROWS_PER_STEP - 1
        t += h
        for j in range(6):
            s[j] = y1[j]
            k[0, j] = k[last, j]
        for j in range(N_EVENTS):
            g0[j] = g1[j]
        rows = _record(rows, n, t, s, res1)
        _advance_turn(res1[EV_STEER_DEG], mode)
        res0 = res1
        n += 1
        if use853:  # dop853.f: h 0.9 err^(-1/8), by at most 6 times, and not up just after a rejection
            grow = min(6.0, 0.9 * err**-0.125) if err > 0.0 else 6.0
            h_next = h * (min(grow, 1.0) if rejected else grow)
        else:
            h_next = h * min(5.0, max(0.2, 0.9 * err**-0.2)) if err > 0.0 else 5.0 * h
        rejected = False
        use853 = dop853 and h_next < DOPRI5_CAPPED_STEP * h_max
        h = min(h_next, h_max)
    return rows[:n], stop, n_rhs
