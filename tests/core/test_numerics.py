"""Building blocks of the integrating methods (core.numerics): Hermite interpolation and
roots, step control, dense solutions, work limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import RigidStop
from core.numerics.dense_output import HermiteDense, PiecewiseDense, line_piece
from core.numerics.hermite import hermite, hermite_max, root, x_crossing
from core.numerics.limits import WorkLimit
from core.numerics.rk import StepControl, rkf45_step
from core.result import Status


def test_hermite_is_exact_for_cubics_and_root_finds_its_zero():
    # y = t^3 - 0.027 on a step of length 2 from t = 0: a cubic, so the interpolant is exact
    h = 2.0
    y0, d0, y1, d1 = -0.027, 0.0, 8.0 - 0.027, 12.0
    for s in (0.1, 0.5, 0.9):
        assert hermite(s, h, y0, d0, y1, d1) == pytest.approx((s * h) ** 3 - 0.027, abs=1e-14)
    s0 = root(lambda s: hermite(s, h, y0, d0, y1, d1), 0.0, 1.0, y0, y1)
    assert s0 * h == pytest.approx(0.3, abs=1e-14)  # a simple root: to rounding


def test_x_crossing_finds_a_crossing_hidden_inside_a_step():
    # x = sin(t) over [0, pi] rises above 0.9 and falls back: no sign change at the ends
    h = math.pi
    s = x_crossing(h, 0.0, 1.0, 0.0, -1.0, 0.5)
    assert s is not None
    x = hermite(s, h, 0.0, 1.0, 0.0, -1.0)
    assert x == pytest.approx(0.5, abs=1e-12)
    assert x_crossing(h, 0.0, 1.0, 0.0, -1.0, 2.0) is None  # the arc stays below


def test_hermite_max_finds_the_top_between_points():
    t = np.array([0.0, math.pi])
    assert hermite_max(t, np.zeros(2), np.array([1.0, -1.0])) == pytest.approx(math.pi / 4)


def test_step_control_accepts_and_grows_small_errors_and_shrinks_large_ones():
    ctl = StepControl(rtol=1e-6, atol=1e-9)
    _, _, ex, ev = rkf45_step(lambda x, v: -x, 1.0, 0.0, -1.0, 0.1)
    err = ctl.error(1.0, math.cos(0.1), ex, 0.0, -math.sin(0.1), ev)
    assert err <= 1.0
    assert ctl.grown(0.1, err) > 0.1
    assert ctl.shrunk(0.1, 100.0) < 0.1
    assert ctl.shrunk(0.1, math.nan) == pytest.approx(0.02)
    assert ctl.too_small(1e-20, 1.0) and not ctl.too_small(1e-6, 1.0)
    with pytest.raises(ValueError, match="rtol"):
        StepControl(rtol=0.0, atol=1e-9)


def test_hermite_dense_keeps_jumps_and_refuses_times_outside():
    t = np.array([0.0, 1.0, 1.0, 2.0])
    d = HermiteDense(t, [0.0, 1.0, 1.0, 0.0], [1.0, 1.0, -1.0, -1.0], np.zeros(4), x_upper=0.9)
    x_left, v_left = d.evaluate(np.array([1.0]), -1)
    _, v_right = d.evaluate(np.array([1.0]), 1)
    assert x_left[0] == 0.9  # clipped to the stop's face
    assert v_left[0] == 1.0 and v_right[0] == -1.0
    with pytest.raises(ValueError, match="t must lie"):
        d.evaluate(np.array([2.5]), 1)


def test_piecewise_dense_picks_the_piece_of_each_side():
    d = PiecewiseDense()
    d.add(0.0, 1.0, line_piece(0.0, 0.0, 1.0))
    d.add(1.0, 1.0, line_piece(1.0, 5.0, 5.0))  # empty: ignored
    d.add(1.0, 3.0, line_piece(1.0, 1.0, -0.5))
    tq = np.array([[0.5, 1.0], [2.0, 3.0]])
    x, v = d.evaluate(tq, 1)
    assert x.shape == tq.shape
    np.testing.assert_allclose(x, [[0.5, 1.0], [0.5, 0.0]])
    np.testing.assert_allclose(v, [[1.0, -0.5], [-0.5, -0.5]])
    assert d.evaluate(np.array([1.0]), -1)[1][0] == 1.0
    assert d.t_last == 3.0


def test_work_limit_counts_steps_and_time():
    limit = WorkLimit(max_steps=3)
    assert [limit.reached(n) for n in range(4)] == [None, None, None, Status.STEP_LIMIT]
    assert WorkLimit(time_budget=1e-12).reached(0) in (None, Status.TIME_BUDGET)
    spent = WorkLimit(time_budget=1e-9)
    while spent.reached(0) is None:  # the deadline lies 1 ns ahead: it passes at once
        pass
    assert spent.reached(0) is Status.TIME_BUDGET
    with pytest.raises(ValueError, match="max_steps"):
        WorkLimit(max_steps=2.5)
    with pytest.raises(ValueError, match="max_steps"):
        WorkLimit(max_steps="10")
    with pytest.raises(ValueError, match="time_budget"):
        WorkLimit(time_budget=0.0)


@pytest.mark.parametrize(
    ("method", "stop"),
    [("exact", RigidStop(0.25, 0.7)), ("event", RigidStop(0.25, 0.7)),
     ("switch", RigidStop(0.25, 0.7)), ("exact", "hysteretic")],
)
def test_a_result_pickles_with_its_dense_solution(method, stop):
    """A result crosses a process boundary whole (a server may solve in worker processes):
    after a pickle round trip it evaluates exactly as before."""
    import pickle

    from core import HystereticStop, Oscillator, simulate

    if stop == "hysteretic":
        stop = HystereticStop(0.25, 1000.0, 500.0, limit_overlap=1e-3, beta_c=10, beta_e=10)
    res = simulate(Oscillator(0.3, 0.2, 0.1), stop, t_end=40.0, method=method)
    again = pickle.loads(pickle.dumps(res))
    times = np.linspace(0.0, 40.0, 97)
    for side in (-1, 1):
        np.testing.assert_array_equal(again.evaluate(times, side)[0], res.evaluate(times, side)[0])
    assert repr(again.steady) == repr(res.steady) and again.stats == res.stats  # nan != nan
