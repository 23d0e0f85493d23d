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


class Page:
    """A page of the explorer with its console messages collected."""

    def __init__(self, browser, url: str) -> None:
        self.page = browser.new_page(viewport=VIEWPORT)
        self.errors: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda exc: self.errors.append(f"pageerror: {exc}"))
        self.page.goto(url, timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        self.settle()

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


