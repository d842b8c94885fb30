"""core.sampled against closed forms: the parabola's vertex, the order of the refined peak, Simpson's 3/8 rule."""

import math

import numpy as np
import pytest

from footprint.core.sampled import parabola_peak, peak, step_integral


def test_the_vertex_of_a_sampled_parabola_is_its_own_at_any_spacing():
    x = np.array([0.0, 0.7, 2.9])
    y = -3.0 * (x - 1.3) ** 2 + 5.0  # vertex (1.3, 5.0)
    assert parabola_peak(x, y, 1) == pytest.approx((1.3, 5.0), rel=1e-14)


@pytest.mark.parametrize(
    ("x", "y", "i"),
    [
        ([0.0, 1.0, 2.0], [3.0, 2.0, 1.0], 0),  # an end sample
        ([0.0, 1.0, 2.0], [1.0, 2.0, 3.0], 2),
        ([0.0, 1.0, 1.0], [1.0, 2.0, 2.0], 1),  # a repeated abscissa (an event row at a step's time)
        ([0.0, 1.0, 2.0], [2.0, 2.0, 2.0], 1),  # no curvature
    ],
)
def test_without_a_maximum_between_its_neighbours_the_sample_stands(x, y, i):
    assert parabola_peak(np.array(x), np.array(y), i) == (x[i], y[i])


def test_the_refined_peak_of_a_smooth_bump_falls_off_as_h_cubed():
    """sin sampled h apart with the peak between samples: the sample is short by ~h^2/8, the vertex by O(h^3)."""
    errors = {}
    for h in (0.2, 0.1, 0.05):
        x = np.arange(0.0, 3.0, h) + 0.37 * h
        errors[h] = (1.0 - float(np.max(np.sin(x))), 1.0 - peak(x, np.sin(x)))
    for h in (0.1, 0.05):
        sampled, refined = errors[h]
        assert refined < 0.02 * sampled
        assert abs(refined) <= abs(errors[2 * h][1]) / 6.0  # third order: 8x in theory, 6x allowed


def test_simpsons_three_eighths_rule_is_exact_for_a_cubic_over_four_row_steps():
    """Steps of different lengths, each with two evenly spaced rows inside (a DOP853 step), then one-row steps
    (DOPRI5) where y is linear: the integral is the closed form."""
    starts = np.array([0.0, 0.5, 1.7, 2.0])
    t = np.concatenate([np.linspace(a, b, 4)[:-1] for a, b in zip(starts[:-1], starts[1:])] + [[2.0, 2.6, 3.1]])
    end = np.ones(t.size, dtype=bool)
    end[1:9] = np.tile([False, False, True], 3)[:8]
    assert list(np.flatnonzero(end)) == [0, 3, 6, 9, 10, 11]
    cubic = 2.0 * t**3 - t**2 + 0.5
    y = np.where(t <= 2.0, cubic, 12.5 + 20.0 * (t - 2.0))  # continuous at t = 2 (12.5), linear after
    exact = (0.5 * 2.0**4 - 2.0**3 / 3.0 + 1.0) + (12.5 * 1.1 + 10.0 * 1.1**2)
    assert step_integral(t, y, end) == pytest.approx(exact, rel=1e-14)
    assert not math.isclose(float(np.trapezoid(y, t)), exact, rel_tol=1e-3)  # the trapezoid alone is not
