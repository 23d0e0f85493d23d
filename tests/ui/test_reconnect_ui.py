"""A page whose server restarts says so and comes back by itself, in the state it showed
(static/reconnect.js).

Before, the page of a restarted server looked normal but its sliders did nothing, with no
notice. Here the server of an open page is killed (SIGKILL, as a crash or a container's
restart leaves it) and started again on the same port: the banner must appear while it is
down, and the page must reload by itself into the same address, with the slider moved
before the restart where it was and the reset button returning to the figure loaded before.
The same for a network drop of a few seconds (the page's connections cut by a forwarder
while the server stays up; Chromium's offline mode leaves an open websocket alone, so it
cannot stand in for one).
"""

from __future__ import annotations

import contextlib
import socket
import threading
from urllib.parse import parse_qs, urlsplit

import pytest
from conftest import ROOT, SCREENSHOT_DIR, free_port, panel_server
from uipage import JS_READY, PAGE_TIMEOUT_MS, Page

pytestmark = pytest.mark.ui

QUERY = "?scene=7c&r=0.3"
BANNER = "#fie-connection"
LOST_TEXT = "Connection to the server lost"
#: JavaScript: a mark on the page's window, gone once the page has reloaded.
JS_MARK = "() => { window.fieBeforeRestart = true; }"
JS_MARKED = "() => window.fieBeforeRestart === true"


def _query(url: str) -> dict[str, list[str]]:
    return parse_qs(urlsplit(url).query)


def test_restart_shows_banner_and_page_comes_back_in_its_state(browser, shots):
    port = free_port()
    log = SCREENSHOT_DIR.parent / "reconnect-serve.log"
    app = ROOT / "app" / "main.py"
    with panel_server(app, port, log) as first:
        p = Page(browser, f"http://127.0.0.1:{port}/main{QUERY}", wait_plots=False)
        try:
            banner = p.page.locator(BANNER)
            assert banner.count() == 1 and not banner.is_visible()  # the live region, idle
            url0 = p.page.url
            p.drag_slider("clearance", 30)
            # The address follows the slider.
            p.page.wait_for_function(
                "old => new URLSearchParams(location.search).get('xbar') !== old",
                arg=(_query(url0).get("xbar") or [None])[0], timeout=30_000)
            p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
            moved_url = p.page.url
            moved_widget = p.text(".fie-w-clearance")
            assert _query(moved_url)["r"] == ["0.3"]  # the link's own value is kept
            assert "Reset to Fig. 7c" in p.text(".fie-reset")  # a custom run from 7c
            p.page.evaluate(JS_MARK)

            first.kill()
            first.wait()
            banner.wait_for(state="visible", timeout=15_000)
            assert LOST_TEXT in banner.inner_text()
            assert banner.get_attribute("aria-live") == "assertive"
            p.page.set_viewport_size({"width": 1280, "height": 800})
            p.page.screenshot(path=shots / "connection-lost.png")
            assert p.page.evaluate(JS_MARKED)  # still the same page while the server is down
        except BaseException:
            p.close()
            raise
    try:
        with panel_server(app, port, log.with_name("reconnect-serve-2.log")):
            p.page.wait_for_function(f"() => !({JS_MARKED.removeprefix('() => ')})",
                                     timeout=PAGE_TIMEOUT_MS)
            p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
            p.settle()
            assert _query(p.page.url) == _query(moved_url)
            assert p.text(".fie-w-clearance") == moved_widget
            # The address says which figure the custom run came from (it said the default).
            assert "Reset to Fig. 7c" in p.text(".fie-reset")
            assert not p.page.locator(BANNER).is_visible()
    finally:
        p.close()


class Link:
    """A TCP forwarder from a loopback port to the server's, whose connections can be cut:
    the page's network drops while the server stays up."""

    def __init__(self, target: int) -> None:
        self.target = target
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.down = threading.Event()
        self.open: set[socket.socket] = set()
        self.lock = threading.Lock()
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while True:
            try:
                client, _ = self.listener.accept()
            except OSError:
                return  # closed
            if self.down.is_set():
                client.close()  # no network: refused at once
                continue
            server = socket.create_connection(("127.0.0.1", self.target))
            with self.lock:
                self.open |= {client, server}
            for a, b in ((client, server), (server, client)):
                threading.Thread(target=self._pump, args=(a, b), daemon=True).start()

    def _pump(self, src: socket.socket, dst: socket.socket) -> None:
        try:
            while data := src.recv(65536):
                dst.sendall(data)
        except OSError:
            pass
        for s in (src, dst):
            with contextlib.suppress(OSError):
                s.shutdown(socket.SHUT_RDWR)

    def cut(self) -> None:
        """Drop every connection and refuse new ones."""
        self.down.set()
        with self.lock:
            for s in self.open:
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)
            self.open.clear()

    def restore(self) -> None:
        self.down.clear()

    def close(self) -> None:
        self.cut()
        self.listener.close()


def test_a_network_drop_of_a_few_seconds_shows_the_banner_and_keeps_the_state(browser):
    port = free_port()
    with contextlib.ExitStack() as stack:
        link = Link(port)
        stack.callback(link.close)
        # The browser's origin is the forwarder's address.
        stack.enter_context(panel_server(
            ROOT / "app" / "main.py", port, SCREENSHOT_DIR.parent / "reconnect-blip.log",
            env={"BOKEH_ALLOW_WS_ORIGIN": f"127.0.0.1:{link.port}"}))
        p = Page(browser, f"http://127.0.0.1:{link.port}/main{QUERY}", wait_plots=False)
        stack.callback(p.close)
        url = p.page.url
        p.page.evaluate(JS_MARK)
        link.cut()
        p.page.locator(BANNER).wait_for(state="visible", timeout=15_000)
        # A few seconds without network: the page's polls of the server fail meanwhile
        # (0.5, 1, 2 s apart: two failures are over a second of it).
        for _ in range(2):
            p.page.wait_for_event("requestfailed", timeout=15_000,
                                  predicate=lambda r: r.url.endswith("/liveness"))
        assert p.page.evaluate(JS_MARKED)
        link.restore()
        p.page.wait_for_function(f"() => !({JS_MARKED.removeprefix('() => ')})",
                                 timeout=PAGE_TIMEOUT_MS)
        p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        assert _query(p.page.url) == _query(url)
        assert not p.page.locator(BANNER).is_visible()
