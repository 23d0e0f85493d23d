"""Long runs of a scene: the horizon keeps the scene; the window over the run."""

from __future__ import annotations

import numpy as np
import panel as pn
import pytest

from app.explorer import Explorer
from app.plots import HISTORY_COLUMNS
from app.plots.window import WINDOW_PERIODS
from app.sampling import HISTORY_DT, MAX_HISTORY_SAMPLES
from app.scenes import CUSTOM
from app.state import ExplorerState, scene_values


def test_a_longer_horizon_keeps_the_scene(monkeypatch):
    """``?scene=5a&tend=5000`` and a horizon typed on scene 10 turned the page 'custom'
    (title and caption gone), though a long run of a figure is still that figure. The
    horizon keeps the scene, by widget and by link; a physical value still leaves it."""
    from panel.io.location import Location

    ex = Explorer()
    ex.scene_select.value = "10"
    ex.controls.commit({"t_end": 3000.0})
    assert ex.state.t_end == 3000.0 and ex.state.scene == "10"
    assert "Fig. 10" in ex.caption.object
    ex.controls.commit({"clearance": ex.state.clearance * 0.9})
    assert ex.state.scene == CUSTOM
    monkeypatch.setattr(pn.state, "_location", Location(search="?scene=5a&tend=5000"))
    linked = Explorer()
    linked.sync_url()
    assert (linked.state.scene, linked.state.t_end) == ("5a", pytest.approx(5000.0))
    assert not linked.alert.visible


def _page(scene: str, t_end: float | None = None) -> Explorer:
    values = scene_values(scene)
    if t_end is not None:
        values["t_end"] = t_end
    ex = Explorer(ExplorerState(scene=scene, **values))
    assert ex.solution is not None and ex.solution.result is not None
    return ex


def _largest_gap(t: np.ndarray, lo: float, hi: float) -> float:
    inside = t[(t >= lo) & (t <= hi)]
    return float(np.diff(inside).max())


#: The finest step the time histories are sampled at over a run of ``t_end``
#: (:func:`app.sampling.fine_samples`); float32 times of ~5000 add 5e-4.
def _fine_step(t_end: float) -> float:
    return max(HISTORY_DT, t_end / MAX_HISTORY_SAMPLES) + 5e-4


@pytest.mark.parametrize(("scene", "t_end"), [("5a", 5000.0), ("10", 3000.0)])
def test_a_long_run_shows_its_last_periods_in_full_detail(scene, t_end):
    """At t_end = 5000 (scene 5a) or 3000 (scene 10) the time histories and the contact
    force were drawn whole: one pixel column of some three time units held half a period,
    and the curves read as solid blocks. The page now shows the last WINDOW_PERIODS
    periods, sampled as finely as a short run, with the whole run below as an overview."""
    ex = _page(scene, t_end)
    sol, plots = ex.solution, ex.plots
    period = sol.result.steady.period
    fx = plots.figures["time_x"].x_range
    assert (fx.end - fx.start) == pytest.approx(WINDOW_PERIODS * period, rel=1e-9)
    assert fx.end == pytest.approx(t_end, rel=1e-12)
    assert plots.figures["force"].x_range.start == pytest.approx(fx.start)
    t = np.asarray(plots.sources["traj"].data["t"], float)
    assert _largest_gap(t, fx.start, fx.end) <= _fine_step(t_end)
    overview = plots.run_window.overview
    assert overview is not None and overview.visible
    assert overview.x_range.end == pytest.approx(t_end)
    assert plots.run_window.brush.x_range is fx
    # Brushing the overview (the browser sets the time axis): the window follows, the
    # histories are sampled for it, the force's axis moves with it.
    lo, hi = 0.4 * t_end, 0.4 * t_end + 3 * period
    fx.update(start=lo, end=hi)
    assert plots.run_window.window == pytest.approx((lo, hi))
    t = np.asarray(plots.sources["traj"].data["t"], float)
    assert _largest_gap(t, lo, hi) <= _fine_step(t_end)
    assert (plots.figures["force"].x_range.start, plots.figures["force"].x_range.end) == (
        pytest.approx(lo), pytest.approx(hi))
    # The bands inside the window are cut at the window's columns, not the whole run's.
    left, right, _ = plots.bands
    inside = (left > lo) & (right < hi)
    assert inside.any() and (right[inside] - left[inside]).min() < t_end / HISTORY_COLUMNS


def test_a_short_run_is_shown_whole_without_an_overview():
    ex = _page("5a")
    fx = ex.plots.figures["time_x"].x_range
    assert (fx.start, fx.end) == (0.0, pytest.approx(ex.solution.t_end))
    assert ex.plots.run_window.window is None and ex.plots.run_window.overview is None


@pytest.mark.parametrize("scene", ["7c", "5a"])
def test_the_page_s_return_map_has_a_point_per_pair_of_impacts(scene):
    """The return map drawn on the page: one point per pair of successive impacts of the
    run (core's count of impacts), the fixed point where the steady state is periodic."""
    ex = _page(scene)
    counts = ex.solution.result.transition_counts
    impacts = counts.get("impact", 0) + counts.get("stick->impact", 0)
    points = ex.plots.sources["ret_points"].data
    assert len(points["x"]) == impacts - 1
    assert f"({impacts - 1} points)" in ex.plots.figures["return"].title.text
    periodic = ex.solution.result.steady.kind.value == "periodic"
    assert len(ex.plots.sources["ret_fixed"].data["x"]) == (1 if periodic else 0)


def test_the_server_s_own_move_of_the_window_is_not_a_brush(monkeypatch):
    """Served, a horizon of 5000 opened on a page of 60 put the contact force on
    (60, 4972): Bokeh told the brush's handler of the server's own move of the time axis
    once per edge, the handler read a range of one old and one new edge and, a moment
    later, drew that as the window. Here the session's event loop is a list of calls run
    after the release, as in the browser."""
    import app.plots.window as window_module

    pending = []
    monkeypatch.setattr(window_module, "later", lambda fn, ms: pending.append(fn) or fn)
    ex = _page("5a")
    ex.controls.commit({"t_end": 5000.0})
    for call in pending:
        call()
    plots = ex.plots
    default = plots.run_window.window
    period = ex.solution.result.steady.period
    assert default == pytest.approx((5000.0 - WINDOW_PERIODS * period, 5000.0))
    fx = plots.figures["time_x"].x_range
    assert (fx.start, fx.end) == pytest.approx(default)
    ex.host.build_in_view({"force"})
    force = plots.figures["force"].x_range
    assert (force.start, force.end) == pytest.approx(default)
