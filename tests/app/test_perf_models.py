"""How many Bokeh models a new session's default page holds (each costs server time to build,
serialise and send, and browser time to render)."""

from __future__ import annotations

import importlib

from bokeh.document import Document
from panel.io.state import set_curdoc

#: Models allowed on a new session's default page: the classroom target of
#: ``benchmarks/load.py``. The page had 946 with Bokeh legends drawn from stand-in renderers
#: (234 of them), 678 with HTML legends, 541 once figures were built only when first shown
#: (the rigid default scene shows no loop, friction law or energy), 432 with one ticker,
#: formatter, label policy, scale, index filter and selection policy shared by all figures,
#: and 347 once the sliders a state does not show (deformable stop, SI units) and the
#: sliders' message boxes joined the page only when first needed, 325 with one empty
#: selection shared by all data sources (no figure has a selection tool), and 231 once only
#: the first row of plots is built with the page (the others when the browser sees them).
#: Most of the rest are the shown sliders (a text input, its tooltip, the slider, a column)
#: and three figures.
MODEL_BUDGET = 350


def count_models() -> int:
    """Models of a new session's page, built and attached as the server does."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        main.serve(main.create_app(), doc)
    return len(doc.models)


def test_a_new_page_stays_within_its_model_budget():
    models = count_models()
    print(f"a new session's default page: {models} Bokeh models (budget {MODEL_BUDGET})")
    assert 100 < models <= MODEL_BUDGET


def test_a_new_page_builds_its_first_plots_and_the_others_when_the_browser_sees_them():
    """Lazy plots (app.explorer): the mechanism, the contact force and the regime map of
    the default scene wait, empty and marked, until the page reports them in view; then
    they are built and filled from the solution on screen, and the plots drawn already
    are not sent again."""
    from app.explorer import FIRST_PLOTS

    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
    ex = template.explorer
    visible = ex.visible_plots()
    assert set(visible) == {"phase", "time", "anim", "force", "map", "return"}
    waiting = [n for n in visible if "fie-plot-pending" in ex.plot_panes[n].css_classes]
    assert sorted(waiting) == ["anim", "force", "map", "return"]
    assert set(ex.plots.figures) == {"phase", "time_x", "time_v"}
    assert ex.anim.figure is None  # nor the mechanism's figure, sources and controls
    assert all(ex.plot_panes[n].min_height and not ex.plot_panes[n].objects for n in waiting)
    assert FIRST_PLOTS <= set(visible)
    phase = ex.plots.sources["path_slip"].data
    sent = []
    ex.plots.sources["path_slip"].on_change("data", lambda attr, old, new: sent.append(new))
    with set_curdoc(doc):
        ex.in_view.value = "force,nonsense,<b>"  # only plot names count
    assert "force" in ex.plots.figures and "map" not in ex.plots.figures
    assert "fie-plot-pending" not in ex.plot_panes["force"].css_classes
    assert ex.plot_panes["force"].min_height is None
    assert len(ex.plots.sources["stems"].data["t"]) > 0  # filled: scene 5a's impacts
    assert sent == [] and ex.plots.sources["path_slip"].data is phase
    assert ex.in_view.value == ""  # ready for the next report
    with set_curdoc(doc):
        ex.in_view.value = "anim,map"
    assert "map" in ex.plots.figures and ex.plot_panes["anim"].objects
    # The mechanism, built now, is drawn at the start of the motion on screen.
    assert ex.anim.figure is not None and ex.anim.mass.data["left"][0] != -0.1
    assert len(ex.anim.belt.data["x0"]) > 0
    assert count_models() < len(doc.models)  # built on demand, not with the page
