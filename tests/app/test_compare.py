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
    PinSpec,
    decode_pins,
    encode_pins,
    ghost_columns,
    pin_label,
    summary,
)
from app.solve.pool import solve
from app.state import scene_values


def _page():
    """A served page, its every plot reported in view (as the browser does on scrolling)."""
    import app.main as main
    from app.scenes import PLOTS

    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
        template.explorer.in_view.value = ",".join(PLOTS)
    return template.explorer, doc


def test_pins_round_trip_through_the_permalink():
    custom = {**scene_values("5b"), "restitution": 0.55, "belt_speed": 0.08}
    pins = [PinSpec("7c", scene_values("7c")), PinSpec("custom", custom),
            PinSpec("10", scene_values("10"))]
    text = encode_pins(pins)
    assert text.startswith("7c|")  # a scene's own values are not repeated
    back = decode_pins(text)
    assert back == pins


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
        # omega = 5 rad/s, L = 1 m
        ex.state.param.update(units="SI", mass=2.0, stiffness=50.0, length_unit=1.0)
        ex.compare.pin(ex.state.scene, ex.state.values(), ex.state.mass,
                       ex.state.stiffness)
        ex.controls.commit({"belt_speed": 0.3})
        v_dr = f"v_dr {ex.compare.pins[0].values['belt_speed'] * 5.0:.4g} m/s"
        assert v_dr == "v_dr 0.5 m/s"
        assert f"pinned 5a: {v_dr}" in ex.plots.legends["phase"].object
        assert f"5a: {v_dr}" in ex.readout.object
        assert " v 0.1" not in ex.readout.object


def test_no_model_until_used_then_ghosts_and_present_mode():
    ex, doc = _page()
    before = {m.id for m in doc.models}
    with set_curdoc(doc):
        ex.menu.presentation.set_mode("4")
        # Presenting adds its control strip only (the figures change properties).
        strip = {m.id for row in doc.models if "fie-present-strip" in getattr(
            row, "css_classes", ()) for m in row.references()}
        assert {m.id for m in doc.models} - before <= strip
        assert ex.plots.point_labels.text == "paper"
        # Fewer ticks in a quarter of the screen (six touched each other at 720p).
        assert ex.plots.shared.ticker.desired_num_ticks == 3
        ex.menu.presentation.set_mode("1")
        assert ex.plots.shared.ticker.desired_num_ticks == 5
        ex.menu.presentation.set_mode("")
        assert ex.plots.point_labels.text == "name"
        assert ex.plots.shared.ticker.desired_num_ticks == 6
        assert ex.compare.renderer_count == 0
        ex.compare.pin(ex.state.scene, ex.state.values(), ex.state.mass,
                       ex.state.stiffness)
        assert ex.compare.pins[0].solution is not None
        assert ex.compare.renderer_count > 0
        assert {m.id for m in doc.models} - before - strip
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


def test_a_menu_entry_the_menu_does_not_hold_is_refused_quietly(caplog):
    """A script's click on an entry the menu does not hold (``preset:99``, ``unpin:x``)
    failed in the handler with an ERROR and a traceback (an IndexError, a ValueError)."""

    ex, doc = _page()
    before = ex.state.values()
    with set_curdoc(doc), caplog.at_level("WARNING"):
        for item in ("preset:99", "unpin:x", "unpin:7", "present:<b>"):
            ex.menu.choose(item)
    assert ex.state.values() == before and not ex.compare.pins
    assert not ex.menu.presentation.on
    assert [r for r in caplog.records if r.levelno >= 40] == []


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
        ex.compare.pin("5a", {**scene_values("5a"), **FAR_PIN}, 1.0, 100.0)
        traj = ex.compare.ghost_source(0, "traj").data
        for fig, column in (("time_x", "x"), ("time_v", "v")):
            assert _covers(figs[fig].y_range, traj[column]), fig
        assert _covers(figs["time_x"].x_range, traj["t"])  # the pin's longer horizon
        # The portrait's equal-aspect ranges are fitted in the browser to the renderers
        # they list: the ghost is one of them.
        ghost = ex.compare.ghost_renderer(0, "phase")
        assert ghost in figs["phase"].x_range.renderers
        assert ghost in figs["phase"].y_range.renderers
        ex.compare.unpin()
        own = ex.plots.sources["traj"].data
        assert figs["time_x"].x_range.end == pytest.approx(float(max(own["t"])))
        assert figs["time_x"].y_range.end < 0.5 * max(traj["x"])


def _force_ghost(ex) -> dict:
    return ex.compare.ghost_source(0, "force").data


def _query(ex, doc, **query) -> None:
    with set_curdoc(doc):
        ex.state.param.update(**{k: v for k, v in query.items() if k != "pins"})
        ex.menu.apply_query({"pins": query["pins"]})


def test_a_pin_of_another_force_quantity_is_not_drawn_on_the_force_axis():
    """/main?scene=7c&units=SI&pins=10 drew scene 10's contact force (up to 175 N) on the
    axis of 7c's impulses (at most 0.91 N s); the preset "7c vs 10" drew 7c's impulses on
    10's axis of newtons."""
    ex, doc = _page()
    with set_curdoc(doc):
        ex.state.load_scene("7c")
    _query(ex, doc, units="SI", pins="10")
    with set_curdoc(doc):
        assert "force" in ex.plots.figures
        assert len(_force_ghost(ex)["t"]) == 0
        assert len(ex.compare.ghost_source(0, "traj").data["t"]) > 100  # drawn elsewhere
        note = "10: contact force, not comparable with impulses: not drawn"
        assert ex.compare.force_note == note
        assert ex.plots.figures["force"].title.text == f"Contact force\n{note}"
        # The axis is fitted to the run's own impulses, not to the pin's newtons.
        impulses = ex.plots.sources["stems"].data["j"]
        assert ex.plots.figures["force"].y_range.end < 2 * float(max(impulses))
        ex.menu.preset(next(k for k in PRESETS if k.startswith("7c vs 10")))
        assert ex.state.scene == "10"
        assert len(_force_ghost(ex)["t"]) == 0
        assert ex.compare.force_note == ("7c: impulses, not comparable with contact force: "
                                         "not drawn")
        # A deformable stop beside a deformable stop: the same quantity, drawn, no note.
        ex.menu.apply_query({"pins": "11"})
        assert len(_force_ghost(ex)["t"]) > 100
        assert ex.compare.force_note == ""
        assert ex.plots.figures["force"].title.text == "Contact force"


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


def test_a_pin_keeps_its_mass_and_stiffness_when_the_page_changes_them():
    """/main?scene=5a&units=SI&pins=5a: typing m = 4 turned the pin into another physical
    run ("5a: v_dr 0.5 m/s, t_end 12 s", period 1.119 s instead of 0.5597 s)."""
    ex, doc = _page()
    _query(ex, doc, units="SI", mass=1.0, stiffness=100.0, pins="5a")
    with set_curdoc(doc):
        pinned = summary(ex.compare.pins[0].solution, ex.state.scales())["period"]
        assert pinned == "0.5597 s"
        t_end = max(ex.compare.ghost_source(0, "traj").data["t"])
        ex.controls.commit_si({"m": 4.0})
        assert ex.state.mass == 4.0
        text = ex.readout.object
        assert "5a: m 1 kg" in text and "v_dr" not in text.split("compared")[1]
        assert f"<td>{pinned}</td>" in text  # the pin's own period, in its own seconds
        # Its ghost keeps its own time axis (seconds with its own omega).
        assert max(ex.compare.ghost_source(0, "traj").data["t"]) == pytest.approx(t_end)
        # The permalink names the pin's mass, the page's is 4 kg.
        assert ex.menu.query({})["pins"] == "5a,m=1.0"
        back = decode_pins("5a,m=1.0", mass=4.0, stiffness=100.0)[0]
        assert (back.mass, back.stiffness) == (1.0, 100.0)
        # A link written before pins kept their own m and k: the page's.
        old = decode_pins("5a", mass=4.0, stiffness=50.0)[0]
        assert (old.mass, old.stiffness) == (4.0, 50.0)


def test_a_pin_keeps_its_stiffness_in_newtons():
    # Scene 10's contact force, pinned with k = 100 N/m, stays in those newtons with k = 400.
    ex, doc = _page()
    with set_curdoc(doc):
        ex.state.load_scene("10")
    _query(ex, doc, units="SI", mass=1.0, stiffness=100.0, pins="10")
    with set_curdoc(doc):
        before = float(np.nanmax(_force_ghost(ex)["f"]))
        ex.controls.commit_si({"k": 400.0})
        assert float(np.nanmax(_force_ghost(ex)["f"])) == pytest.approx(before, rel=1e-6)
        assert "10: k 100 N/m" in ex.readout.object


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


@pytest.mark.parametrize("units, scene, current, words", [
    # The clearance by its display name and, in SI, its unit (it read "xbar 0.1").
    # SI with the default m = 0.5 kg, k = 200 N/m, L = 10 mm: omega L = 0.2 m/s.
    ("SI", "6b", "5a", ("v_dr 0.06 m/s", "x̄ 1 mm", "r 0.7")),
    ("dimensionless", "6b", "5a", ("v 0.3", "x̄ 0.1", "r 0.7")),
    ("dimensionless", "7c", "10", ("stop rigid", "r 0.3", "t_end 60")),
    ("SI", "7c", "10", ("stop rigid", "r 0.3", "t_end 3 s")),
])
def test_label_items_are_named_as_the_page_names_them(units, scene, current, words):
    from app.state import ExplorerState

    scales = ExplorerState(units=units).scales()
    label = pin_label(scene, scene_values(scene), scene_values(current), scales)
    assert label == f"{scene}: {', '.join(words)}"
    for key in ("xbar", "tend", "us ", "kc0", "ke0"):
        assert key not in label


def test_every_label_item_has_its_name_and_unit():
    from app.state import si_scales

    pin = {**scene_values("10"), "u_s": 2.0, "k_c0": 300.0, "k_e0": 30.0,
           "limit_overlap": 0.02, "x0": -0.1, "v0": 0.2, "beta_c": 200.0, "beta_e": 250.0,
           "contact_law": "passive", "mu_s": 0.4, "mu_k": 0.25, "belt_speed": 0.05,
           "clearance": 0.3, "t_end": 40.0}
    cur = scene_values("10")
    items = dict(LABEL_ITEMS_EXPECTED)
    for name, (dimensionless, si) in items.items():
        one = {**cur, name: pin[name]}
        assert pin_label("10", one, cur) == f"10: {dimensionless}", name
        assert pin_label("10", one, cur, si_scales(1.0, 100.0, 1.0)) == f"10: {si}", name


#: Each parameter of scene 10 changed alone, as a label says it: dimensionless, SI (m = 1 kg,
#: k = 100 N/m: omega = 10 rad/s; L = 1 m, lengths in mm).
LABEL_ITEMS_EXPECTED = (
    ("belt_speed", ("v 0.05", "v_dr 0.5 m/s")),
    ("clearance", ("x̄ 0.3", "x̄ 300 mm")),
    ("mu_s", ("μₛ 0.4", "μₛ 0.4")),
    ("mu_k", ("μₖ 0.25", "μₖ 0.25")),
    ("u_s", ("uₛ 2", "F_N 200 N")),
    ("k_c0", ("k_c0/k 300", "k_c0 3e+04 N/m")),
    ("k_e0", ("k_e0/k 30", "k_e0 3000 N/m")),
    ("limit_overlap", ("D 0.02", "D 20 mm")),
    ("beta_c", ("β_c 200", "β_c 200")),
    ("beta_e", ("β_e 250", "β_e 250")),
    ("contact_law", ("law passive", "law passive")),
    ("x0", ("x₀ -0.1", "x₀ -100 mm")),
    ("v0", ("x₀' 0.2", "x₀' 2 m/s")),
    ("t_end", ("t_end 40", "t_end 4 s")),
)


def test_pins_differ_in_colour_and_dash_in_the_portrait_and_its_legend():
    """Every pin was drawn dashed, in a muted colour near the others: three pins on the
    phase portrait were hard to tell apart and from the run. Each pin now has its own
    colour and dash, on its ghost and on its legend entry (which names its label); the
    colours stay apart from each other and from the modes' to colour-blind viewers."""
    from app.compare import PIN_DASHES, SVG_DASHES
    from app.plots.colour_vision import min_difference
    from app.plots.style import MODE_COLORS

    ex, doc = _page()
    with set_curdoc(doc):
        for key in ("7c", "5b", "10"):
            values = scene_values(key)
            ex.compare.pin(key, values, ex.state.mass, ex.state.stiffness)
        assert all(p.solution is not None for p in ex.compare.pins)
        styles = []
        for slot in range(3):
            glyph = ex.compare.ghost_renderer(slot, "phase").glyph
            styles.append((glyph.line_color, tuple(glyph.line_dash)))
        assert len({dash for _, dash in styles}) == 3 and len({c for c, _ in styles}) == 3
        legend = ex.plots.legends["phase"].object
        for label, pin in zip(ex.compare.labels(ex.state.values()), ex.compare.pins,
                              strict=True):
            assert label in legend
            assert (f'stroke="{pin.color}" stroke-width="2.5" '
                    f'stroke-dasharray="{SVG_DASHES[PIN_DASHES[pin.color]]}"') in legend
    # The pins' colours keep apart from each other and from the modes' for every viewer
    # by more than the palette before (lilac, teal, tan: 10.3 to a protanope).
    for vision in ("normal", "deuteranopia", "protanopia"):
        assert min_difference([*MODE_COLORS.values(), *PIN_COLORS], vision) > 12, vision
