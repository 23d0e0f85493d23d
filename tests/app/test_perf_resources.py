"""The page's resources (app.perf.resources): each bundle once, MathJax only where needed.

Before, a first open fetched Bootstrap's CSS at two addresses (the page's link without
Panel's version suffix, the shadow roots' copies with it) and MathJax (1.8 MB) for a page
that holds no TeX.
"""

from __future__ import annotations

import importlib

import panel.io.resources as panel_resources
import pytest
from bokeh.document import Document
from bokeh.embed.util import contains_tex_string
from bokeh.resources import Resources
from panel.io.state import set_curdoc
from panel.models.markup import HTML as PanelHTML
from panel.theme.base import Design

from app import perf
from app.perf import resources


@pytest.fixture(scope="module")
def page():
    """(template, document) of a whole page, as a session builds it."""
    main = importlib.import_module("app.main")
    doc = Document()
    with pytest.MonkeyPatch.context() as mp, set_curdoc(doc):
        mp.setenv(perf.SWITCH, "on")  # `make test` runs tests/app once more with it off
        template = main.create_app()
        main.serve(template, doc)
        yield template, doc


def test_the_page_loads_no_mathjax_and_none_of_its_panes_needs_it(page):
    _, doc = page
    with set_curdoc(doc):
        bundle = panel_resources.bundle_resources(doc.roots, Resources(mode="server"))
    assert not [f for f in bundle.js_files if "mathjax" in str(f)]
    # What makes that safe: no HTML pane of the page holds TeX (Bokeh's own test).
    panes = [m for m in doc.models if isinstance(m, PanelHTML)]
    assert len(panes) > 5
    assert not [m.text for m in panes if contains_tex_string(m.text or "")]


def test_the_page_links_bootstrap_at_the_shadow_roots_address(page):
    template, doc = page
    with set_curdoc(doc):
        css = template.resolve_resources()["css"]
    links = [url for url in css.values() if url.endswith(".css") or "?v=" in url]
    bootstrap = [url for url in links if "bootstrap.min.css" in url]
    # patch_stylesheet gives the shadow roots' copy exactly this suffix.
    assert bootstrap == [f"static/extensions/panel/bundled/bootstrap5/css/bootstrap.min.css"
                         f"?v={panel_resources.JS_VERSION}"]


@pytest.mark.parametrize("url", [
    "https://cdn.example/extensions/panel/x.css",   # Panel's dist elsewhere: versioned
    "static/extensions/panel/a.css?v=1",            # already versioned
    "static/extensions/panel/a.js",                 # not CSS
    "assets/explorer.css",                          # the app's own
])
def test_only_panel_s_unversioned_css_gets_the_suffix(url):
    expected = url + "?v=9" if url.startswith("https://") else url
    assert resources.versioned_css(url, "extensions/panel/", "?v=9") == expected


def test_switched_off_nothing_is_patched(monkeypatch):
    original_resolve = resources.PANEL_DESIGN_RESOLVE or Design.__dict__["resolve_resources"]
    monkeypatch.setattr(Design, "resolve_resources", original_resolve)
    monkeypatch.setattr(resources, "PANEL_DESIGN_RESOLVE", None)
    original_tex = resources.PANEL_USE_MATHJAX or panel_resources._panel_use_mathjax
    monkeypatch.setattr(panel_resources, "_panel_use_mathjax", original_tex)
    monkeypatch.setenv(perf.SWITCH, "off")
    resources.load_each_bundle_once()
    assert Design.__dict__["resolve_resources"] is original_resolve
    assert panel_resources._panel_use_mathjax is original_tex
