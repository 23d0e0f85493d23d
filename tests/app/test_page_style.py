"""The phone's width limit is one number in every file that lays the page out by it."""

from __future__ import annotations

from pathlib import Path

from app.page_style import MAIN_COLUMN_CSS, PHONE_MAX_WIDTH
from app.widgets import SLIDER_CSS

ROOT = Path(__file__).resolve().parents[2]


def test_every_phone_rule_uses_the_same_width():
    query = f"(max-width: {PHONE_MAX_WIDTH}px)"
    for path in ("static/explorer.css", "static/widgets.css", "static/drawer.js"):
        assert query in (ROOT / path).read_text(), path
    assert query in SLIDER_CSS and query in MAIN_COLUMN_CSS


def _page(design, widgets: int):
    """A column of ``widgets`` number boxes and an HTML pane in a new document, with
    ``design``: its models."""
    import panel as pn
    from bokeh.document import Document
    from panel.io.state import set_curdoc

    doc = Document()
    with set_curdoc(doc), pn.config.set(design=design):
        column = pn.Column(*(pn.widgets.TextInput(name=f"box {i}") for i in range(widgets)),
                           pn.pane.HTML("<b>head</b>"))
        root = column.get_root(doc)
    return [m for m in root.references()]


def _sheets(models) -> list[list[str]]:
    """Each model's style sheets (an address or the text), in a stable order."""
    out = []
    for m in models:
        sheets = getattr(m, "stylesheets", None)
        if sheets:
            out.append([getattr(s, "url", s) for s in sheets])
    return sorted(out)


def test_the_design_finds_its_themes_sheets_once_not_per_widget(monkeypatch):
    """Panel's themes look their style sheets up on the disk at every read, twice per
    widget; the page's design has them found once: a page with ten times the widgets
    does not look up one file more."""
    import param.parameters

    from app.page_style import ExplorerDesign

    lookups = []
    resolve = param.parameters.resolve_path

    def counted(*args, **kwargs):
        lookups.append(kwargs.get("path", args[0] if args else None))
        return resolve(*args, **kwargs)

    _page(ExplorerDesign, 2)  # first use: imports and class set-up
    monkeypatch.setattr(param.parameters, "resolve_path", counted)
    _page(ExplorerDesign, 2)
    few = len(lookups)
    lookups.clear()
    _page(ExplorerDesign, 20)
    assert len(lookups) == few, lookups


def test_the_resolved_themes_give_the_same_style_sheets():
    """The same sheets, in the same order, as the design with Panel's own themes."""
    from panel.theme import Bootstrap

    from app.page_style import ExplorerDesign

    class PanelThemes(ExplorerDesign):
        _themes = Bootstrap._themes

    for theme in ("default", "dark"):
        ours, panels = (ExplorerDesign(theme=theme), PanelThemes(theme=theme))
        assert type(ours.theme).__mro__[1] is type(panels.theme)
        assert (ours.theme.css, ours.theme.base_css) == (panels.theme.css, panels.theme.base_css)
        # The page's own links to the themes' sheets (the template's head).
        assert ours.resolve_resources() == panels.resolve_resources()
    assert _sheets(_page(ExplorerDesign, 3)) == _sheets(_page(PanelThemes, 3))
