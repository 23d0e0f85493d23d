"""The sweep card (app.bifurcation): its data, its chunks, its tap, the simulated map."""

from __future__ import annotations

import asyncio
import contextlib
import math
import threading
from types import SimpleNamespace

import numpy as np
import panel as pn
import pytest

from app.bifurcation import (
    DENSITY_SAMPLES,
    ChunkedSweep,
    check_spec,
    default_range,
    sweep_points,
    theory_lines,
)
from app.explorer import Explorer
from app.state import ExplorerState, scene_values
from core import Oscillator, RigidStop, theory
from core.sweep import sweep


def _scene_5a_directly():
    """Scene 5a's oscillator and stop built here from its values, not by the app."""
    v = scene_values("5a")
    osc = Oscillator(mu_s=v["mu_s"], mu_k=v["mu_k"], belt_speed=v["belt_speed"],
                     u_s=v["u_s"])
    return v, osc, RigidStop(clearance=v["clearance"], restitution=v["restitution"])


@pytest.mark.parametrize("quantity", ["impact_speed", "stick_x", "x_max"])
def test_the_diagram_of_scene_5a_is_core_sweep_s(quantity):
    values, osc, stop = _scene_5a_directly()
    speeds = np.linspace(0.01, 0.4, 300)
    data = sweep_points(values, "belt_speed", speeds, quantity)
    res = sweep(osc, stop, "belt_speed", speeds, t_end=200.0, x0=values["x0"],
                v0=values["v0"], quantity=None if quantity == "x_max" else quantity)
    if quantity == "x_max":
        keep = np.isfinite(res.x_max)
        x, y = speeds[keep], res.x_max[keep]
    else:
        x, y = res.points(quantity)
    # The same closed form on the same inputs: equal to the last bit.
    np.testing.assert_array_equal(data.x, x)
    np.testing.assert_array_equal(data.y, y)
    assert len(data.y) > 100
    np.testing.assert_array_equal(data.swept_label, res.labels)


def test_cancel_after_the_first_chunk_submits_no_other():
    calls = []

    events = []

    def work(task, chunk, cancelled):
        calls.append(len(chunk))
        events.append(cancelled)
        return chunk.sum()

    chunks = []
    job = ChunkedSweep(work, lambda done, total, part: (chunks.append(done), job.cancel()),
                       lambda exc: pytest.fail(str(exc)))
    job.start(None, np.arange(100.0), 10, scene_values("5a"))
    assert calls == [10] and chunks == [10] and job.submitted == 1
    assert not job.running
    # The event a running chunk holds is set: a chunk in a child process is stopped.
    assert events[0].is_set()


def test_a_sweep_without_cancel_covers_every_value_once():
    seen = []
    job = ChunkedSweep(lambda task, chunk, cancelled: chunk, lambda d, t, part: seen.append(part),
                       lambda exc: pytest.fail(str(exc)))
    job.start(None, np.arange(50.0), 7, scene_values("5a"))
    np.testing.assert_array_equal(np.concatenate(seen), np.arange(50.0))
    assert not job.running


def test_a_new_sweep_drops_the_old_one_s_answers():
    """A sweep started while another runs: the old one's further chunks are neither
    computed nor delivered."""
    got, work = [], []

    def on_chunk(done, total, part):
        got.append(part)
        if part == "old":  # a new sweep starts while the old one has chunks to go
            job.start("new", np.arange(4.0), 4, scene_values("5a"))

    def compute(task, chunk, cancelled):
        work.append(task)
        return task

    job = ChunkedSweep(compute, on_chunk, lambda exc: pytest.fail(str(exc)))
    job.start("old", np.arange(8.0), 4, scene_values("5a"))
    assert got == ["old", "new"] and work == ["old", "new"]
    assert not job.running


def test_a_sweep_s_chunks_reach_the_session_on_its_event_loop(monkeypatch):
    """Regression: the worker thread added each chunk's callback to the document itself,
    which Bokeh can lose (app/session_loop.py): the sweep then stalled."""
    added, seen = [], []

    class Doc:
        session_context = SimpleNamespace(destroyed=False)

        def add_next_tick_callback(self, fn):
            added.append(threading.current_thread().name)
            asyncio.get_running_loop().call_soon(fn)  # as the session would, on the loop

    doc = Doc()
    monkeypatch.setattr(type(pn.state), "curdoc", property(lambda self: doc))
    # (Panel's set_curdoc would set the property replaced here.)
    monkeypatch.setattr("app.bifurcation.chunks.set_curdoc", lambda d: contextlib.nullcontext())
    job = ChunkedSweep(lambda task, chunk, cancelled: chunk, lambda d, t, part: seen.append(part),
                       lambda exc: pytest.fail(str(exc)))

    async def page() -> str:
        job.start(None, np.arange(12.0), 4, scene_values("5a"))
        for _ in range(500):
            if not job.running:
                break
            await asyncio.sleep(0.01)
        return threading.current_thread().name

    loop_thread = asyncio.run(page())
    np.testing.assert_array_equal(np.concatenate(seen), np.arange(12.0))
    assert added and set(added) == {loop_thread}


def _opened(scene: str = "5a") -> Explorer:
    ex = Explorer(ExplorerState(scene=scene, **scene_values(scene)))
    ex.open_sweeps.clicks += 1
    return ex


def test_opening_sweeps_1000_belt_speeds_of_the_scene():
    ex = _opened()
    view = ex.sweeps
    assert len(view.data.swept) == 1000
    assert view.spec.parameter == "belt_speed"
    assert "1000 of 1000" in view.status.object
    assert len(view.source.data["x"]) == len(view.data.x) > 0
    assert view.current.location == ex.state.belt_speed


def test_in_si_units_the_card_shows_metres_seconds_and_newtons():
    """In SI units the card said 'belt speed v (dimensionless units)' over 0.005-0.5 beside
    a slider in m/s, and its simulated map covered a tenth of the map's m/s axis."""
    ex = _opened()
    view = ex.sweeps
    values, osc, stop = _scene_5a_directly()
    # t = omega tau (docs/physics.md, "Dimensionless form"),
    # and a velocity omega L [m/s] per dimensionless unit (docs/physics.md, "The page's
    # SI units")
    omega = math.sqrt(ex.state.stiffness / ex.state.mass) * ex.state.length_unit
    dimensionless_lo, dimensionless_hi = view.lo.value, view.hi.value
    view.disagree_layer.value = True
    ex.state.units = "SI"
    fig = view.fig
    assert fig.xaxis[0].axis_label == "belt speed v_dr (m/s)"
    assert fig.yaxis[0].axis_label == "impact speed before (at each impact) (m/s)"
    assert "SI units" in view.layout.title
    assert "1000 of 1000 values of belt speed v_dr in" in view.status.object
    assert view.parameter.labels[view.parameter.values.index("belt_speed")] == \
        "belt speed v_dr"
    assert view.parameter.value == "belt_speed"
    # The boxes, the diagram, the theory's v* and the current value, all in m/s: the same
    # closed form scaled by omega L (rtol: one multiplication's rounding).
    assert view.lo.value == pytest.approx(dimensionless_lo * omega, rel=1e-3)
    assert view.hi.value == pytest.approx(dimensionless_hi * omega, rel=1e-3)
    res = sweep(osc, stop, "belt_speed", view.data.swept, t_end=200.0, x0=values["x0"],
                v0=values["v0"], quantity="impact_speed")
    x, y = res.points("impact_speed")
    np.testing.assert_allclose(view.source.data["x"], x * omega, rtol=1e-15)
    np.testing.assert_allclose(view.source.data["y"], y * omega, rtol=1e-15)
    v_star = dict((t.split(":")[0], x) for x, t in zip(view.vlines.data["x"],
                                                       view.vlines.data["text"],
                                                       strict=True))["v*"]
    assert v_star == pytest.approx(theory.critical_speed(osc, values["x0"], values["v0"])
                                   * omega, rel=1e-15)
    assert view.current.location == pytest.approx(ex.state.belt_speed * omega, rel=1e-15)
    # The simulated layer covers the map's own image, whose axis is in m/s.
    map_image = ex.plots.sources["map"].data
    assert view.layers.sources["disagree"].data["dw"] == pytest.approx(map_image["dw"], rel=1e-15)
    # A tap at a point in m/s loads the dimensionless value swept there.
    swept = view.data.swept
    view.tap(swept[300] * omega)
    assert ex.state.belt_speed == swept[300]
    # A sweep started from the boxes in m/s sweeps the same dimensionless range.
    view.start()
    assert view.spec.lo == pytest.approx(dimensionless_lo, rel=1e-3)
    assert view.spec.hi == pytest.approx(dimensionless_hi, rel=1e-3)
    # Back in dimensionless units, everything is the core's numbers again.
    ex.state.units = "dimensionless"
    assert fig.xaxis[0].axis_label == "belt speed v (dimensionless units)"
    np.testing.assert_allclose(view.source.data["x"], view.data.x, rtol=1e-15)
    assert view.layers.sources["disagree"].data["dw"] == pytest.approx(
        ex.plots.sources["map"].data["dw"])


def test_in_si_units_a_period_is_in_seconds_and_a_static_deflection_a_normal_force():
    ex = _opened()
    view = ex.sweeps
    ex.state.units = "SI"
    omega = math.sqrt(ex.state.stiffness / ex.state.mass)
    view.quantity.value = "period"
    view.parameter.value = "u_s"
    lo, hi = default_range(ex.state.values(), "u_s")
    # The sidebar shows N = k L u_s in newtons (app.state.ExplorerState.physical).
    force = ex.state.stiffness * ex.state.length_unit
    assert view.lo.value == pytest.approx(lo * force, rel=1e-3)
    view.points.value = 50
    view.start()
    assert view.fig.xaxis[0].axis_label == "normal force N (N)"
    assert view.fig.yaxis[0].axis_label == "period (s)"
    np.testing.assert_allclose(view.source.data["y"], view.data.y / omega, rtol=1e-15)
    np.testing.assert_allclose(view.source.data["x"], view.data.x * force, rtol=1e-15)


def test_a_tap_loads_the_nearest_swept_value_into_the_explorer():
    ex = _opened()
    view = ex.sweeps
    swept = view.data.swept
    target = swept[417] + 0.3 * (swept[418] - swept[417])  # nearer 417 than 418
    view.tap(target)
    assert ex.state.belt_speed == swept[417]
    assert ex.sliders["belt_speed"].value == swept[417]
    assert ex.solution.values["belt_speed"] == swept[417]  # the main plots re-solved
    assert ex.state.scene == "custom"
    assert view.spec.values["clearance"] == ex.state.clearance
    assert len(view.data.swept) == 1000  # the same diagram: only its marker moved
    assert view.current.location == swept[417]


def test_another_scene_sweeps_again():
    ex = _opened()
    first = ex.sweeps.spec
    ex.state.load_scene("5b")
    assert ex.sweeps.spec is not first
    assert ex.sweeps.spec.values["clearance"] == ex.state.clearance


def test_a_large_sweep_is_one_density_image():
    ex = _opened()
    view = ex.sweeps
    view.points.value = 2 * DENSITY_SAMPLES + 1000
    view.start()
    assert len(view.data.y) > DENSITY_SAMPLES
    assert len(view.source.data["x"]) == 0
    image = view.image_source.data["image"][0]
    # Every sample lies in one bin: the log counts add back up to the samples.
    assert np.nansum(np.expm1(image.astype(float))) == pytest.approx(len(view.data.y),
                                                                     rel=1e-4)


def test_bad_ranges_are_refused_with_the_parameter_s_name():
    values = scene_values("5a")
    with pytest.raises(ValueError, match="restitution"):
        check_spec(values, "restitution", 0.5, 1.5, 10, "impact_speed")
    with pytest.raises(ValueError, match="from < to"):
        check_spec(values, "belt_speed", 0.3, 0.1, 10, "impact_speed")
    with pytest.raises(ValueError, match="quantity"):
        check_spec(values, "belt_speed", 0.1, 0.3, 10, "force_peak")


def test_theory_lines_of_a_clearance_sweep_are_the_closed_forms():
    values, osc, stop = _scene_5a_directly()
    vertical, _ = theory_lines(values, "clearance", 0.0, 1.0, "impact_speed")
    named = {text.split(":")[0]: x for x, text in vertical}
    assert named["a"] == osc.a and named["b"] == osc.b
    assert named["x*"] == theory.x_star(osc, stop.restitution)
    assert named["x_max without stop"] == theory.x_max_impactless(osc, values["x0"],
                                                                   values["v0"])


def test_the_simulated_map_of_a_rigid_stop_agrees_with_the_theory():
    ex = _opened()
    view = ex.sweeps
    view.disagree_layer.value = True
    sim = view.sim_map
    assert sim is not None and sim.labels.shape == (128, 128)
    # docs/sweeps.md: for an elastic or inelastic rigid stop the maps are equal.
    assert not sim.disagree.any()
    assert (sim.labels == "periodic").sum() > 1000
    assert "map" in ex.plots.figures
    assert view.layers.renderers[1].visible and not view.layers.renderers[0].visible
    assert "simulated: disagreement in red" in ex.plots.figures["map"].title.text
    assert "fie-map-covered" not in ex.map_legend.object  # the red cells only mark
    view.disagree_layer.value = False
    assert not any(r.visible for r in view.layers.renderers)
    assert ex.plots.figures["map"].title.text == "Regime map (tap to move there)"


def test_the_map_legend_says_when_the_simulated_layer_covers_the_theory():
    """The legend under the map named the theory's colours while the simulated steady
    states covered them: it now says so, and stops saying it when the layer goes."""
    ex = _opened()
    view = ex.sweeps
    theory_names = ex.map_legend.object
    view.sim_layer.value = True
    assert view.layers.renderers[0].visible
    assert "The simulated steady states cover the map" in ex.map_legend.object
    assert theory_names.split("fie-legend'>")[1] in ex.map_legend.object
    view.sim_layer.value = False
    assert "fie-map-covered" not in ex.map_legend.object


def test_every_steady_label_has_its_own_colour_and_missing_samples_are_said():
    """contact_train (a deformable stop's train of contacts) was drawn black, unnamed in
    the legend; a clearance sweep of scene 11 drew 3 force peaks for 60 clearances
    without saying why the others had none."""
    from app.bifurcation import LABEL_COLORS, Points, SweepSpec, legend_text, missing_note
    from core.sweep import LABELS

    assert set(LABELS) <= set(LABEL_COLORS)
    assert len(set(LABEL_COLORS.values())) == len(LABEL_COLORS)
    assert "contact_train" in legend_text()
    spec = SweepSpec(scene_values("11"), "clearance", 0.1, 0.3, 4, "force_peak")
    labels = np.array(["rest", "periodic", "periodic", "rest"], dtype=object)
    data = Points(np.array([0.2, 0.2, 0.3]), np.array([1.0, 2.0, 1.5]),
                  labels[[1, 1, 2]], np.array([0.1, 0.2, 0.3, 0.4]), labels)
    assert "2 of 4 values have no sample" in missing_note(data, spec)
    assert missing_note(Points(data.x, data.y, data.label, np.array([0.2, 0.3]),
                              labels[1:3]), spec) == ""


def test_an_oscillation_on_the_stop_is_not_a_disagreement_where_theory_expects_rest():
    """Loops on a pressed deformable stop still swinging at the horizon are labelled an
    oscillation, on their way to the rest the theory expects for the equivalent rigid stop
    (they were "rest" approached): the simulated map must not mark those cells as
    disagreeing, as it does not mark cells that have not settled ("none")."""
    from app.bifurcation import compare_map

    values = scene_values("11")
    frame = (0.1, 0.05, 0.15)  # slow belts, clearances below a = 0.2: pressed
    cells = 3
    plain = compare_map(values, frame, np.full((cells, cells), "rest", dtype=object))
    expected = plain.expected.T  # rows: speeds, as the simulated labels come
    assert (expected == "rest").any()
    labels = np.where(expected == "rest", "oscillation", expected).astype(object)
    sim = compare_map(values, frame, labels)
    assert not sim.disagree.any()
    # a label the theory does not expect still disagrees
    other = np.where(expected == "rest", "periodic", expected).astype(object)
    assert compare_map(values, frame, other).disagree[(expected == "rest").T].all()


@pytest.mark.parametrize("module", ["spec", "theory_lines", "sim_map", "chunks", "style",
                                    "map_layers", "view"])
def test_docstring_examples_of_the_sweep_modules(module):
    """The examples of each module of :mod:`app.bifurcation` hold (those with none pass)."""
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(f"app.bifurcation.{module}"))
    assert result.failed == 0
