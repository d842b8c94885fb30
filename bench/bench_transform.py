"""Moving 100,000 footprint points on one core: ours against the report's way (Section IV.1, eqs. 8-15).

The job: points of an L/D 1.89-sized footprint about (0 deg, 0 deg, heading 90 deg) re-noded to longitude
-40 deg, re-inclined to heading 30 deg (inclination 60 deg), stepped 500 nmi around the orbit, and shifted
west by omega_p t for the earth's rotation (Section IV.3), each point with its own flight time.

- ours: footprint.core.sphere.move (one 3x3 rotation of unit vectors) + rotation_shift.
- the report's way, vectorized: eqs. (8)-(11) forward in numpy, the step added to the down-range, then eqs.
  (12)-(14) and the iteration on latitude (guess phi, eq. 8 for the longitude difference, eq. 9 for zeta,
  compare with zeta_M) run as a bisection over all points at once for a fixed 56 halvings (the bracket
  starts at most 180 deg wide: 56 halvings bring it under 1e-16 rad, the iteration's own convergence),
  then eq. (15) and the same shift.
- the report's way, as a Python loop: the same equations point by point (math module), timed over the
  first 2,000 points and scaled by 50 to 100,000 (linear: each point is independent).

One core: BLAS and OpenMP threads are set to 1 before numpy loads, and the process is pinned to one CPU.

    python3 bench/bench_transform.py      # prints the figures, writes bench/results/transform.json
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import json  # noqa: E402
import math  # noqa: E402

import numpy as np  # noqa: E402
from _timing import median_ms, save_result  # noqa: E402

from footprint.core.constants import OMEGA_EARTH_DEG_S  # noqa: E402
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, latlon_from_ranges, move, rotation_shift  # noqa: E402

N_POINTS = 100_000
LOOP_SUBSET = 2_000
BISECTIONS = 56
TARGET_MS = 50.0
SRC = Reference(0.0, 0.0, 90.0)
DST = Reference(0.0, -40.0, 30.0)
STEP_NMI = 500.0
R = MEAN_RADIUS_NMI


def points(n=N_POINTS, seed=1982):
    """Uniform in an L/D 1.89 footprint's box: down-range 900-7,300 nmi, cross-range +-1,800 nmi, flight
    times 250-2,900 s."""
    rng = np.random.default_rng(seed)
    lat, lon = latlon_from_ranges(
        rng.uniform(900.0, 7_300.0, n),
        rng.uniform(-1_800.0, 1_800.0, n),
        SRC.latitude_deg,
        SRC.longitude_deg,
        SRC.heading_deg,
    )
    return lat, lon, rng.uniform(250.0, 2_900.0, n)


# ------------------------------------------------------------------------------------------------ ours
def ours(lat, lon, t):
    lat2, lon2 = move(lat, lon, SRC, DST, STEP_NMI)
    return lat2, rotation_shift(lon2, t, OMEGA_EARTH_DEG_S)


# ---------------------------------------------------------------------------- the report's way, numpy
def report_vectorized(lat, lon, t):
    phi_L, theta_L = np.radians(lat), np.radians(lon)
    phi_L0, theta_L0, sigma_0 = map(math.radians, (SRC.latitude_deg, SRC.longitude_deg, SRC.heading_deg))
    LF = np.arccos(
        np.clip(
            np.sin(phi_L) * math.sin(phi_L0) + np.cos(phi_L) * math.cos(phi_L0) * np.cos(theta_L - theta_L0), -1.0, 1.0
        )
    )  # (8)
    zeta = np.arctan2(
        np.sin(theta_L - theta_L0) * np.cos(phi_L) * math.cos(phi_L0), np.sin(phi_L) - math.sin(phi_L0) * np.cos(LF)
    )  # (9)
    xi = zeta - sigma_0
    s = np.sin(LF) * np.sin(xi)
    Y = np.arcsin(s)  # (11), positive right as printed (radians of arc)
    X = np.copysign(np.arccos(np.clip(np.cos(LF) / np.cos(Y), -1.0, 1.0)), np.cos(xi))  # (10), signed
    X_DM = X + STEP_NMI / R  # step around the orbit

    phi_M0, theta_M0, sigma_M = map(math.radians, (DST.latitude_deg, DST.longitude_deg, DST.heading_deg))
    PF = Y
    LF_M = np.arccos(np.cos(PF) * np.cos(X_DM))  # (12)
    xi_M = np.arcsin(np.clip(np.sin(PF) / np.sin(LF_M), -1.0, 1.0))  # (13)
    xi_M = np.where(np.sin(X_DM) < 0.0, math.pi - xi_M, xi_M)
    zeta_M = xi_M + sigma_M  # (14)
    zeta_M = np.arctan2(np.sin(zeta_M), np.cos(zeta_M))
    sign = np.where(np.sin(zeta_M) >= 0.0, 1.0, -1.0)
    abs_zeta_M = np.abs(zeta_M)
    cos_LF, sin_LF = np.cos(LF_M), np.sin(LF_M)
    lo = np.arcsin(math.sin(phi_M0) * cos_LF - math.cos(phi_M0) * sin_LF)
    hi = np.arcsin(math.sin(phi_M0) * cos_LF + math.cos(phi_M0) * sin_LF)

    def dtheta(phi):  # eq. (8) for (theta_L - theta_L0)_M
        c = (cos_LF - np.sin(phi) * math.sin(phi_M0)) / (np.cos(phi) * math.cos(phi_M0))
        return sign * np.arccos(np.clip(c, -1.0, 1.0))

    for _ in range(BISECTIONS):  # guess phi_LM, eq. (8), eq. (9), compare with zeta_M
        mid = 0.5 * (lo + hi)
        z = np.arctan2(np.sin(dtheta(mid)) * np.cos(mid) * math.cos(phi_M0), np.sin(mid) - math.sin(phi_M0) * cos_LF)
        south = np.abs(z) > abs_zeta_M
        lo = np.where(south, mid, lo)
        hi = np.where(south, hi, mid)
    phi_LM = 0.5 * (lo + hi)
    theta_LM = dtheta(phi_LM) + theta_M0  # (15)
    return np.degrees(phi_LM), rotation_shift(np.degrees(theta_LM), t, OMEGA_EARTH_DEG_S)


# ------------------------------------------------------------------------- the report's way, a loop
def report_point(lat, lon, t):
    phi_L, theta_L = math.radians(lat), math.radians(lon)
    phi_L0, theta_L0, sigma_0 = map(math.radians, (SRC.latitude_deg, SRC.longitude_deg, SRC.heading_deg))
    LF = math.acos(
        max(
            -1.0,
            min(
                1.0,
                math.sin(phi_L) * math.sin(phi_L0) + math.cos(phi_L) * math.cos(phi_L0) * math.cos(theta_L - theta_L0),
            ),
        )
    )  # (8)
    zeta = math.atan2(
        math.sin(theta_L - theta_L0) * math.cos(phi_L) * math.cos(phi_L0),
        math.sin(phi_L) - math.sin(phi_L0) * math.cos(LF),
    )  # (9)
    xi = zeta - sigma_0
    Y = math.asin(math.sin(LF) * math.sin(xi))  # (11)
    X = math.copysign(math.acos(max(-1.0, min(1.0, math.cos(LF) / math.cos(Y)))), math.cos(xi))  # (10)
    X_DM = X + STEP_NMI / R
    phi_M0, theta_M0, sigma_M = map(math.radians, (DST.latitude_deg, DST.longitude_deg, DST.heading_deg))
    LF_M = math.acos(math.cos(Y) * math.cos(X_DM))  # (12)
    xi_M = math.asin(max(-1.0, min(1.0, math.sin(Y) / math.sin(LF_M))))  # (13)
    if math.sin(X_DM) < 0.0:
        xi_M = math.pi - xi_M
    zeta_M = xi_M + sigma_M  # (14)
    zeta_M = math.atan2(math.sin(zeta_M), math.cos(zeta_M))
    east = math.sin(zeta_M) >= 0.0

    def dtheta(phi):
        c = (math.cos(LF_M) - math.sin(phi) * math.sin(phi_M0)) / (math.cos(phi) * math.cos(phi_M0))
        d = math.acos(max(-1.0, min(1.0, c)))
        return d if east else -d

    lo = math.asin(math.sin(phi_M0) * math.cos(LF_M) - math.cos(phi_M0) * math.sin(LF_M))
    hi = math.asin(math.sin(phi_M0) * math.cos(LF_M) + math.cos(phi_M0) * math.sin(LF_M))
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        z = math.atan2(
            math.sin(dtheta(mid)) * math.cos(mid) * math.cos(phi_M0), math.sin(mid) - math.sin(phi_M0) * math.cos(LF_M)
        )
        if abs(z) > abs(zeta_M):
            lo = mid
        else:
            hi = mid
    phi = 0.5 * (lo + hi)
    lon_m = math.degrees(dtheta(phi) + theta_M0) - OMEGA_EARTH_DEG_S * t  # (15) and the shift
    return math.degrees(phi), (lon_m + 180.0) % 360.0 - 180.0


def report_loop(lat, lon, t):
    return [report_point(a, b, c) for a, b, c in zip(lat.tolist(), lon.tolist(), t.tolist())]


# --------------------------------------------------------------------------------------------- timing


def arc_deg(lat1, lon1, lat2, lon2):
    p1, p2, dl = np.radians(lat1), np.radians(lat2), np.radians(np.asarray(lon2) - np.asarray(lon1))
    y = np.hypot(np.cos(p2) * np.sin(dl), np.cos(p1) * np.sin(p2) - np.sin(p1) * np.cos(p2) * np.cos(dl))
    return np.degrees(np.arctan2(y, np.sin(p1) * np.sin(p2) + np.cos(p1) * np.cos(p2) * np.cos(dl)))


def main():
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    lat, lon, t = points()
    a = ours(lat, lon, t)
    b = report_vectorized(lat, lon, t)
    sub = slice(0, LOOP_SUBSET)
    c = np.array(report_loop(lat[sub], lon[sub], t[sub]))
    ms_ours = median_ms(lambda: ours(lat, lon, t), 50)
    ms_vec = median_ms(lambda: report_vectorized(lat, lon, t), 7)
    ms_loop_subset = median_ms(lambda: report_loop(lat[sub], lon[sub], t[sub]), 3)
    ms_loop = ms_loop_subset * N_POINTS / LOOP_SUBSET
    result = {
        "points": N_POINTS,
        "job": "re-node (lon 0 -> -40 deg) + re-incline (heading 90 -> 30 deg) + step 500 nmi + omega_p t shift",
        "cpu_cores": 1,
        "ours_ms": round(ms_ours, 2),
        "ours_target_ms": TARGET_MS,
        "ours_within_target": ms_ours <= TARGET_MS,
        "ours_ns_per_point": round(1e6 * ms_ours / N_POINTS, 1),
        "report_vectorized_ms": round(ms_vec, 1),
        "report_vectorized_bisections": BISECTIONS,
        "speedup_vs_report_vectorized": round(ms_vec / ms_ours, 1),
        "report_python_loop_ms_scaled": round(ms_loop, 0),
        "report_python_loop_measured": f"{LOOP_SUBSET} points in {ms_loop_subset:.1f} ms, x{N_POINTS // LOOP_SUBSET}",
        "speedup_vs_report_python_loop": round(ms_loop / ms_ours, 0),
        "max_difference_report_vectorized_deg": float(np.max(arc_deg(a[0], a[1], b[0], b[1]))),
        "max_difference_report_loop_deg": float(np.max(arc_deg(a[0][sub], a[1][sub], c[:, 0], c[:, 1]))),
        "numpy": np.__version__,
    }
    save_result("transform", result)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
