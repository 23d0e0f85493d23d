"""A new page without Panel's walks that find nothing to do (app.perf.attach): the same page,
with fewer walks, and a model of another page refused loudly instead of taken in silence."""

from __future__ import annotations

import importlib
from collections import Counter

import panel.io.model as panel_model
import panel.io.server as panel_server
import panel.template.base as template_base
import pytest
from bokeh.document import Document
from bokeh.model import Model
from bokeh.models import Column, Div, ImportedStyleSheet
from panel.io.resources import LOCAL_DIST
from panel.io.state import set_curdoc

from app import perf
from app.perf import attach


def _page(patched: bool, monkeypatch: pytest.MonkeyPatch) -> Document:
    """A whole page as a session builds it, with the patches or with Panel's own functions,
    its stylesheets given their address as the page's HTML does."""
    main = importlib.import_module("app.main")
    monkeypatch.setenv(perf.SWITCH, "on")  # `make test` runs tests/app once more with it off
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()  # installs the patches
        if not patched:
            monkeypatch.setattr(template_base, "add_to_doc", attach.PANEL_ADD_TO_DOC)
            monkeypatch.setattr(panel_server, "patch_model_css", attach.PANEL_PATCH_MODEL_CSS)
        main.serve(template, doc)
        for root in doc.roots:  # as panel.io.server.server_html_page_for_session
            panel_server.patch_model_css(root, dist_url=LOCAL_DIST)
    monkeypatch.undo()
    return doc


def _counting(monkeypatch: pytest.MonkeyPatch, owner: object, name: str) -> list:
    calls: list = []
    own = getattr(owner, name)

    def counted(*args, **kwargs):
        calls.append(args)
        return own(*args, **kwargs)

    monkeypatch.setattr(owner, name, counted)
    return calls


def test_the_page_is_the_same_with_and_without_the_patches(monkeypatch):
    patched, own = _page(True, monkeypatch), _page(False, monkeypatch)
    for doc in (patched, own):
        assert all(m.document is doc for m in doc.models)
    assert Counter(type(m).__name__ for m in patched.models) == \
        Counter(type(m).__name__ for m in own.models)
    assert [r.name.split("-")[0] for r in patched.roots] == \
        [r.name.split("-")[0] for r in own.roots]

    def addresses(doc):
        return sorted(m.url for m in doc.models if isinstance(m, ImportedStyleSheet))

    # Every stylesheet was given the server's versioned address, the same ones either way.
    assert addresses(patched) == addresses(own)
    assert len(addresses(patched)) >= 5
    assert all("?v=" in url for url in addresses(patched) if LOCAL_DIST in url)


def test_the_patched_page_walks_none_of_its_roots(monkeypatch):
    """Panel's ``remove_root`` walks a root, and ``patch_model_css`` each root's models
    (``Model.select``): neither runs for a new page with the patches."""
    monkeypatch.setenv(perf.SWITCH, "on")
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        removed = _counting(monkeypatch, panel_model, "remove_root")
        main.serve(template, doc)
        walks = _counting(monkeypatch, Model, "select")
        for root in doc.roots:
            panel_server.patch_model_css(root, dist_url=LOCAL_DIST)
    assert removed == []
    assert walks == []
    assert len(doc.roots) >= 4
    # Panel's own functions do walk (the count above could not pass by being blind).
    monkeypatch.undo()
    removed = _counting(monkeypatch, panel_model, "remove_root")
    walks = _counting(monkeypatch, Model, "select")
    other = Document()
    with set_curdoc(other):
        template = main.create_app()
        monkeypatch.setattr(template_base, "add_to_doc", attach.PANEL_ADD_TO_DOC)
        main.serve(template, other)
        before = len(walks)
        for root in other.roots:
            attach.PANEL_PATCH_MODEL_CSS(root, dist_url=LOCAL_DIST)
    # Each root the template adds itself (Panel adds the location apart).
    assert {args[0] for args in removed} == {r for r in other.roots
                                             if type(r).__name__ != "Location"}
    assert len(walks) - before == len(other.roots)


def test_a_model_of_another_page_is_refused_not_taken(monkeypatch):
    """A fresh root holding a model of another document: Bokeh refuses it (Panel's walk
    would have taken it from the other page in silence)."""
    monkeypatch.setattr(attach, "PANEL_ADD_TO_DOC", panel_model.add_to_doc)
    other, doc = Document(), Document()
    shared = Div(text="on another page")
    other.add_root(shared)
    with pytest.raises(RuntimeError, match="owned by only a single document"):
        attach.add_fresh_root(Column(children=[shared]), doc)
    assert shared.document is other


def test_a_root_already_attached_goes_panels_way(monkeypatch):
    monkeypatch.setattr(attach, "PANEL_ADD_TO_DOC", panel_model.add_to_doc)
    old, new = Document(), Document()
    root = Column(children=[Div(text="moved")])
    old.add_root(root)
    attach.add_fresh_root(root, new)
    assert root in new.roots and root not in old.roots
    assert root.children[0].document is new
