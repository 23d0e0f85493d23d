"""A page of the explorer in Chromium, and pixel helpers for the UI tests."""

from __future__ import annotations

import io
import time

import numpy as np

#: Milliseconds to wait for a page to be ready.
PAGE_TIMEOUT_MS = 60_000
#: Browser window size: wide enough for two columns of plots.
VIEWPORT = {"width": 1600, "height": 2000}
#: JavaScript: true once the document exists, its websocket is open and it is idle.
JS_READY = """() => {
  const B = window.Bokeh;
  if (!B || B.documents.length === 0) return false;
  return B.documents[0].is_idle === true;
}"""
#: JavaScript: the text of an element including its shadow roots (Panel renders panes in
#: shadow DOMs, which ``innerText`` does not enter), without style sheets.
JS_DEEP_TEXT = """el => {
  const skip = ["STYLE", "SCRIPT", "LINK"];
  function t(n) {
    let s = n.shadowRoot ? t(n.shadowRoot) : "";
    for (const c of n.childNodes) {
      if (c.nodeType === 3) s += c.textContent;
      else if (c.nodeType === 1 && !skip.includes(c.tagName)) s += t(c) + " ";
    }
    return s;
  }
  return t(el).replace(/\\s+/g, " ").trim();
}"""
#: JavaScript: the number of plots that wait to be built (lazy plots, app.explorer) within
#: ``margin`` pixels of the window, or in the whole page with no margin given.
JS_WAITING = """margin => {
  let n = 0;
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (!el.classList.contains("fie-plot-pending")) continue;
      const r = el.getBoundingClientRect();
      if (r.width > 0 && (margin == null ||
          (r.top < window.innerHeight + margin && r.bottom > -margin))) n += 1;
    }
  }
  walk(document);
  return n;
}"""


class Page:
    """A page of the explorer with its console messages collected."""

    def __init__(self, browser, url: str, wait_plots: bool = True,
                 viewport: dict[str, int] | None = None) -> None:
        self.page = browser.new_page(viewport=viewport or VIEWPORT)
        self.errors: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda exc: self.errors.append(f"pageerror: {exc}"))
        self.page.goto(url, timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        if wait_plots:
            self.wait_plots()
        self.settle()

    def wait_plots(self, everywhere: bool = False) -> None:
        """Wait until no plot in view (within the page's 400 px margin) waits to be built;
        with ``everywhere``, scroll each waiting plot of the page into view first."""
        deadline = time.monotonic() + PAGE_TIMEOUT_MS / 1000
        while time.monotonic() < deadline:
            if everywhere and self.page.evaluate(JS_WAITING, None):
                self.page.locator(".fie-plot-pending").first.scroll_into_view_if_needed()
            elif not self.page.evaluate(JS_WAITING, 400):
                self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
                return
            self.page.wait_for_timeout(50)
        raise AssertionError("plots still wait to be built")

    def _console(self, msg) -> None:
        if msg.type == "error":
            self.errors.append(msg.text)

    def settle(self) -> None:
        """Let BokehJS paint what arrived (two animation frames)."""
        self.page.evaluate("() => new Promise(r => requestAnimationFrame(() => "
                           "requestAnimationFrame(r)))")

    def text(self, css: str) -> str:
        """Visible text of the first element matching ``css``, shadow DOM included."""
        return self.page.locator(css).first.evaluate(JS_DEEP_TEXT)

    def wait_text_change(self, css: str, old: str, timeout: float = 30_000) -> str:
        """Wait until the element's text differs from ``old`` (the server answered)."""
        deadline = time.monotonic() + timeout / 1000
        while time.monotonic() < deadline:
            new = self.text(css)
            if new != old:
                self.settle()
                return new
            self.page.wait_for_timeout(25)
        raise AssertionError(f"{css} did not change")

    def pixels(self, css: str) -> np.ndarray:
        """RGB pixels of the first element matching ``css`` (its screenshot)."""
        from PIL import Image

        png = self.page.locator(css).first.screenshot()
        return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)

    def drag_slider(self, name: str, dx: float, steps: int = 8) -> None:
        """Drag the handle of slider ``name`` (its ``fie-w-<name>`` widget) by ``dx``
        pixels with the mouse, in ``steps`` moves, and release it."""
        handle = self.page.locator(f".fie-w-{name} .noUi-handle").first
        box = handle.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        self.page.mouse.move(x, y)
        self.page.mouse.down()
        self.page.mouse.move(x + dx, y, steps=steps)
        self.page.mouse.up()

    def close(self) -> None:
        self.page.close()


def count_color(rgb: np.ndarray, hex_color: str, tol: int = 40) -> int:
    """Pixels within ``tol`` (per channel) of ``hex_color``."""
    target = np.array([int(hex_color[i:i + 2], 16) for i in (1, 3, 5)])
    return int(np.all(np.abs(rgb - target) <= tol, axis=-1).sum())


