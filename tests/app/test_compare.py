"""Pinned runs and the presentation mode without a browser: the permalink's pins round-trip
and refuse bad values by name, the comparison reads Newton's law back, and neither feature
adds a Bokeh model to a page until it is used."""

from __future__ import annotations

import numpy as np
import pytest
from bokeh.document import Document
from panel.io.state import set_curdoc

from app.compare import (
    MAX_PINS,
    PIN_COLORS,
    PRESETS,
    decode_pins,
    encode_pins,
    ghost_columns,
    pin_label,
    summary,
)
from app.solver import solve
from app.state import scene_values


def _page():
    import app.main as main

    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
    return template.explorer, doc


def test_pins_round_trip_through_the_permalink():
    custom = {**scene_values("5b"), "restitution": 0.55, "belt_speed": 0.08}
    pins = [("7c", scene_values("7c")), ("custom", custom), ("10", scene_values("10"))]
    text = encode_pins(pins)
    assert text.startswith("7c|")  # a scene's own values are not repeated
    back = decode_pins(text)
    assert [scene for scene, _ in back] == ["7c", "custom", "10"]
    for (_, values), (_, restored) in zip(pins, back, strict=True):
        assert restored == values


@pytest.mark.parametrize("raw, words", [
    ("7c,r=2", "r (restitution) must be a number in [0, 1]; got '2'"),
    ("9z", "scene must be one of"),
    ("5b,zz=1", "unknown parameter 'zz'"),
    ("5b,x0=0.9", "the stop must lie ahead of the start position"),
    ("5b|5b|5b|5b", f"at most {MAX_PINS} pins"),
])
def test_bad_pins_are_refused_by_name(raw, words):
    with pytest.raises(ValueError, match="pin|pins") as info:
        decode_pins(raw)
    assert words in str(info.value)


def test_summary_reads_newtons_law_and_the_period_back():
    # Scene 7c: r = 0.3, so every impact's rebound over approach speed is 0.3 (Eq. 8).
    assert float(summary(solve(scene_values("7c")))["restitution"]) == pytest.approx(0.3)
    # Scene 4a, elastic fast belt: period 2 arccos(1 - x_bar/a) (Sec. 4.1), one impact.
    import math

    s = summary(solve(scene_values("4a")))
    assert float(s["period"]) == pytest.approx(2 * math.acos(1 - 0.3 / 0.2), rel=1e-3)
    assert s["impacts"] == "1" and s["steady"] == "periodic"


def test_ghost_columns_hold_the_run():
    sol = solve(scene_values("5a"))
    cols = ghost_columns(sol)
    assert len(cols["phase"]["x"]) > 100 and len(cols["traj"]["t"]) > 100
    # Rigid stop: each impulse is a stem (0 -> j) of a broken line.
    assert len(cols["force"]["t"]) == 3 * len(sol.result.impulses)


def test_label_names_what_differs():
    assert pin_label("7c", scene_values("7c"), {**scene_values("7c"), "restitution": 1.0}) \
        == "7c: r 0.3"


def test_in_si_units_a_pin_is_labelled_in_si_units():
    """The legend and the table said "5a: v 0.1" (the core's belt speed) for a run pinned
    at 0.5 m/s on a page in SI units."""
    ex, doc = _page()
    with set_curdoc(doc):
        ex.state.param.update(units="SI", mass=2.0, stiffness=50.0)  # omega = 5 rad/s
        ex.compare.pin(ex.state.scene, ex.state.values())
        ex._commit({"belt_speed": 0.3})
        v_dr = f"v_dr {ex.compare.pins[0].values['belt_speed'] * 5.0:.4g} m/s"
        assert v_dr == "v_dr 0.5 m/s"
        assert f"pinned 5a: {v_dr}" in ex.plots.legends["phase"].object
        assert f"5a: {v_dr}" in ex.readout.object
        assert " v 0.1" not in ex.readout.object


def test_no_model_until_used_then_ghosts_and_present_mode():
    ex, doc = _page()
    before = len(doc.models)
    with set_curdoc(doc):
        ex.menu.presentation.set_mode("4")
        assert len(doc.models) == before  # presentation changes properties only
        assert ex.plots.point_labels.text == "paper"
        # Fewer ticks in a quarter of the screen (six touched each other at 720p).
        assert ex.plots.shared.ticker.desired_num_ticks == 3
        ex.menu.presentation.set_mode("1")
        assert ex.plots.shared.ticker.desired_num_ticks == 5
        ex.menu.presentation.set_mode("")
        assert ex.plots.point_labels.text == "name"
        assert ex.plots.shared.ticker.desired_num_ticks == 6
        assert ex.compare.renderer_count == 0
        ex.compare.pin(ex.state.scene, ex.state.values())
        assert ex.compare.pins[0].solution is not None
        assert ex.compare.renderer_count > 0
        assert len(doc.models) > before
        assert "compared" in ex.readout.object
        assert PIN_COLORS[0] in ex.plots.legends["phase"].object


def test_presets_load_one_scene_and_pin_the_other():
    ex, doc = _page()
    with set_curdoc(doc):
        ex.menu.preset(next(k for k in PRESETS if k.startswith("7c vs 10")))
        assert ex.state.scene == "10"
        assert [p.scene for p in ex.compare.pins] == ["7c"]
        ex.state.load_scene("5b")
        ex.menu.preset(next(k for k in PRESETS if k.startswith("r = 1")))
        assert ex.state.restitution == 1.0
        assert ex.compare.pins[0].values["restitution"] < 1.0


#: A pin far from scene 5a's run: a three times larger static deflection, a farther stop
#: and a faster belt (its excursion and speeds are some three times 5a's).
FAR_PIN = {"u_s": 3.0, "clearance": 2.0, "belt_speed": 0.3, "t_end": 120.0}


def _covers(rng, values) -> bool:
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return rng.start <= values.min() and values.max() <= rng.end


def test_a_far_off_pin_widens_every_axis_and_its_unpinning_narrows_them():
    ex, doc = _page()
    with set_curdoc(doc):
        ex.state.load_scene("5a")
        figs = ex.plots.figures
        ex.compare.pin("5a", {**scene_values("5a"), **FAR_PIN})
        traj = ex.compare._sources[0]["traj"].data
        for fig, column in (("time_x", "x"), ("time_v", "v")):
            assert _covers(figs[fig].y_range, traj[column]), fig
        assert _covers(figs["time_x"].x_range, traj["t"])  # the pin's longer horizon
        # The portrait's equal-aspect ranges are fitted in the browser to the renderers
        # they list: the ghost is one of them.
        ghost = ex.compare._renderers[(0, "phase")]
        assert ghost in figs["phase"].x_range.renderers
        assert ghost in figs["phase"].y_range.renderers
        ex.compare.unpin()
        own = ex.plots.sources["traj"].data
        assert figs["time_x"].x_range.end == pytest.approx(float(max(own["t"])))
        assert figs["time_x"].y_range.end < 0.5 * max(traj["x"])


def test_the_preset_pairs_fig_11_with_fig_7d():
    """The paper: "Fig. 11a should be compared with Fig. 7d" (same v and x_bar); the preset
    paired 11 with 6b (a fast belt, another clearance)."""
    from app.scenes import SCENES

    label = next(k for k in PRESETS if "11" in k)
    assert label.startswith("7d vs 11")
    assert "rigid" in label and "deformable" in label
    assert PRESETS[label] == ("11", "7d")
    fig7d, fig11 = SCENES["7d"].values, SCENES["11"].values
    for name in ("belt_speed", "clearance"):
        assert fig7d[name] == fig11[name], name
    assert "Fig. 7d" in SCENES["11"].caption


def test_the_table_says_which_contact_its_restitution_is_from():
    """Scene 10 read 0.969 (its last contact) beside rigid 7c's 0.3; the readout says
    0.3986 at the first contact."""
    deformable = summary(solve(scene_values("10")))["restitution"]
    assert deformable == "0.399 / 0.969"
    assert summary(solve(scene_values("7c")))["restitution"] == "0.3"  # Newton's r, each
    ex, doc = _page()
    with set_curdoc(doc):
        ex.state.load_scene("10")
        ex.menu.apply_query({"pins": "7c"})
        assert "restitution, first / last contact" in ex.readout.object
        assert f"<td>{deformable}</td>" in ex.readout.object
