"""Bokeh models and server CPU of a new session's default page, built in one process.

Each page is built and attached as the server does (``app.main.create_app`` then
``app.main.serve`` into a fresh ``Document``, Bokeh's development checks off as a served
page has them, ``app.main.skip_development_checks``); the CPU time of the process per page is
measured (``time.process_time``), the first page (imports, caches) is reported apart. The
document's serialisation, which the server does once more when the browser pulls the
page (``Document.to_json``), is timed apart (``to_json``), not in the page's CPU; so is the
page's HTML (``html``: Panel's ``server_html_page_for_session``, as the server answers the
browser's first request).

    PYTHONPATH=. python benchmarks/page_models.py [pages]
"""

from __future__ import annotations

import importlib
import statistics
import sys
import time
import types

from bokeh.document import Document
from panel.io.resources import Resources
from panel.io.server import server_html_page_for_session
from panel.io.state import set_curdoc


def build_page() -> Document:
    """Build one session's page; return its document."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        main.serve(main.create_app(), doc)
    return doc


def html_page(doc: Document) -> str:
    """The page's HTML, as the server writes it for the browser's first request."""
    session = types.SimpleNamespace(document=doc, token="token", id="session")
    with set_curdoc(doc):
        return server_html_page_for_session(
            session, Resources(mode="server", root_url="/"), title=doc.title,
            template=doc.template, template_variables=dict(doc._template_variables))


def main(pages: int = 20) -> None:
    t0 = time.process_time()
    # As the served app does before its first page (the environment may set them).
    importlib.import_module("app.main").skip_development_checks()
    models = len(build_page().models)
    first = time.process_time() - t0
    cpu, html, sent = [], [], []
    for _ in range(pages):
        t0 = time.process_time()
        doc = build_page()
        t1 = time.process_time()
        html_page(doc)
        t2 = time.process_time()
        doc.to_json()
        sent.append(time.process_time() - t2)
        html.append(t2 - t1)
        cpu.append(t1 - t0)
    cpu.sort()
    print("| pages | models | first page cpu [s] | cpu/open median [s] | p90 [s] | "
          "html median [s] | to_json median [s] |")
    print("|---|---|---|---|---|---|---|")
    print(f"| {pages} | {models} | {first:.3f} | {statistics.median(cpu):.3f} | "
          f"{cpu[int(0.9 * (len(cpu) - 1))]:.3f} | {statistics.median(html):.4f} | "
          f"{statistics.median(sent):.3f} |")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
