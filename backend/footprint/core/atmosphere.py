"""Atmosphere models: 1959 ARDC (the report's, and the default), U.S. Standard Atmosphere 1976, exponential.

One compiled entry point, `atmosphere(model, altitude_ft, rho0_slug_ft3, scale_height_ft, temperature_R)`,
serves the trajectory integrator's inner loop: it allocates nothing, raises nothing and returns
(density_slug_ft3, pressure_psf, temperature_R, speed_of_sound_fps) at a GEOMETRIC altitude in ft.
An unknown model id gives NaNs.

Sources
-------
* 1959 ARDC: shared/data/ardc1959.md (§1 constants, §2 layers, §3 option 1 above 105 km', §4 formulas).
  Reproduces the published ARDC table transcriptions (tests/authorities/ardc1959_reference.csv) to
  <= 0.008 % in p and rho, and every base value of the note's §2 to its printed digits.
* U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562, "USSA-76"): below 86 km the standard's layer
  formulas (eqs. 18, 23, 33a, 33b, 42, 50); 86 to 1,000 km the table data/us1976_upper.csv, written by
  scripts/make_us1976_table.py (ussa1976 package, corrected; see that script).
* Exponential: rho = rho0 exp(-h/H), isothermal at a given T; p = rho R T with the 1959 ARDC R.

Density dispersion (Monte Carlo samples): the density of any model times 1 + delta(h), delta the natural cubic
spline through fixed nodes every 10,000 ft from 0 to 400,000 ft and held beyond them (`density_factor`). Temperature,
pressure and the speed of sound are left as the model gives them. core/dispersion.py draws the nodes.

Layer base temperatures and pressures are computed once at import (numpy) into module-level arrays
that the kernels read. Numba freezes module-level arrays into the compiled (and disk-cached) code:
after regenerating us1976_upper.csv, clear this module's numba cache (__pycache__/atmosphere.*.nbi/.nbc).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core._jit import njit
from footprint.core.constants import FT_PER_M, G0_FT_S2, GAMMA_AIR

# --- Model ids (the kernel takes the integer) --------------------------------------------------------
ARDC1959 = 0
US1976 = 1
EXPONENTIAL = 2
MODEL_IDS = {"ardc1959": ARDC1959, "us1976": US1976, "exponential": EXPONENTIAL}

# --- Unit conversions (exact definitions) ------------------------------------------------------------
N_PER_LBF = 0.45359237 * 9.80665  # avoirdupois pound mass times standard gravity
KG_PER_SLUG = N_PER_LBF * FT_PER_M  # 1 slug = 1 lbf s^2/ft = 14.5939 kg
PSF_PER_PA = N_PER_LBF**-1 / FT_PER_M**2  # 1 Pa = 0.0208854 lbf/ft^2
SLUG_FT3_PER_KG_M3 = 1.0 / (KG_PER_SLUG * FT_PER_M**3)  # 1 kg/m^3 = 0.00194032 slug/ft^3
R_PER_K = 1.8  # degrees Rankine per kelvin
FT_PER_KM = 1000.0 * FT_PER_M

# --- 1959 ARDC, ardc1959.md §1-§3 ----------------------------------------------------------------------
ARDC_EARTH_RADIUS_FT = 20_855_531.0  # ardc1959.md §1, r0 = 6,356,766 m (REFT59)
ARDC_T0_R = 518.688  # ardc1959.md §1, 288.16 K
ARDC_P0_PSF = 101_325.0 * PSF_PER_PA  # ardc1959.md §1, 101,325 Pa = 2116.2166 lb/ft^2 (printed 2116.22)
ARDC_RHO0_SLUG_FT3 = 1.2250 * SLUG_FT3_PER_KG_M3  # ardc1959.md §1, 1.2250 kg/m^3 = 0.00237689 slug/ft^3
# ardc1959.md §1: R = p0/(rho0 T0) = 287.042913 J/(kg K), kept unrounded. constants.R_AIR_FT2_S2_R is the same
# value rounded to 287.0429 (4e-8 lower); with the rounded value three of the §2 base values printed to 6
# figures come out one unit off in the last digit (the note computed them with the unrounded ratio).
ARDC_GAS_CONSTANT_FT2_S2_R = ARDC_P0_PSF / (ARDC_RHO0_SLUG_FT3 * ARDC_T0_R)
# ardc1959.md §2: base geopotential altitudes (km') and molecular-scale temperature gradients (K/km').
# The last gradient, +4.0 K/km' from 90 km', is continued above 105 km' without end (§3 option 1).
ARDC_BASE_ALTITUDE_KM = np.array([0.0, 11.0, 25.0, 47.0, 53.0, 79.0, 90.0])
ARDC_GRADIENT_K_PER_KM = np.array([-6.5, 0.0, 3.0, 0.0, -4.5, 0.0, 4.0])

# --- U.S. Standard Atmosphere 1976, Part 1, Tables 1-4 ------------------------------------------------
US1976_EARTH_RADIUS_FT = 6_356_766.0 * FT_PER_M  # USSA-76 r0 = 6,356,766 m
US1976_T0_R = 288.15 * R_PER_K  # USSA-76 T0 = 288.15 K
US1976_P0_PSF = 101_325.0 * PSF_PER_PA  # USSA-76 P0 = 101,325 N/m^2
US1976_MOLAR_MASS_KG_KMOL = 28.9644  # USSA-76 M0
US1976_GAS_CONSTANT_J_KMOL_K = 8314.32  # USSA-76 R*
US1976_GAS_CONSTANT_FT2_S2_R = US1976_GAS_CONSTANT_J_KMOL_K / US1976_MOLAR_MASS_KG_KMOL * FT_PER_M**2 / R_PER_K
US1976_BASE_ALTITUDE_KM = np.array([0.0, 11.0, 20.0, 32.0, 47.0, 51.0, 71.0, 84.852])  # H_b, km'
US1976_GRADIENT_K_PER_KM = np.array([-6.5, 0.0, 1.0, 2.8, 0.0, -2.8, -2.0, 0.0])  # L_M,b, K/km' (last unused)
US1976_TABLE_START_FT = 86.0 * FT_PER_KM  # 86 km geometric: the layer formulas end, the table starts
US1976_TABLE_PATH = Path(__file__).with_name("data") / "us1976_upper.csv"

# --- Exponential model defaults (callers normally pass their own) --------------------------------------
EXPONENTIAL_RHO0_DEFAULT_SLUG_FT3 = ARDC_RHO0_SLUG_FT3
# A round value, not from the report: the 1959 ARDC density falls by e^-10.96 from 0 to 80 km, a mean
# density scale height of 23,940 ft over the pull-out and glide region.
EXPONENTIAL_SCALE_HEIGHT_DEFAULT_FT = 23_500.0

# --- Density dispersion nodes: delta(h) at 0, 10,000, ..., 400,000 ft (above the report's 364,800 ft entry) ------
DENSITY_NODE_SPACING_FT = 10_000.0
DENSITY_NODE_COUNT = 41
DENSITY_NODES_FT = DENSITY_NODE_SPACING_FT * np.arange(DENSITY_NODE_COUNT)


def isothermal_temperature_R(scale_height_ft: float) -> float:
    """Temperature (deg R) of the isothermal atmosphere whose density scale height is `scale_height_ft`.

    H = R T / g0 for an isothermal atmosphere in hydrostatic balance under constant gravity g0.
    """
    return G0_FT_S2 * scale_height_ft / ARDC_GAS_CONSTANT_FT2_S2_R


def _layer_bases(
    base_km: NDArray[np.float64],
    gradient_k_per_km: NDArray[np.float64],
    t0_r: float,
    p0_psf: float,
    gas_constant: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Base altitudes (ft'), gradients (deg R/ft'), base T (deg R), base p (psf) and the exponents g0/(R L)."""
    base_ft = np.asarray(base_km, dtype=np.float64) * FT_PER_KM
    gradient_r_per_ft = np.asarray(gradient_k_per_km, dtype=np.float64) * R_PER_K / FT_PER_KM
    n = base_ft.size
    base_t = np.empty(n)
    base_p = np.empty(n)
    exponent = np.zeros(n)
    base_t[0], base_p[0] = t0_r, p0_psf
    for i in range(n):
        lapse = gradient_r_per_ft[i]
        if lapse != 0.0:
            exponent[i] = G0_FT_S2 / (gas_constant * lapse)
        if i + 1 < n:
            dh = base_ft[i + 1] - base_ft[i]
            if lapse != 0.0:
                base_t[i + 1] = base_t[i] + lapse * dh
                base_p[i + 1] = base_p[i] * (base_t[i] / base_t[i + 1]) ** exponent[i]
            else:
                base_t[i + 1] = base_t[i]
                base_p[i + 1] = base_p[i] * math.exp(-G0_FT_S2 * dh / (gas_constant * base_t[i]))
    return base_ft, gradient_r_per_ft, base_t, base_p, exponent


(
    ARDC_BASE_ALTITUDE_FT,
    ARDC_GRADIENT_R_PER_FT,
    ARDC_BASE_TEMPERATURE_R,
    ARDC_BASE_PRESSURE_PSF,
    _ARDC_EXPONENT,
) = _layer_bases(ARDC_BASE_ALTITUDE_KM, ARDC_GRADIENT_K_PER_KM, ARDC_T0_R, ARDC_P0_PSF, ARDC_GAS_CONSTANT_FT2_S2_R)

(
    US1976_BASE_ALTITUDE_FT,
    US1976_GRADIENT_R_PER_FT,
    US1976_BASE_TEMPERATURE_R,
    US1976_BASE_PRESSURE_PSF,
    _US1976_EXPONENT,
) = _layer_bases(
    US1976_BASE_ALTITUDE_KM, US1976_GRADIENT_K_PER_KM, US1976_T0_R, US1976_P0_PSF, US1976_GAS_CONSTANT_FT2_S2_R
)


def _read_us1976_table(
    path: Path,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Altitude (ft), ln density (slug/ft^3), ln pressure (psf), kinetic temperature (deg R) from the CSV."""
    lines = [line for line in path.read_text().splitlines() if line.strip() and not line.startswith("#")]
    columns = lines[0].split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    col = {name: data[:, i] for i, name in enumerate(columns)}
    altitude_ft = np.ascontiguousarray(col["altitude_ft"])
    ln_density = np.log(col["density_kg_m3"] * SLUG_FT3_PER_KG_M3)
    ln_pressure = np.log(col["pressure_Pa"] * PSF_PER_PA)
    temperature_r = col["temperature_K"] * R_PER_K
    return altitude_ft, np.ascontiguousarray(ln_density), np.ascontiguousarray(ln_pressure), temperature_r


(
    US1976_TABLE_ALTITUDE_FT,
    _US1976_TABLE_LN_DENSITY,
    _US1976_TABLE_LN_PRESSURE,
    US1976_TABLE_TEMPERATURE_R,
) = _read_us1976_table(US1976_TABLE_PATH)


# Geometric altitudes (ft) where a model's density or speed of sound changes its slope (layer bases: T is continuous,
# dT/dh jumps; the upper US 1976 table is linear between its rows): the integrator ends a rejected step there
# (integrate._kink_fraction) instead of shrinking it step by step across the kink. Geometric z = r0 H / (r0 - H).
ARDC_KINK_ALTITUDE_FT = (
    ARDC_EARTH_RADIUS_FT * ARDC_BASE_ALTITUDE_FT[1:] / (ARDC_EARTH_RADIUS_FT - ARDC_BASE_ALTITUDE_FT[1:])
)
US1976_KINK_ALTITUDE_FT = np.concatenate(
    [
        US1976_EARTH_RADIUS_FT * US1976_BASE_ALTITUDE_FT[1:] / (US1976_EARTH_RADIUS_FT - US1976_BASE_ALTITUDE_FT[1:]),
        US1976_TABLE_ALTITUDE_FT,
    ]
)


# --- Kernels ---------------------------------------------------------------------------------------------


@njit
def _ardc1959(altitude_ft: float) -> tuple[float, float, float, float]:
    """1959 ARDC at geometric altitude (ft): (rho slug/ft^3, p psf, T_M deg R, a ft/s)."""
    r0 = ARDC_EARTH_RADIUS_FT
    gas = ARDC_GAS_CONSTANT_FT2_S2_R
    h = r0 * altitude_ft / (r0 + altitude_ft)  # ardc1959.md §4, geopotential H = r0 z/(r0 + z)
    i = ARDC_BASE_ALTITUDE_FT.shape[0] - 1
    while i > 0 and h < ARDC_BASE_ALTITUDE_FT[i]:  # below 0 ft the first layer continues
        i -= 1
    dh = h - ARDC_BASE_ALTITUDE_FT[i]
    t_b = ARDC_BASE_TEMPERATURE_R[i]
    lapse = ARDC_GRADIENT_R_PER_FT[i]
    if lapse != 0.0:
        t = t_b + lapse * dh  # ardc1959.md §4, gradient layer T_M = T_b + L (H - H_b)
        p = ARDC_BASE_PRESSURE_PSF[i] * (t_b / t) ** _ARDC_EXPONENT[i]  # ardc1959.md §4, gradient layer
    else:
        t = t_b
        p = ARDC_BASE_PRESSURE_PSF[i] * math.exp(-G0_FT_S2 * dh / (gas * t_b))  # ardc1959.md §4, isothermal layer
    rho = p / (gas * t)  # ardc1959.md §4, density rho = p/(R T_M)
    a = math.sqrt(GAMMA_AIR * gas * t)  # ardc1959.md §4, a = sqrt(gamma R T_M)
    return rho, p, t, a


@njit
def _us1976(altitude_ft: float) -> tuple[float, float, float, float]:
    """U.S. Standard Atmosphere 1976 at geometric altitude (ft): (rho slug/ft^3, p psf, T deg R, a ft/s)."""
    gas = US1976_GAS_CONSTANT_FT2_S2_R
    if altitude_ft < US1976_TABLE_START_FT:
        r0 = US1976_EARTH_RADIUS_FT
        h = r0 * altitude_ft / (r0 + altitude_ft)  # U.S. Standard Atmosphere 1976, eq. 18
        i = US1976_BASE_ALTITUDE_FT.shape[0] - 1
        while i > 0 and h < US1976_BASE_ALTITUDE_FT[i]:
            i -= 1
        dh = h - US1976_BASE_ALTITUDE_FT[i]
        t_b = US1976_BASE_TEMPERATURE_R[i]
        lapse = US1976_GRADIENT_R_PER_FT[i]
        if lapse != 0.0:
            t = t_b + lapse * dh  # U.S. Standard Atmosphere 1976, eq. 23
            p = US1976_BASE_PRESSURE_PSF[i] * (t_b / t) ** _US1976_EXPONENT[i]  # U.S. Standard Atmosphere 1976, eq. 33a
        else:
            t = t_b
            p = US1976_BASE_PRESSURE_PSF[i] * math.exp(-G0_FT_S2 * dh / (gas * t_b))  # USSA 1976, eq. 33b
        rho = p / (gas * t)  # U.S. Standard Atmosphere 1976, eq. 42
        a = math.sqrt(GAMMA_AIR * gas * t)  # U.S. Standard Atmosphere 1976, eq. 50
        return rho, p, t, a
    # 86 to 1,000 km: the standard's tabulated high-altitude model (data/us1976_upper.csv), interpolated
    # linearly in ln rho, ln p and T; above 1,000 km the last interval's log-slopes continue, T is held.
    z = US1976_TABLE_ALTITUDE_FT
    n = z.shape[0]
    lo = 0
    hi = n - 1
    if altitude_ft >= z[n - 1]:
        lo = n - 2
    else:
        while hi - lo > 1:  # bisection: z[lo] <= altitude < z[hi]
            mid = (lo + hi) // 2
            if altitude_ft < z[mid]:
                hi = mid
            else:
                lo = mid
    f = (altitude_ft - z[lo]) / (z[lo + 1] - z[lo])
    ln_rho = _US1976_TABLE_LN_DENSITY[lo] + f * (_US1976_TABLE_LN_DENSITY[lo + 1] - _US1976_TABLE_LN_DENSITY[lo])
    ln_p = _US1976_TABLE_LN_PRESSURE[lo] + f * (_US1976_TABLE_LN_PRESSURE[lo + 1] - _US1976_TABLE_LN_PRESSURE[lo])
    if altitude_ft >= z[n - 1]:
        t = US1976_TABLE_TEMPERATURE_R[n - 1]
    else:
        t = US1976_TABLE_TEMPERATURE_R[lo] + f * (US1976_TABLE_TEMPERATURE_R[lo + 1] - US1976_TABLE_TEMPERATURE_R[lo])
    # Above 86 km the standard tabulates no speed of sound; sqrt(gamma R0 T) with the kinetic temperature
    # only serves to form a Mach number (> 25 up there), which saturates the aero tables anyway.
    a = math.sqrt(GAMMA_AIR * gas * t)
    return math.exp(ln_rho), math.exp(ln_p), t, a


@njit
def atmosphere(
    model: int, altitude_ft: float, rho0_slug_ft3: float, scale_height_ft: float, temperature_R: float
) -> tuple[float, float, float, float]:
    """Return (density_slug_ft3, pressure_psf, temperature_R, speed_of_sound_fps) at GEOMETRIC altitude (ft).

    `model` is ARDC1959 (0), US1976 (1) or EXPONENTIAL (2); any other value gives NaNs.
    The last three arguments are used only by EXPONENTIAL (ignored otherwise).
    For ARDC1959 the temperature is the molecular-scale temperature T_M; for US1976 it is the kinetic
    temperature (equal to T_M below 86 km).
    """
    if model == ARDC1959:
        return _ardc1959(altitude_ft)
    if model == US1976:
        return _us1976(altitude_ft)
    if model == EXPONENTIAL:
        gas = ARDC_GAS_CONSTANT_FT2_S2_R
        rho = rho0_slug_ft3 * math.exp(-altitude_ft / scale_height_ft)  # exponential: rho = rho0 exp(-h/H)
        p = rho * gas * temperature_R  # ideal gas, isothermal at temperature_R
        a = math.sqrt(GAMMA_AIR * gas * temperature_R)
        return rho, p, temperature_R, a
    nan = math.nan
    return nan, nan, nan, nan


def density_profile(delta: ArrayLike) -> NDArray[np.float64]:
    """The packed profile density_factor reads: delta at DENSITY_NODES_FT, then the second derivatives of the natural
    cubic spline through them (per node spacing squared; zero at the end nodes). A spline, not the polyline through
    the nodes: its slope has no jump at the 39 inner nodes, where a DOPRI5 step across each had its error estimate
    spoiled and was rejected (issue 29: an L/D 1.89 flight with a 5 % profile took 1.34x the right-hand sides of the
    undispersed one, with the spline 1.04x). The nodal values, which the Gauss-Markov draw sets, are the same."""
    values = np.zeros(2 * DENSITY_NODE_COUNT)
    values[:DENSITY_NODE_COUNT] = delta
    _natural_spline_curvature(values)
    return values


@njit
def _natural_spline_curvature(values: NDArray[np.float64]) -> None:
    """values[n:2n] = M, the second derivatives of the natural cubic spline through values[:n] at unit spacing:
    M[k-1] + 4 M[k] + M[k+1] = 6 (d[k+1] - 2 d[k] + d[k-1]), M[0] = M[n-1] = 0 (de Boor, A Practical Guide to
    Splines, ch. IV), by the Thomas algorithm (diagonally dominant: no pivoting)."""
    n = DENSITY_NODE_COUNT
    d, m = values[:n], values[n:]
    ratio = np.zeros(n)  # the eliminated superdiagonal
    m[0] = m[n - 1] = 0.0
    for k in range(1, n - 1):
        pivot = 4.0 - ratio[k - 1]
        ratio[k] = 1.0 / pivot
        m[k] = (6.0 * (d[k + 1] - 2.0 * d[k] + d[k - 1]) - m[k - 1]) / pivot
    for k in range(n - 3, 0, -1):
        m[k] -= ratio[k] * m[k + 1]


@njit(allocates=False)
def density_factor(profile: NDArray[np.float64], start: int, altitude_ft: float) -> float:
    """1 + delta(h), profile[start:start + 2 DENSITY_NODE_COUNT] a density_profile: the natural cubic spline through
    delta at DENSITY_NODES_FT, held below the first node and above the last (and at a NaN altitude, the first); kept
    above half the lower of the two nodes' factors where a spline through extreme nodes would dip towards zero."""
    x = altitude_ft / DENSITY_NODE_SPACING_FT
    last = DENSITY_NODE_COUNT - 1
    delta_h: float  # one return of a typed value (numpy types an array's item as Any)
    if not x > 0.0:
        delta_h = profile[start]
    elif x >= last:
        delta_h = profile[start + last]
    else:
        i = int(x)
        w = x - i
        d0, d1 = profile[start + i], profile[start + i + 1]
        m0, m1 = profile[start + DENSITY_NODE_COUNT + i], profile[start + DENSITY_NODE_COUNT + i + 1]
        # the chord, then the cubic terms (w^3 - w) m1 / 6 + ((1 - w)^3 - (1 - w)) m0 / 6, factored
        delta_h = d0 + w * (d1 - d0) - w * (1.0 - w) * ((2.0 - w) * m0 + (1.0 + w) * m1) / 6.0
        delta_h = max(delta_h, 0.5 * (1.0 + min(d0, d1)) - 1.0)
    return 1.0 + delta_h


@njit(allocates=False)
def _nearest_between(nodes: NDArray[np.float64], from_value: float, to_value: float) -> float:
    """The node strictly between from_value and to_value nearest from_value (NaN if none); nodes ascending."""
    found = math.nan
    if to_value > from_value:
        for node in nodes:
            if node > to_value:
                break
            if node > from_value and node < to_value:
                return float(node)
    else:
        for node in nodes:
            if node >= from_value:
                break
            if node > to_value:
                found = float(node)
    return found


@njit(allocates=False)
def kink_between_ft(model: int, from_ft: float, to_ft: float) -> float:
    """The altitude (ft) strictly between from_ft and to_ft nearest from_ft where the model's density or speed of
    sound has a kink (a layer base; a row of the upper US 1976 table); NaN if none."""
    if model == ARDC1959:
        return _nearest_between(ARDC_KINK_ALTITUDE_FT, from_ft, to_ft)
    if model == US1976:
        return _nearest_between(US1976_KINK_ALTITUDE_FT, from_ft, to_ft)
    return math.nan


@njit(allocates=False)
def density_kink_between_ft(profile: NDArray[np.float64], start: int, from_ft: float, to_ft: float) -> float:
    """The end node of DENSITY_NODES_FT (0 or 400,000 ft) strictly between from_ft and to_ft where density_factor's
    spline meets its held value with a slope (profile[start:] a density_profile); NaN if none. The spline has no kink
    at the inner nodes."""
    found = math.nan
    n = DENSITY_NODE_COUNT
    for i in (0, n - 1):
        node = DENSITY_NODES_FT[i]
        if not (from_ft < node < to_ft or to_ft < node < from_ft):
            continue
        j = 0 if i == 0 else n - 2  # the interval next to the end node: the spline's slope there
        d0, d1 = profile[start + j], profile[start + j + 1]
        m0, m1 = profile[start + n + j], profile[start + n + j + 1]
        slope = d1 - d0 - ((2.0 * m0 + m1) if i == 0 else -(m0 + 2.0 * m1)) / 6.0
        if slope == 0.0:
            continue
        if not (abs(node - from_ft) >= abs(found - from_ft)):
            found = node
    return found


@njit
def _density_factor_fill(
    profile: NDArray[np.float64], altitudes_ft: NDArray[np.float64], out: NDArray[np.float64]
) -> None:
    for k in range(altitudes_ft.shape[0]):
        out[k] = density_factor(profile, 0, altitudes_ft[k])


def density_factor_table(profile: ArrayLike, altitudes_ft: ArrayLike) -> NDArray[np.float64]:
    """density_factor at many altitudes (ft): an array shaped like `altitudes_ft`; `profile` a density_profile (as
    a flight's parameters hold it: the spline is not solved again)."""
    profile = np.ascontiguousarray(profile, dtype=np.float64)
    if profile.shape != (2 * DENSITY_NODE_COUNT,):
        raise ValueError(f"profile: {profile.shape} values, need {2 * DENSITY_NODE_COUNT} (density_profile(delta))")
    altitudes = np.asarray(altitudes_ft, dtype=np.float64)
    flat = np.ascontiguousarray(altitudes.ravel())
    out = np.empty_like(flat)
    _density_factor_fill(profile, flat, out)
    return out.reshape(altitudes.shape)


@njit
def _atmosphere_fill(
    model: int,
    altitudes_ft: NDArray[np.float64],
    rho0: float,
    scale_height: float,
    temperature: float,
    rho: NDArray[np.float64],
    p: NDArray[np.float64],
    t: NDArray[np.float64],
    a: NDArray[np.float64],
) -> None:
    for k in range(altitudes_ft.shape[0]):
        rho[k], p[k], t[k], a[k] = atmosphere(model, altitudes_ft[k], rho0, scale_height, temperature)


def atmosphere_table(
    model: int | str,
    altitudes_ft: ArrayLike,
    rho0_slug_ft3: float = EXPONENTIAL_RHO0_DEFAULT_SLUG_FT3,
    scale_height_ft: float = EXPONENTIAL_SCALE_HEIGHT_DEFAULT_FT,
    temperature_R: float | None = None,
) -> dict[str, NDArray[np.float64]]:
    """The atmosphere at many geometric altitudes (ft), for tests and plots.

    `model` is an id (ARDC1959, US1976, EXPONENTIAL) or a name of MODEL_IDS. For EXPONENTIAL,
    `temperature_R` defaults to isothermal_temperature_R(scale_height_ft). Returns arrays shaped like
    `altitudes_ft` under the keys density_slug_ft3, pressure_psf, temperature_R, speed_of_sound_fps.
    """
    model_id = MODEL_IDS.get(model, -1) if isinstance(model, str) else int(model)
    if model_id not in MODEL_IDS.values():
        raise ValueError(f"model: {model!r} is not one of {sorted(MODEL_IDS)} or ids {sorted(MODEL_IDS.values())}")
    if temperature_R is None:
        temperature_R = isothermal_temperature_R(scale_height_ft)
    altitudes = np.asarray(altitudes_ft, dtype=np.float64)
    flat = np.ascontiguousarray(altitudes.ravel())
    out = [np.empty_like(flat) for _ in range(4)]
    _atmosphere_fill(model_id, flat, float(rho0_slug_ft3), float(scale_height_ft), float(temperature_R), *out)
    keys = ("density_slug_ft3", "pressure_psf", "temperature_R", "speed_of_sound_fps")
    return {key: values.reshape(altitudes.shape) for key, values in zip(keys, out)}
