"""Aerodynamic coefficients of an entry vehicle: the compiled kernel and the packing of its data.

Every vehicle is packed into ONE flat float64 array, the "aero blob", so that the trajectory integrator
takes a single argument. Angles are in degrees, altitudes in feet.

Blob layout
-----------
    blob[0]  form: 0 = lift/drag tables (CL, CD), 1 = normal/axial tables (CN, CA, body axes),
             2 = polynomials in alpha (CL, CD)
    blob[1]  alpha_min_deg   } the valid alpha range: the tables' alpha axis, or for polynomials the
    blob[2]  alpha_max_deg   } range given by the user (default 0-60 deg)
    blob[3]  offset of the first table (CL or CN)  | form 2: offset of the CL polynomial
    blob[4]  offset of the second table (CD or CA) | form 2: offset of the CD polynomial
    blob[5]  offset of the control grid "alpha of (L/D)max" (deg) over (Mach, altitude)
    blob[6]  offset of the control grid "alpha of CL max" (deg)
    blob[7]  offset of the control grid "alpha of zero lift" (deg)

A table at offset o:
    blob[o] = n_mach, blob[o+1] = n_alpha, blob[o+2] = n_alt,
    then the Mach axis (n_mach), the alpha axis (n_alpha, deg), the altitude axis (n_alt, ft),
    then the values in C order [mach][alpha][alt].
An axis on which the coefficient does not depend has one node. A control grid has the same layout with
n_alpha = 1 (alpha axis = [0]).
A polynomial at offset o: blob[o] = n, then n coefficients, lowest power first, alpha in degrees.

Interpolation is multilinear; outside an axis the value is HELD at the edge (no extrapolation).
The control grids are computed once, when the blob is packed, by a 0.01 deg sweep of the alpha range at
nodes = the tables' Mach and altitude axes refined 8x between nodes (less for very large user tables, so
that packing stays well under a second). The grid alpha is then interpolated bilinearly in (Mach,
altitude); where the optimum jumps between table alpha nodes (e.g. the flat L/D 1.89 maximum) the
interpolated alpha loses up to ~1 % of (L/D)max inside the grid cell that contains the jump.

Vehicles
--------
The built-in vehicles are the Appendix B configurations, in data/vehicles/<id>.json (provenance and every
OCR reading decision are in those files); `builtin_vehicle(id)` loads and packs one (cached).
`vehicle_from_definition(d)` packs a user vehicle; its definition (the "aero" part is also the format of
the data files):
    {"name": str, "wing_loading_psf": W/S  |  "weight_lb" and "reference_area_ft2",
     "aero": {"constant": {"cl": c, "cd": c}}
           | {"polynomial": {"cl": [a0, a1, ...], "cd": [b0, ...], "alpha_range_deg": [lo, hi]}}
           | {"tables": {"form": "lift_drag" | "normal_axial", "first": T, "second": T}}}
with T = {"mach": [...], "alpha_deg": [...], "altitude_ft": [...], "values": [mach][alpha][altitude]}.
"""

import functools
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core._jit import njit
from footprint.core.errors import InputError
from footprint.core.limits import Limits

FORM_LIFT_DRAG = 0
FORM_NORMAL_AXIAL = 1
FORM_POLYNOMIAL = 2
FORM_NAMES = {"lift_drag": FORM_LIFT_DRAG, "normal_axial": FORM_NORMAL_AXIAL}

HEADER_SIZE = 8
GRID_REFINEMENT = 8  # control-grid nodes per table interval, in Mach and in altitude
SWEEP_STEP_DEG = 0.01  # alpha step of the control-grid sweep
DEFAULT_ALPHA_RANGE_DEG = (0.0, 60.0)
BISECTION_ITERATIONS = 30  # alpha_for_cl_deg: 60 deg / 2**30 ~ 6e-8 deg (CL to ~1e-9)
_SWEEP_CHUNK = 150_000  # (Mach x altitude x alpha) points evaluated at once while packing (cache-sized)
# Refinement is reduced below 8x when nodes x sweep would exceed this (user tables only: the largest
# built-in, high-lod, has 65 x 57 x 2001 = 7.4 M points)
_MAX_SWEEP_POINTS = 10_000_000

# a table as arrays: (mach, alpha_deg, altitude_ft, values[mach][alpha][alt])
_Table = tuple[NDArray[np.float64], ...]


# ------------------------------------------------------------------------------------------------
# Compiled kernel (inner loop of the integrator: no allocation, no exceptions)
# ------------------------------------------------------------------------------------------------


@njit(allocates=False)
def _locate(blob: NDArray[np.float64], start: int, n: int, x: float) -> tuple[int, float]:
    """Interval of x on the axis blob[start:start+n]: (index i, weight of node i+1), held at the edges."""
    if n == 1:
        return 0, 0.0
    if x <= blob[start]:
        return 0, 0.0
    if x >= blob[start + n - 1]:
        return n - 2, 1.0
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if blob[start + mid] <= x:
            lo = mid
        else:
            hi = mid
    x0 = blob[start + lo]
    return lo, (x - x0) / (blob[start + lo + 1] - x0)


@njit(allocates=False)
def lookup(blob: NDArray[np.float64], offset: float, mach: float, alpha_deg: float, altitude_ft: float) -> float:
    """Multilinear interpolation of the table at `offset`; one-node axes skipped, values held at the edges."""
    o = int(offset)
    n_m = int(blob[o])
    n_a = int(blob[o + 1])
    n_h = int(blob[o + 2])
    s_m = o + 3
    s_a = s_m + n_m
    s_h = s_a + n_a
    s_v = s_h + n_h
    i_m, w_m = _locate(blob, s_m, n_m, mach)
    i_a, w_a = _locate(blob, s_a, n_a, alpha_deg)
    i_h, w_h = _locate(blob, s_h, n_h, altitude_ft)
    total = 0.0
    for d_m in range(2):
        f_m = 1.0 - w_m if d_m == 0 else w_m
        if f_m == 0.0:
            continue
        for d_a in range(2):
            f_a = 1.0 - w_a if d_a == 0 else w_a
            if f_a == 0.0:
                continue
            row = s_v + ((i_m + d_m) * n_a + (i_a + d_a)) * n_h
            for d_h in range(2):
                f_h = 1.0 - w_h if d_h == 0 else w_h
                if f_h == 0.0:
                    continue
                total += f_m * f_a * f_h * blob[row + i_h + d_h]
    return total


@njit(allocates=False)
def _axis_node_between(
    blob: NDArray[np.float64], offset: float, axis: int, from_value: float, to_value: float
) -> float:
    """The node of axis `axis` (0 Mach, 2 altitude) of the table at `offset` strictly between from_value and
    to_value nearest from_value; NaN if none."""
    o = int(offset)
    start = o + 3
    for a in range(axis):
        start += int(blob[o + a])
    found = math.nan
    for i in range(start, start + int(blob[o + axis])):
        node = blob[i]
        if (from_value < node < to_value or to_value < node < from_value) and not (
            abs(node - from_value) >= abs(found - from_value)
        ):
            found = node
    return found


@njit(allocates=False)
def kink_between(blob: NDArray[np.float64], axis: int, from_value: float, to_value: float) -> float:
    """The Mach number (axis 0) or altitude (axis 2, ft) strictly between from_value and to_value nearest from_value
    at which the coefficients or the (L/D)max alpha, multilinear in them, may change slope: a node of the tables or of
    the (L/D)max grid. NaN if none. The integrator ends a rejected step there (integrate._kink_fraction)."""
    found = math.nan
    first = 5 if blob[0] == FORM_POLYNOMIAL else 3
    for slot in range(first, 6):
        node = _axis_node_between(blob, blob[slot], axis, from_value, to_value)
        if not math.isnan(node) and not (abs(node - from_value) >= abs(found - from_value)):
            found = node
    return found


@njit(allocates=False)
def _horner(blob: NDArray[np.float64], offset: float, x: float) -> float:
    o = int(offset)
    n = int(blob[o])
    total = 0.0
    for k in range(n - 1, -1, -1):
        total = total * x + blob[o + 1 + k]
    return total


@njit(allocates=False)
def coefficients(blob: NDArray[np.float64], mach: float, alpha_deg: float, altitude_ft: float) -> tuple[float, float]:
    """(CL, CD) at Mach, alpha (deg), altitude (ft).

    Form 1: the tables hold body-axis CN, CA (held at the table edges); lift and drag are their rotation by
    the actual alpha. Form 2: polynomials in alpha, with alpha held inside [alpha_min, alpha_max].
    """
    form = blob[0]
    if form == FORM_POLYNOMIAL:
        a = min(max(alpha_deg, blob[1]), blob[2])
        return _horner(blob, blob[3], a), _horner(blob, blob[4], a)
    c1 = lookup(blob, blob[3], mach, alpha_deg, altitude_ft)
    c2 = lookup(blob, blob[4], mach, alpha_deg, altitude_ft)
    if form == FORM_LIFT_DRAG:
        return c1, c2
    # Body to wind axes, aero_tables.md "Force-coefficient conversion" (report App. B, Tables B-4..B-8 are
    # normal/axial force): CL = CN cos(alpha) - CA sin(alpha), CD = CN sin(alpha) + CA cos(alpha).
    a = math.radians(alpha_deg)
    ca = math.cos(a)
    sa = math.sin(a)
    return c1 * ca - c2 * sa, c1 * sa + c2 * ca


@njit(allocates=False)
def alpha_max_ld_deg(blob: NDArray[np.float64], mach: float, altitude_ft: float) -> float:
    """Alpha (deg) of (L/D)max at Mach, altitude: bilinear lookup of the precomputed grid."""
    return lookup(blob, blob[5], mach, 0.0, altitude_ft)


@njit(allocates=False)
def alpha_cl_max_deg(blob: NDArray[np.float64], mach: float, altitude_ft: float) -> float:
    """Alpha (deg) of CL max over the valid alpha range at Mach, altitude (precomputed grid)."""
    return lookup(blob, blob[6], mach, 0.0, altitude_ft)


@njit(allocates=False)
def alpha_zero_lift_deg(blob: NDArray[np.float64], mach: float, altitude_ft: float) -> float:
    """Alpha (deg) of zero lift at Mach, altitude (precomputed grid; alpha_min if CL >= 0 there)."""
    return lookup(blob, blob[7], mach, 0.0, altitude_ft)


@njit(allocates=False)
def alpha_for_cl_deg(
    blob: NDArray[np.float64], cl: float, mach: float, altitude_ft: float, alpha_lo_deg: float, alpha_hi_deg: float
) -> float:
    """Alpha in [lo, hi] where CL(alpha) = cl, by bisection (CL assumed increasing on [lo, hi]).

    Returns lo when cl <= CL(lo) and hi when cl >= CL(hi).
    """
    lo = alpha_lo_deg
    hi = alpha_hi_deg
    cl_lo, _ = coefficients(blob, mach, lo, altitude_ft)
    if cl <= cl_lo:
        return lo
    cl_hi, _ = coefficients(blob, mach, hi, altitude_ft)
    if cl >= cl_hi:
        return hi
    for _ in range(BISECTION_ITERATIONS):
        mid = 0.5 * (lo + hi)
        cl_mid, _ = coefficients(blob, mach, mid, altitude_ft)
        if cl_mid < cl:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------------------------------------------
# Packing (Python side, once per vehicle)
# ------------------------------------------------------------------------------------------------


def _table_segment(mach: ArrayLike, alpha: ArrayLike, alt: ArrayLike, values: ArrayLike) -> NDArray[np.float64]:
    mach, alpha, alt = (np.asarray(x, dtype=np.float64).ravel() for x in (mach, alpha, alt))
    values = np.asarray(values, dtype=np.float64).reshape(mach.size, alpha.size, alt.size)
    head = np.array([mach.size, alpha.size, alt.size], dtype=np.float64)
    return np.concatenate([head, mach, alpha, alt, values.ravel()])


def _weights(axis: ArrayLike, x: ArrayLike) -> NDArray[np.float64]:
    """Matrix W (len(x), len(axis)) of the kernel's linear interpolation with edge holding: f(x) = W @ f."""
    axis = np.asarray(axis, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    w_mat = np.zeros((x.size, axis.size))
    if axis.size == 1:
        w_mat[:, 0] = 1.0
        return w_mat
    xc = np.clip(x, axis[0], axis[-1])
    i = np.clip(np.searchsorted(axis, xc, side="right") - 1, 0, axis.size - 2)
    w = (xc - axis[i]) / (axis[i + 1] - axis[i])
    rows = np.arange(x.size)
    w_mat[rows, i] += 1.0 - w
    w_mat[rows, i + 1] += w
    return w_mat


def _refine(nodes: ArrayLike, factor: int = GRID_REFINEMENT) -> NDArray[np.float64]:
    nodes = np.unique(np.asarray(nodes, dtype=np.float64))
    if nodes.size == 1:
        return nodes
    steps = np.arange(factor) / factor
    inner = (nodes[:-1, None] + np.diff(nodes)[:, None] * steps[None, :]).ravel()
    return np.append(inner, nodes[-1])


def alpha_sweep_deg(alpha_min: float, alpha_max: float) -> NDArray[np.float64]:
    """Alpha from alpha_min to alpha_max (deg) every SWEEP_STEP_DEG, both ends included."""
    n = int(round((alpha_max - alpha_min) / SWEEP_STEP_DEG)) + 1
    return np.linspace(alpha_min, alpha_max, max(n, 2))


def _grid_alphas(
    cl: NDArray[np.floating[Any]], cd: NDArray[np.floating[Any]], sweep: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], bool]:
    """Alpha of (L/D)max, of CL max and of zero lift along the last axis of cl, cd (sampled at `sweep`)."""
    i_cl = np.argmax(cl, axis=-1)  # first maximum: smallest alpha on ties
    a_cl = sweep[i_cl]
    ok = cl > 0.0
    ok &= cd > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = cl / cd
    ratio[~ok] = -np.inf
    i_ld = np.argmax(ratio, axis=-1)  # first maximum: smallest alpha on ties
    a_ld = np.where(ok.any(axis=-1), sweep[i_ld], a_cl)  # no positive L/D anywhere: alpha of CL max
    # zero lift: first sign change scanning up from alpha_min (alpha_min itself if CL >= 0 there)
    nonneg = cl >= 0.0
    k = np.argmax(nonneg, axis=-1)
    km = np.maximum(k - 1, 0)
    c0 = np.take_along_axis(cl, km[..., None], -1)[..., 0]
    c1 = np.take_along_axis(cl, k[..., None], -1)[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        a_zero = sweep[km] + (0.0 - c0) / (c1 - c0) * (sweep[k] - sweep[km])
    a_zero = np.where(k == 0, sweep[0], a_zero)
    a_zero = np.where(nonneg.any(axis=-1), a_zero, a_cl)  # CL < 0 everywhere: alpha of CL max
    return a_ld, a_cl, a_zero, bool((cd > 0.0).any())


def _table_on_grid(
    table: _Table, mach_nodes: NDArray[np.float64], alt_nodes: NDArray[np.float64], sweep: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Values of a (mach, alpha, alt, values) table at every (mach node, alt node, sweep alpha)."""
    mach, alpha, alt, values = table
    v: NDArray[np.float64] = np.einsum("mi,ijk,hk->mhj", _weights(mach, mach_nodes), values, _weights(alt, alt_nodes))
    if alpha.size == 1:
        return v  # (mach, alt, 1): broadcasts over the sweep
    return v @ _weights(alpha, sweep).T


def _control_grids_tables(
    form: int, first: _Table, second: _Table, alpha_min: float, alpha_max: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], list[NDArray[np.float64]], bool]:
    sweep = alpha_sweep_deg(alpha_min, alpha_max)
    mach_axis = np.concatenate([first[0], second[0]])
    alt_axis = np.concatenate([first[2], second[2]])
    for factor in range(GRID_REFINEMENT, 0, -1):  # 8x; less only for big user tables (packing time)
        mach_nodes = _refine(mach_axis, factor)
        alt_nodes = _refine(alt_axis, factor)
        if mach_nodes.size * alt_nodes.size * sweep.size <= _MAX_SWEEP_POINTS:
            break
    shape = (mach_nodes.size, alt_nodes.size)
    grids = [np.empty(shape) for _ in range(3)]
    cd_positive = False
    if form == FORM_NORMAL_AXIAL:
        cos_a = np.cos(np.radians(sweep))
        sin_a = np.sin(np.radians(sweep))
    step = max(1, _SWEEP_CHUNK // (alt_nodes.size * sweep.size))
    for start in range(0, mach_nodes.size, step):
        block = mach_nodes[start : start + step]
        c1 = _table_on_grid(first, block, alt_nodes, sweep)
        c2 = _table_on_grid(second, block, alt_nodes, sweep)
        if form == FORM_NORMAL_AXIAL:  # to wind axes, as in coefficients()
            cl = c1 * cos_a
            cl -= c2 * sin_a
            cd = c1 * sin_a
            cd += c2 * cos_a
            c1, c2 = cl, cd
        else:
            c1, c2 = np.broadcast_arrays(c1, c2)
        *alphas, positive = _grid_alphas(c1, c2, sweep)
        cd_positive |= positive
        for grid, a in zip(grids, alphas):
            grid[start : start + step] = a
    return mach_nodes, alt_nodes, grids, cd_positive


def _alpha_range(first: _Table, second: _Table) -> tuple[float, float]:
    ranges = [(t[1][0], t[1][-1]) for t in (first, second) if t[1].size > 1]
    if not ranges:
        return DEFAULT_ALPHA_RANGE_DEG
    return max(r[0] for r in ranges), min(r[1] for r in ranges)


def _assemble(
    form: int,
    alpha_min: float,
    alpha_max: float,
    seg1: NDArray[np.float64],
    seg2: NDArray[np.float64],
    mach_nodes: NDArray[np.float64],
    alt_nodes: NDArray[np.float64],
    grids: list[NDArray[np.float64]],
) -> NDArray[np.float64]:
    segments = [seg1, seg2] + [_table_segment(mach_nodes, [0.0], alt_nodes, g[:, None, :]) for g in grids]
    offsets = np.cumsum([HEADER_SIZE] + [s.size for s in segments[:-1]])
    header = np.array([form, alpha_min, alpha_max, *offsets], dtype=np.float64)
    blob = np.ascontiguousarray(np.concatenate([header] + segments))
    blob.flags.writeable = False  # blobs are shared (cached built-ins): one read-only numba array type for all
    return blob


def pack_tables(form: int, first: Sequence[ArrayLike], second: Sequence[ArrayLike]) -> tuple[NDArray[np.float64], bool]:
    """Blob of a table vehicle. form: FORM_LIFT_DRAG or FORM_NORMAL_AXIAL; first/second: (mach, alpha_deg,
    altitude_ft, values[mach][alpha][alt]) of CL/CN and CD/CA, axes strictly increasing (validated by the caller).

    Returns (blob, cd_positive): cd_positive says whether CD > 0 anywhere on the control-grid sweep.
    """
    first_t: _Table = tuple(np.asarray(x, dtype=np.float64) for x in first)
    second_t: _Table = tuple(np.asarray(x, dtype=np.float64) for x in second)
    alpha_min, alpha_max = _alpha_range(first_t, second_t)
    mach_nodes, alt_nodes, grids, cd_positive = _control_grids_tables(form, first_t, second_t, alpha_min, alpha_max)
    blob = _assemble(
        form,
        alpha_min,
        alpha_max,
        _table_segment(*first_t),
        _table_segment(*second_t),
        mach_nodes,
        alt_nodes,
        grids,
    )
    return blob, cd_positive


def pack_polynomial(
    cl_coeffs: ArrayLike, cd_coeffs: ArrayLike, alpha_range_deg: Sequence[float] = DEFAULT_ALPHA_RANGE_DEG
) -> tuple[NDArray[np.float64], bool]:
    """Blob of a polynomial vehicle (coefficients lowest power first, alpha in degrees).

    Returns (blob, cd_positive) as pack_tables.
    """
    cl_coeffs = np.asarray(cl_coeffs, dtype=np.float64).ravel()
    cd_coeffs = np.asarray(cd_coeffs, dtype=np.float64).ravel()
    alpha_min, alpha_max = (float(a) for a in alpha_range_deg)
    sweep = alpha_sweep_deg(alpha_min, alpha_max)
    cl = np.polynomial.polynomial.polyval(sweep, cl_coeffs)
    cd = np.polynomial.polynomial.polyval(sweep, cd_coeffs)
    *alphas, cd_positive = _grid_alphas(cl, cd, sweep)
    grids = [np.array([[a]]) for a in alphas]
    seg1 = np.concatenate([[cl_coeffs.size], cl_coeffs])
    seg2 = np.concatenate([[cd_coeffs.size], cd_coeffs])
    blob = _assemble(FORM_POLYNOMIAL, alpha_min, alpha_max, seg1, seg2, np.zeros(1), np.zeros(1), grids)
    return blob, cd_positive


# ------------------------------------------------------------------------------------------------
# Vehicles
# ------------------------------------------------------------------------------------------------

DATA_DIR = Path(__file__).resolve().parent / "data" / "vehicles"
_BUILTIN_ORDER = ("lod-1.89", "lod-2.2", "lod-2.6", "low-lod", "high-lod")

WING_LOADING_RANGE_PSF = (1.0, 2000.0)
MAX_AXIS_NODES = 20
MAX_POLY_TERMS = 12
ALPHA_LIMIT_DEG = 90.0
SUMMARY_MACH, SUMMARY_ALTITUDE_FT = 20.0, 200_000.0  # where `footprint vehicles` gives (L/D)max: hypersonic glide


@dataclass(frozen=True)
class Vehicle:
    id: str
    name: str
    wing_loading_psf: float
    blob: NDArray[np.float64] = field(repr=False, compare=False)
    provenance: str = ""
    readings: tuple[str, ...] = ()
    reported_ld_max: float | None = None
    note: str = ""
    limits: Limits = Limits()  # what the summary checks each flight against (core.limits: a glider's by default)


# --- validation helpers ---------------------------------------------------------------------------


def _show(value: object, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


MAX_FORCE_COEFFICIENT = 100.0  # |C_L|, |C_D|, |C_N|, |C_A|: physical ones are O(1) (Appendix B's stay below 3)


def _table(tab: Mapping[str, Any]) -> _Table:
    """A table's axes and values as arrays (its shape and bounds checked by the contract, contracts.vehicle)."""
    axes = (np.array(tab[k], dtype=np.float64) for k in ("mach", "alpha_deg", "altitude_ft"))
    return (*axes, np.array(tab["values"], dtype=np.float64))


def _tables_blob(tables: Mapping[str, Any], where: str) -> NDArray[np.float64]:
    first, second = _table(tables["first"]), _table(tables["second"])
    (a1, b1), (a2, b2) = ((t[1][0], t[1][-1]) for t in (first, second))
    if first[1].size > 1 and second[1].size > 1 and min(b1, b2) <= max(a1, a2):
        raise InputError(f"{where}.second.alpha_deg", f"alpha range {a2}..{b2} does not overlap {a1}..{b1}")
    blob, cd_positive = pack_tables(FORM_NAMES[tables["form"]], first, second)
    if not cd_positive:
        raise InputError(f"{where}.second.values", "CD is nowhere positive over the alpha range")
    return blob


def _within_force_range(where: str, values: ArrayLike) -> None:
    """A force coefficient's magnitude at most MAX_FORCE_COEFFICIENT: a C_D of 1e308 overflowed the forces to inf."""
    worst = float(np.max(np.abs(values)))
    if not worst <= MAX_FORCE_COEFFICIENT:
        raise InputError(
            where,
            f"reaches {worst:.4g}: a force coefficient must stay within "
            f"-{MAX_FORCE_COEFFICIENT:g}..{MAX_FORCE_COEFFICIENT:g}",
        )


def _polynomial_blob(
    cl: Sequence[float], cd: Sequence[float], alpha_range: tuple[float, float], where: str
) -> NDArray[np.float64]:
    """`where`: the definition's path; its .cl and .cd name the coefficient that is refused."""
    alpha = np.linspace(
        *alpha_range, 721
    )  # the polynomial's values over the range it is flown in (every 0.25 deg at most)
    for coefficients, name in ((cl, "cl"), (cd, "cd")):
        _within_force_range(f"{where}.{name}", np.polyval(coefficients[::-1], alpha))
    cd_where = f"{where}.cd"
    blob, cd_positive = pack_polynomial(cl, cd, alpha_range)
    if not cd_positive:
        lo, hi = alpha_range
        raise InputError(cd_where, f"{_show(cd)}: CD is nowhere positive over alpha {lo}..{hi} deg")
    return blob


def _aero_blob(aero: Mapping[str, Any], where: str) -> NDArray[np.float64]:
    """The blob of an aero definition (one of "constant", "polynomial", "tables"; see the module docstring)."""
    (kind, body), w = next(iter(aero.items())), f"{where}.{next(iter(aero))}"
    if kind == "tables":
        return _tables_blob(body, w)
    if kind == "constant":
        return _polynomial_blob([float(body["cl"])], [float(body["cd"])], DEFAULT_ALPHA_RANGE_DEG, w)
    alpha_range = tuple(body.get("alpha_range_deg") or DEFAULT_ALPHA_RANGE_DEG)
    return _polynomial_blob([float(x) for x in body["cl"]], [float(x) for x in body["cd"]], alpha_range, w)


# --- public API -----------------------------------------------------------------------------------


def vehicle_from_definition(
    aero: Mapping[str, Any], wing_loading_psf: float, name: str = "custom vehicle", field: str = "vehicle"
) -> Vehicle:
    """A user vehicle from its aero definition, as contracts.vehicle checked it; InputError (naming the field below
    `field`) for what only the numbers show: a drag nowhere positive, a force past the range, tables whose alpha
    ranges do not overlap."""
    blob = _aero_blob(aero, f"{field}.aero")
    return Vehicle(
        id="custom", name=name, wing_loading_psf=wing_loading_psf, blob=blob, provenance="user-defined vehicle"
    )


def builtin_vehicle_ids() -> list[str]:
    return list(_builtin_ids())


@functools.cache
def _builtin_ids() -> tuple[str, ...]:
    """The package's vehicle files, read once (every parse of a case looks its vehicle up: a glob each was 15 % of
    fly(dict), issue 29)."""
    ids = {p.stem for p in DATA_DIR.glob("*.json")}
    return tuple([i for i in _BUILTIN_ORDER if i in ids] + sorted(ids - set(_BUILTIN_ORDER)))


@functools.cache
def _load_builtin(vehicle_id: str) -> Vehicle:
    d = json.loads((DATA_DIR / f"{vehicle_id}.json").read_text(encoding="utf-8"))
    blob = _aero_blob(d["aero"], f"vehicle.builtin[{vehicle_id}].aero")
    return Vehicle(
        id=d["id"],
        name=d["name"],
        wing_loading_psf=float(d["wing_loading_psf"]),
        blob=blob,
        provenance=d["provenance"],
        readings=tuple(d["readings"]),
        reported_ld_max=None if d.get("reported_ld_max") is None else float(d["reported_ld_max"]),
        note=d.get("note", ""),
    )


def builtin_vehicle(vehicle_id: str) -> Vehicle:
    """A built-in vehicle (cached: the blob is shared and read-only)."""
    ids = builtin_vehicle_ids()
    if vehicle_id not in ids:
        raise InputError(
            "vehicle.builtin", f"unknown vehicle {_show(vehicle_id)} (the built-in vehicles are {', '.join(ids)})"
        )
    return _load_builtin(vehicle_id)


def _blob(vehicle: Vehicle | NDArray[np.float64]) -> NDArray[np.float64]:
    return vehicle.blob if isinstance(vehicle, Vehicle) else vehicle


def alpha_range_deg(vehicle: Vehicle | NDArray[np.float64]) -> tuple[float, float]:
    """The vehicle's valid alpha range (deg): its tables' alpha axis, or the range its polynomials were given."""
    blob = _blob(vehicle)
    return float(blob[1]), float(blob[2])


def ld_max(vehicle: Vehicle | NDArray[np.float64], mach: float, altitude_ft: float) -> tuple[float, float]:
    """((L/D)max, alpha_deg) at Mach, altitude, from the control grid's alpha."""
    blob = _blob(vehicle)
    alpha = float(alpha_max_ld_deg(blob, mach, altitude_ft))
    cl, cd = coefficients(blob, mach, alpha, altitude_ft)
    return (float(cl / cd) if cd > 0.0 else float("nan")), alpha


def vehicle_summaries() -> list[dict[str, Any]]:
    """One row per built-in vehicle for `footprint vehicles` ((L/D)max and CL max at Mach 20 / 200,000 ft)."""
    mach, altitude_ft = SUMMARY_MACH, SUMMARY_ALTITUDE_FT
    rows: list[dict[str, Any]] = []
    for vid in builtin_vehicle_ids():
        v = builtin_vehicle(vid)
        ld, alpha = ld_max(v, mach, altitude_ft)
        alpha_cl = float(alpha_cl_max_deg(v.blob, mach, altitude_ft))
        cl_max, _ = coefficients(v.blob, mach, alpha_cl, altitude_ft)
        rows.append(
            {
                "id": v.id,
                "name": v.name,
                "wing_loading_psf": v.wing_loading_psf,
                "reported_ld_max": v.reported_ld_max,
                "ld_max_m20_200kft": round(ld, 4),
                "alpha_ld_max_deg": round(alpha, 2),
                "cl_max": round(float(cl_max), 4),
                "alpha_cl_max_deg": round(alpha_cl, 2),
                "alpha_range_deg": list(alpha_range_deg(v)),
                "note": v.note,
            }
        )
    return rows
