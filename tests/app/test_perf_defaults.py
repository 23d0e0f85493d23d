"""The patch that keeps Bokeh's immutable property defaults per class
(app.perf.defaults): every read answers what Bokeh itself computes, no instance shares a
mutable default with another, and the page's JSON is the same with and without it."""

from __future__ import annotations

import importlib
import json
import re

import pytest
from bokeh.core.has_props import HasProps
from bokeh.core.property.descriptors import PropertyDescriptor, UnsetValueError
from bokeh.core.property.singletons import Undefined
from bokeh.document import Document
from bokeh.models import Column, ColumnDataSource, Div, Line
from bokeh.themes import Theme
from panel.io.state import set_curdoc

import app.perf as perf
from app.perf import defaults


@pytest.fixture
def patched(monkeypatch):
    """The patch applied for one test, Bokeh's own descriptor restored after it."""
    monkeypatch.setenv(perf.SWITCH, "on")
    _restore_bokeh(monkeypatch)
    defaults.forget_kept()
    defaults.cache_immutable_defaults()
    assert PropertyDescriptor._get_default is defaults.get_default
    assert PropertyDescriptor.has_unstable_default is defaults.has_unstable_default
    assert HasProps.themed_values is defaults.themed_values
    yield


#: What the patch replaces: (class, name, the patch's function, where it keeps Bokeh's).
REPLACED = ((PropertyDescriptor, "_get_default", "get_default", "BOKEH_GET_DEFAULT"),
            (PropertyDescriptor, "has_unstable_default", "has_unstable_default",
             "BOKEH_HAS_UNSTABLE_DEFAULT"),
            (HasProps, "themed_values", "themed_values", "BOKEH_THEMED_VALUES"))


def _restore_bokeh(monkeypatch):
    """Bokeh's own functions for the test (also where an earlier page applied the patch),
    whatever was there back after it."""
    for cls, name, ours, kept in REPLACED:
        current = getattr(cls, name)
        monkeypatch.setattr(cls, name, getattr(defaults, kept)
                            if current is getattr(defaults, ours) else current)


def _page() -> Document:
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
        template.explorer.in_view.value = "anim,force,map"  # the scene's other plots too
    return doc


def _page_models():
    doc = _page()
    doc.to_json()
    return list(doc.models)


def _given(model) -> set[str]:
    """The properties of ``model`` given a value (by the code, a theme, or as Bokeh's
    per-instance default), by Bokeh's public query; an unset property without a default
    (Bokeh's ``Undefined``) is listed there too and is not one."""
    found = model.query_properties_with_values(lambda _: True, include_defaults=False,
                                               include_undefined=True)
    return {name for name, value in found.items() if value is not Undefined}


def _read(model, name: str):
    """The value ``model.name`` reads, ``Undefined`` where it has none."""
    try:
        return getattr(model, name)
    except UnsetValueError:
        return Undefined


def _page_json() -> str:
    """The page's JSON with what differs between two builds of it made equal: model ids,
    the counters and object addresses in names, the solve's measured time."""
    text = json.dumps(_page().to_json(), default=repr, sort_keys=True)
    text = re.sub(r"(?<=['\":])p\d+", "p", text)
    text = re.sub(r"(?<=[A-Za-z])\d{5}\b|0x[0-9a-f]+|\d{9,}", "N", text)
    return re.sub(r"\d+\.\d+ ms", "T ms", text)


def test_every_unset_property_of_a_page_reads_as_bokeh_computes_it(patched):
    """Two pages built with the patch (the second from the kept defaults): each unset
    property with a stable default, of each of their models, equals Bokeh's own default
    for it, computed afresh."""
    _page_models()
    models = _page_models()
    assert defaults.kept_defaults()  # the page did read kept defaults
    checked = 0
    for model in models:
        given = _given(model)
        for name in model.properties():
            descriptor = model.lookup(name)
            if name in given or descriptor.has_unstable_default(model):
                continue  # set, or Bokeh's own per-instance default (a new model, a list)
            fresh = descriptor.instance_default(model)
            value = _read(model, name)
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


def test_container_defaults_are_fresh_copies_that_notify(patched):
    """A container default made from the class's kept one is the instance's own, of
    Bokeh's type, and a change to it in place is a change of the model (its owner)."""
    Column(), Column()  # the first computes and keeps it, the others copy it
    assert any(key[0].name == "children" for key in defaults.kept_containers())
    c, d = Column(), Column()
    assert c.children == d.children == [] and c.children is not d.children
    assert type(c.children) is type(d.children)
    changes = []  # the copy's owner is c, by its property "children": c hears of it
    c.on_change("children", lambda attr, old, new: changes.append(new))
    c.children.append(Div())
    assert len(changes) == 1 and d.children == []


def test_unstable_default_answers_as_bokeh(patched):
    """Whether a default is kept per instance, asked of every property of a page's models,
    is Bokeh's own answer."""
    models = _page_models()
    for model in models:
        for name in model.properties():
            descriptor = model.lookup(name)
            assert descriptor.has_unstable_default(model) == \
                defaults.BOKEH_HAS_UNSTABLE_DEFAULT(descriptor, model), name


def test_a_theme_still_applies(patched):
    """A theme's value is read where it applies, and the default again once it is gone."""
    div = Div()
    assert div.themed_values() is None and div.width is None
    theme = Theme(json={"attrs": {"Div": {"width": 123}}})
    doc = Document()
    doc.add_root(div)
    doc.theme = theme
    assert div.themed_values() == {"width": 123} and div.width == 123
    doc.theme = Theme(json={})
    assert div.themed_values() is None and div.width is None


def test_the_page_is_the_same_with_and_without_it(monkeypatch):
    """The default page with every plot, serialized: the same JSON whether Bokeh or the
    patch answers the defaults."""
    monkeypatch.setenv(perf.SWITCH, "off")
    _restore_bokeh(monkeypatch)
    _page()  # imports and caches, then a page as the server builds the next one
    without = _page_json()
    monkeypatch.setenv(perf.SWITCH, "on")
    defaults.cache_immutable_defaults()
    assert PropertyDescriptor._get_default is defaults.get_default
    _page()
    assert _page_json() == without


def test_switched_off_it_leaves_bokeh_alone(monkeypatch):
    monkeypatch.setenv(perf.SWITCH, "off")
    _restore_bokeh(monkeypatch)
    own = (PropertyDescriptor._get_default, PropertyDescriptor.has_unstable_default,
           HasProps.themed_values)
    defaults.cache_immutable_defaults()
    assert (PropertyDescriptor._get_default, PropertyDescriptor.has_unstable_default,
            HasProps.themed_values) == own
