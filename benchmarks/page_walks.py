"""Server CPU of a new page with and without the patches of Panel's walks (app.perf.attach).

Pages are built in one process, alternately with the patches and with Panel's own
``add_to_doc`` and ``patch_model_css`` (the pairs share the machine's state); for each, the
CPU of building and attaching the page (``build``, as ``benchmarks/page_models.py``) and of
its HTML (``html``) is measured with ``time.process_time``.

    PYTHONPATH=. python benchmarks/page_walks.py [pairs]
"""

from __future__ import annotations

import importlib
import statistics
import sys
import time

import panel.io.server as panel_server
import panel.template.base as template_base
from page_models import build_page, html_page

from app.perf import attach


def one_page(patched: bool) -> tuple[float, float]:
    """(build, html) CPU seconds of one page."""
    main = importlib.import_module("app.main")
    install = main.attach_without_walks
    if not patched:  # Panel's own functions, for this page only
        main.attach_without_walks = lambda: None
        template_base.add_to_doc = attach.PANEL_ADD_TO_DOC
        panel_server.patch_model_css = attach.PANEL_PATCH_MODEL_CSS
    try:
        t0 = time.process_time()
        doc = build_page()
        t1 = time.process_time()
        html_page(doc)
        t2 = time.process_time()
    finally:
        main.attach_without_walks = install
        install()
    return t1 - t0, t2 - t1


def main(pairs: int = 25) -> None:
    importlib.import_module("app.main").skip_development_checks()
    build_page()  # imports, caches; installs the patches
    if attach.PANEL_ADD_TO_DOC is None or attach.PANEL_PATCH_MODEL_CSS is None:
        sys.exit("the patches do not apply here (EXPLORER_PERF_PATCHES, versions)")
    for _ in range(3):
        one_page(True), one_page(False)
    runs: dict[bool, list[tuple[float, float]]] = {True: [], False: []}
    for _ in range(pairs):
        for patched in (True, False):
            runs[patched].append(one_page(patched))
    print("| walks | pages | build median [ms] | html median [ms] | build + html [ms] |")
    print("|---|---|---|---|---|")
    total = {}
    for patched, label in ((False, "Panel's"), (True, "patched")):
        build = statistics.median(b for b, _ in runs[patched])
        html = statistics.median(h for _, h in runs[patched])
        total[patched] = build + html
        print(f"| {label} | {pairs} | {1e3 * build:.1f} | {1e3 * html:.1f} | "
              f"{1e3 * (build + html):.1f} |")
    print(f"\npatched / Panel's (build + html): {total[True] / total[False]:.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 25)
