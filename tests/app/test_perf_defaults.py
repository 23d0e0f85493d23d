"""The patch that keeps Bokeh's immutable property defaults per class
(app.perf.defaults): every read answers what Bokeh itself computes, and no instance shares a
mutable default with another."""

from __future__ import annotations

import importlib

import pytest
from bokeh.core.property.descriptors import PropertyDescriptor
from bokeh.document import Document
from bokeh.models import ColumnDataSource, Line
from panel.io.state import set_curdoc

import app.perf as perf
from app.perf import defaults


@pytest.fixture
def patched(monkeypatch):
    """The patch applied for one test, Bokeh's own descriptor restored after it."""
    monkeypatch.setenv(perf.SWITCH, "on")
    monkeypatch.setattr(PropertyDescriptor, "_get_default", PropertyDescriptor._get_default)
    monkeypatch.setattr(defaults, "_DEFAULTS", {})
    defaults.cache_immutable_defaults()
    assert PropertyDescriptor._get_default is defaults._get_default
    yield


def _page_models():
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
        template.explorer.in_view.value = "anim,force,map"  # the scene's other plots too
    doc.to_json()
    return list(doc.models)


def test_every_unset_property_of_a_page_reads_as_bokeh_computes_it(patched):
    """Two pages built with the patch (the second from the kept defaults): each unset
    property with a stable default, of each of their models, equals Bokeh's own default
    for it, computed afresh."""
    _page_models()
    models = _page_models()
    assert defaults._DEFAULTS  # the page did read kept defaults
    checked = 0
    for model in models:
        for name in model.properties():
            descriptor = model.lookup(name)
            if name in model._property_values or descriptor.has_unstable_default(model):
                continue  # set, or Bokeh's own per-instance default (a new model, a list)
            fresh = descriptor.instance_default(model)
            value = descriptor._get(model)
            # (nan is a default too: a data range's start)
            assert value == fresh or value != value and fresh != fresh, (
                type(model).__name__, name)
            checked += 1
    assert checked > 5000


def test_mutable_defaults_stay_per_instance(patched):
    """A data spec's default (a ``Field``) and a container default are each instance's
    own, as in Bokeh: changing one instance's leaves the other's alone."""
    a, b = Line(), Line()
    assert a.x == b.x and a.x is not b.x
    s, t = ColumnDataSource(), ColumnDataSource()
    s.data["x"] = [1.0]
    assert t.data == {}


def test_switched_off_it_leaves_bokeh_alone(monkeypatch):
    monkeypatch.setenv(perf.SWITCH, "off")
    monkeypatch.setattr(PropertyDescriptor, "_get_default", PropertyDescriptor._get_default)
    own = PropertyDescriptor._get_default
    defaults.cache_immutable_defaults()
    assert PropertyDescriptor._get_default is own
