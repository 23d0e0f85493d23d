"""The explorer's logic without a browser: widgets -> state -> solve -> sources."""

from __future__ import annotations

import doctest
import html
import importlib
import re

import numpy as np
import panel as pn
import param
import pytest
from bokeh.events import Tap

from app.explorer import SHOWN_LATER, Explorer
from app.perf import applies
from app.readout import DIGITS
from app.scenes import CUSTOM, PLOTS, SCENES
from app.solve import pool
from app.solve.pool import Solver
from app.solve.presets import ACCURACY
from app.solve.regime_map import MAP_CELLS
from app.solve.solution import compute
from app.state import ExplorerState, scene_values, si_bound_error, si_units
from app.widgets import format_number


@pytest.fixture
def ex() -> Explorer:
    return Explorer()


def _release(ex: Explorer, name: str, value: float) -> None:
    """What the browser sends when a drag ends at ``value``."""
    slider = ex.sliders[name].slider
    slider.value = value
    with param.edit_constant(slider):
        slider.value_throttled = value


def _same(a, b) -> bool:
    """Equal arrays, NaN where NaN."""
    try:
        np.testing.assert_array_equal(a, b)
    except AssertionError:
        return False
    return True


def _theory(ex: Explorer) -> list:
    """The phase portrait's renderers of the theory (limit cycle, gamma0, points)."""
    theory = {id(ex.plots.sources[n]) for n in ("gamma0", "cycle", "removed", "points")}
    return [r for r in ex.plots.figures["phase"].renderers
            if id(getattr(r, "data_source", None)) in theory]


def _traj(ex: Explorer) -> dict:
    return {k: np.array(v) for k, v in ex.plots.sources["traj"].data.items()}


def test_opens_on_a_scene_with_a_picture(ex):
    assert ex.error is None and ex.solution is not None
    traj = _traj(ex)
    assert 100 < len(traj["x"]) <= 2 * ACCURACY["standard"]["n_samples"]
    assert traj["x"].dtype == np.float32
    assert "Steady state found" in ex.readout.object
    visible = [n for n, p in ex.plot_panes.items() if p.visible]
    assert visible == [p for p in PLOTS if p in ("phase", "time", "anim", "force", "map", "return")]
    # The box that shows the others names them.
    assert ex.show_all.name == "show all plots (+ friction law, energy)"
    ex.show_all.value = True
    assert [n for n, p in ex.plot_panes.items() if p.visible] == [
        p for p in PLOTS if p != "loop"]
    assert ex.show_all.name == "show all plots"


def test_invalid_input_shows_a_message_and_keeps_the_last_result(ex):
    before, traj_before = ex.solution, _traj(ex)
    _release(ex, "clearance", -0.5)  # behind the start x0 = 0
    assert ex.state.clearance == -0.5  # the user's value is shown ...
    assert ex.alert.visible and "ahead of the start" in ex.alert.object
    assert ex.solution is before  # ... but the last good picture stays
    for key, col in _traj(ex).items():
        np.testing.assert_array_equal(col, traj_before[key])
    _release(ex, "clearance", 0.3)  # a valid value clears the alert
    assert not ex.alert.visible and ex.solution is not before


def test_a_crashing_solver_does_not_take_the_session_down(ex, monkeypatch):
    before = ex.solution

    def boom(*args, **kwargs):
        raise RuntimeError("numerical trouble")

    monkeypatch.setattr(pool, "SOLVER", Solver(compute=boom))  # in the worker thread
    _release(ex, "belt_speed", 0.12)
    assert ex.alert.visible and "numerical trouble" in ex.alert.object
    assert ex.solution is before


def test_mu_k_is_clamped_to_mu_s(ex):
    _release(ex, "mu_s", 0.15)  # below mu_k = 0.2
    assert ex.state.mu_s == 0.15 and ex.state.mu_k == 0.15
    w = ex.sliders["mu_k"]
    assert w.slider.end == pytest.approx(0.15) and w.bounds[1] == pytest.approx(0.15)
    assert ex.error is None
    _release(ex, "mu_s", 0.5)  # the end follows mu_s back up
    assert w.slider.end == pytest.approx(0.5) and ex.state.mu_k == 0.15


def test_typed_entry_commits_and_widens_the_slider(ex):
    w = ex.sliders["belt_speed"]
    w.input.value = "0.9"  # beyond the slider's soft end
    assert ex.state.belt_speed == 0.9 and ex.state.scene == CUSTOM
    assert w.slider.end >= 0.9 and w.slider.value == 0.9
    w.input.value = "50"  # beyond the hard bound: refused, said, the value in use shown
    assert ex.state.belt_speed == 0.9 and w.invalid and w.input.value == "0.9"
    assert "belt_speed must lie in [0, 10]; got 50" in w.message.object


def test_drag_previews_without_committing(ex):
    before = _traj(ex)["x"]
    theory = _theory(ex)
    ex.sliders["belt_speed"].slider.value = 0.15
    assert ex.state.belt_speed == 0.1  # not committed
    assert not np.array_equal(_traj(ex)["x"], before)  # a preview was drawn
    assert not any(r.visible for r in theory)  # without the last state's theory
    _release(ex, "belt_speed", 0.15)
    assert ex.state.belt_speed == 0.15 and all(r.visible for r in theory)


def test_a_pending_preview_is_dropped_once_the_release_has_arrived(ex, monkeypatch):
    """A drag's preview is drawn a moment after it is solved. A release read from the
    browser before that moment, even if Panel has not processed it yet, makes the preview
    stale: drawing it would only delay the release's full picture."""
    deferred = []
    monkeypatch.setattr("app.plots_host.later", lambda fn, delay_ms: deferred.append(fn))
    slider = ex.sliders["belt_speed"].slider
    before = _traj(ex)
    slider.value = 0.15  # a drag step: the preview is solved, its drawing deferred
    [draw_preview] = deferred
    # The release as it arrives from the browser (app.perf.slider calls the slider's
    # ``on_release`` then), before Panel processes it.
    slider.on_release()
    draw_preview()  # the preview's moment comes first: it is not drawn
    assert all(_same(col, before[key]) for key, col in _traj(ex).items())
    _release(ex, "belt_speed", 0.15)  # the release's turn: committed, full picture
    assert ex.state.belt_speed == 0.15 and ex.solution.values["belt_speed"] == 0.15
    # Without a release in between, a deferred preview is drawn.
    full = _traj(ex)
    deferred.clear()
    slider.value = 0.2
    [draw_preview] = deferred
    draw_preview()
    assert not np.array_equal(_traj(ex)["x"], full["x"])
    assert not _theory(ex)[0].visible  # a preview is shown


def test_a_release_where_the_slider_was_last_released_commits_after_a_typed_value(ex):
    """Released at 0.12, then 0.15 typed, then released at 0.12 again: the browser sends that
    release (static/perf/release_hold.js), and the Bokeh model behind the slider must see a change,
    or it drops the release before Panel hears of it."""
    from bokeh.document import Document

    doc = Document()
    model = ex.sliders["belt_speed"].slider.get_root(doc)
    doc.add_root(model)

    def release(value):  # as the server applies the browser's message
        model.set_from_json("value", value)
        model.set_from_json("value_throttled", value)

    release(0.12)
    assert ex.state.belt_speed == 0.12
    ex.sliders["belt_speed"].input.value = "0.15"
    assert ex.state.belt_speed == 0.15
    release(0.12)
    if not applies("slider-release"):  # app.perf.slider keeps the model in step
        assert ex.state.belt_speed == 0.15  # the documented limitation without it
        return
    assert ex.state.belt_speed == 0.12 and ex.solution.values["belt_speed"] == 0.12
    assert ex.sliders["belt_speed"].input.value == "0.12"


def test_a_release_is_not_counted_as_busy_work_where_the_patch_applies(ex):
    """The page shows no busy indicator: Panel's busy counter (public ``pn.state.busy``) is
    not kept for a slider's values where ``slider-not-busy`` applies (app.perf.slider),
    and is where it does not, as Panel does."""
    from bokeh.document import Document

    doc = Document()
    model = ex.sliders["belt_speed"].slider.get_root(doc)
    doc.add_root(model)
    seen = []
    watcher = pn.state.param.watch(lambda event: seen.append(event.new), "busy")
    try:  # as the server applies the browser's message
        model.set_from_json("value", 0.14)
        model.set_from_json("value_throttled", 0.14)
    finally:
        pn.state.param.unwatch(watcher)
    assert ex.state.belt_speed == 0.14  # the release was applied either way
    assert seen == ([] if applies("slider-not-busy") else [True, False] * 2)


def test_release_where_the_drag_started_restores_the_full_picture(ex):
    full = _traj(ex)
    ex.sliders["belt_speed"].slider.value = 0.13
    _release(ex, "belt_speed", 0.1)  # back to the committed value
    np.testing.assert_array_equal(_traj(ex)["x"], full["x"])


def test_scene_selector_loads_the_scene_and_its_plots(ex):
    ex.scene_select.value = "3a"
    assert ex.state.scene == "3a" and ex.state.stop_type == "none"
    visible = {n for n, p in ex.plot_panes.items() if p.visible}
    assert "force" not in visible and "loop" not in visible and "friction" in visible
    res = ex.solution.result  # an impactless scene computes no contact force
    assert len(res.impulses) == 0 and not np.any(res.contact_force)
    assert "Fig. 3a" in ex.caption.object
    ex.scene_select.value = "11"
    visible = {n for n, p in ex.plot_panes.items() if p.visible}
    assert {"force", "loop"} <= visible
    assert np.max(ex.plots.sources["force"].data["phi"]) > 0
    assert ex.hysteretic_box.visible and not ex.sliders["restitution"].visible


def test_hidden_slider_groups_join_the_page_when_first_shown(ex):
    # A rigid scene in dimensionless units: the deformable-stop and SI sliders are not in
    # the page (their models would be built and sent for nothing) until a state shows them.
    assert ex.state.stop_type == "rigid" and ex.state.units != "SI"
    waiting = (ex.hysteretic_box, ex.si_box, *ex.si_start.values())
    assert not any(box.built or box.objects for box in waiting)
    # Nor are their sliders' widgets made (Python objects a new page does not need).
    assert not any(ex.sliders[n].built for n in SHOWN_LATER)
    assert all(ex.sliders[n].built for n in set(ex.sliders) - SHOWN_LATER)
    ex.state.param.update(k_c0=250.0, k_e0=30.0)
    assert not ex.sliders["k_c0"].built and ex.sliders["k_e0"].value == 30.0
    ex.stop_type.value = "hysteretic"
    assert ex.hysteretic_box.built and ex.hysteretic_box.visible
    assert ex.sliders["k_c0"].layout in ex.hysteretic_box.objects
    # Kept in step while it waited: the widgets show the state's values when they join.
    k_c0, k_e0 = ex.sliders["k_c0"], ex.sliders["k_e0"]
    assert k_c0.value == ex.state.k_c0 == 250.0
    assert (k_c0.slider.value, k_c0.input.value) == (250.0, "250")
    assert k_e0.slider.value == 30.0 and k_e0.bounds[1] == 250.0  # k_e0 <= k_c0
    # The tooltip names the bound that moves (its number would make a new model per move).
    assert "to compression stiffness" in k_e0.input.description
    assert "250" not in k_e0.input.description
    assert not ex.sliders["mass"].built
    ex.units.value = "SI"
    assert all(box.built and box.visible for box in (ex.si_box, *ex.si_start.values()))
    ex.units.value = "dimensionless"
    assert ex.si_box.built and not ex.si_box.visible  # built once, then only hidden
    ex.stop_type.value = "rigid"
    assert not ex.hysteretic_box.visible


def test_a_slider_message_joins_its_widget_when_first_needed(ex):
    w = ex.sliders["restitution"]
    assert w.message not in w.layout.objects
    w.input.value = "1.5"
    assert w.message in w.layout.objects and w.message.visible and w.invalid
    w.input.value = "0.5"
    assert not w.message.visible and not w.invalid


def test_tap_in_the_phase_plane_sets_the_start(ex):
    fig = ex.plots.figures["phase"]
    ex.host.phase_tapped(Tap(fig, x=-0.2, y=0.05))
    assert (ex.state.x0, ex.state.v0) == (-0.2, 0.05)
    assert ex.plots.sources["start"].data["x"] == [-0.2]


def test_tap_on_the_map_moves_belt_speed_and_clearance(ex):
    ex.host.map_tapped(Tap(ex.plots.figures["map"], x=0.3, y=0.25))
    assert (ex.state.belt_speed, ex.state.clearance) == (0.3, 0.25)
    assert ex.sliders["belt_speed"].value == 0.3
    assert ex.plots.sources["here"].data == {"v": [0.3], "x": [0.25]}


@pytest.mark.parametrize(("x", "y"), [(1e9, 0.0), (0.1, float("nan")), ("a", 0.1),
                                       (float("inf"), 0.1)])
def test_a_tap_no_user_can_make_is_refused_quietly(ex, caplog, x, y):
    """A script's tap outside the state's bounds, or not at numbers, failed in the handler
    with an ERROR and a traceback (the state's bounds, ``float('a')``)."""
    before = ex.state.values()
    with caplog.at_level("WARNING"):
        ex.host.phase_tapped(Tap(ex.plots.figures["phase"], x=x, y=y))
        ex.host.map_tapped(Tap(ex.plots.figures["map"], x=x, y=y))
    assert ex.state.values() == before
    assert [r for r in caplog.records if r.levelno >= 40] == []


def test_si_units_convert_the_view(ex):
    ex.units.value = "SI"
    assert ex.si_box.visible and not ex.sliders["u_s"].visible
    phys = ex.state.physical()
    assert ex.sliders["normal_force"].value == pytest.approx(phys["normal_force"])
    assert ex.plots.figures["phase"].yaxis.axis_label == "dx/dt (m/s)"
    omega = ex.state.omega
    t = np.array(ex.plots.sources["traj"].data["t"])
    from app.plots import trajectory_columns

    t_dimensionless = trajectory_columns(ex.solution)["t"]  # float32: rtol 1e-6
    np.testing.assert_allclose(t, t_dimensionless / omega, rtol=1e-6)
    _release(ex, "normal_force", 2 * phys["normal_force"])
    assert ex.state.u_s == pytest.approx(2.0)


def test_si_start_velocity_and_horizon_are_in_metres_per_second_and_seconds(ex):
    ex.state.param.update(mass=1.0, stiffness=100.0)  # omega = 10 rad/s, as said below
    ex.units.value = "SI"
    omega = ex.state.omega
    visible = {name: s.visible for name, s in ex.sliders.items()}
    assert visible["v0_si"] and visible["t_end_si"]
    assert not visible["v0"] and not visible["t_end"]
    assert ex.sliders["t_end_si"].value == pytest.approx(ex.state.t_end / omega)
    assert "(mm)" in ex.sliders["x0_si"].label and visible["x0_si"] and not visible["x0"]
    _release(ex, "t_end_si", 3.0)  # seconds
    assert ex.state.t_end == pytest.approx(3.0 * omega)
    _release(ex, "v0_si", -0.002)  # m/s: the dimensionless x'0 is v / (omega L)
    assert ex.state.v0 == pytest.approx(-0.002 / (omega * ex.state.length_unit))
    assert ex.plots.sources["start"].data["v"] == [pytest.approx(-0.002)]
    t = np.array(ex.plots.sources["traj"].data["t"])
    assert t[-1] == pytest.approx(3.0, rel=1e-6)  # the time axis ends at 3 s
    # A horizon the core cannot take is refused with its range, and the picture stays.
    _release(ex, "t_end_si", 1e6)
    # In the seconds the box shows (5000 / omega), not the core's dimensionless bound.
    assert ex.alert.visible and "t_end must lie in [0.01, 500] s" in ex.alert.object
    assert ex.state.t_end == pytest.approx(3.0 * omega)
    ex.units.value = "dimensionless"
    assert ex.sliders["t_end"].visible and not ex.sliders["t_end_si"].visible
    assert ex.sliders["t_end"].value == pytest.approx(3.0 * omega)


def test_si_stop_stiffnesses_are_in_newtons_per_metre_and_keep_their_order(ex):
    ex.scene_select.value = "10"
    ex.units.value = "SI"
    k = ex.state.stiffness
    shown = {name for name in ("k_c0", "k_c0_si", "k_e0", "k_e0_si") if ex.sliders[name].visible}
    assert shown == {"k_c0_si", "k_e0_si"}
    assert ex.sliders["k_c0_si"].value == pytest.approx(ex.state.k_c0 * k)
    assert "N/m" in ex.sliders["k_c0_si"].label
    # The expansion stiffness ends where the compression stiffness stands (k_e0 <= k_c0).
    assert ex.sliders["k_e0_si"].bounds[1] == pytest.approx(ex.state.k_c0 * k)
    _release(ex, "k_c0_si", 20_000.0)
    assert ex.state.k_c0 == pytest.approx(20_000.0 / k) and ex.state.scene == "custom"
    # Below the expansion stiffness: the expansion stiffness follows it down, as in the
    # dimensionless view, and nothing is refused.
    _release(ex, "k_c0_si", 0.5 * ex.sliders["k_e0_si"].value)
    assert ex.state.k_e0 == ex.state.k_c0 and not ex.alert.visible
    assert ex.sliders["k_e0_si"].value == pytest.approx(ex.state.k_c0 * k)
    ex.units.value = "dimensionless"
    assert ex.sliders["k_c0"].visible and not ex.sliders["k_c0_si"].visible
    assert ex.sliders["k_c0"].value == pytest.approx(ex.state.k_c0)
    ex.scene_select.value = "2b"  # the stop alone: the readout names its stiffnesses
    assert f"k_c0/k = {ex.state.k_c0:.{DIGITS}g}," in ex.readout.object
    ex.units.value = "SI"
    assert f"k_c0 = {ex.state.k_c0 * k:.{DIGITS}g} N/m" in ex.readout.object


def test_csv_export(ex):
    text = ex.downloads.trajectory_file().getvalue().splitlines()
    assert text[0].startswith("#") and text[1].startswith("# overlap")
    assert text[2] == ("t [1/omega],x [length],xdot [length],mode,"
                       "contact_force [phi/k: length],overlap [length]")
    assert len(text) == 3 + len(ex.solution.result.t)
    assert text[3].split(",")[3] in ("slip", "stick", "contact")
    assert ex.downloads.trajectory.filename.startswith(
        "fie_5a_trajectory_stop-rigid_v-0.1_xbar-0.32")


def test_a_csv_header_keeps_apart_the_values_the_stop_does_not_use(ex):
    """Scene 10's deformable stop has no Newton restitution: its CSV header listed
    restitution=1.0 among the run's parameters (the rigid stop's slider value, kept by the
    page). It now says which values this stop does not use; a rigid stop's file lists its
    restitution and keeps the deformable stop's values apart."""
    ex.scene_select.value = "10"
    head = ex.downloads.trajectory_file().getvalue().splitlines()[0]
    used, _, kept = head.partition("; kept by the page, not used with this stop: ")
    assert "restitution" not in used and kept == "restitution=1.0"
    assert "k_c0=400.0" in used and "beta_e=300.0" in used
    ex.scene_select.value = "7c"
    head = ex.downloads.trajectory_file().getvalue().splitlines()[0]
    used, _, kept = head.partition("; kept by the page")
    assert "restitution=0.3" in used and "k_c0=" not in used and "k_c0=" in kept


def test_transitions_export_has_impacts_with_speeds_and_impulses(ex):
    """Scene 7c (r = 0.3): each impact's impulse is m (v_before - v_after) and Newton's law
    v_after = -r v_before holds to rounding (the closed-form solver applies it exactly)."""
    ex.scene_select.value = "7c"
    ex.state.param.update(mass=1.0, stiffness=100.0)  # omega = 10 rad/s, as said below
    ex.units.value = "SI"
    lines = ex.downloads.transitions_file().getvalue().splitlines()
    assert lines[2].startswith("t [s],kind,x [mm],v_before [m/s],v_after [m/s]")
    rows = [line.split(",") for line in lines[3:] if not line.startswith("#")]
    impacts = [r for r in rows if r[1] == "impact"]
    assert len(rows) == len(ex.solution.result.transitions) and len(impacts) > 3
    scales = ex.state.scales()
    for r in impacts:
        v_before, v_after, impulse = float(r[3]), float(r[4]), float(r[6])
        assert v_before > 0 and v_after == pytest.approx(-0.3 * v_before, rel=1e-12)
        assert impulse == pytest.approx((v_before - v_after) / scales.velocity
                                        * scales.impulse, rel=1e-12)
        assert float(r[5]) == 0.0  # a rigid stop is never entered
    assert all(r[6] == "" for r in rows if r[1] != "impact" and r[1] != "stick->impact")
    # The header and the file name give the run as the SI page showed it (they gave the
    # core's dimensionless numbers under "units: SI", without m and k).
    head = lines[0]
    omega = 10.0
    assert head.startswith("# Friction-Impact Explorer transitions; units: SI; m=1 kg, "
                           "k=100 N/m, omega=10 rad/s, L=10 mm, ")
    assert f"v_dr={ex.state.belt_speed * omega * 0.01:.12g} m/s" in head
    assert f"t_end={ex.state.t_end / omega:.12g} s" in head
    assert f"the core's dimensionless values: belt_speed={ex.state.belt_speed}" in head
    name = ex.downloads.transitions.filename
    assert name.startswith("fie_7c_transitions_SI_m-1_k-100_L-10mm_stop-rigid_v_dr-")
    assert f"_t_end-{ex.state.t_end / omega:.6g}.csv" in name
    assert re.fullmatch(r"[A-Za-z0-9._-]+", name)
    ex.controls.commit({"belt_speed": 0.123})  # custom values: named after the figure they left
    ex.downloads.transitions_file()
    assert ex.downloads.transitions.filename.startswith("fie_custom-from-7c_transitions")


def test_overlap_program_scene(ex):
    ex.scene_select.value = "2b"
    assert [n for n, p in ex.plot_panes.items() if p.visible] == ["force", "loop"]
    loop = ex.plots.sources["loop"].data
    assert len(loop["d"]) > 100 and np.nanmax(loop["phi"]) > 0
    assert "Fig. 2b" in ex.readout.object


@pytest.mark.parametrize("module", ["app.scenes", "app.state", "app.solve.pool", "app.plots",
                                    "app.readout", "app.export", "app.commit_rules",
                                    "app.widgets", "app.solve.trade", "app.compare",
                                    "app.bifurcation", "app.glyphs", "app.sampling", "app.pins",
                                    "app.control_specs", "app.plot_choice"])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module))
    assert result.failed == 0 and result.attempted > 0


def test_a_too_slow_numerical_solve_keeps_the_picture_and_says_so(ex, monkeypatch):
    import threading

    release = threading.Event()

    def slow(*args, **kwargs):
        release.wait(5.0)  # a Zeno scene with the event method takes minutes
        return compute(*args, **kwargs)

    monkeypatch.setattr(pool, "SOLVER", Solver(compute=slow, budget_s=0.2))
    before = ex.solution
    try:
        ex.method.value = "event"
        assert ex.alert.visible and "too slow" in ex.alert.object
        assert "did not finish within 0.2 s" in ex.alert.object
        assert ex.solution is before
        _release(ex, "clearance", 0.26)  # a preview or a solve never waits past its budget
        assert ex.solution is before
    finally:
        release.set()


@pytest.mark.parametrize("scene", ["11", "10", "5b"])
def test_permalink_with_a_scene_name_opens_that_scene(monkeypatch, scene):
    """Regression: Panel parses ``?scene=11`` as the number 11, which matched no scene
    and showed 'Some URL parameters could not be applied'."""
    from panel.io.location import Location

    loc = Location(search=f"?scene={scene}")
    monkeypatch.setattr(pn.state, "_location", loc)
    ex = Explorer()
    ex.sync_url()
    assert ex.state.scene == scene
    assert not ex.alert.visible and ex.error is None
    assert ex.state.clearance == SCENES[scene].values.get("clearance", ex.state.clearance)
    assert loc.query_params["scene"] in (scene, int(scene) if scene.isdigit() else scene)



def test_permalink_reads_a_parameter_by_its_name_and_names_an_unknown_key(monkeypatch):
    """``?t_end=1000`` (the parameter's own name, not its short key ``tend``) was dropped
    without a word: the page kept the scene's horizon. A key the page does not know is
    now named in the page's message; the keys other parts of the page read are not."""
    from panel.io.location import Location

    loc = Location(search="?scene=5a&t_end=1000&belt_speed=0.12&colour=red"
                          "&present=0&paint_shortcuts=off")
    monkeypatch.setattr(pn.state, "_location", loc)
    ex = Explorer()
    ex.sync_url()
    assert ex.state.t_end == 1000.0 and ex.state.belt_speed == 0.12
    shown = html.unescape(ex.alert.object)
    assert ex.alert.visible and "unknown key 'colour'" in shown
    for other in ("present", "paint_shortcuts", "t_end", "belt_speed"):
        assert repr(other) not in shown

def test_an_si_permalink_holds_and_reads_the_values_the_boxes_show(monkeypatch):
    """``?units=SI&v=0.5`` gave 2.5 m/s at omega = 5 rad/s: the address held the core's
    dimensionless values whatever its units. In SI it now holds m/s, s and N/m, as written
    by the page, so that a link written by hand means what it says and round-trips."""
    from panel.io.location import Location

    loc = Location(search="?scene=11&units=SI&m=2&k=50&v=0.5&tend=12&kc0=5000&v0=0.25")
    monkeypatch.setattr(pn.state, "_location", loc)
    ex = Explorer()
    ex.sync_url()
    assert not ex.alert.visible, ex.alert.object
    phys = ex.state.physical()  # omega = 5 rad/s
    assert phys["belt_speed"] == pytest.approx(0.5, rel=1e-12)  # 12-digit round trips
    assert phys["t_end"] == pytest.approx(12.0, rel=1e-12)
    assert phys["k_c0"] == pytest.approx(5000.0, rel=1e-12)
    assert phys["v0"] == pytest.approx(0.25, rel=1e-12)
    assert ex.state.belt_speed == pytest.approx(0.1, rel=1e-12)
    ex.permalink.write_url()
    written = loc.query_params
    assert float(written["v"]) == 0.5 and float(written["tend"]) == 12.0
    assert float(written["kc0"]) == 5000.0
    # The page's own address, read again, is the same state (no drift, no 'custom').
    again = Explorer()
    monkeypatch.setattr(pn.state, "_location", Location(search="?" + "&".join(
        f"{key}={value}" for key, value in written.items())))
    again.sync_url()
    for name in ("belt_speed", "t_end", "k_c0", "v0", "mass", "stiffness"):
        assert getattr(again.state, name) == pytest.approx(getattr(ex.state, name),
                                                           rel=1e-11)


@pytest.mark.parametrize("units", ["dimensionless", "SI"])
def test_a_link_that_changes_a_scene_s_values_opens_custom_values(monkeypatch, units):
    """``?scene=4a&v=0.5`` opened under the title and caption of Fig. 4a (fast belt) a
    slow belt. Values that differ from the scene's make the page 'custom' (reset returns
    to the scene); the page's own link of an untouched scene keeps its name."""
    from panel.io.location import Location

    monkeypatch.setattr(pn.state, "_location", Location(search="?scene=4a&v=0.5"))
    ex = Explorer()
    ex.sync_url()
    assert ex.state.belt_speed == 0.5 and ex.state.scene == CUSTOM
    assert ex.state.figure == "4a" and not ex.alert.visible
    # The page's own address of scene 7c (in SI: 12-digit m/s, s and N/m) keeps 7c.
    own = Explorer(ExplorerState(scene="7c", units=units, mass=3.0, stiffness=70.0,
                                 **scene_values("7c")))
    loc = Location(search="?scene=7c")
    monkeypatch.setattr(pn.state, "_location", loc)
    own.permalink.write_url()
    monkeypatch.setattr(pn.state, "_location", Location(search="?" + "&".join(
        f"{key}={value}" for key, value in loc.query_params.items())))
    again = Explorer()
    again.sync_url()
    assert again.state.scene == "7c" and again.state.units == units
    assert not again.alert.visible


def test_the_method_and_accuracy_keep_the_scene(monkeypatch):
    """Choosing the method or the accuracy made the page 'custom' (title and caption gone),
    while loading a scene keeps the ones chosen: the same state was 'Fig. 10' or
    'custom' by the order of the clicks, and the link ``?scene=10&method=event`` opened
    'custom'. How a motion is solved is not which motion: the scene stays, by widget and
    by link; a physical value still makes it custom."""
    from panel.io.location import Location

    ex = Explorer()
    ex.scene_select.value = "10"
    ex.method.value = "switch"
    ex.accuracy.value = "draft"
    assert ex.state.scene == "10"
    first = Explorer()  # the other order
    first.method.value = "switch"
    first.accuracy.value = "draft"
    first.scene_select.value = "10"
    assert first.state.scene == "10" and first.state.values() == ex.state.values()
    ex.controls.commit({"belt_speed": ex.state.belt_speed * 1.1})
    assert ex.state.scene == CUSTOM
    monkeypatch.setattr(pn.state, "_location",
                        Location(search="?scene=10&method=event&acc=draft"))
    linked = Explorer()
    linked.sync_url()
    assert (linked.state.scene, linked.state.method, linked.state.accuracy) == (
        "10", "event", "draft")
    assert not linked.alert.visible


def test_an_si_permalink_out_of_range_is_refused_in_si(monkeypatch):
    """A horizon beyond the slider's in an SI link is told in seconds, with m and k."""
    from panel.io.location import Location

    loc = Location(search="?scene=5a&units=SI&m=2&k=50&tend=1500&v=abc")
    monkeypatch.setattr(pn.state, "_location", loc)
    ex = Explorer()
    ex.sync_url()
    shown = html.unescape(ex.alert.object)
    assert ("tend: horizon t_end must lie in [0.02, 1000] s with m = 2 kg, k = 50 N/m; got "
            "1500 s") in shown
    assert "v: belt speed v_dr must be a number in" in shown and "'abc'" in shown
    assert ex.state.t_end == scene_values("5a")["t_end"]


def test_an_si_permalink_s_non_number_is_told_its_si_range(monkeypatch):
    """Regression: in an SI link ``v`` is in m/s and ``tend`` in s, yet a value that is no
    number (``tend=true``) was told the state's dimensionless range ('must be a number in
    [0.1, 5000]'), which a number in seconds would not have been held to. The range named
    is the one the same link's numbers are checked against (the message of ``tend=1500``
    there), from m and k; keys read the same in both units keep their range."""
    from panel.io.location import Location

    monkeypatch.setattr(pn.state, "_location", Location(
        search="?scene=5a&units=SI&m=2&k=50&tend=true&v=abc&r=abc"))
    ex = Explorer()
    ex.sync_url()
    shown = html.unescape(ex.alert.object)
    numeric = si_bound_error("t_end", 1e9, 2.0, 50.0)  # the link's range for a number
    t_range = numeric[numeric.index("["):numeric.index("; got")]
    assert f"tend: horizon t_end must be a number in {t_range}; got 'true'" in shown
    v_si = si_units(2.0, 50.0, 1.0)["belt_speed"]  # an SI link without L: L = 1 m
    assert (f"[{0.0:.4g}, {ExplorerState.param.belt_speed.bounds[1] * v_si[2]:.4g}] m/s"
            in shown)
    assert "r (restitution) must be a number in [0, 1]; got 'abc'" in shown
    assert ex.state.t_end == scene_values("5a")["t_end"]


def test_regime_map_of_a_hysteretic_scene(ex):
    """Regression: the map's cache key left out parameters the hysteretic stop needs, so
    'show all plots' on a hysteretic scene failed to draw the map."""
    ex.scene_select.value = "11"
    ex.show_all.value = True
    assert ex.plot_panes["map"].visible
    image = ex.plots.sources["map"].data["image"]
    assert len(image) == 1 and np.asarray(image[0]).shape == (MAP_CELLS, MAP_CELLS)
    assert "inelastic" in ex.map_legend.object


def test_a_new_regime_map_follows_the_rest_of_the_picture(ex, monkeypatch):
    """A change of friction needs a new map: the trajectory is drawn first and the
    map in a later callback of the session's loop; a map already computed comes at once."""
    from app.solve.regime_map import regime_map

    deferred = []
    monkeypatch.setattr("app.plots_host.later", lambda fn, delay_ms: deferred.append(fn))

    def map_callbacks():
        return [fn for fn in deferred if "._draw." in fn.__qualname__]

    old_image = ex.plots.sources["map"].data["image"]
    _release(ex, "mu_s", 0.337)
    assert ex.state.mu_s == 0.337 and ex.solution.values["mu_s"] == 0.337
    assert regime_map(ex.state.values(), compute=False) is None
    assert ex.plots.sources["map"].data["image"] is old_image  # not yet
    [draw_map] = map_callbacks()
    draw_map()
    assert ex.plots.sources["map"].data["image"] is not old_image
    assert regime_map(ex.state.values(), compute=False) is not None
    deferred.clear()
    _release(ex, "clearance", ex.state.clearance + 0.01)  # the same map, cached
    assert map_callbacks() == []


@pytest.mark.parametrize(("name", "text", "said"), [
    ("mu_k", "0.5", "mu_k must lie in [0, 0.3]; got 0.5"),
    ("restitution", "1.5", "restitution must lie in [0, 1]; got 1.5"),
    ("t_end", "0", "t_end must lie in [0.1, 5000]; got 0"),
    ("belt_speed", "abc", "belt_speed must be a number; got 'abc'"),
    ("clearance", "-0.5", "the stop must lie ahead of the start position"),
])
def test_refused_entry_names_parameter_range_and_value(ex, name, text, said):
    """A refused entry stayed in its box ("abc", red) while the page ran with the value
    before it; the box now shows that value again, and the message says what was
    refused and which value stays."""
    before = ex.state.values()
    w = ex.sliders[name]
    in_use = w.input.value
    assert in_use == format_number(getattr(ex.state, name))
    w.input.value = text
    assert ex.state.values() == before and not ex.alert.visible
    assert w.invalid and w.input.value == in_use and html.escape(said) in w.message.object
    assert f"the value in use stays {in_use}" in w.message.object
    assert "fie-msg-error" in w.message.object
    ex.controls.commit({"x0": -0.01})  # another change leaves the message below the box
    assert w.invalid and w.message.visible and w.input.value == in_use
    ex.controls.reset()
    assert not w.invalid and not w.message.visible and ex.state.scene == "5a"


@pytest.mark.parametrize(("name", "text", "said"), [
    ("belt_speed_si", "-1", "belt speed v_dr must lie in [0, 100] m/s with m = 1 kg, "
                            "k = 100 N/m, L = 1000 mm; got -1 m/s"),
    ("belt_speed_si", "1000", "belt speed v_dr must lie in [0, 100] m/s"),
    ("normal_force", "-5", "normal force F_N must lie in [0.0001, 1e+04] N"),
    ("normal_force", "0", "normal force F_N must lie in [0.0001, 1e+04] N"),
    ("length_unit_si", "0", "length unit L must lie in [0.001, 1e+06] mm; got 0 mm"),
    ("t_end_si", "0.001", "horizon t_end must lie in [0.01, 500] s"),
])
def test_a_refused_si_entry_names_its_range_in_si(ex, name, text, said):
    """In SI a value below the range was told '[0, 1e+09]' (the box's placeholder) or the
    core's '(0, inf]'; the range is the state's, in SI with the current m and k, and the
    box's tooltip says it."""
    # omega = 10 rad/s, L = 1 m, as said below
    ex.state.param.update(mass=1.0, stiffness=100.0, length_unit=1.0)
    ex.state.units = "SI"  # m = 1 kg, k = 100 N/m: omega = 10 rad/s
    before = ex.state.values()
    w = ex.sliders[name]
    w.input.value = text
    assert ex.state.values() == before
    assert w.invalid and html.escape(said) in w.message.object
    assert "1e+09" not in w.input.description
    w.input.value = "0.01" if name == "t_end_si" else "0.5"  # a bound by rounding is taken
    assert not w.invalid


@pytest.mark.parametrize("units", ["dimensionless", "SI"])
def test_a_release_sends_no_tooltip_that_did_not_change(units):
    """Each release set the SI box of k_e0 to its state bounds and then to k_c0's value as
    its upper end: its tooltip changed twice, two models sent per release (+60 ms of
    scene 10's release latency in Chromium)."""
    ex = Explorer(ExplorerState(scene="10", units=units, **scene_values("10")))
    changed = []
    for w in ex.sliders.values():
        w.input.param.watch(lambda e, n=w.name: changed.append(n), "description")
    for step in (1, 2):
        _release(ex, "clearance", ex.state.clearance + 1e-3 * step)
    assert changed == []
    if units != "SI":
        ex.units.value = "SI"  # hidden SI boxes are brought up to date when shown
    assert ex.sliders["k_e0_si"].bounds[1] == pytest.approx(ex.state.physical()["k_c0"])


def test_coupled_bound_note_and_program_toggle(ex):
    ex.sliders["mu_s"].input.value = "0.1"
    assert ex.state.mu_k == 0.1
    assert "mu_k lowered from 0.2 to 0.1 to stay ≤ mu_s" in ex.sliders["mu_k"].message.object
    ex.controls.commit({"belt_speed": 0.11})  # the note is about the last change only
    assert not ex.sliders["mu_k"].message.visible
    ex.scene_select.value = "2b"
    assert ex.program.visible and ex.program.value and ex.state.program
    ex.stop_type.value = "rigid"  # the program drives a deformable stop only
    assert not ex.state.program and not ex.program.visible
    ex.stop_type.value = "hysteretic"
    assert ex.program.visible and not ex.program.value
    assert "phase" in ex.visible_plots()
    assert ex.controls.reset_button.label == "Reset to Fig. 2b"


def _periodic_switch(*args, method, **kwargs):
    """Stands in for ``core.simulate`` (a solver process gets it by reference): the switch
    model calls every run periodic."""
    import dataclasses

    from core import simulate
    from core.result import Steady, SteadyKind

    res = simulate(*args, method=method, **kwargs)
    if method != "switch":
        return res
    return dataclasses.replace(res, steady=Steady(SteadyKind.PERIODIC))


def test_trade_table_measures_every_method_and_marks_a_changed_verdict(monkeypatch):
    """Scene 10: the reference (exact flight, contact at rtol 1e-12) grazes the stop; the
    exact method's error falls with the preset (its contact is integrated at the preset's
    rtol). Every method at every preset labels the train as the reference does: the switch
    model at draft called it periodic while its contacts still lost 4 % each (the row said
    "verdict differs"). A verdict that differs is marked in the row and the table."""
    from app.solve import trade
    from app.solve.trade import measure, trade_html

    rows = {(r.method, r.accuracy): r for r in measure(scene_values("10"))}
    assert len(rows) == 9
    assert rows["exact", "precise"].verdict == "grazing"
    errors = [rows["exact", a].error for a in ("draft", "standard", "precise")]
    assert errors[0] > errors[1] > errors[2]
    assert all(r.verdict == "grazing" and not r.note for r in rows.values())
    assert "verdict differs" not in trade_html(list(rows.values()))

    monkeypatch.setattr(trade, "simulate", _periodic_switch)
    rows = measure(scene_values("10"), methods=("switch",))
    assert all("verdict differs from the reference (grazing)" in r.note for r in rows)
    assert "verdict differs" in trade_html(rows)


def test_a_plot_is_built_when_first_shown_and_shows_the_current_solution(ex):
    from app.plots import energy_columns, friction_columns

    hidden = {"loop", "friction", "energy"}
    assert not hidden & ex.plots.built  # the rigid scene does not show them
    assert not any(ex.plot_panes[n].objects for n in hidden)
    ex.show_all.value = True  # no new solve: the last solution fills the new figures
    assert {"friction", "energy"} <= ex.plots.built and "loop" not in ex.plots.built
    sol, scales = ex.solution, ex.state.scales()
    energy = ex.plots.sources["energy"].data
    for name, col in energy_columns(sol, scales).items():
        assert _same(energy[name], col), name
    law = friction_columns(sol, scales)["law"]
    assert _same(ex.plots.sources["law"].data["f"], law["f"])
    fig = ex.plots.figures["energy"]
    # The pane holds the new figure, its axes span the run and are labelled.
    body, legend = ex.plot_panes["energy"].objects[0].objects
    assert body.object is ex.plots.panes["energy"] and legend is ex.plots.legends["energy"]
    assert fig.x_range.end >= float(np.max(energy["t"])) > fig.x_range.start
    assert fig.xaxis[0].axis_label == scales.time_label


def test_a_stop_type_change_builds_the_hysteresis_loop_with_its_solution(ex):
    from app.plots import loop_columns

    assert "loop" not in ex.plots.built
    ex.stop_type.value = "hysteretic"
    assert "loop" in ex.plots.built and ex.plot_panes["loop"].visible
    loop = loop_columns(ex.solution, ex.state.scales())["loop"]
    assert len(loop["d"]) and _same(ex.plots.sources["loop"].data["d"], loop["d"])
    # Built once: shown again later, the same figure is kept.
    fig = ex.plots.figures["loop"]
    ex.stop_type.value = "rigid"
    assert not ex.plot_panes["loop"].visible
    ex.stop_type.value = "hysteretic"
    assert ex.plots.figures["loop"] is fig


def test_each_full_solution_is_signalled_by_its_own_model(ex):
    """The page holds its repaints after a release until the hidden pane's text changes
    (static/perf/release_hold.js); no source carries the signal."""
    before = ex.arrived.object
    _release(ex, "belt_speed", 0.3)
    assert ex.arrived.object != before and not ex.arrived.visible
    assert "fie-solution-arrived" in ex.arrived.css_classes
    assert not any(src.tags for src in ex.plots.sources.values())
    assert "t_raw" not in ex.plots.sources["traj"].data  # one time column, in shown units


def test_a_release_handled_after_the_slider_moved_on_does_not_pull_it_back(ex):
    """Two key presses on a slider in quick succession (mu_s 0.3 -> 0.295 -> 0.27): when
    the server is slow to take the first release, Panel may hand it the second position
    with the first release in one batch. Committing 0.295, the page set the slider back to
    0.295 under the user's hand (a handle that jumps back, a box that disagrees with it in
    one CI run). The slider keeps its newer position; that position's release follows and
    is committed."""
    slider = ex.sliders["mu_s"].slider
    start = ex.state.mu_s
    first, second = start - 0.005, start - 0.03
    with param.edit_constant(slider):
        slider.param.update(value=second, value_throttled=first)
    assert ex.state.mu_s == first  # the release that was handled
    assert slider.value == second  # not pulled back
    _release(ex, "mu_s", second)
    assert ex.state.mu_s == second and ex.solution.values["mu_s"] == second
    assert slider.value == second and ex.sliders["mu_s"].input.value == f"{second:g}"


def test_a_scene_loaded_over_another_keeps_none_of_its_transition_kinds(ex):
    """The legend names the transition kinds the run shows. Loading scene 5b over 5a (whose
    run has impacts from slip) drew 5b's answer before the plots forgot 5a's kinds when the
    answer came at once (a cached run): 5b's legend named 5a's impacts too. The page opened
    on 5b is the reference."""
    fresh = Explorer(ExplorerState(scene="5b", **scene_values("5b")))
    assert "</svg>impact</span>" in ex.plots.legends["phase"].object  # 5a's
    ex.permalink.apply_query("scene=5b")
    assert ex.plots.legends["phase"].object == fresh.plots.legends["phase"].object


def test_a_measurement_that_ends_leaves_the_alert_of_another_matter(ex):
    """The end of a measurement hides the alert only if it says that a measurement was
    refused; the page's components once hid whatever alert was shown (a link's refused
    key here)."""
    import time

    ex.permalink.apply_query("zz=1")
    assert ex.alert.visible and "unknown key 'zz'" in html.unescape(ex.alert.object)
    ex.measure_trade()
    deadline = time.monotonic() + 120.0  # a measurement ends within its 30 s budget
    while ex.measure.disabled:
        assert time.monotonic() < deadline, "the measurement did not end"
        time.sleep(0.05)
    assert ex.alert.visible


def test_a_run_cut_short_says_so_in_the_units_it_is_shown_in(ex):
    """A run the core stopped at its budget says where it stopped, and offers more time.
    Shown again in other units (SI here), the page hid that notice with the last alert and
    did not say it again."""
    from app.solve.pool import SOLVER
    from app.solve.solution import cut_short

    # The switch model at "precise" over t_end = 5000: about 2 s (tests/ui/test_retry_ui.py),
    # far more than 0.2 s.
    values = {**scene_values("10"), "method": "switch", "accuracy": "precise", "t_end": 5000.0}
    short = SOLVER.submit(values, budget=0.2).result(timeout=60)
    assert cut_short(short)
    ex.state.param.update(**values)  # the state the run is of (its own solve is replaced)
    ex.state.solution = short
    assert ex.alert.visible and "Solved only in part" in ex.alert.object
    assert "t_end = 5000:" in ex.alert.object and ex.retry.visible
    ex.state.param.update(mass=1.0, stiffness=100.0)  # omega = 10 rad/s, as said below
    ex.state.units = "SI"  # omega = 10 rad/s: the horizon in seconds
    assert ex.alert.visible and "Solved only in part" in ex.alert.object
    assert "t_end = 500 s:" in ex.alert.object and ex.retry.visible


def test_moving_mu_s_keeps_mu_k_s_tooltip_and_still_bounds_it(ex):
    """μₖ's upper bound is μₛ: its tooltip names μₛ instead of quoting its number, so that
    moving μₛ sends no new tooltip model (after each, Bokeh walked the whole document
    again); a typed μₖ above μₛ is still refused with the number."""
    changed = []
    ex.sliders["mu_k"].input.param.watch(lambda e: changed.append(e.new), "description")
    for mu_s in (0.45, 0.5, 0.55):
        _release(ex, "mu_s", mu_s)
        assert ex.sliders["mu_k"].bounds[1] == mu_s
    assert changed == []
    assert "to static friction μₛ" in ex.sliders["mu_k"].input.description
    ex.sliders["mu_k"].input.value = "0.6"
    assert ex.sliders["mu_k"].invalid and ex.state.mu_k < 0.55
    assert "0.55" in ex.sliders["mu_k"].message.object
