"""A script's malformed widget values over the websocket: refused quietly, the browser set back.

A value outside a slider's range or a select's options, set on the page's Bokeh document by
a script (as any script in the browser can), was refused by Panel with an ERROR and a full
traceback in the server's log (twice), while the browser kept showing it; a radio index of
-1 picked the last option, 'precise'; a value of a type the property cannot hold was
refused by Bokeh, also with an ERROR and a traceback. Now at most one WARNING line is logged
(app.perf.browser_values, app.protocol_refusals), the widget shows the value in use again
(except after Bokeh's own refusal), and the page works.
"""

from __future__ import annotations

import json
import re

import pytest
from conftest import SCREENSHOT_DIR, free_port, panel_server
from playwright.sync_api import TimeoutError as PlaywrightTimeout
from uipage import Page

from app import perf

pytestmark = pytest.mark.ui

#: The log of this file's own server.
SERVER_LOG = SCREENSHOT_DIR.parent / "panel-serve-browser-values.log"
#: Tornado's report of a write to the websocket of a page closed meanwhile.
CLOSED_SOCKET = re.compile(r"Task exception was never retrieved\n.*?"
                           r"tornado\.websocket\.WebSocketClosedError\n", re.S)
#: JavaScript: set property ``prop`` of the widget model with CSS class ``css`` (the
#: slider inside a typed slider ``fie-w-<name>``) to ``value``; returns its id.
JS_SET = """([css, prop, value]) => {
  for (let m of Bokeh.documents[0].all_models) {
    if (!(m.css_classes && m.css_classes.includes(css))) continue;
    if (css.startsWith("fie-w-")) m = m.children.find(c => c.type === "Slider");
    m[prop] = value;
    return m.id;
  }
  throw new Error("no model with class " + css);
}"""
#: JavaScript: whether model ``id``'s ``prop`` is ``value`` (compared as JSON).
JS_IS = """([id, prop, value]) => JSON.stringify(Bokeh.documents[0].get_model_by_id(id)[prop])
  === JSON.stringify(JSON.parse(value))"""
#: JavaScript: model ``id``'s ``prop`` as JSON.
JS_GET = """([id, prop]) => JSON.stringify(Bokeh.documents[0].get_model_by_id(id)[prop])"""
#: (widget's class, Bokeh property, malformed value, the value in use it must show again).
MALFORMED = [
    ("fie-accuracy", "active", -1, 1),  # was taken as the last option, 'precise'
    ("fie-accuracy", "active", 9, 1),
    ("fie-stop-type", "active", None, 1),
    ("fie-method", "value", "bogus", "auto"),
    ("fie-scene", "value", "zzz", "5a"),
    ("fie-w-restitution", "value", 5.0, 1.0),
    ("fie-w-restitution", "value", -0.5, 1.0),
    ("fie-w-restitution", "end", 50.0, 1.0),  # widening the range first is refused too
    ("fie-program", "active", True, False),  # hidden with a rigid stop: no user ticks it
]


@pytest.fixture(scope="module")
def server():
    """A server of its own with the patches switched on: the refusal at the widget is a
    patch (app.perf.browser_values), and `make test` runs tests/ui once more with the
    switch off."""
    port = free_port()
    with panel_server("app/main.py", port, SERVER_LOG, env={perf.SWITCH: "on"}):
        yield f"http://127.0.0.1:{port}/main"


def test_malformed_values_are_refused_quietly_and_the_browser_set_back(browser, server,
                                                                        shots):
    start = SERVER_LOG.stat().st_size
    p = Page(browser, server + "?scene=5a", viewport={"width": 1280, "height": 800})
    try:
        for css, prop, value, in_use in MALFORMED:
            model = p.page.evaluate(JS_SET, [css, prop, value])
            try:
                p.page.wait_for_function(JS_IS, arg=[model, prop, json.dumps(in_use)],
                                         timeout=10_000)
            except PlaywrightTimeout:
                shown = p.page.evaluate(JS_GET, [model, prop])
                raise AssertionError(f"{css}.{prop} = {value!r} still shows {shown}, "
                                     f"not {in_use!r}") from None
        # A type Bokeh itself refuses (app.protocol_refusals): said quietly too (the browser
        # keeps it: Bokeh's refusal does not say which page sent it).
        p.page.evaluate(JS_SET, ["fie-w-restitution", "value", None])
        # A value inside the range is still taken, and the page still solves and draws.
        readout = p.text(".fie-readout-pane")
        p.drag_slider("clearance", 40)
        p.wait_text_change(".fie-readout-pane", readout)
        p.page.wait_for_function("() => location.search.includes('scene=custom')",
                                 timeout=10_000)
        assert "acc=standard" in p.page.url and "r=1.0" in p.page.url
        p.page.screenshot(path=shots / "websocket-values.png")
        # BokehJS reports Bokeh's reply to the null in the console: the script's own doing.
        assert [e for e in p.errors if "Unhandled ERROR reply" not in e] == []
    finally:
        p.close()
    with open(SERVER_LOG, encoding="utf-8", errors="replace") as f:
        f.seek(start)
        log = f.read()
    # A page closed by an earlier test may leave Tornado's note of a write to its closed
    # websocket: not about these values.
    log = CLOSED_SOCKET.sub("", log)
    assert "Traceback" not in log and "ERROR" not in log, log[-3000:]
    # One line at most for all of them (rate-limited: none if one was written just before).
    assert log.count("refused from the browser") <= 1, log
