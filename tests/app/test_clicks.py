"""The page's click handlers run with its changes held (:func:`app.widgets.on_click`).

Panel runs a click that reaches the server while another widget's change is still due
outside the document's lock; a handler that then set a Bokeh model's property raised, and
the page stayed as it was (``tests/ui/test_presentation_strip_ui.py`` drives that in a
browser). Here: the helper holds the document, and every click handler of the app is
registered through it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import panel as pn
from bokeh.document import Document
from panel.io.state import set_curdoc

from app.widgets import on_click

APP = Path(__file__).resolve().parents[2] / "app"


def _hold_during_click(register) -> str | None:
    """The document's hold policy seen by a click handler registered by ``register``."""
    seen = []
    button = pn.widgets.Button(label="go")
    register(button, lambda event: seen.append(doc.callbacks.hold_value))
    doc = Document()
    with set_curdoc(doc):
        button.clicks += 1
    assert len(seen) == 1
    return seen[0]


def test_a_click_handler_runs_under_a_hold():
    assert _hold_during_click(on_click) == "combine"
    # Panel's own registration holds nothing: the helper is what holds.
    assert _hold_during_click(lambda b, fn: b.on_click(fn)) is None


def bare_on_clicks(source: str) -> list[int]:
    """Lines of ``source`` that register a click handler with a widget's own ``on_click``."""
    return [node.lineno for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr == "on_click"]


def test_bare_on_click_is_found():
    assert bare_on_clicks("b.on_click(f)\non_click(b, f)\nb.js_on_click(code='')\n") == [1]


def test_every_click_handler_of_the_app_is_held():
    faults = [f"{path.relative_to(APP.parent)}:{line}"
              for path in sorted(APP.rglob("*.py")) if path.name != "widgets.py"
              for line in bare_on_clicks(path.read_text())]
    assert faults == [], f"register click handlers with app.widgets.on_click: {faults}"
