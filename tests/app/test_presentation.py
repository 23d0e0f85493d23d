"""The presentation mode without a browser: the Present button, the control strip built on the
first entry only and linked both ways to the state, the layouts of one to four plots in the
permalink, the figures freed of their width cap."""

from __future__ import annotations

import numpy as np
import param
from bokeh.document import Document
from panel.io.state import set_curdoc

from app.compare_menu import PRESENT_FIRST
from app.present_strip import STRIP_SLIDERS
from app.presentation import MODES, PLOT_COUNT


def _page(query: str = "", in_view: bool = True):
    """A served page (its every plot reported in view, unless not ``in_view``), its address
    ``query``."""
    import app.main as main
    from app.scenes import PLOTS

    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        if query:
            template.explorer.apply_query(query)
        main.serve(template, doc)
        if in_view:
            template.explorer.in_view.value = ",".join(PLOTS)
    return template.explorer, doc


def _release(slider, value: float) -> None:
    """The browser's release of ``slider`` at ``value`` (a read-only value from Python)."""
    with param.edit_constant(slider):
        slider.value_throttled = value


def test_present_button_starts_and_the_strip_comes_only_then_once():
    ex, doc = _page("scene=7c")
    pres = ex.presentation
    with set_curdoc(doc):
        before = len(doc.models)
        assert pres.strip is None  # a page not presenting carries no strip
        ex.menu.present.clicks += 1
        assert ex.state.present == PRESENT_FIRST
        assert pres.strip is not None and pres.strip.layout.visible
        assert any(obj is pres.strip.layout for obj in ex.plot_box.objects)
        built = len(doc.models)
        assert built > before
        assert not ex.caption.visible  # the strip's picker names the scene
        pres.strip.exit.clicks += 1
        assert ex.state.present == ""
        assert not pres.strip.layout.visible and ex.caption.visible
        ex.menu.present.clicks += 1
        assert len(doc.models) == built  # no second strip


def test_strip_sliders_commit_into_the_state_and_follow_it():
    ex, doc = _page("scene=7c&present=1")
    strip = ex.presentation.strip
    with set_curdoc(doc):
        shown = [n for n, s in strip.sliders.items() if s.visible]
        assert shown == list(STRIP_SLIDERS["rigid"])
        run = ex.solution
        _release(strip.sliders["restitution"], 0.5)
        assert ex.state.restitution == 0.5
        assert ex.solution is not run and ex.solution.values["restitution"] == 0.5
        # The page's own widgets and the copies show the one state.
        assert ex.sliders["restitution"].value == 0.5
        ex.controls.commit({"belt_speed": 0.05})
        assert strip.sliders["belt_speed"].value == 0.05
        # A scene of another stop shows that stop's sliders.
        strip.scene.value = "10"
        assert ex.state.scene == "10" and ex.state.stop_type == "hysteretic"
        assert [n for n, s in strip.sliders.items() if s.visible] == list(
            STRIP_SLIDERS["hysteretic"])
        strip.layouts.value = "3"
        assert ex.state.present == "3"


def test_layouts_show_their_number_of_plots_and_round_trip_in_the_address():
    ex, doc = _page("scene=10")
    with set_curdoc(doc):
        for mode in MODES:
            ex.presentation.set_mode(mode)
            shown = [n for n, pane in ex.plot_panes.items() if pane.visible]
            assert len(shown) == PLOT_COUNT[mode], mode
            assert f"present={mode}" in ex.query.split("&")
            other, _ = _page(f"scene=10&present={mode}")
            assert other.state.present == mode
    refused, _ = _page("scene=10&present=5")
    assert refused.state.present == ""
    assert "present must be one of 1, 2, 3, 4" in refused.error


def test_presented_figures_lose_their_width_cap():
    """The one-plot layout's phase portrait kept the page's 900 px cap (its layout is the
    figure itself, whose sizing mode was set first): it filled 45 % of a 1920 px screen."""
    ex, doc = _page("scene=5a")
    with set_curdoc(doc):
        ex.presentation.set_mode("1")
        fig = ex.plots.figures["phase"]
        assert fig.sizing_mode == "stretch_both" and fig.max_width is None
        ex.presentation.set_mode("")
        assert fig.sizing_mode == "stretch_width" and fig.max_width is not None


def test_a_lazy_page_builds_every_plot_of_the_layout():
    """On the served (lazy) page the third and fourth plots waited, empty, for the browser
    to report them in view: the three-plot layout showed half a row blank."""
    ex, doc = _page("scene=10", in_view=False)
    with set_curdoc(doc):
        for mode in ("3", "4"):
            ex.presentation.set_mode(mode)
            shown = [n for n, pane in ex.plot_panes.items() if pane.visible]
            assert len(shown) == PLOT_COUNT[mode]
            assert all(ex.plot_panes[n].objects for n in shown), mode


def test_panes_hidden_by_a_lesson_stay_hidden_when_not_presenting():
    """The caption is shown again on leaving the presentation only: a lesson's question
    hides it meanwhile, and a redraw of the plots must not show it."""
    ex, doc = _page("scene=5a")
    with set_curdoc(doc):
        ex.caption.visible = False  # as a step that asks a question does
        ex.host.show_plots()
        assert not ex.caption.visible
        ex.presentation.set_mode("2")
        ex.presentation.set_mode("")
        assert ex.caption.visible


def test_a_page_opened_presenting_hides_the_caption():
    """The address is read before the page is laid out: the caption, registered after the
    mode was on, stayed above the strip."""
    from app.explorer import Explorer

    ex = Explorer()
    ex.apply_query("scene=5a&present=1")
    ex.main()
    assert not ex.caption.visible
    ex.presentation.set_mode("")
    assert ex.caption.visible


def test_a_plot_the_layout_shows_with_a_new_scene_is_drawn_from_that_scene_s_run():
    """Presenting 2x2 on a lazy page, a scene of another stop brings a plot into the layout
    with its run (the hysteresis loop): the layout built the plot as the run was drawn and
    filled it from the run before; the run's own draw then left the plot out, empty."""
    from app.plots.columns import loop_columns

    ex, doc = _page("scene=7c&present=4", in_view=False)
    with set_curdoc(doc):
        assert "loop" not in ex.presentation.shown(ex.visible_plots())
        ex.presentation.strip.scene.value = "11"  # a hysteretic stop
        assert "loop" in ex.presentation.shown(ex.visible_plots())
        sol = ex.solution
        assert sol.values["stop_type"] == "hysteretic"
        expected = loop_columns(sol, ex.state.scales())["loop"]
        drawn = ex.plots.sources["loop"].data
        assert len(expected["d"]) > 0
        # The same columns (their NaNs, the breaks between contacts, equal too).
        np.testing.assert_array_equal(drawn["d"], expected["d"])
        np.testing.assert_array_equal(drawn["phi"], expected["phi"])


def test_a_layout_draws_only_the_plots_it_shows_and_the_others_when_shown(monkeypatch):
    """In a one-plot layout every release still filled the plots it hides (the return map,
    the contact force, the regime map, the mechanism): server time and bytes for nothing on
    the screen. They wait, and are filled from the run on screen when a layout shows them."""
    ex, doc = _page("scene=7c")
    with set_curdoc(doc):
        plots = ex.host.plots
        filled = []
        for name in ("_fill_return", "_fill_force"):
            fill = getattr(plots, name)
            monkeypatch.setattr(plots, name, lambda *a, fill=fill, name=name: (
                filled.append(name), fill(*a))[1])
        ex.state.present = "1"
        slider = ex.sliders["clearance"].slider
        for value in (0.25, 0.22, 0.2):  # 0.2: a grazing run, other points than 7c's
            _release(slider, value)
        assert ex.solution.values["clearance"] == 0.2
        assert filled == []
        ex.state.present = ""
        assert sorted(filled) == ["_fill_force", "_fill_return"]
        counts = ex.solution.result.transition_counts
        impacts = counts.get("impact", 0) + counts.get("stick->impact", 0)
        assert len(plots.sources["ret_points"].data["x"]) == impacts - 1
        assert f"({impacts - 1} points)" in plots.figures["return"].title.text
