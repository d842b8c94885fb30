"""Gravity of AFWAL-TR-82-3036 Appendix A, eq. (A10), and a spherical mu/r^2 option.

Eq. (A10) gives the downward (g_Zg) and northward (g_Xg) components in the local geocentric horizon
frame with zonal coefficients J, H, K. They are the gradient of the zonal potential with
J2 = J/1.5, J3 = H/2.5 and J4 = -K/3.75 (the tests check this against the potential by finite
differences). The printed H is positive, so the report's J3 is +2.42e-6 where modern models have
-2.53e-6; we keep the report's value (the effect on a trajectory is below a foot).
"""

import math

from footprint.core._jit import njit


@njit
def zonal_down_north(g0: float, s: float, q: float, j: float, h: float, k: float) -> tuple[float, float]:
    """(g_Zg, g_Xg / cos(phi_L)): App. A eq. (A10), downward and northward over cos(latitude), at
    g0 = mu/r^2, s = sin(phi_L) (geocentric), q = R_e/r. Plain arithmetic, so the collocation's CasADi model
    (core.model_casadi) calls the same lines through `zonal_down_north.py_func`."""
    s2 = s * s
    q2 = q * q
    # App. A eq. (A10), downward component g_Zg with P2, P3, P4
    p2 = 1.0 - 3.0 * s2
    p3 = 3.0 * s - 5.0 * s * s2
    p4 = 3.0 - 30.0 * s2 + 35.0 * s2 * s2
    g_down = g0 * (1.0 + j * q2 * p2 + 0.8 * h * q2 * q * p3 + k / 6.0 * q2 * q2 * p4)
    # App. A eq. (A10), northward component g_Xg = g0 [..] with P5, P6, P7; each P carries a factor
    # cos(phi_L) that cancels against the 1/cos of the north unit vector (ez - s er)/cos, so the
    # poles are regular.
    g_north_over_cos = g0 * (
        -2.0 * j * q2 * s + 0.6 * h * q2 * q * (1.0 - 5.0 * s2) + (2.0 * k / 3.0) * q2 * q2 * s * (-3.0 + 7.0 * s2)
    )
    return g_down, g_north_over_cos


@njit
def gravity_ecef(
    x_ft: float, y_ft: float, z_ft: float, mu_ft3_s2: float, re_ft: float, j: float, h: float, k: float, oblate: bool
) -> tuple[float, float, float]:
    """Gravitational acceleration (ft/s^2) at an earth-fixed position; z along the north pole."""
    ir = 1.0 / math.sqrt(x_ft * x_ft + y_ft * y_ft + z_ft * z_ft)  # one division: the rest multiply by it
    g0 = mu_ft3_s2 * ir * ir
    ex, ey, ez = x_ft * ir, y_ft * ir, z_ft * ir
    if not oblate:
        return -g0 * ex, -g0 * ey, -g0 * ez
    s = ez  # sine of the geocentric latitude phi_L
    g_down, g_north_over_cos = zonal_down_north(g0, s, re_ft * ir, j, h, k)
    gx = -g_down * ex + g_north_over_cos * (-s * ex)
    gy = -g_down * ey + g_north_over_cos * (-s * ey)
    gz = -g_down * ez + g_north_over_cos * (1.0 - s * ez)
    return gx, gy, gz
