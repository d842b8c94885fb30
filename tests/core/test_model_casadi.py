"""core.model_casadi (the collocation's flight model) against the integrator and the core's models, by
independent routes; no number of the model is checked against another of its own.

Routes:
* Equations of motion. At an earth-fixed state, core.dynamics.evaluate gives the integrator's cartesian
  acceleration a. The state is stepped by +-dt with a second-order Taylor step (x +- v dt + a dt^2/2,
  v +- a dt), turned into (r, longitude, geocentric latitude, V, gamma, heading) with core.frames, and
  central-differenced (Richardson over dt and 2 dt): d/dt of the spherical state under the integrator's
  forces, compared with FlightModel.point(...)['rates'].
  - exact forces: polynomial aero and an exponential atmosphere (uniform on the oblate earth, so that the
    model's radial altitude gives the integrator's density), on the rotating oblate earth and the
    non-rotating sphere: kinematics, gravity, rotation and force directions agree to round-off;
  - tables: the built-in L/D 1.89 vehicle and ARDC 1959, at states away from table nodes and atmosphere
    layer kinks: the aerodynamic terms differ only by the B-spline atmosphere and the radial altitude.
* Altitude: radial_altitude_ft and geodetic() at points placed by frames.ecef_from_geodetic.
* Tables: smooth_table against core.aero.lookup on the built-in L/D 1.89 CL and CD tables.
* Atmosphere: the B-splines against core.atmosphere.atmosphere_table.
* Heating: the sign of Heating.temperature_margin against ReferenceHeating.evaluate's temperature.
"""

import dataclasses
import math

import casadi as ca
import numpy as np
import pytest

from footprint.contracts.vehicle import user_vehicle
from footprint.core.aero import builtin_vehicle, lookup
from footprint.core.atmosphere import ARDC_BASE_ALTITUDE_FT, ARDC_EARTH_RADIUS_FT, atmosphere_table
from footprint.core.collocation import SMOOTHING_STAGES
from footprint.core.constants import G0_FT_S2
from footprint.core.controls import pack_controls
from footprint.core.dynamics import M_BANK_ACTIVE, M_SIZE, evaluate
from footprint.core.frames import (
    altitude_ft,
    ecef_from_geodetic,
    flight_angles,
    geodetic_from_ecef,
    velocity_from_angles,
)
from footprint.core.heating import TABLE1_ALPHA_DEG, ReferenceHeating
from footprint.core.model_casadi import (
    ATMOSPHERE_GRID_FT,
    Atmosphere,
    FlightModel,
    Heating,
    geodetic,
    planet_model,
    radial_altitude_ft,
    smooth_table,
)
from footprint.core.sphere import great_circle_frame
from footprint.core.trajectory import Entry, FlightSpec, Planet, pack_parameters

LOD189 = builtin_vehicle("lod-1.89")
POLYNOMIAL_VEHICLE = user_vehicle(
    {
        "name": "polynomial test vehicle",
        "wing_loading_psf": 60.0,
        "aero": {"polynomial": {"cl": [-0.05, 0.035], "cd": [0.06, 0.0, 0.0006]}},  # alpha in deg, L/D ~2.2 at 20
    }
)
# rotating oblate earth, density 1e-6 slug/ft^3 (that of ~130,000 ft) falling by 3e-9 over the <= 3 ft between
# the model's radial and the integrator's geodetic altitude: the same density on both sides
OBLATE_UNIFORM_AIR = Planet(atmosphere="exponential", rho0_slug_ft3=1e-6, scale_height_ft=1e9, temperature_R=400.0)
SPHERE = Planet(rotating=False, oblate=False, atmosphere="exponential")  # radial altitude = geodetic altitude
ARDC_EARTH = Planet()  # App. A rotating oblate earth, ARDC 1959
SMOOTHING = SMOOTHING_STAGES[-1]  # the collocation's final corner width

# (geodetic lat deg, lon deg, altitude ft, V ft/s, gamma deg, heading deg, alpha deg, bank deg): away from the
# L/D 1.89 table nodes (Mach, alpha, altitude) and the ARDC layer kinks (checked in the table test)
STATES = [
    (60.0, 10.0, 210_000.0, 19_000.0, -2.0, 30.0, 22.3, 35.0),
    (-60.0, -100.0, 280_000.0, 25_000.0, 3.0, 200.0, 33.7, -60.0),
    (20.0, 45.0, 120_000.0, 6_500.0, -5.0, 90.0, 13.9, 0.0),
    (0.0, 0.0, 161_300.0, 15_000.0, 0.0, 90.0, 22.3, -35.0),
    (35.0, 170.0, 235_000.0, 11_000.0, -1.0, 90.0, 33.7, 80.0),
    (-35.0, -45.0, 105_000.0, 5_600.0, -3.0, 200.0, 13.9, 60.0),
]
STATE_IDS = [f"lat{c[0]:+.0f}-hdg{c[5]:.0f}-bank{c[7]:+.0f}" for c in STATES]

# frames for the spherical coordinates (rows: their axes in earth-fixed components): the geographic one, and the
# entry great circle's of an entry at 40 N, 150 E heading north (the collocation's frame for a flight over the pole)
IDENTITY = np.eye(3)
POLAR_ENTRY_FRAME = np.array(great_circle_frame(40.0, 150.0, 0.0))
NEAR_POLE = (89.95, 30.0, 210_000.0, 19_000.0, -2.0, 170.0, 22.3, 35.0)  # 0.05 deg from the north pole

FD_STEP_S = 0.01
# Rates relative to |rate| + its natural size (_rate_units): the Richardson difference has truncation
# O((dt/T)^4) ~ 1e-14 for time scales T >= 25 s and round-off eps r / (V dt) <= 1e-8 (r ~ 2e7 ft, V dt >= 56 ft)
RATE_REL = 1e-7
# Tabled run: lift and drag scale with density. The ARDC B-spline is within 1.2e-4 of the table two nodes away
# from a layer kink (test_ardc1959_splines_between_the_nodes), the radial altitude <= 3 ft above the geodetic moves
# it by 3 ft / (scale height >= 20,000 ft) = 1.5e-4, and Mach (speed of sound 6e-5) moves CL, CD by less.
AERO_REL = 5e-4
ALTITUDE_GAP_FT = 3.0  # radial height above the ellipsoid minus geodetic altitude, below 400,000 ft
ARDC_KINKS_FT = ARDC_EARTH_RADIUS_FT * ARDC_BASE_ALTITUDE_FT[1:] / (ARDC_EARTH_RADIUS_FT - ARDC_BASE_ALTITUDE_FT[1:])
KINK_CLEARANCE_FT = 2 * (ATMOSPHERE_GRID_FT[1] - ATMOSPHERE_GRID_FT[0])  # two spline intervals


# --- helpers ------------------------------------------------------------------------------------------------


def _spec(vehicle, planet, alpha_deg, bank_deg):
    ctrl = pack_controls(
        bank_law="constant", bank_deg=bank_deg, bank_start="entry", alpha_law="constant", alpha_deg=alpha_deg
    )
    return FlightSpec(
        vehicle=vehicle,
        planet=planet,
        entry=Entry(200_000.0, 20_000.0, -1.0),  # unused here
        ctrl=ctrl,
    )


def _ecef_state(planet, lat_deg, lon_deg, alt_ft, v_fps, gamma_deg, heading_deg):
    x, y, z = ecef_from_geodetic(
        math.radians(lat_deg), math.radians(lon_deg), alt_ft, planet.radius_ft, planet.polar_radius_ft, planet.oblate
    )
    return np.array(
        [x, y, z, *velocity_from_angles(x, y, z, v_fps, math.radians(gamma_deg), math.radians(heading_deg))]
    )


def _spherical(s, frame=IDENTITY):
    """(r ft, longitude rad, geocentric latitude rad, V ft/s, gamma rad, heading rad) of an earth-fixed state, in
    the coordinates of `frame` (rows: its axes in earth-fixed components)."""
    s = np.concatenate([frame @ s[:3], frame @ s[3:]])
    x, y, z = s[:3]
    return np.array(
        [math.sqrt(x * x + y * y + z * z), math.atan2(y, x), math.atan2(z, math.hypot(x, y)), *flight_angles(*s)]
    )


def _integrator(spec, s):
    """core.dynamics.evaluate at s with the constant laws active."""
    mode = np.zeros(M_SIZE)
    mode[M_BANK_ACTIVE] = 1.0
    return evaluate(0.0, s, pack_parameters(spec), spec.vehicle.blob, spec.ctrl, mode)


def _central_difference(s, acceleration, dt, frame):
    x, v = s[:3], s[3:]
    plus = _spherical(np.concatenate([x + v * dt + 0.5 * acceleration * dt * dt, v + acceleration * dt]), frame)
    minus = _spherical(np.concatenate([x - v * dt + 0.5 * acceleration * dt * dt, v - acceleration * dt]), frame)
    d = plus - minus
    d[[1, 5]] = (d[[1, 5]] + math.pi) % (2.0 * math.pi) - math.pi  # longitude, heading: across the cut
    return d / (2.0 * dt)


def _integrator_rates(spec, s, frame=IDENTITY):
    """d/dt of the spherical state (in `frame`) under the integrator's acceleration (Richardson: error O(dt^4))."""
    acceleration = np.array(_integrator(spec, s)[:3])
    fine, coarse = (_central_difference(s, acceleration, dt, frame) for dt in (FD_STEP_S, 2.0 * FD_STEP_S))
    return (4.0 * fine - coarse) / 3.0


def _model_point(spec, state, alpha_deg, bank_deg, smoothing, frame=IDENTITY):
    """FlightModel.point as a CasADi Function of SX symbols (as the NLP builds it), evaluated at floats; the
    state's coordinates those of `frame`, where the planet's axis is frame @ z."""
    x, a, b, w = ca.SX.sym("x", 6), ca.SX.sym("alpha"), ca.SX.sym("bank"), ca.SX.sym("smoothing")
    out = FlightModel(spec, axis=frame[:, 2]).point(x, a, b, w)
    f = ca.Function("point", [x, a, b, w], [ca.SX(v) for v in out.values()], ["x", "a", "b", "w"], list(out))
    values = f(x=state, a=alpha_deg, b=bank_deg, w=smoothing)
    return {k: np.asarray(v, dtype=float).ravel() if k == "rates" else float(v) for k, v in values.items()}


def _rate_units(state):
    """Natural size of each rate: V for dr/dt, g0 for dV/dt, V/r (a great circle's turn rate) for the angles."""
    r_ft, v_fps = state[0], state[3]
    return np.array([v_fps, v_fps / r_ft, v_fps / r_ft, G0_FT_S2, v_fps / r_ft, v_fps / r_ft])


def _assert_within(actual, expected, tolerance, what):
    excess = np.abs(np.asarray(actual) - np.asarray(expected)) / tolerance
    assert np.all(excess <= 1.0), f"{what}: |model - reference| / tolerance = {np.array2string(excess, precision=3)}"


def _relative(actual, expected):
    return abs(actual / expected - 1.0)


def _blob_table(blob, offset):
    """(axes, values[mach][alpha][alt]) of the table at `offset` (layout: core.aero docstring)."""
    o = int(offset)
    sizes = [int(blob[o + i]) for i in range(3)]
    start, axes = o + 3, []
    for n in sizes:
        axes.append(blob[start : start + n].copy())
        start += n
    return axes, blob[start : start + int(np.prod(sizes))].reshape(sizes)


def _corner_widths(axes, smoothing):
    """smooth_table's rounding half-width per axis: smoothing x the shortest interval (0 for a one-node axis)."""
    return [smoothing * np.diff(a).min() if a.size > 1 else 0.0 for a in axes]


def _node_distance(axis, x):
    """Distance of each x to the nearest node of axis (inf for a one-node axis: the table is constant on it)."""
    x = np.atleast_1d(np.asarray(x, float))
    return np.abs(x[:, None] - axis[None, :]).min(axis=1) if axis.size > 1 else np.full(x.shape, np.inf)


def _casadi_map(fn, *columns):
    """fn (CasADi expressions of scalar arguments, one result or a tuple) evaluated at many points by map()."""
    args = [ca.SX.sym(f"a{i}") for i in range(len(columns))]
    out = fn(*args)
    f = ca.Function("f", args, [ca.SX(v) for v in (out if isinstance(out, tuple) else (out,))])
    values = f.map(len(columns[0]))(*columns)
    return [np.asarray(v, float).ravel() for v in (values if isinstance(values, tuple) else (values,))]


def _atmosphere_splines(planet, altitudes_ft):
    """(rho slug/ft^3, T degR, a ft/s) of model_casadi.Atmosphere at many altitudes."""
    return _casadi_map(Atmosphere(_spec(LOD189, planet, 0.0, 0.0)), altitudes_ft)


# --- 1. equations of motion ---------------------------------------------------------------------------------


@pytest.mark.parametrize("planet", [OBLATE_UNIFORM_AIR, SPHERE], ids=["rotating-oblate", "sphere"])
@pytest.mark.parametrize("case", STATES, ids=STATE_IDS)
def test_rates_match_the_integrator_with_exact_forces(planet, case):
    *where, alpha_deg, bank_deg = case
    spec = _spec(POLYNOMIAL_VEHICLE, planet, alpha_deg, bank_deg)
    s = _ecef_state(planet, *where)
    state = _spherical(s)
    res = _integrator(spec, s)
    assert (res[3], res[4]) == (alpha_deg, bank_deg)  # the constant laws fly the commanded angles
    model = _model_point(spec, state, alpha_deg, bank_deg, SMOOTHING)
    reference = _integrator_rates(spec, s)
    _assert_within(model["rates"], reference, RATE_REL * (np.abs(reference) + _rate_units(state)), "rates")
    # derived quantities: the same air and aero (the uniform air hides the <= 3 ft altitude gap)
    assert -1e-6 <= model["altitude_ft"] - res[9] <= (ALTITUDE_GAP_FT if planet.oblate else 1e-6)
    for key, i in (("rho", 14), ("q_psf", 6), ("cl", 7), ("cd", 8)):
        assert _relative(model[key], res[i]) <= 1e-8, key
    # model_casadi's exponential speed of sound takes constants.R_AIR_FT2_S2_R (287.0429, rounded), core.atmosphere
    # ARDC_GAS_CONSTANT_FT2_S2_R (287.042913): Mach differs by 2.3e-8
    assert _relative(model["mach"], res[5]) <= 1e-7
    # load factor: the aerodynamic acceleration is what the integrator loses without air (rho0 = 0), over g0
    vacuum = _spec(POLYNOMIAL_VEHICLE, dataclasses.replace(planet, rho0_slug_ft3=0.0), alpha_deg, bank_deg)
    aero_g = np.linalg.norm(np.subtract(res[:3], _integrator(vacuum, s)[:3])) / G0_FT_S2
    assert _relative(model["load_factor"], aero_g) <= 1e-8


@pytest.mark.parametrize("case", STATES, ids=STATE_IDS)
def test_rates_match_the_integrator_with_tables_and_ardc1959(case):
    *where, alpha_deg, bank_deg = case
    _, _, alt_ft, v_fps, _, _ = where
    spec = _spec(LOD189, ARDC_EARTH, alpha_deg, bank_deg)
    s = _ecef_state(ARDC_EARTH, *where)
    state = _spherical(s)
    res = _integrator(spec, s)
    # the premise: off every corner the smoothing rounds, and off the atmosphere's layer kinks
    mach = v_fps / atmosphere_table("ardc1959", np.array([alt_ft]))["speed_of_sound_fps"][0]
    for offset in LOD189.blob[3:5]:
        axes, _ = _blob_table(LOD189.blob, offset)
        for axis, x, eps in zip(axes, (mach, alpha_deg, alt_ft), _corner_widths(axes, SMOOTHING)):
            assert _node_distance(axis, x)[0] > eps
    assert np.abs(ARDC_KINKS_FT - alt_ft).min() > KINK_CLEARANCE_FT
    model = _model_point(spec, state, alpha_deg, bank_deg, SMOOTHING)
    reference = _integrator_rates(spec, s)
    aero_fps2 = res[6] * math.hypot(res[7], res[8]) * G0_FT_S2 / LOD189.wing_loading_psf  # |L + D| / m
    v, cos_gamma = state[3], math.cos(state[4])
    aero_units = np.array([0.0, 0.0, 0.0, aero_fps2, aero_fps2 / v, aero_fps2 / (v * cos_gamma)])
    tolerance = RATE_REL * (np.abs(reference) + _rate_units(state)) + AERO_REL * aero_units
    _assert_within(model["rates"], reference, tolerance, "rates")
    assert -1e-6 <= model["altitude_ft"] - res[9] <= ALTITUDE_GAP_FT
    for key, i in (("rho", 14), ("mach", 5), ("q_psf", 6), ("cl", 7), ("cd", 8)):
        assert _relative(model[key], res[i]) <= AERO_REL, key


@pytest.mark.parametrize("planet", [OBLATE_UNIFORM_AIR, SPHERE], ids=["rotating-oblate", "sphere"])
@pytest.mark.parametrize("case", [*STATES, NEAR_POLE], ids=[*STATE_IDS, "near-the-pole"])
def test_rates_in_the_entry_frame_match_the_integrator(planet, case):
    """The same equations in the coordinates of a frame whose poles are on the geographic equator: the planet's
    rotation and oblateness about a general axis, checked by the integrator's cartesian forces differenced in that
    frame, near the geographic north pole too."""
    *where, alpha_deg, bank_deg = case
    spec = _spec(POLYNOMIAL_VEHICLE, planet, alpha_deg, bank_deg)
    s = _ecef_state(planet, *where)
    state = _spherical(s, POLAR_ENTRY_FRAME)
    model = _model_point(spec, state, alpha_deg, bank_deg, SMOOTHING, POLAR_ENTRY_FRAME)
    reference = _integrator_rates(spec, s, POLAR_ENTRY_FRAME)
    _assert_within(model["rates"], reference, RATE_REL * (np.abs(reference) + _rate_units(state)), "rates")
    res = _integrator(spec, s)
    assert -1e-6 <= model["altitude_ft"] - res[9] <= (ALTITUDE_GAP_FT if planet.oblate else 1e-6)


# --- 2. altitude and latitude -------------------------------------------------------------------------------

LATITUDES_DEG = np.linspace(-90.0, 90.0, 181)
ALTITUDES_FT = np.linspace(0.0, 400_000.0, 21)


def _ellipsoid_points():
    """(geodetic lat rad, altitude ft, radius ft, geocentric lat rad, ECEF xyz ft) on a latitude x altitude grid."""
    pl = ARDC_EARTH
    lat, alt = (g.ravel() for g in np.meshgrid(np.radians(LATITUDES_DEG), ALTITUDES_FT))
    xyz = np.array([ecef_from_geodetic(la, 1.1, h, pl.radius_ft, pl.polar_radius_ft, True) for la, h in zip(lat, alt)])
    r = np.linalg.norm(xyz, axis=1)
    return lat, alt, r, np.arctan2(xyz[:, 2], np.hypot(xyz[:, 0], xyz[:, 1])), xyz


def test_radial_altitude_is_within_3_ft_above_the_geodetic():
    """The radius meets the ellipsoid off the normal, so the radial height exceeds the geodetic altitude (the
    shortest distance to the ellipsoid) by O(f^2 h): 2.2 ft at 45 deg, 400,000 ft."""
    pm = planet_model(_spec(LOD189, ARDC_EARTH, 0.0, 0.0))
    _, alt, r, lat_c, _ = _ellipsoid_points()
    (radial,) = _casadi_map(lambda r_, l_: radial_altitude_ft(pm, r_, ca.sin(l_)), r, lat_c)
    gap = radial - alt
    assert gap.min() >= -1e-6 and gap.max() <= ALTITUDE_GAP_FT


def test_geodetic_matches_frames():
    """One Bowring step: latitude as frames.geodetic_from_ecef (two steps) within 1e-9 rad, altitude as
    frames.altitude_ft within 1e-6 ft (both claim 1e-8 ft below 3,000,000 ft)."""
    pl = ARDC_EARTH
    pm = planet_model(_spec(LOD189, pl, 0.0, 0.0))
    lat, alt, r, lat_c, xyz = _ellipsoid_points()
    lat_model, alt_model = _casadi_map(lambda r_, l_: geodetic(pm, r_, l_), r, lat_c)
    lat_frames = np.array([geodetic_from_ecef(*p, pl.radius_ft, pl.polar_radius_ft, True)[0] for p in xyz])
    alt_frames = np.array([altitude_ft(*p, pl.radius_ft, pl.polar_radius_ft, True) for p in xyz])
    assert np.abs(lat_model - lat_frames).max() <= 1e-9
    assert np.abs(lat_model - lat).max() <= 1e-9
    assert np.abs(alt_model - alt_frames).max() <= 1e-6


# --- 3. smoothed tables -------------------------------------------------------------------------------------

TABLES = {"CL": LOD189.blob[3], "CD": LOD189.blob[4]}


def _sample_points(axes, widths, n, rng):
    """n points over each axis' range widened by 10 % and two corner widths each side (the held edges too)."""
    return [
        rng.uniform(a[0] - 0.1 * (a[-1] - a[0]) - 2 * eps, a[-1] + 0.1 * (a[-1] - a[0]) + 2 * eps, n)
        for a, eps in zip(axes, widths)
    ]


def _corner_bound(axes, values, smoothing):
    """max |smoothed - linear|: per axis the ramp's rounding at a node, 3 eps / 16, times the largest slope jump
    there (the held edges count as slope 0 outside); the other axes' weights are convex, so the axes add."""
    bound = 0.0
    for d, (axis, eps) in enumerate(zip(axes, _corner_widths(axes, smoothing))):
        if axis.size < 2:
            continue
        shape = [1] * values.ndim
        shape[d] = -1
        slopes = np.diff(values, axis=d) / np.diff(axis).reshape(shape)
        pad = [(0, 0)] * values.ndim
        pad[d] = (1, 1)
        bound += 3.0 * eps / 16.0 * np.abs(np.diff(np.pad(slopes, pad), axis=d)).max()
    return bound


def _near_nodes(axes, widths, n, rng):
    """n points within a corner width of a node on every axis."""
    return [rng.choice(a, n) + rng.uniform(-1.0, 1.0, n) * eps for a, eps in zip(axes, widths)]


@pytest.mark.parametrize("smoothing", SMOOTHING_STAGES)
@pytest.mark.parametrize("name", TABLES)
def test_smooth_table_is_the_linear_lookup_off_the_nodes_and_bounded_near_them(name, smoothing):
    blob, offset = LOD189.blob, TABLES[name]
    axes, values = _blob_table(blob, offset)
    widths = _corner_widths(axes, smoothing)
    rng = np.random.default_rng(189)
    spread, near = _sample_points(axes, widths, 3000, rng), _near_nodes(axes, widths, 3000, rng)
    cols = [np.concatenate(pair) for pair in zip(spread, near)]
    (smoothed,) = _casadi_map(smooth_table(axes, values), *cols, np.full(cols[0].size, smoothing))
    deviation = np.abs(smoothed - np.array([lookup(blob, offset, *p) for p in zip(*cols)]))
    far = np.all([_node_distance(a, x) > eps for a, x, eps in zip(axes, cols, widths)], axis=0)
    assert far.sum() >= 1000 and (~far).sum() >= 1000  # both regimes sampled
    assert deviation[far].max() <= 1e-12
    assert deviation.max() <= _corner_bound(axes, values, smoothing) + 1e-12


def _weight_and_slope(axis, node, x, smoothing):
    """Weight of one node (smooth_table of a one-hot table on one axis) and its derivative, at many x."""
    u, w = ca.SX.sym("x"), ca.SX.sym("smoothing")
    weight = smooth_table([axis], np.eye(axis.size)[node])(u, w)
    f = ca.Function("weight", [u, w], [weight, ca.jacobian(weight, u)])
    return [np.asarray(v, float).ravel() for v in f.map(x.size)(x, np.full(x.size, smoothing))]


@pytest.mark.parametrize("smoothing", SMOOTHING_STAGES)
def test_smooth_table_weights_are_a_smooth_partition_of_unity(smoothing):
    """On every CD axis the node weights are >= 0 and sum to 1 (at random points, at the nodes, half a corner
    width past them), and are C2 where the rounding meets the straight parts (node +- corner width): across
    +-d the value moves by at most the steepest hat slope 1/h_min x 2 d, the slope by 1e-9 / h_min (a jump of
    the second derivative there, ~1 / (eps h), would move it by ~2e-6 / h)."""
    axes, _ = _blob_table(LOD189.blob, TABLES["CD"])
    rng = np.random.default_rng(3)
    for axis in (a for a in axes if a.size > 1):
        eps, h_min = _corner_widths([axis], smoothing)[0], np.diff(axis).min()
        (x,) = _sample_points([axis], [eps], 2000, rng)
        x = np.concatenate([x, axis, axis + 0.5 * eps])
        edges, d = np.concatenate([axis - eps, axis + eps]), 1e-6 * eps
        weights = []
        for node in range(axis.size):
            weights.append(_weight_and_slope(axis, node, x, smoothing)[0])
            (w_lo, s_lo), (w_hi, s_hi) = (_weight_and_slope(axis, node, edges + side, smoothing) for side in (-d, d))
            assert np.abs(w_hi - w_lo).max() <= 2.0 * d / h_min * (1.0 + 1e-6)
            assert np.abs(s_hi - s_lo).max() <= 1e-9 / h_min
        assert np.min(weights) >= -1e-15
        assert np.abs(np.sum(weights, axis=0) - 1.0).max() <= 1e-14


# --- 4. atmosphere ------------------------------------------------------------------------------------------

ALTITUDE_SAMPLES_FT = np.linspace(0.0, 400_000.0, 40_001)  # every 10 ft
AIR_KEYS = ("density_slug_ft3", "temperature_R", "speed_of_sound_fps")  # atmosphere_table's, in Atmosphere's order


def test_ardc1959_splines_interpolate_the_table_at_the_nodes():
    nodes = ATMOSPHERE_GRID_FT[ATMOSPHERE_GRID_FT <= 400_000.0]
    tab = atmosphere_table("ardc1959", nodes)
    for spline, key in zip(_atmosphere_splines(ARDC_EARTH, nodes), AIR_KEYS):
        assert np.abs(spline / tab[key] - 1.0).max() <= 1e-12, key


def test_ardc1959_splines_between_the_nodes():
    """The cubic splines through nodes 2,000 ft apart ring at the layer kinks (dT/dh jumps at 11, 25, 47, 53, 79,
    90 km'): density 0.17 % and speed of sound 0.088 % off at 262,450 ft (the 79 km' kink), decaying ~3.7x per
    interval; two intervals from a kink 0.012 % and 0.006 %."""
    rho, _, sound = _atmosphere_splines(ARDC_EARTH, ALTITUDE_SAMPLES_FT)
    tab = atmosphere_table("ardc1959", ALTITUDE_SAMPLES_FT)
    rho_error = np.abs(rho / tab["density_slug_ft3"] - 1.0)
    sound_error = np.abs(sound / tab["speed_of_sound_fps"] - 1.0)
    assert rho_error.max() <= 2e-3 and sound_error.max() <= 1e-3
    clear = np.abs(ALTITUDE_SAMPLES_FT[:, None] - ARDC_KINKS_FT[None, :]).min(axis=1) > KINK_CLEARANCE_FT
    assert rho_error[clear].max() <= 1.5e-4 and sound_error[clear].max() <= 7.5e-5


def test_exponential_atmosphere_is_the_core_formula():
    planet = SPHERE
    rho, t_inf, sound = _atmosphere_splines(planet, ALTITUDE_SAMPLES_FT[::100])
    tab = atmosphere_table("exponential", ALTITUDE_SAMPLES_FT[::100], planet.rho0_slug_ft3, planet.scale_height_ft)
    assert np.abs(rho / tab["density_slug_ft3"] - 1.0).max() <= 1e-14
    assert np.abs(t_inf / tab["temperature_R"] - 1.0).max() <= 1e-14
    assert np.abs(sound / tab["speed_of_sound_fps"] - 1.0).max() <= 1e-7  # rounded gas constant: 2.3e-8


# --- 5. heating ---------------------------------------------------------------------------------------------

LIMIT_STEP = 1e-6  # relative step of the limit around the temperature: 1000x core.heating's Newton tolerance


@pytest.mark.parametrize("smoothing", SMOOTHING_STAGES)
@pytest.mark.parametrize(
    "alt_ft, v_fps, alpha_deg",
    [
        (150_000.0, 12_000.0, 10.0),
        (200_000.0, 20_000.0, 22.5),
        (250_000.0, 24_000.0, 35.0),
        (180_000.0, 16_000.0, 47.5),
        (220_000.0, 22_000.0, 55.0),  # 55: Table 1 held beyond 50 deg
    ],
)
def test_temperature_margin_is_negative_exactly_within_the_limit(alt_ft, v_fps, alpha_deg, smoothing):
    # off Table 1's corners the smoothed ratio is np.interp's, so the margin's zero is core.heating's temperature
    assert _node_distance(TABLE1_ALPHA_DEG, alpha_deg)[0] > smoothing * np.diff(TABLE1_ALPHA_DEG).min()
    reference = ReferenceHeating()
    air = atmosphere_table("ardc1959", np.array([alt_ft]))
    rho, t_inf = air["density_slug_ft3"], air["temperature_R"]
    (temperature_R,) = reference.evaluate(rho, np.array([v_fps]), np.array([alpha_deg]), t_inf)[1]
    heating = Heating(reference)

    def margin(limit_R):
        return float(heating.temperature_margin(rho[0], v_fps, t_inf[0], alpha_deg, limit_R, smoothing))

    assert margin(temperature_R * (1.0 + LIMIT_STEP)) < 0.0 < margin(temperature_R * (1.0 - LIMIT_STEP))
    assert abs(margin(temperature_R)) <= 1e-8  # ~4 x the relative temperature error (Newton: <= 1e-9)
