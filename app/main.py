"""Entry point: ``panel serve app/main.py --static-dirs assets=static``.

Running this module builds one session's page (an :class:`~app.explorer.Explorer` in a
template) and marks it servable; it does nothing else on import.
"""

from __future__ import annotations

import sys
from pathlib import Path

import panel as pn

#: The project root, so that ``app`` and ``core`` import when served from any directory.
ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:  # `panel serve app/main.py` puts only app/ on the path
    sys.path.insert(0, str(ROOT))

from app.connection import send_arrays_inline, send_without_delay_once_loaded  # noqa: E402
from app.explorer import WIDGET_WIDTH, Explorer  # noqa: E402
from app.memory import keep_long_lived_out_of_collections  # noqa: E402

#: Static files are served under this URL prefix (``--static-dirs assets=static``).
ASSETS = "assets"
#: Scripts of the page: repaint shortcuts for BokehJS, no repaint of a stale preview after
#: a slider's release, and no history entry per change of the address (see their headers).
JS_FILES = {"fie_paint": f"{ASSETS}/bokeh_paint.js",
            "fie_release_hold": f"{ASSETS}/release_hold.js",
            "fie_url_history": f"{ASSETS}/url_history.js"}
#: Page title.
TITLE = "Friction–Impact Explorer"


class _Page(pn.template.BootstrapTemplate):
    """The Bootstrap template, attached to a session's document in one pass.

    Attaching adds each of the template's roots and sets its theme, and after each of these
    Bokeh walked the whole document again (~930 models) to list its models; with the
    document's model list frozen until the template is attached it walks it once. A page
    costs ~15 % less server CPU, and a class that opens the explorer at once waits less.
    """

    def _init_doc(self, doc=None, comm=None, title=None, notebook=False, location=True):
        if doc is None:
            return super()._init_doc(doc, comm, title, notebook, location)
        with doc.models.freeze():
            return super()._init_doc(doc, comm, title, notebook, location)


def create_app() -> pn.template.BaseTemplate:
    """One session's page: the explorer's controls in the sidebar, plots in the main area."""
    pn.extension(notifications=False, design="bootstrap", js_files=JS_FILES)
    explorer = Explorer()
    explorer.sync_url()
    template = _Page(
        title=TITLE,
        # One root each: every extra root makes Bokeh re-walk the whole document.
        sidebar=[pn.Column(*explorer.sidebar(), sizing_mode="stretch_width", margin=0)],
        main=[pn.Column(*explorer.main(), sizing_mode="stretch_width", margin=0)],
        sidebar_width=WIDGET_WIDTH + 40,
        favicon=f"{ASSETS}/favicon.svg",
        css_files=[f"{ASSETS}/explorer.css"],
        header_background="#1f3b5f",
        # The spinner would restyle the page twice per slider release, each time forcing
        # every figure that repaints next to recompute its styles.
        busy_indicator=None,
    )
    template.explorer = explorer  # reachable from tests and the benchmark
    keep_long_lived_out_of_collections()
    send_without_delay_once_loaded()
    send_arrays_inline()
    return template


create_app().servable(title=TITLE)
