"""The "last N periods" box of a long run's window (app.plots.window), without a browser:
the number typed sets the window to the last N periods of the run's steady state (core's
period, an independent reference), the histories are sampled for it, a number out of
1..periods is refused in the box's words, and a new run at the same horizon keeps N
(tests/ui/test_long_run_ui.py types into it in Chromium)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.plots import HISTORY_COLUMNS, PlotSet
from app.plots.window import WINDOW_PERIODS, period_count
from app.solve.pool import solve
from app.state import DIMENSIONLESS, scene_values

#: Scene 5a's periodic cycle to t_end = 2000: some 300 periods.
SCENE, T_END = "5a", 2000.0
#: Budget [s] of the solve: it tests the window, not the page's 2 s budget.
BUDGET_S = 120.0
#: Relative tolerance of window edges: sums and differences of times ~2000 in float64.
REL = 1e-12
#: Samples are float32 in the browser's columns: 2000 * 2^-23 ~ 2.4e-4.
T_TOL = 1e-3
#: Samples of the window per period at least: the default window of 5 periods gets ~60, the
#: rest of the run some 15; a window of many periods gets one or more per pixel column of
#: the figure (HISTORY_COLUMNS: M4 thinning keeps each column's extremes). The first sample
#: may lie up to a period in (a stick's straight line is thinned to its ends).
MIN_SAMPLES_PER_PERIOD = 40


@pytest.fixture(scope="module")
def drawn():
    sol = solve({**scene_values(SCENE), "t_end": T_END}, budget=BUDGET_S)
    plots = PlotSet()
    plots.update(sol, DIMENSIONLESS, ("phase", "time", "force"))
    return plots, sol


def _time_range(plots: PlotSet) -> tuple[float, float]:
    rng = plots.figures["time_x"].x_range
    return rng.start, rng.end


def _check_window(plots: PlotSet, sol, n: int) -> None:
    period = sol.result.steady.period
    lo, hi = _time_range(plots)
    assert hi == pytest.approx(sol.t_end, rel=REL)
    assert hi - lo == pytest.approx(n * period, rel=REL)
    assert plots.run_window.window == (pytest.approx(lo, rel=REL), pytest.approx(hi, rel=REL))
    # The histories are sampled for the window (the rest of the run, thinly, for a pan):
    # from its start to its end, as densely per period whatever N.
    t = np.asarray(plots.sources["traj"].data["t"], dtype=float)
    inside = t[(t >= lo - T_TOL) & (t <= hi + T_TOL)]
    assert inside.min() <= lo + period and inside.max() >= hi - period / 10
    assert len(inside) >= min(MIN_SAMPLES_PER_PERIOD * n, HISTORY_COLUMNS)


def test_the_box_sets_the_last_n_periods(drawn):
    plots, sol = drawn
    box, period = plots.run_window.periods_box, sol.result.steady.period
    count = math.floor(sol.t_end / period)
    assert count == period_count(sol) > 2 * WINDOW_PERIODS
    # Unbounded in the browser, which would clamp silently: the server refuses (below).
    assert box.visible and (box.low, box.high) == (None, None)
    assert box.value == WINDOW_PERIODS and str(count) in box.title
    _check_window(plots, sol, WINDOW_PERIODS)
    box.value = 12  # what the browser sends when N is typed
    _check_window(plots, sol, 12)
    box.value = count  # the whole run's periods
    _check_window(plots, sol, count)
    assert _time_range(plots)[0] >= 0.0
    box.value = 1
    _check_window(plots, sol, 1)


@pytest.mark.parametrize("n", [0, -3, 1e9, 2.5])
def test_a_number_out_of_the_run_is_refused_naming_the_range(drawn, n):
    plots, sol = drawn
    window, box = plots.run_window, plots.run_window.periods_box
    window.show_last(3)
    count = period_count(sol)
    message = rf"last periods must be a whole number in \[1, {count}\] \(the run's periods\)"
    with pytest.raises(ValueError, match=message + rf"; got {n!r}"):
        window.show_last(n)
    box.value = n  # from the page: the box says why, and shows N again
    assert box.title == f"N must be from 1 to {count}; got {n!r}" and box.value == 3
    _check_window(plots, sol, 3)
    box.value = 4  # a good number puts the title back
    assert box.title.startswith("Show the last N periods") and box.value == 4


def test_a_new_run_at_the_same_horizon_keeps_n_and_a_new_horizon_the_default(drawn):
    plots, sol = drawn
    plots.run_window.show_last(7)
    plots.update(sol, DIMENSIONLESS, ("phase", "time", "force"))  # e.g. a pin, a redraw
    assert plots.run_window.periods_box.value == 7
    _check_window(plots, sol, 7)
    longer = solve({**scene_values(SCENE), "t_end": T_END + 500.0}, budget=BUDGET_S)
    plots.update(longer, DIMENSIONLESS, ("phase", "time", "force"))
    assert plots.run_window.periods_box.value == WINDOW_PERIODS
    _check_window(plots, longer, WINDOW_PERIODS)
    plots.update(sol, DIMENSIONLESS, ("phase", "time", "force"))  # back, for the others


@pytest.mark.parametrize(("scene", "t_end"), [("11", 80.0), ("6b", 500.0)])
def test_a_run_that_settles_is_shown_whole(scene, t_end):
    """Scene 11's mass ends pressed on the stop, its swing shrinking (core's steady state:
    an oscillation, period 0.17): its last five periods drew flat lines over 0.8 time units.
    Scene 6b's comes to rest, which to t_end = 500 is 80 turns. A run that settles is shown
    whole, the transient and the decay, with no overview."""
    from app.plots.window import SETTLING, default_window

    sol = solve({**scene_values(scene), "t_end": t_end}, budget=BUDGET_S)
    assert sol.result.steady.kind in SETTLING
    assert default_window(sol) is None
    plots = PlotSet()
    plots.update(sol, DIMENSIONLESS, ("phase", "time", "force"))
    lo, hi = _time_range(plots)
    assert lo <= 0.0 and hi >= sol.t_end * (1 - REL)
