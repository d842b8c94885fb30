"""Plane geometry in the (down-range, cross-range) plane of a footprint: the one point-in-polygon test."""

import numpy as np
from numpy.typing import NDArray

from footprint.core._jit import njit


@njit
def inside_polygon(px: NDArray[np.float64], py: NDArray[np.float64], m: int, x: float, y: float) -> bool:
    """Whether (x, y) lies in the polygon px[:m], py[:m] by the even-odd rule: a ray cast along +x crosses the
    boundary an odd number of times (Shimrat, "Algorithm 112: Position of point relative to polygon", CACM 1962)."""
    inside = False
    for e in range(m):
        x0, y0, x1, y1 = px[e], py[e], px[(e + 1) % m], py[(e + 1) % m]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def inside_points(x: float, y: float, polygon: list[tuple[float, float]]) -> bool:
    """inside_polygon for a polygon given as (x, y) pairs."""
    pts = np.asarray(polygon, float).reshape(-1, 2)
    return bool(inside_polygon(np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1]), len(pts), x, y))
