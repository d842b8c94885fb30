"""Aerodynamic heating along a flown trajectory: the reference-heating method of AFWAL-TR-82-3036 Section III,
and a generic stagnation correlation for published problems that bring their own heating law.

Both are evaluated on the histories after the flight (heating does not act on the motion), vectorized in numpy.

Reference heating, report eqs. (5)-(7) (reconstruction: shared/data/heating.md)
----------------------------------------------------------------------------
* h_F&R, the stagnation-point heat-transfer coefficient of Fay & Riddell (J. Aeronaut. Sci. 25(2), 73-85, 1958),
  in the closed form of Detra, Kemp & Riddell (Jet Propulsion 27, 1256, 1957) that fits it for a sphere of
  radius R_N in equilibrium air:
      q_cw = 17,600 / sqrt(R_N) * sqrt(rho / rho_SL) * (V / 26,000)^3.15   [Btu/(ft^2 s), cold wall at 540 degR]
      h_F&R = q_cw / (H_0 - H_W,cold)                                      [lbm/(ft^2 s)]
* h = h_F&R * (h/h_F&R)(alpha), Table 1, linear in alpha, held at the table's ends      (eq. 5)
* q = h (H_AW - H_W), with H_AW = H_0 = c_p T_inf + V^2/2 and H_W = c_p T_W              (eq. 6)
* T_W = [q / (4.75e-13 eps)]^0.25, the radiation-equilibrium temperature (RET)           (eq. 7)
  Since H_W depends on T_W, eqs. (6)-(7) together are the quartic
      4.75e-13 eps T^4 + h c_p T - h H_0 = 0,
  solved by Newton's method from above (the left side is convex and increasing for T > 0, so the iterates
  decrease monotonically onto the one positive root).

Thin skin (optional): the report's temperatures came from "a one-dimensional conduction analysis on a simplified
structure" (Section III), which it does not describe. Its simplest form is a thin skin of areal heat capacity C
(Btu/(ft^2 degR)) with an insulated back face:  C dT/dt = h (H_AW - c_p T) - 4.75e-13 eps T^4.  C = 0 is eq. (7)'s
RET (the default, and what the calibration below is for); C > 0 lags and damps short heat pulses.

The report does not give R_N, eps or the wall-enthalpy model. We fix eps and c_p (below) and calibrate one
scale, the effective reference radius R_N, so that the unconstrained maximum cross-range trajectory of the
L/D 1.89 vehicle peaks at the report's 2,670 degR (Section III.1). `calibrate_reference_radius_ft` recomputes it;
tests/core/test_heating.py checks that the constant below still reproduces 2,670 degR.

V is the earth-relative speed (the air turns with the earth), as in the report's heating program.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core._jit import njit
from footprint.core.atmosphere import atmosphere_table

# --- Constants, each with its unit and source -----------------------------------------------------------------
SIGMA_REPORT_BTU_FT2_S_R4 = 4.75e-13  # eq. (7): Stefan-Boltzmann constant to 3 figures (CODATA: 4.7564e-13)
FT2_S2_PER_BTU_LBM = 2326.0 / 0.3048**2  # 1 Btu_IT/lbm = 2,326 J/kg exactly = 25,036.9 ft^2/s^2
CP_AIR_BTU_LBM_R = 0.24  # heating.md §4: c_p of air for H_0 and H_W (calorically perfect wall gas)
EMISSIVITY_DEFAULT = 0.8  # heating.md §4: typical of 1970s-80s radiative TPS; not given in the report
DKR_Q_BTU_FT2_S = 17_600.0  # Detra-Kemp-Riddell (1957): cold-wall stagnation heat rate, 1-ft sphere, at V_DKR
DKR_V_FPS = 26_000.0  # Detra-Kemp-Riddell reference (circular) speed
DKR_V_EXPONENT = 3.15  # Detra-Kemp-Riddell velocity exponent
DKR_RHO_SL_SLUG_FT3 = 0.0023769  # Detra-Kemp-Riddell sea-level density
DKR_COLD_WALL_R = 540.0  # Detra-Kemp-Riddell cold wall, 300 K
# Table 1 of AFWAL-TR-82-3036: h/h_F&R against alpha (deg). The repeated .23 at 30 and 40 deg is as printed.
TABLE1_ALPHA_DEG: NDArray[np.float64] = np.array([0.0, 20.0, 25.0, 30.0, 40.0, 45.0, 50.0])
TABLE1_RATIO: NDArray[np.float64] = np.array([0.17, 0.175, 0.20, 0.23, 0.23, 0.26, 0.30])
# Calibrated effective reference radius of h_F&R (ft). The calibration flight is Section III.1's: the unconstrained
# maximum cross-range of the L/D 1.89 vehicle (Table 2 entry, (L/D)max alpha, zero bank to pull-out, stop at
# 50,000 ft), flying the optimal 8-point bank table vs zeta = -15..90 deg (creep + pattern, 2,044.5 nmi,
# bench/results/optimize.json) below. It then peaks at 2,670 degR with eps = 0.8 and c_p = 0.24.
# calibrate_reference_radius_ft recomputes the radius (tests/core/test_heating.py).
CALIBRATION_BANK_DEG = (0.0, 2.109375, 7.5, 18.75, 30.9375, 43.125, 59.0625, 84.375)
REFERENCE_RADIUS_FT = 3.034  # ft; calibrate_reference_radius_ft gave 3.0341 (heating.md guessed ~1 ft)
REPORT_PEAK_RET_R = 2_670.0  # Section III.1: max RET of the unconstrained L/D 1.89 footprint
SKIN_SUBSTEP_S = 0.5  # s: trapezoidal sub-steps of the thin-skin equation between history rows
SKIN_INITIAL_R = 530.0  # degR: skin temperature at entry (a cold-soaked structure)


def table1_ratio(alpha_deg: ArrayLike) -> NDArray[np.float64]:
    """h/h_F&R of Table 1 (eq. 5): linear in alpha (deg), held at the ends."""
    return np.interp(np.asarray(alpha_deg, dtype=np.float64), TABLE1_ALPHA_DEG, TABLE1_RATIO)


def total_enthalpy_btu_lbm(velocity_fps: ArrayLike, temperature_inf_R: ArrayLike) -> NDArray[np.float64]:
    """H_0 = c_p T_inf + V^2/2 (Btu/lbm)."""
    v = np.asarray(velocity_fps, dtype=np.float64)
    return CP_AIR_BTU_LBM_R * np.asarray(temperature_inf_R, dtype=np.float64) + 0.5 * v * v / FT2_S2_PER_BTU_LBM


def fay_riddell_cold_wall_btu_ft2_s(
    density_slug_ft3: ArrayLike, velocity_fps: ArrayLike, nose_radius_ft: float
) -> NDArray[np.float64]:
    """Cold-wall stagnation heat rate (Btu/(ft^2 s)), Fay-Riddell in the Detra-Kemp-Riddell closed form."""
    rho = np.maximum(np.asarray(density_slug_ft3, dtype=np.float64), 0.0)
    v = np.abs(np.asarray(velocity_fps, dtype=np.float64))
    q_cw: NDArray[np.float64] = (  # typed: numpy types np.sqrt of a float as Any
        DKR_Q_BTU_FT2_S
        / np.sqrt(nose_radius_ft)
        * np.sqrt(rho / DKR_RHO_SL_SLUG_FT3)
        * (v / DKR_V_FPS) ** DKR_V_EXPONENT
    )
    return q_cw


def fay_riddell_coefficient_lbm_ft2_s(
    density_slug_ft3: ArrayLike, velocity_fps: ArrayLike, temperature_inf_R: ArrayLike, nose_radius_ft: float
) -> NDArray[np.float64]:
    """h_F&R = q_cw / (H_0 - H_W,cold) (lbm/(ft^2 s)); zero where H_0 does not exceed the cold-wall enthalpy."""
    q_cw = fay_riddell_cold_wall_btu_ft2_s(density_slug_ft3, velocity_fps, nose_radius_ft)
    drive = total_enthalpy_btu_lbm(velocity_fps, temperature_inf_R) - CP_AIR_BTU_LBM_R * DKR_COLD_WALL_R
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(drive > 0.0, q_cw / np.where(drive > 0.0, drive, 1.0), 0.0)


def radiation_equilibrium_R(heat_rate_btu_ft2_s: ArrayLike, emissivity: float) -> NDArray[np.float64]:
    """Eq. (7): T = [q / (4.75e-13 eps)]^0.25 (degR), for a heat rate that does not depend on T."""
    q = np.maximum(np.asarray(heat_rate_btu_ft2_s, dtype=np.float64), 0.0)
    return (q / (SIGMA_REPORT_BTU_FT2_S_R4 * emissivity)) ** 0.25


def wall_equilibrium_R(
    coefficient_lbm_ft2_s: ArrayLike, recovery_enthalpy_btu_lbm: ArrayLike, emissivity: float, iterations: int = 60
) -> NDArray[np.float64]:
    """Eqs. (6)-(7) together: the T with h (H_AW - c_p T) = 4.75e-13 eps T^4 (degR), Newton's method at each point
    (compiled: the numpy loop over the whole history had been half a heated summary's cost after the integrator)."""
    h, haw = np.broadcast_arrays(
        np.maximum(np.asarray(coefficient_lbm_ft2_s, dtype=np.float64), 0.0),
        np.maximum(np.asarray(recovery_enthalpy_btu_lbm, dtype=np.float64), 0.0),
    )
    out = np.empty(h.shape)
    _wall_equilibrium_fill(
        np.ascontiguousarray(h).ravel(), np.ascontiguousarray(haw).ravel(), float(emissivity), iterations, out.ravel()
    )
    return out


@njit(allocates=False)
def _wall_equilibrium_fill(
    h: NDArray[np.float64], haw: NDArray[np.float64], emissivity: float, iterations: int, out: NDArray[np.float64]
) -> None:
    es = SIGMA_REPORT_BTU_FT2_S_R4 * emissivity
    for k in range(h.shape[0]):
        hk, ak = h[k], haw[k]
        t = min((hk * ak / es) ** 0.25, ak / CP_AIR_BTU_LBM_R)  # both bound the root from above
        for _ in range(iterations):  # f convex and increasing in t: the iterates fall monotonically onto the root
            f = es * t**4 + hk * CP_AIR_BTU_LBM_R * t - hk * ak
            df = 4.0 * es * t**3 + hk * CP_AIR_BTU_LBM_R
            step = f / df if df > 0.0 else 0.0
            t -= step
            if abs(step) <= 1e-9 * max(t, 1.0):
                break
        out[k] = t


@njit
def thin_skin_R(
    time_s: NDArray[np.float64],
    coefficient_lbm_ft2_s: NDArray[np.float64],
    recovery_enthalpy_btu_lbm: NDArray[np.float64],
    emissivity: float,
    capacity_btu_ft2_R: float,
    initial_R: float,
) -> NDArray[np.float64]:
    """Skin temperature (degR) from C dT/dt = h (H_AW - c_p T) - 4.75e-13 eps T^4 (thin skin, insulated back).

    Trapezoidal rule (A-stable, 2nd order) on sub-steps of at most SKIN_SUBSTEP_S, h and H_AW linear in time
    between the history rows; each implicit step by Newton's method from the last temperature (the residual is
    convex and increasing in T, so after at most one step the iterates decrease monotonically onto the root)."""
    n = time_s.shape[0]
    out = np.empty(n)
    es = SIGMA_REPORT_BTU_FT2_S_R4 * emissivity
    cp, cap = CP_AIR_BTU_LBM_R, capacity_btu_ft2_R
    t_w = initial_R
    out[0] = t_w
    for i in range(1, n):
        if time_s[i] <= time_s[i - 1]:  # an event row repeats its time
            out[i] = t_w
            continue
        m = int(np.ceil((time_s[i] - time_s[i - 1]) / SKIN_SUBSTEP_S))
        dt = (time_s[i] - time_s[i - 1]) / m
        dh = (coefficient_lbm_ft2_s[i] - coefficient_lbm_ft2_s[i - 1]) / m
        da = (recovery_enthalpy_btu_lbm[i] - recovery_enthalpy_btu_lbm[i - 1]) / m
        h1, a1 = coefficient_lbm_ft2_s[i - 1], recovery_enthalpy_btu_lbm[i - 1]
        for _ in range(m):
            net0 = h1 * (a1 - cp * t_w) - es * t_w**4  # net heating at the sub-step's start
            h1, a1 = h1 + dh, a1 + da
            x = t_w
            for _ in range(50):  # g(x) = C (x - t_w) / dt - (net0 + net(x)) / 2 = 0
                g = cap * (x - t_w) / dt - 0.5 * (net0 + h1 * (a1 - cp * x) - es * x**4)
                step = g / (cap / dt + 0.5 * (h1 * cp + 4.0 * es * x**3))
                x -= step
                if abs(step) <= 1e-10 * x:
                    break
            t_w = x
        out[i] = t_w
    return out


@dataclass(frozen=True)
class ReferenceHeating:
    """AFWAL-TR-82-3036 eqs. (5)-(7) at the report's point ~10 ft aft of the nose, lower centreline."""

    reference_radius_ft: float = REFERENCE_RADIUS_FT
    emissivity: float = EMISSIVITY_DEFAULT
    ratio_alpha_deg: tuple[float, ...] = tuple(TABLE1_ALPHA_DEG)
    ratio: tuple[float, ...] = tuple(TABLE1_RATIO)
    skin_heat_capacity_btu_ft2_R: float = 0.0  # 0: RET of eq. (7); > 0: thin-skin temperature (needs time_s)

    def evaluate(
        self,
        density_slug_ft3: ArrayLike,
        velocity_fps: ArrayLike,
        alpha_deg: ArrayLike,
        temperature_inf_R: ArrayLike,
        time_s: ArrayLike | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(heat_rate_btu_ft2_s, temperature_R) along the histories: q of eq. (6) at the wall temperature."""
        h_fr = fay_riddell_coefficient_lbm_ft2_s(
            density_slug_ft3, velocity_fps, temperature_inf_R, self.reference_radius_ft
        )
        h = h_fr * np.interp(np.asarray(alpha_deg, dtype=np.float64), self.ratio_alpha_deg, self.ratio)  # eq. (5)
        h_aw = total_enthalpy_btu_lbm(velocity_fps, temperature_inf_R)
        if self.skin_heat_capacity_btu_ft2_R > 0.0:
            if time_s is None:
                raise ValueError("a thin-skin temperature needs the time history (time_s)")
            t_w = thin_skin_R(
                np.asarray(time_s, dtype=np.float64),
                np.ascontiguousarray(h, dtype=np.float64),
                np.ascontiguousarray(h_aw, dtype=np.float64),
                float(self.emissivity),
                float(self.skin_heat_capacity_btu_ft2_R),
                SKIN_INITIAL_R,
            )
        else:
            t_w = wall_equilibrium_R(h, h_aw, self.emissivity)  # eqs. (6)-(7)
        q = h * (h_aw - CP_AIR_BTU_LBM_R * t_w)  # eq. (6)
        return q, t_w


@dataclass(frozen=True)
class CorrelationHeating:
    """q = C rho^a V^b f(alpha), f(alpha) = sum c_i alpha_deg^i; rho in slug/ft^3, V in ft/s, q in Btu/(ft^2 s).

    E.g. Betts' shuttle reentry (Practical Methods for Optimal Control, 2nd ed., sec. 6.1):
    C = 17,700 * 1e-4^3.07, a = 0.5, b = 3.07, f = 1.0672181 - 1.9213774e-2 a + 2.1286289e-4 a^2 - 1.0117249e-6 a^3.
    With an emissivity, the temperature is eq. (7) of the heat rate (q does not depend on the wall here).
    """

    coefficient: float
    density_exponent: float = 0.5
    velocity_exponent: float = 3.0
    alpha_polynomial: tuple[float, ...] = (1.0,)  # ascending powers of alpha in degrees
    emissivity: float | None = None

    def evaluate(
        self,
        density_slug_ft3: ArrayLike,
        velocity_fps: ArrayLike,
        alpha_deg: ArrayLike,
        temperature_inf_R: ArrayLike | None = None,
        time_s: ArrayLike | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        rho = np.maximum(np.asarray(density_slug_ft3, dtype=np.float64), 0.0)
        v = np.abs(np.asarray(velocity_fps, dtype=np.float64))
        f = np.polynomial.polynomial.polyval(np.asarray(alpha_deg, dtype=np.float64), np.asarray(self.alpha_polynomial))
        q = self.coefficient * rho**self.density_exponent * v**self.velocity_exponent * f
        t = radiation_equilibrium_R(q, self.emissivity) if self.emissivity is not None else np.full_like(q, np.nan)
        return q, t


def trajectory_heating(
    model: ReferenceHeating | CorrelationHeating,
    altitude_ft: ArrayLike,
    velocity_fps: ArrayLike,
    alpha_deg: ArrayLike,
    atmosphere_args: tuple[float, float, float, float],
    time_s: ArrayLike | None = None,
    density_factor: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(heat_rate_btu_ft2_s, temperature_R) along a flown history; atmosphere_args = (model id, rho0, H, T).
    density_factor: the dispersed density over the model's along the history (atmosphere.density_factor_table);
    None: the model's density."""
    model_id, rho0, scale_h, temp = atmosphere_args
    atm = atmosphere_table(int(model_id), altitude_ft, rho0, scale_h, temp)
    density = atm["density_slug_ft3"] if density_factor is None else atm["density_slug_ft3"] * density_factor
    return model.evaluate(density, velocity_fps, alpha_deg, atm["temperature_R"], time_s)


def calibrate_reference_radius_ft(
    altitude_ft: ArrayLike,
    velocity_fps: ArrayLike,
    alpha_deg: ArrayLike,
    atmosphere_args: tuple[float, float, float, float],
    target_R: float = REPORT_PEAK_RET_R,
    emissivity: float = EMISSIVITY_DEFAULT,
    skin_heat_capacity_btu_ft2_R: float = 0.0,
    time_s: ArrayLike | None = None,
) -> float:
    """The reference radius (ft) that makes the peak temperature along one flown history equal target_R
    (bisection; a thin skin needs time_s).

    Heating does not act on the motion, so one flight serves every trial radius. The peak falls
    monotonically as the radius grows (h_F&R ~ R^-1/2)."""

    def peak(radius_ft: float) -> float:
        model = ReferenceHeating(radius_ft, emissivity, skin_heat_capacity_btu_ft2_R=skin_heat_capacity_btu_ft2_R)
        _, t = trajectory_heating(model, altitude_ft, velocity_fps, alpha_deg, atmosphere_args, time_s)
        return float(np.max(t))

    lo, hi = 1e-3, 1e3  # ft
    for _ in range(200):
        mid = np.sqrt(lo * hi)
        if peak(mid) > target_R:
            lo = mid
        else:
            hi = mid
        if hi / lo - 1.0 < 1e-12:
            break
    return float(np.sqrt(lo * hi))
