"""A widget value that no user can give, arriving from the browser (app.perf.browser_values).

Setting a property of a widget's Bokeh model on the server runs the same path as a change
from the browser (Panel's model-change handler, then ``_process_events``). Before, a value
outside a slider's range or a select's options failed there with an ERROR and a traceback,
and an index of -1 chose the last radio button.
"""

from __future__ import annotations

import importlib.util
import logging

import pytest
from bokeh.document import Document

import app.widgets
from app import perf
from app.perf import browser_values


@pytest.fixture(scope="module")
def widgets():
    """``app.widgets`` with the patch applied whatever the switch says (`make test` runs
    tests/app once more with it off): the patch is chosen when the classes are defined, so
    a copy of the module is loaded under a name of its own, the app's classes untouched."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(perf.SWITCH, "on")
        spec = importlib.util.spec_from_file_location("_patched_widgets", app.widgets.__file__)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    assert issubclass(module.Select, browser_values.SelectValues)
    return module


@pytest.fixture
def said(caplog):
    """The log records of the test, with the rate limit starting afresh (and again after
    it, as at the server's start)."""
    browser_values.restart_rate_limit()
    caplog.set_level(logging.DEBUG)
    yield caplog
    browser_values.restart_rate_limit()


def _model(widget):
    return widget.get_root(Document())


def test_a_radio_index_outside_the_buttons_is_refused(said, widgets):
    w = widgets.RadioButtonGroup(options=["draft", "standard", "precise"], value="standard")
    model = _model(w)
    for index in (-1, 3, 99):
        model.active = index
        assert w.value == "standard"  # -1 was taken as the last option, 'precise'
        assert model.active == 1  # the browser is sent the button in use
    model.active = 0
    assert w.value == "draft"  # a button's own index is taken
    _one_quiet_line(said, "RadioButtonGroup", "active=-1")


def test_a_select_value_outside_the_options_is_refused(said, widgets):
    w = widgets.Select(options=["auto", "exact"], value="auto")
    model = _model(w)
    for value in ("bogus", "", "x" * 5000):
        model.value = value
        assert w.value == "auto" and model.value == "auto"
    model.value = "exact"
    assert w.value == "exact"
    _one_quiet_line(said, "Select", "value='bogus'")


def test_a_slider_value_outside_its_range_is_neither_committed_nor_kept(said, widgets):
    committed, dragged = [], []
    t = widgets.TypedSlider("r", 0.5, 0.01, (0.0, 1.0), (0.0, 1.0), on_drag=dragged.append,
                    on_commit=committed.append, width=200, css_class="fie-w-r")
    model = _model(t.slider)
    for value in (5.0, -0.5, float("nan")):
        model.value = value
        assert t.value == 0.5 and model.value == 0.5
    model.end = 50.0  # a wider range first: refused too
    assert t.slider.end == 1.0 and model.end == 1.0
    assert committed == [] and dragged == []
    model.value = 0.75
    assert dragged == [0.75]
    _one_quiet_line(said, "_Slider", "value=5.0")


def test_a_hidden_checkbox_takes_nothing(said, widgets):
    w = widgets.Checkbox(value=False, visible=False)
    model = _model(w)
    model.active = True
    assert w.value is False and model.active is False
    _one_quiet_line(said, "Checkbox", "active=True")


def _one_quiet_line(caplog, widget: str, what: str) -> None:
    """Every refusal of the test was said in one WARNING line (the rate limit), and
    nothing at ERROR."""
    assert [r for r in caplog.records if r.levelno >= logging.ERROR] == []
    lines = [r for r in caplog.records if "refused from the browser" in r.getMessage()]
    assert len(lines) == 1 and lines[0].levelno == logging.WARNING
    assert widget in lines[0].getMessage() and what in lines[0].getMessage()
    assert lines[0].exc_info is None


def test_a_type_bokeh_refuses_is_said_in_one_quiet_line(said):
    """Bokeh refuses a value of the wrong type itself (``null`` for a slider's value) and
    logged it at ERROR with a traceback (bokeh.server.protocol_handler)."""
    from types import SimpleNamespace

    from app.protocol_refusals import QuietRefusals

    message = SimpleNamespace(msgtype="PATCH-DOC", content={"events": [
        {"kind": "ModelChanged", "model": {"id": "p1"}, "attr": "value", "new": None}]})
    error = ValueError("failed to validate Slider(id='p1', ...).value: expected a value of "
                       "type Real, got None of type NoneType")
    records = [logging.makeLogRecord({
        "name": "bokeh.server.protocol_handler", "levelno": logging.ERROR,
        "msg": "error handling message\n message: %r \n error: %r", "args": (message, error),
        "exc_info": (ValueError, error, None)}) for _ in range(3)]
    assert [QuietRefusals().filter(r) for r in records] == [False] * 3
    lines = [r for r in said.records if "refused from the browser" in r.getMessage()]
    assert len(lines) == 1 and lines[0].levelno == logging.WARNING
    assert "expected a value of type Real" in lines[0].getMessage()
    other = logging.makeLogRecord({"msg": "error handling message", "args": ("x", "y")})
    assert QuietRefusals().filter(other)  # anything else passes unchanged
