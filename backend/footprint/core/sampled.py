"""The peak and the integral of a quantity known only at samples (a flight's rows, a search grid).

A maximum read off the samples is short of the true one by up to (1/8) |y''| h^2 for samples h apart; the vertex of
the parabola through the largest sample and its two neighbours leaves O(h^3). The trapezoidal rule's error is O(h^2)
too; where a step was recorded at four evenly spaced rows (a DOP853 step, integrate.DOP853_ROWS_PER_STEP = 3),
Simpson's 3/8 rule over them leaves O(h^5) a step.
"""

import numpy as np
from numpy.typing import NDArray


def parabola_peak(x: NDArray[np.float64], y: NDArray[np.float64], i: int) -> tuple[float, float]:
    """(x, y) of the vertex of the parabola through samples i - 1, i, i + 1 (any spacing, x increasing) where it is
    a maximum between them; (x[i], y[i]) otherwise (an end sample, a repeated abscissa, no curvature)."""
    if not 0 < i < len(y) - 1:
        return float(x[i]), float(y[i])
    x0, x1, x2 = float(x[i - 1]), float(x[i]), float(x[i + 1])
    y0, y1, y2 = float(y[i - 1]), float(y[i]), float(y[i + 1])
    if not x0 < x1 < x2:
        return x1, y1
    d01 = (y1 - y0) / (x1 - x0)
    curve = ((y2 - y1) / (x2 - x1) - d01) / (x2 - x0)  # Newton's form: y0 + d01 (x - x0) + curve (x - x0)(x - x1)
    if not curve < 0.0:
        return x1, y1
    xv = 0.5 * (x0 + x1) - 0.5 * d01 / curve  # where the slope d01 + curve (2 x - x0 - x1) is zero
    if not x0 <= xv <= x2:
        return x1, y1
    return xv, y0 + d01 * (xv - x0) + curve * (xv - x0) * (xv - x1)


def peak(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    """The largest value of y(x) from its samples: the parabola's vertex about the largest sample."""
    return parabola_peak(x, y, int(np.argmax(y)))[1]


def step_integral(t: NDArray[np.float64], y: NDArray[np.float64], step_end: NDArray[np.bool_]) -> float:
    """The integral of y over t from rows of which step_end marks each step's end (and the first row): Simpson's
    3/8 rule over a step recorded at four evenly spaced rows, the trapezoidal rule elsewhere."""
    total = float(np.trapezoid(y, t))
    ends = np.flatnonzero(step_end)
    s = ends[:-1][np.diff(ends) == 3]  # the first rows of the steps with two rows inside
    if s.size:
        h = t[s + 3] - t[s]
        simpson = h / 8.0 * (y[s] + 3.0 * y[s + 1] + 3.0 * y[s + 2] + y[s + 3])
        trapezoid = sum(0.5 * (y[s + j] + y[s + j + 1]) * (t[s + j + 1] - t[s + j]) for j in range(3))
        total += float(np.sum(simpson - trapezoid))
    return total
