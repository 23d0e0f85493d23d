"""A page of the explorer in Chromium, and pixel helpers for the UI tests."""

from __future__ import annotations

import io
import time

import numpy as np
from playwright.sync_api import TimeoutError as PlaywrightTimeout

#: The readout's notes while its rows are not the sliders' run (app.readout.pending_text).
PENDING_NOTES = ("Preview of ", "Not shown yet: ")
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


#: JavaScript: the first element matching ``css`` under ``root``, shadow roots included (as
#: Playwright's CSS locators pierce them; here a selector matches within one root only).
JS_DEEP_QUERY = """(root, css) => {
  function find(node) {
    const el = node.querySelector(css);
    if (el) return el;
    for (const host of node.querySelectorAll("*")) {
      if (host.shadowRoot) {
        const inner = find(host.shadowRoot);
        if (inner) return inner;
      }
    }
    return null;
  }
  return find(root);
}"""
#: JavaScript: resolves once the document is idle and neither any range of the figures
#: (BokehJS fits data ranges in a paint) nor the box of any plot or of the readout has
#: changed for ``frames`` animation frames in a row; false if that has not happened within
#: ``ms`` milliseconds.
JS_STILL = """({frames, ms}) => new Promise(resolve => {
  const doc = Bokeh.documents[0];
  const end = performance.now() + ms;
  function boxes(node, out) {
    for (const el of node.querySelectorAll("*")) {
      if (el.shadowRoot) boxes(el.shadowRoot, out);
      if (el.classList.contains("fie-plot") || el.classList.contains("fie-readout-pane")) {
        const r = el.getBoundingClientRect();
        out.push(`${r.x},${r.y},${r.width},${r.height}`);
      }
    }
    return out;
  }
  function key() {
    const ranges = [...doc.all_models]
      .filter(m => m.type === "Range1d" || m.type === "DataRange1d")
      .map(r => `${r.start},${r.end}`);
    return ranges.concat(boxes(document, [])).join(";");
  }
  let last = null, still = 0;
  (function tick() {
    const now = doc.is_idle ? key() : null;
    still = now !== null && now === last ? still + 1 : 0;
    last = now;
    if (still >= frames) resolve(true);
    else if (performance.now() > end) resolve(false);
    else requestAnimationFrame(tick);
  })();
})"""
#: Animation frames without a change that :meth:`Page.still` waits for.
STILL_FRAMES = 3


#: Exceptions in a server's log that are no fault of the app: a page closed while the
#: server wrote to it.
CLOSED_PAGE = ("WebSocketClosedError", "StreamClosedError")


def server_faults(log: str) -> list[str]:
    """The exception line of each traceback in ``log`` (a server's output), but for a
    closed page's."""
    lines = log.splitlines()
    faults = []
    for i, line in enumerate(lines):
        if not line.startswith("Traceback (most recent call last):"):
            continue
        # The exception line: the first after the frames (which are indented).
        end = next((after for after in lines[i + 1:] if after and not after[0].isspace()), "")
        if end.split(":")[0].rsplit(".", 1)[-1] not in CLOSED_PAGE:
            faults.append(end)
    return faults


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
        while everywhere and (waiting := self.page.evaluate(JS_WAITING, None)):
            self.page.locator(".fie-plot-pending").first.scroll_into_view_if_needed()
            # The one scrolled into view is built (it loses its class).
            self.page.wait_for_function(f"n => ({JS_WAITING})(null) < n", arg=waiting,
                                        timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(f"() => ({JS_WAITING})(400) === 0",
                                    timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)

    def _console(self, msg) -> None:
        if msg.type == "error":
            self.errors.append(msg.text)

    def settle(self) -> None:
        """Let BokehJS paint what arrived (two animation frames)."""
        self.page.evaluate("() => new Promise(r => requestAnimationFrame(() => "
                           "requestAnimationFrame(r)))")

    def still(self, frames: int = STILL_FRAMES) -> None:
        """Wait until the page is idle and its figures' ranges and plots' boxes have stopped
        changing (a data range is fitted in a paint, a layout settles as plots fill)."""
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        assert self.page.evaluate(JS_STILL, {"frames": frames, "ms": PAGE_TIMEOUT_MS}), (
            "the figures' ranges or the plots' boxes kept changing")

    def text(self, css: str) -> str:
        """Visible text of the first element matching ``css``, shadow DOM included."""
        return self.page.locator(css).first.evaluate(JS_DEEP_TEXT)

    def wait_text_change(self, css: str, old: str, timeout: float = 30_000) -> str:
        """Wait until the element's text differs from ``old`` and holds no note of a run
        still to come (the readout's note of a drag or of a release being solved,
        :func:`app.readout.pending_text`): the server answered with its run."""
        self.wait_text(css, lambda text: text != old and not any(
            note in text for note in PENDING_NOTES), f"{css} did not change", timeout)
        self.settle()
        return self.text(css)

    def wait_text(self, css: str, test, what: str, timeout: float = 30_000) -> str:
        """Wait until ``test(text)`` holds for the deep text of the first element matching
        ``css`` (checked each time the page's DOM changes, and every 100 ms); returns the
        text. ``what`` is the message of the failure."""
        deadline = time.monotonic() + timeout / 1000
        js = (f"([css, old]) => {{ const el = ({JS_DEEP_QUERY})(document, css); "
              f"return el === null ? old : ({JS_DEEP_TEXT})(el); }}")
        text = self.text(css)
        while not test(text):
            left = deadline - time.monotonic()
            if left <= 0:
                raise AssertionError(f"{what}: {text!r}")
            # The browser waits for any other text; Python decides whether it passes.
            try:
                self.page.wait_for_function(f"args => ({js})(args) !== args[1]",
                                            arg=[css, text], polling=100,
                                            timeout=left * 1000)
            except PlaywrightTimeout:
                raise AssertionError(f"{what}: {text!r}") from None
            text = self.text(css)
        return text

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


