"""Entry point: ``panel serve app/main.py --static-dirs assets=static``.

Run by the server, this module builds one session's page (an
:class:`~app.explorer.Explorer` in a template) and attaches it to the session's document;
imported elsewhere it does nothing.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import panel as pn
from bokeh.document import Document

#: The project root, so that ``app`` and ``core`` import when served from any directory.
ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:  # `panel serve app/main.py` puts only app/ on the path
    sys.path.insert(0, str(ROOT))

from app.explorer import WIDGET_WIDTH, Explorer  # noqa: E402
from app.memory import keep_long_lived_out_of_collections  # noqa: E402
from app.page_style import VIEWPORT, ExplorerDesign  # noqa: E402
from app.perf import report  # noqa: E402
from app.perf.attach import attach_without_walks  # noqa: E402
from app.perf.defaults import cache_immutable_defaults  # noqa: E402
from app.perf.page import page_scripts  # noqa: E402
from app.perf.resources import load_each_bundle_once  # noqa: E402
from app.perf.websocket import send_arrays_inline, send_without_delay_once_loaded  # noqa: E402
from app.protocol_refusals import quiet_refusals  # noqa: E402
from app.solve.pool import hand_the_lock_back_soon  # noqa: E402
from app.solve.process import warm_up  # noqa: E402

#: Static files are served under this URL prefix (``--static-dirs assets=static``).
ASSETS = "assets"
#: Scripts of the page: the JavaScript patches of BokehJS (``static/perf/``: repaint
#: shortcuts, no repaint of a stale preview after a slider's release; ``paint_shortcuts=off``
#: in the page's address turns them off), no history entry per change of the address,
#: a name and exact values on every slider's handle for screen readers, the help icons
#: by keyboard and a name on the checkbox and the menu's arrow (``static/a11y.js``), the
#: presentation mode's page classes (app.presentation), the report of the waiting
#: plots in view (``static/lazy_plots.js``, app.plots_host's lazy plots), and the controls
#: as a closed drawer on a phone (``static/drawer.js``).
JS_FILES = {"fie_paint": f"{ASSETS}/perf/bokeh_paint.js",
            "fie_release_hold": f"{ASSETS}/perf/release_hold.js",
            "fie_url_history": f"{ASSETS}/url_history.js",
            "fie_a11y": f"{ASSETS}/a11y.js",
            "fie_present": f"{ASSETS}/present.js",
            "fie_lazy_plots": f"{ASSETS}/lazy_plots.js",
            "fie_reconnect": f"{ASSETS}/reconnect.js",
            "fie_drawer": f"{ASSETS}/drawer.js"}
#: Page title.
TITLE = "Friction–Impact Explorer"
#: Bokeh's development checks, off on a served page (public settings, ``bokeh.settings``):
#: the integrity check of every new document (~25 ms of server CPU per page, and its only
#: findings are the hidden, still empty plot panes) and the signature check of each of the
#: ~430 callbacks Panel registers per page (~20 ms, an ``inspect.signature`` each; Bokeh
#: 3.9.2 and later: before, they always run). The environment decides where it sets them;
#: ``tests/app/test_main.py`` runs both checks on a whole page, so a defect they would find
#: still fails the tests.
DEVELOPMENT_CHECKS = {"BOKEH_VALIDATE_DOC": "false", "BOKEH_PERFORM_ERROR_DIAGNOSTICS": "false"}


def create_app() -> pn.template.BaseTemplate:
    """One session's page: the explorer's controls in the sidebar, plots in the main area."""
    # The patching scripts' addresses name the patches that apply (app.perf.page). Panel's
    # signatures of its classes serve an editor's completion, not a served page: ~1.7 ms
    # of every new page's server CPU.
    pn.extension(notifications=False, design=ExplorerDesign, js_files=page_scripts(JS_FILES),
                 apply_signatures=False)
    cache_immutable_defaults()  # before the page's models are built
    explorer = Explorer(lazy_plots=True)
    explorer.sync_url()
    template = pn.template.BootstrapTemplate(
        title=TITLE,
        # One root each: every extra root makes Bokeh re-walk the whole document.
        sidebar=[pn.Column(*explorer.sidebar(), sizing_mode="stretch_width", margin=0)],
        main=[explorer.main_panel()],
        sidebar_width=WIDGET_WIDTH + 40,
        favicon=f"{ASSETS}/favicon.svg",
        css_files=[f"{ASSETS}/explorer.css"],
        header_background="#1f3b5f",
        design=ExplorerDesign,  # Bootstrap with a focus ring on every control
        meta_viewport=VIEWPORT,  # a phone lays the page out at its own width
        # The spinner would restyle the page twice per slider release, each time forcing
        # every figure that repaints next to recompute its styles.
        busy_indicator=None,
    )
    template.explorer = explorer  # reachable from tests and the benchmark
    doc = pn.state.curdoc
    if doc is not None:
        # A closed page's measurement, sweeps and solves stop, freeing their solver
        # processes (the server discards a session its unused-session lifetime after its
        # last connection closed).
        doc.on_session_destroyed(lambda session_context: explorer.close())
    keep_long_lived_out_of_collections()
    send_without_delay_once_loaded()
    send_arrays_inline()
    load_each_bundle_once()
    attach_without_walks()
    return template


def serve(template: pn.template.BaseTemplate, doc: Document) -> None:
    """Attach ``template`` to the session's document ``doc`` in one pass.

    Attaching adds each of the template's roots and sets its theme, and after each of these
    Bokeh walked the whole document again (~930 models) to list its models; with the
    document's model list frozen (``Document.models.freeze``) while the public
    ``server_doc`` attaches it, it walks it once: a page costs ~15 % less server CPU
    (Panel's own walk of each root as it is added is patched away, ``fresh-roots`` of
    :mod:`app.perf.attach`).
    The page's location is the one its explorer read the address from
    (:func:`app.links.session_location`): Panel's own would parse the address again.
    """
    location = template.explorer.location
    with doc.models.freeze():
        template.server_doc(doc, title=TITLE,
                            location=location if location is not None else True)
    hand_reconnection_to_the_page(doc)


def hand_reconnection_to_the_page(doc: Document) -> None:
    """Leave a lost connection to ``static/reconnect.js`` alone (public ``Document.config``).

    BokehJS would otherwise try the websocket again itself (at once, then after 2, 4, 8
    and 16 s) and show a notice of its own beside the page's banner. A try that reaches a
    restarted server has it build a new session from the address the page was first opened
    with (a page's worth of server CPU per student, in a class's restart) and replaces the
    page's document with it, its values those of that first address, while reconnect.js's
    reload of the current address comes up to seconds later: a race that the page's own
    way back (its address holds its state) does not need."""
    doc.config.reconnect_session = False
    doc.config.notify_connection_status = False


def skip_development_checks() -> None:
    """Turn off Bokeh's development checks (:data:`DEVELOPMENT_CHECKS`) for this server
    process, except those the environment sets."""
    for name, value in DEVELOPMENT_CHECKS.items():
        os.environ.setdefault(name, value)


if pn.state.curdoc is not None and pn.state.curdoc.session_context is not None:  # served
    skip_development_checks()  # before Bokeh validates this session's document
    report()  # logs each perf patch left out (app.perf)
    quiet_refusals()  # a value of a type Bokeh refuses from the browser: one quiet line
    warm_up()  # the solver's child processes (once per server process)
    hand_the_lock_back_soon()  # the event loop waits less behind a solver thread
    serve(create_app(), pn.state.curdoc)
