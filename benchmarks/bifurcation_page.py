"""Click on "Bifurcation diagram" -> the diagram of 1,000 belt speeds drawn, in real Chromium.

Serves the explorer with ``panel serve`` on a free loopback port, opens scene 5a in a new
page several times, clicks the sweep button and measures (from the harness) the time until
the card's status says that all 1,000 values are drawn and BokehJS is idle. Prints, per
repeat, the whole time, the time until the card appeared (built on the server, sent and
laid out: the first use of the card) and the sweep's own time on the server (from its
status line), then the median against the target of 2 s, and the machine's load.

Usage: ``PYTHONPATH=. .venv/bin/python benchmarks/bifurcation_page.py [--repeats N]``
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import shutil
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "ui"), str(ROOT / "benchmarks")]

from browser_latency import serve_explorer  # noqa: E402
from uipage import Page  # noqa: E402

CHROMIUM = os.environ.get("CHROMIUM", shutil.which("chromium") or "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
#: Target [s]: click to drawn diagram of 1,000 belt speeds (scene 5a).
TARGET_S = 2.0
#: How often [s] the harness reads the card's status.
POLL_S = 0.02


def measure(browser, url: str) -> tuple[float, float, float]:
    """(whole, card appeared, server sweep) seconds of one click on a new page."""
    p = Page(browser, url + "?scene=5a")
    try:
        start = time.perf_counter()
        p.page.locator(".fie-open-sweeps button").first.click()
        card = None
        while True:
            if p.page.locator(".fie-bif-status").count():
                card = card or time.perf_counter() - start
                status = p.text(".fie-bif-status")
                if "1000 of 1000" in status:
                    break
            time.sleep(POLL_S)
        p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
        whole = time.perf_counter() - start
        sweep_s = float(re.search(r"in ([0-9.]+) s", status).group(1))
        return whole, card, sweep_s
    finally:
        p.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    import bokeh
    import panel
    from playwright.sync_api import sync_playwright

    proc, url = serve_explorer()
    rows = []
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            for _ in range(args.repeats):
                rows.append(measure(browser, url))
            browser.close()
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    print(f"python {platform.python_version()}, panel {panel.__version__}, bokeh "
          f"{bokeh.__version__}, {platform.machine()}, {os.cpu_count()} cores, load average "
          f"{os.getloadavg()[0]:.1f}")
    print(f"{'repeat':>6} {'click->drawn s':>15} {'card shown s':>13} {'sweep s':>8}")
    for i, (whole, card, sweep_s) in enumerate(rows):
        print(f"{i:>6} {whole:>15.2f} {card:>13.2f} {sweep_s:>8.2f}")
    med = float(np.median([r[0] for r in rows]))
    print(f"median click->drawn: {med:.2f} s (target {TARGET_S:g} s: "
          f"{'met' if med <= TARGET_S else 'NOT met'})")


if __name__ == "__main__":
    main()
