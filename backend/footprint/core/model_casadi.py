"""The flight model of the integrator written as CasADi expressions, for the collocation transcription.

State (r ft, longitude rad, geocentric latitude rad, V ft/s, gamma rad, psi rad): the spherical form of the
earth-relative motion of eqs. (1)-(3) with the forces of App. A (lift and drag in wind axes, coordinated turn,
no side force; oblate gravity A10 through gravity.zonal_down_north; Coriolis and centrifugal terms of the
rotating frame). psi is the heading (azimuth from north, clockwise) and gamma the flight-path angle, both in
the local geocentric horizon, as in App. A and core.frames; a positive bank turns left.

The spherical coordinates may be those of any earth-fixed frame (FlightModel's `axis`: the planet's axis of
rotation and symmetry in it): the collocation takes the frame whose equator is the entry's great circle, so that
a flight over a geographic pole stays far from the coordinates' own poles, where longitude and heading are singular.

Where this model differs from the integrator's (core.dynamics), and why:
  * tables (Appendix B aero in Mach x alpha [x altitude], Table 1) and the ARDC 1959 / US 1976 atmospheres
    are cubic B-spline interpolants through the same nodes (IPOPT needs continuous derivatives); the
    integrator interpolates linearly. The re-flight of every optimum by core.trajectory.simulate measures
    the difference (collocation.Result.agreement).
  * the altitude in the equations of motion is the height above the ellipsoid along the radius
    (radial_altitude_ft), up to 2.2 ft above the geodetic altitude below 400,000 ft; final latitudes are geodetic.
  * polynomial aerodynamics are not held at the ends of their alpha range: the NLP's alpha bounds lie inside it.
  * nothing else: the same constants and gravity (App. A eq. (A10) through the integrator's own lines).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core import constants as c
from footprint.core._jit import python_function
from footprint.core.aero import FORM_LIFT_DRAG, FORM_NORMAL_AXIAL, FORM_POLYNOMIAL
from footprint.core.atmosphere import (
    ARDC_GAS_CONSTANT_FT2_S2_R,
    EXPONENTIAL,
    MODEL_IDS,
    atmosphere_table,
    isothermal_temperature_R,
)
from footprint.core.gravity import zonal_down_north
from footprint.core.heating import (
    CP_AIR_BTU_LBM_R,
    DKR_COLD_WALL_R,
    DKR_Q_BTU_FT2_S,
    DKR_RHO_SL_SLUG_FT3,
    DKR_V_EXPONENT,
    DKR_V_FPS,
    FT2_S2_PER_BTU_LBM,
    SIGMA_REPORT_BTU_FT2_S_R4,
    CorrelationHeating,
    ReferenceHeating,
)
from footprint.core.trajectory import FlightSpec

_zonal = python_function(zonal_down_north)  # App. A eq. (A10), the integrator's own lines
# spline nodes of the tabulated atmospheres. The cubic spline overshoots at the layers' temperature-gradient
# corners (11, 25, 47, 53, 79, 90 km') by up to 0.17 % in density, 0.09 % in the speed of sound, falling 3.7x
# per node away (tests/core/test_model_casadi.py); finer nodes cost IPOPT in proportion (500 ft: 13x per iteration)
ATMOSPHERE_GRID_FT = np.arange(0.0, 1_200_001.0, 2_000.0)
# a number or a CasADi expression (SX, MX, DM) alike: the functions below build the NLP's expressions from SX or MX
# symbols and evaluate the same lines on floats. Any: CasADi's stubs type SX, MX and DM, but no union of them checks
# (their operators take one kind each, and ca.if_else of floats is a DM)
Expr = Any


@dataclass(frozen=True)
class PlanetModel:
    radius_ft: float
    polar_radius_ft: float
    mu_ft3_s2: float
    j: float
    h: float
    k_zonal: float
    omega_rad_s: float
    oblate: bool


def planet_model(spec: FlightSpec) -> PlanetModel:
    pl = spec.planet
    return PlanetModel(
        pl.radius_ft,
        pl.polar_radius_ft,
        pl.mu_ft3_s2,
        pl.j,
        pl.h,
        pl.k,
        np.radians(pl.rotation_rate_deg_s) if pl.rotating else 0.0,
        pl.oblate,
    )


def geodetic(pm: PlanetModel, r: Expr, lat_c: Expr) -> tuple[Expr, Expr]:
    """(geodetic latitude rad, altitude ft) of a point at radius r, geocentric latitude lat_c: one Bowring
    step (Survey Review 23, 1976), as core.frames.altitude_ft; spherical: (lat_c, r - R_e)."""
    if not pm.oblate:
        return lat_c, r - pm.radius_ft
    re, rp = pm.radius_ft, pm.polar_radius_ft
    e2 = 1.0 - rp * rp / (re * re)
    ep2 = re * re / (rp * rp) - 1.0
    p, z = r * ca.cos(lat_c), r * ca.sin(lat_c)
    beta = ca.atan2(re * z, rp * p)
    sb, cb = ca.sin(beta), ca.cos(beta)
    lat = ca.atan2(z + ep2 * rp * sb**3, p - e2 * re * cb**3)
    sl, cl = ca.sin(lat), ca.cos(lat)
    return lat, p * cl + z * sl - re * ca.sqrt(1.0 - e2 * sl * sl)


def radial_altitude_ft(pm: PlanetModel, r: Expr, sin_lat_c: Expr) -> Expr:
    """Height above the ellipsoid along the radius, r - R_e R_p / sqrt(R_p^2 cos^2 + R_e^2 sin^2) of the
    geocentric latitude: the equations of motion's altitude (cheap for the NLP's derivatives). It differs from the
    geodetic altitude by O(f^2 h): under 3 ft below 400,000 ft (tests/core/test_model_casadi.py)."""
    if not pm.oblate:
        return r - pm.radius_ft
    re, rp = pm.radius_ft, pm.polar_radius_ft
    return r - re * rp / ca.sqrt(rp * rp + (re * re - rp * rp) * sin_lat_c * sin_lat_c)


def _clamped(x: Expr, lo: float, hi: float) -> Expr:
    return ca.fmin(ca.fmax(x, lo), hi)


class Atmosphere:
    """(density slug/ft^3, temperature degR, speed of sound ft/s) at a geometric altitude (ft)."""

    def __init__(self, spec: FlightSpec) -> None:
        pl = spec.planet
        self.model = MODEL_IDS[pl.atmosphere]
        self.rho0, self.scale_ft = pl.rho0_slug_ft3, pl.scale_height_ft
        self.temperature_R = (
            pl.temperature_R if pl.temperature_R is not None else isothermal_temperature_R(pl.scale_height_ft)
        )
        if self.model != EXPONENTIAL:
            tab = atmosphere_table(self.model, ATMOSPHERE_GRID_FT)
            grid = [ATMOSPHERE_GRID_FT]
            self._ln_rho = ca.interpolant("ln_rho", "bspline", grid, np.log(tab["density_slug_ft3"]))
            self._t = ca.interpolant("t_inf", "bspline", grid, tab["temperature_R"])
            self._a = ca.interpolant("sound", "bspline", grid, tab["speed_of_sound_fps"])

    def __call__(self, altitude_ft: Expr) -> tuple[Expr, Expr, Expr]:
        if self.model == EXPONENTIAL:  # rho = rho0 exp(-h/H), isothermal (core.atmosphere)
            gas = ARDC_GAS_CONSTANT_FT2_S2_R
            return (
                self.rho0 * ca.exp(-altitude_ft / self.scale_ft),
                self.temperature_R,
                np.sqrt(c.GAMMA_AIR * gas * self.temperature_R),
            )
        h = _clamped(altitude_ft, ATMOSPHERE_GRID_FT[0], ATMOSPHERE_GRID_FT[-1])
        return ca.exp(self._ln_rho(h)), self._t(h), self._a(h)


def _ramp(z: Expr, eps: Expr) -> Expr:
    """max(z, 0) with its corner rounded on |z| < eps by the C2 blend (z + eps)^3 (3 eps - z) / (16 eps^3):
    equal to max(z, 0) outside, so a table is the integrator's own linear table away from its nodes."""
    blend = (z + eps) ** 3 * (3.0 * eps - z) / (16.0 * eps**3)
    return ca.if_else(z <= -eps, 0.0, ca.if_else(z >= eps, z, blend))


def _segment_fractions(axis: NDArray[np.float64], x: Expr, smoothing: Expr) -> list[Expr]:
    """S_k(x), k = 0..n-2: how much of interval k lies below x (0 to 1), corners rounded:
    (R(x - x_k) - R(x - x_k+1)) / h_k with R the rounded ramp over eps = smoothing x the shortest interval."""
    h = np.diff(axis)
    eps = smoothing * h.min()
    ramp = [_ramp(x - xk, eps) for xk in axis]
    return [(ramp[k] - ramp[k + 1]) / h[k] for k in range(len(h))]


def _hat_weights(axis: NDArray[np.float64], x: Expr, smoothing: Expr) -> Expr:
    """Weights of the nodes of one axis at x: the hats of linear interpolation held at the ends, corners
    rounded; they sum to exactly 1, and reproduce the integrator's linear interpolation away from the nodes."""
    s = _segment_fractions(axis, x, smoothing)
    return ca.vertcat(1.0 - s[0], *[s[k - 1] - s[k] for k in range(1, len(s))], s[-1])


def smooth_table(axes: Sequence[ArrayLike], values: ArrayLike) -> Callable[..., Expr]:
    """f(x_1, ..., x_d, smoothing): multilinear interpolation of values (shape = axis lengths) held at the
    edges, as core.aero.lookup does, with the corners at the nodes rounded (over `smoothing` of the shortest
    interval of each axis) so that IPOPT sees continuous derivatives. Axes of one node are constant."""
    axis_arrays: list[NDArray[np.float64]] = [np.asarray(a, float) for a in axes]
    values = np.asarray(values, float)

    def f(*args: Expr) -> Expr:
        *x, smoothing = args
        # contract the last axis first: t[i..] = sum_k values[i.., k] w_k (linear in each axis' weights)
        t: Expr = values.reshape(-1, values.shape[-1]) if values.ndim > 1 else values.reshape(1, -1)  # then DM, SX/MX
        t = ca.DM(t)
        for axis, xi, size in zip(reversed(axis_arrays), reversed(x), reversed(values.shape)):
            rows = t.shape[0] * t.shape[1] // size
            t = ca.reshape(ca.vec(t.T), size, rows).T if t.shape[1] != size else t
            t = ca.mtimes(t, _hat_weights(axis, xi, smoothing)) if size > 1 else t[:, 0]
        return t[0]

    return f


def _table_function(blob: NDArray[np.float64], offset: float) -> Callable[..., Expr]:
    """A table of the aero blob (layout: core.aero) as a smoothed multilinear function of (Mach, alpha, h)."""
    o = int(offset)
    n_m, n_a, n_h = (int(blob[o + i]) for i in range(3))
    s = o + 3
    axes = [blob[s : s + n_m], blob[s + n_m : s + n_m + n_a], blob[s + n_m + n_a : s + n_m + n_a + n_h]]
    values = blob[s + n_m + n_a + n_h : s + n_m + n_a + n_h + n_m * n_a * n_h].reshape(n_m, n_a, n_h)
    return smooth_table(axes, values)


class Aerodynamics:
    """(CL, CD) at Mach, alpha (deg), altitude (ft), as core.aero.coefficients."""

    def __init__(self, blob: NDArray[np.float64]) -> None:
        self.form = int(blob[0])
        self.alpha_range_deg = (float(blob[1]), float(blob[2]))
        if self.form == FORM_POLYNOMIAL:
            self._poly = [blob[int(o) + 1 : int(o) + 1 + int(blob[int(o)])].copy() for o in (blob[3], blob[4])]
        else:
            self._first = _table_function(blob, blob[3])
            self._second = _table_function(blob, blob[4])

    def __call__(self, mach: Expr, alpha_deg: Expr, altitude_ft: Expr, smoothing: Expr) -> tuple[Expr, Expr]:
        if self.form == FORM_POLYNOMIAL:
            a = alpha_deg
            return tuple(sum(coef * a**i for i, coef in enumerate(p)) for p in self._poly)
        c1 = self._first(mach, alpha_deg, altitude_ft, smoothing)
        c2 = self._second(mach, alpha_deg, altitude_ft, smoothing)
        if self.form == FORM_LIFT_DRAG:
            return c1, c2
        assert self.form == FORM_NORMAL_AXIAL
        a = alpha_deg * (np.pi / 180.0)  # body to wind axes, as core.aero.coefficients
        return c1 * ca.cos(a) - c2 * ca.sin(a), c1 * ca.sin(a) + c2 * ca.cos(a)


class Heating:
    """Heat rate and the path constraint of a temperature limit, for core.heating's two models."""

    def __init__(self, model: ReferenceHeating | CorrelationHeating) -> None:
        self.model = model
        if isinstance(model, ReferenceHeating):
            if model.skin_heat_capacity_btu_ft2_R > 0.0:
                raise ValueError(
                    "heating.skin_heat_capacity_btu_ft2_R: the collocation solves radiation-equilibrium "
                    "temperatures only (0)"
                )
            self._ratio = smooth_table([model.ratio_alpha_deg], model.ratio)  # Table 1, eq. (5)

    def coefficient(self, rho: Expr, v: Expr, t_inf: Expr, alpha_deg: Expr, smoothing: Expr) -> tuple[Expr, Expr]:
        """(h lbm/(ft^2 s), H_AW Btu/lbm) of eqs. (5)-(6): Fay-Riddell (Detra-Kemp-Riddell form) times Table 1."""
        m = self.model
        assert isinstance(m, ReferenceHeating)  # the reference model's coefficient: temperature_margin calls it so
        h0 = CP_AIR_BTU_LBM_R * t_inf + 0.5 * v * v / FT2_S2_PER_BTU_LBM
        q_cw = (
            DKR_Q_BTU_FT2_S
            / np.sqrt(m.reference_radius_ft)
            * ca.sqrt(rho / DKR_RHO_SL_SLUG_FT3)
            * (v / DKR_V_FPS) ** DKR_V_EXPONENT
        )
        # core.heating sets h = 0 where H_0 <= the cold-wall enthalpy (below ~2,200 ft/s); a floor of 1 Btu/lbm
        # keeps the NLP's derivatives finite there instead (the stop altitudes lie above that speed)
        drive = ca.fmax(h0 - CP_AIR_BTU_LBM_R * DKR_COLD_WALL_R, 1.0)
        ratio = self._ratio(alpha_deg, smoothing)
        return q_cw / drive * ratio, h0

    def correlation_rate(self, rho: Expr, v: Expr, alpha_deg: Expr) -> Expr:
        m = self.model  # q = C rho^a V^b f(alpha) (core.heating.CorrelationHeating)
        assert isinstance(m, CorrelationHeating)  # temperature_margin and heat_rate call it for this model only
        f = sum(coef * alpha_deg**i for i, coef in enumerate(m.alpha_polynomial))
        return m.coefficient * rho**m.density_exponent * v**m.velocity_exponent * f

    def temperature_margin(
        self, rho: Expr, v: Expr, t_inf: Expr, alpha_deg: Expr, limit_R: float, smoothing: Expr
    ) -> Expr:
        """<= 0 exactly when the wall temperature is within limit_R, scaled by the radiated flux at the limit.

        Reference model: eqs. (6)-(7) give T as the root of eps sigma T^4 + h c_p T - h H_AW, increasing in
        h H_AW, so T <= T_lim  <=>  h (H_AW - c_p T_lim) <= eps sigma T_lim^4 (no root to solve in the NLP).
        Correlation with an emissivity: eq. (7), T <= T_lim  <=>  q <= eps sigma T_lim^4."""
        m = self.model
        if m.emissivity is None:
            raise ValueError("max_temperature_R: the correlation heating model needs an emissivity for a temperature")
        radiated = SIGMA_REPORT_BTU_FT2_S_R4 * m.emissivity * limit_R**4
        if isinstance(m, ReferenceHeating):
            h, h_aw = self.coefficient(rho, v, t_inf, alpha_deg, smoothing)
            return h * (h_aw - CP_AIR_BTU_LBM_R * limit_R) / radiated - 1.0
        return self.correlation_rate(rho, v, alpha_deg) / radiated - 1.0

    def heat_rate(self, rho: Expr, v: Expr, t_inf: Expr, alpha_deg: Expr) -> Expr:
        """q (Btu/(ft^2 s)) of the correlation model (the reference model's q depends on the wall temperature,
        which the NLP does not carry: it constrains max_temperature_R instead)."""
        if isinstance(self.model, ReferenceHeating):
            raise ValueError(
                "max_heat_rate_btu_ft2_s / heat_load_btu_ft2: with the reference heating model the "
                "collocation constrains max_temperature_R; use a correlation model for heat rates"
            )
        return self.correlation_rate(rho, v, alpha_deg)


class FlightModel:
    """Rates of the spherical state and the derived quantities, as CasADi expressions."""

    def __init__(self, spec: FlightSpec, axis: ArrayLike = (0.0, 0.0, 1.0)) -> None:
        """axis: the planet's axis (unit vector) in the frame of the state's spherical coordinates; the default is
        the geographic frame. Components that are exactly 0 drop their terms from the expressions."""
        self.spec = spec
        self.axis = tuple(float(k) for k in np.asarray(axis, dtype=float))
        self.planet = planet_model(spec)
        self.atmosphere = Atmosphere(spec)
        self.aero = Aerodynamics(spec.vehicle.blob)
        self.heating = None if spec.heating is None else Heating(spec.heating)
        # smoothed tables (aero or Table 1) make the solution depend on the corners' width
        self.smoothed = self.aero.form != FORM_POLYNOMIAL or isinstance(spec.heating, ReferenceHeating)
        self.lift_per_cl_per_q = c.G0_FT_S2 / spec.vehicle.wing_loading_psf  # L/m = CL q g0 / (W/S)

    def point(self, state: Expr, alpha_deg: Expr, bank_deg: Expr, smoothing: Expr) -> dict[str, Expr]:
        """Everything at one state: a dict of CasADi expressions (rates under 'rates')."""
        pm = self.planet
        r, lon, lat, v, gam, psi = (state[i] for i in range(6))
        s, cs = ca.sin(lat), ca.cos(lat)
        # the planet's axis k in the (up, east, north) horizon of the state's frame; k_up is the sine of the
        # geographic geocentric latitude (geographic frame: s, 0, cs)
        kx, ky, kz = self.axis
        so, co = ca.sin(lon), ca.cos(lon)
        k_up = kx * cs * co + ky * cs * so + kz * s
        k_east = -kx * so + ky * co
        k_north = -kx * s * co - ky * s * so + kz * cs
        g0 = pm.mu_ft3_s2 / (r * r)
        if pm.oblate:
            g_down, g_north_over_cos = _zonal(g0, k_up, pm.radius_ft / r, pm.j, pm.h, pm.k_zonal)
        else:
            g_down, g_north_over_cos = g0, 0.0
        # App. A (A10): g = -g_down u + g_north n_geographic, and cos(lat) n_geographic = k - k_up u
        alt = radial_altitude_ft(pm, r, k_up)
        rho, t_inf, sound = self.atmosphere(alt)
        mach = v / sound
        cl, cd = self.aero(mach, alpha_deg, alt, smoothing)
        qbar = 0.5 * rho * v * v
        lift, drag = cl * qbar * self.lift_per_cl_per_q, cd * qbar * self.lift_per_cl_per_q
        w = pm.omega_rad_s
        sg, cg, sp, cp = ca.sin(gam), ca.cos(gam), ca.sin(psi), ca.cos(psi)
        v_up, v_east, v_north = v * sg, v * cg * sp, v * cg * cp
        # gravity, Coriolis -2 w k x v and centrifugal w^2 r (u - k_up k) in the (up, east, north) horizon (a
        # right-handed basis), eqs. (1)-(2)
        a_up = -g_down - 2.0 * w * (k_east * v_north - k_north * v_east) + w * w * r * (1.0 - k_up * k_up)
        a_east = g_north_over_cos * k_east - 2.0 * w * (k_north * v_up - k_up * v_north) - w * w * r * k_up * k_east
        a_north = g_north_over_cos * k_north - 2.0 * w * (k_up * v_east - k_east * v_up) - w * w * r * k_up * k_north
        bank = bank_deg * (np.pi / 180.0)
        rates = ca.vertcat(
            v_up,  # dr/dt
            v_east / (r * cs),  # dlongitude/dt
            v_north / r,  # dlatitude/dt
            -drag + a_up * sg + a_east * cg * sp + a_north * cg * cp,  # dV/dt: along the velocity
            (lift * ca.cos(bank) + a_up * cg - a_east * sg * sp - a_north * sg * cp) / v + v * cg / r,  # dgamma/dt
            (-lift * ca.sin(bank) + a_east * cp - a_north * sp) / (v * cg) + v * cg * sp * s / (cs * r),  # dpsi/dt
        )
        return {
            "rates": rates,
            "altitude_ft": alt,
            "rho": rho,
            "t_inf": t_inf,
            "mach": mach,
            "q_psf": qbar,
            "cl": cl,
            "cd": cd,
            "load_factor": qbar * ca.sqrt(cl * cl + cd * cd) / self.spec.vehicle.wing_loading_psf,
        }
