"""Screenshots of the page at the sizes of a lecture room, to be looked at.

Serves the explorer with ``panel serve`` (or uses ``--url``), opens each scene in Debian's
Chromium at 1280x800, 1920x1080 and 800 px wide (800x1000), waits until the page is idle
and writes a PNG of the window and one of the whole page per scene and size into the output folder
(outside the repository: the pictures are for looking, not for keeping).

Usage: ``.venv/bin/python benchmarks/screenshots.py [OUT] [--port N] [--url URL]
[--scenes 4b,5a:tend=5000,7c,10]``; OUT defaults to ``/tmp/fie-screenshots``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = os.environ.get("CHROMIUM", shutil.which("chromium") or "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
#: Window sizes (width, height) [px]: a projector, a wide screen, a narrow window.
SIZES = ((1280, 800), (1920, 1080), (800, 1000))
#: Scenes, with extra permalink parameters after a colon (``&``-separated).
SCENES = ("4b", "5a:tend=5000", "7c", "10")
#: Seconds to wait for the server and for a page.
TIMEOUT_S = 60.0
#: Extra wait [ms] after the page is idle (the regime map follows the rest).
SETTLE_MS = 1500
#: JavaScript: the height [px] a window needs to show the whole page without scrolling.
JS_CONTENT_HEIGHT = """() => {
  const parts = ["#sidebar", "#main"].map(s => document.querySelector(s)).filter(Boolean);
  const top = Math.max(0, ...parts.map(e => e.getBoundingClientRect().top));
  return Math.ceil(top + Math.max(0, ...parts.map(e => e.scrollHeight)) + 16);
}"""


#: JavaScript: true when no plot waits to be built (app.explorer's lazy plots).
JS_NONE_WAITING = """() => {
  function waiting(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.classList.contains("fie-plot-pending")) return true;
      if (el.shadowRoot && waiting(el.shadowRoot)) return true;
    }
    return false;
  }
  return !waiting(document);
}"""


def serve(port: int) -> subprocess.Popen:
    """``panel serve`` of the explorer on loopback ``port``, once it answers."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port),
         "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}",
         "--static-dirs", "assets=static", "--liveness"],
        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + TIMEOUT_S
    while time.monotonic() < deadline:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2):
                return proc
        except OSError:
            if proc.poll() is not None:
                break
            time.sleep(0.2)
    proc.kill()
    raise RuntimeError("panel serve did not start")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def shoot(url: str, out: Path, scenes: list[str]) -> list[Path]:
    """Viewport and full-page screenshots of ``scenes`` at every size into ``out``."""
    from playwright.sync_api import sync_playwright

    written = []
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for width, height in SIZES:
            page = browser.new_page(viewport={"width": width, "height": height})
            for spec in scenes:
                scene, _, extra = spec.partition(":")
                page.goto(f"{url}?scene={scene}{'&' + extra if extra else ''}",
                          timeout=TIMEOUT_S * 1000)
                page.wait_for_function(
                    "() => window.Bokeh && Bokeh.documents.length > 0 && "
                    "Bokeh.documents[0].is_idle", timeout=TIMEOUT_S * 1000)
                page.wait_for_timeout(SETTLE_MS)
                name = f"{scene}{'-' + extra.replace('=', '') if extra else ''}_{width}x{height}"
                page.screenshot(path=out / f"{name}.png")
                # The template scrolls its sidebar and main area inside the window: the
                # whole page is drawn by a window as tall as their content.
                tall = page.evaluate(JS_CONTENT_HEIGHT)
                page.set_viewport_size({"width": width, "height": max(height, tall)})
                # Every plot is in view now: those that waited (lazy plots) are built.
                page.wait_for_function(JS_NONE_WAITING, timeout=TIMEOUT_S * 1000)
                page.wait_for_timeout(SETTLE_MS)
                page.screenshot(path=out / f"{name}_full.png")
                page.set_viewport_size({"width": width, "height": height})
                written += [out / f"{name}.png", out / f"{name}_full.png"]
            page.close()
        browser.close()
    return written


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="/tmp/fie-screenshots", type=Path)
    parser.add_argument("--port", type=int, default=0, help="port to serve on (default: free)")
    parser.add_argument("--url", help="an explorer already served (its /main address)")
    parser.add_argument("--scenes", default=",".join(SCENES))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    proc = None
    url = args.url
    if url is None:
        port = args.port or free_port()
        proc = serve(port)
        url = f"http://127.0.0.1:{port}/main"
    try:
        for path in shoot(url, args.out, args.scenes.split(",")):
            print(path)
    finally:
        if proc is not None:
            proc.terminate()
            proc.wait(timeout=10)


if __name__ == "__main__":
    main()
