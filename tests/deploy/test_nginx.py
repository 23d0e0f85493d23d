"""Two `panel serve` processes behind a real nginx with sticky sessions, on loopback.

scripts/serve-behind-nginx.sh, as an operator runs it: nginx (Debian's package; `make nginx`
installs it) with docs/nginx-example.conf itself, loopback ports put in for its `listen` and
`server` lines, in front of two scripts/serve.sh processes, each with --allow-websocket-origin
set to the proxy's host:port (the browser's Origin) and --use-xheaders. Checked through the
proxy:

- /liveness and /main answer;
- every session's websocket reaches the process that built it on GET /main. Were it to reach
  the other process, that process would build the session a second time (Bokeh creates any
  session a websocket names), so each process's own session list (Panel's
  /rest/session_info, asked directly) must hold exactly the sessions opened through it;
- new browsers are shared out evenly (the process with the fewest open connections), and a
  cookie that names no upstream counts as none;
- a websocket from a foreign Origin is refused behind the proxy too;
- in headless Chromium the page loads through the proxy and a slider move updates it.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from processes import TOKEN_RE, open_session, stop_group, wait_live

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE_CONF = ROOT / "docs" / "nginx-example.conf"
STARTUP_TIMEOUT = 180.0
COOKIE = "explorer_upstream"
#: Sessions opened through the proxy, one after another, each as a new browser (no cookie;
#: the page's cookie then goes with its websocket). Were a session's page and websocket sent
#: to upstreams independently (no stickiness), each session would show it with probability
#: 1/2, so 10 sessions miss it with probability 2**-10.
SESSIONS = 10
#: JavaScript: an element's text including its shadow roots (Panel renders panes in them).
JS_DEEP_TEXT = """el => {
  function t(n) {
    let s = n.shadowRoot ? t(n.shadowRoot) : "";
    for (const c of n.childNodes) {
      if (c.nodeType === 3) s += c.textContent;
      else if (c.nodeType === 1 && !["STYLE", "SCRIPT", "LINK"].includes(c.tagName)) s += t(c);
    }
    return s;
  }
  return t(el);
}"""
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str, headers: dict | None = None, timeout: float = 60.0):
    req = urllib.request.Request(url, headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=timeout) as resp:
            return resp.status, resp.headers, resp.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as exc:
        return exc.code, exc.headers, exc.read().decode("utf-8", "replace")


def _nginx() -> str:
    found = shutil.which("nginx") or ("/usr/sbin/nginx" if os.path.exists("/usr/sbin/nginx")
                                      else None)
    if found is None:
        pytest.fail("nginx is not installed: `make nginx` (apt-get install -y nginx-light)")
    return found


def _wait_live(url: str, proc: subprocess.Popen, log: Path) -> None:
    wait_live(url, proc, log, STARTUP_TIMEOUT)


@pytest.fixture(scope="module")
def deployment(tmp_path_factory):
    """(proxy base URL, [upstream base URLs], nginx access log): scripts/serve-behind-nginx.sh
    with two processes on free loopback ports."""
    nginx = _nginx()
    run_dir = tmp_path_factory.mktemp("nginx")
    proxy_port, upstream_ports = _free_port(), [_free_port(), _free_port()]
    env = dict(os.environ)
    env.update(
        NGINX=nginx, RUN_DIR=str(run_dir), PROXY_ADDRESS="127.0.0.1", PROXY_PORT=str(proxy_port),
        UPSTREAM_PORTS=" ".join(map(str, upstream_ports)), VENV=sys.prefix, WARM="0",
        # Sessions stay until the module ends, so the processes' session lists are complete.
        SESSION_LIFETIME_MS="600000",
    )
    log = run_dir / "serve-behind-nginx.log"
    with open(log, "w") as out:
        proc = subprocess.Popen(
            [str(ROOT / "scripts" / "serve-behind-nginx.sh"), "--rest-session-info",
             "--session-history", "100"],
            env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        for port in upstream_ports:
            _wait_live(f"http://127.0.0.1:{port}/liveness", proc, log)
        _wait_live(f"http://127.0.0.1:{proxy_port}/liveness", proc, log)
        yield (f"http://127.0.0.1:{proxy_port}",
               [f"http://127.0.0.1:{p}" for p in upstream_ports], run_dir / "access.log")
    finally:
        stop_group(proc)


def _sessions(upstream: str) -> dict:
    """Panel's record of the sessions one process built: id -> launched/rendered/..."""
    status, _, body = _get(f"{upstream}/rest/session_info")
    assert status == 200, body
    info = json.loads(body)
    return info.get("session_info", info)["sessions"]


def test_liveness_and_page_through_the_proxy(deployment):
    proxy, _, _ = deployment
    assert _get(f"{proxy}/liveness")[0] == 200
    status, headers, html = _get(f"{proxy}/main")
    assert status == 200
    assert "data-root-id" in html and TOKEN_RE.search(html)
    # A browser without the cookie is given one, which keeps it on its upstream.
    assert f"{COOKIE}=" in (headers.get("Set-Cookie") or "")


def test_each_websocket_reaches_the_process_that_built_its_session(deployment, run_async):
    proxy, upstreams, access_log = deployment
    before = {u: set(_sessions(u)) for u in upstreams}
    opened = [run_async(lambda: open_session(proxy)) for _ in range(SESSIONS)]
    built = {u: set(_sessions(u)) - before[u] for u in upstreams}
    # Every session was built once, in one process: a websocket on the wrong process would
    # have added the session to that process's list as well.
    assert sorted(opened) == sorted(s for u in upstreams for s in built[u])
    # Shared out evenly: each new browser went to the process with the fewest open
    # connections (here each closed its websocket before the next came: nginx takes the
    # upstreams in turn). One apart at most, or two where a connection of an earlier
    # request was still closing when a choice was made.
    counts = sorted(len(s) for s in built.values())
    assert counts[-1] - counts[0] <= 2, built
    # nginx's own record agrees: each websocket carried the cookie of the upstream it
    # reached, the one that answered its page.
    sockets = [line.split(" ") for line in access_log.read_text().splitlines()
               if line.startswith("/main/ws")]
    assert len(sockets) >= SESSIONS
    assert all(upstream == key for _, _, upstream, key in sockets), sockets


def test_a_cookie_naming_no_upstream_counts_as_none(deployment):
    """A cookie the proxy did not give (another deployment's, or forged to name any
    address) is not followed: the browser is sent as a new one and given a cookie that
    names one of the upstreams."""
    proxy, upstreams, _ = deployment
    status, headers, _ = _get(f"{proxy}/main", {"Cookie": f"{COOKIE}=192.0.2.1:80"})
    assert status == 200
    given = (headers.get("Set-Cookie") or "").split(";")[0]
    assert given in {f"{COOKIE}={u.removeprefix('http://')}" for u in upstreams}, given


def test_foreign_origin_is_refused_behind_the_proxy(deployment, run_async):
    from tornado.httpclient import HTTPClientError, HTTPRequest
    from tornado.websocket import websocket_connect

    proxy, _, _ = deployment
    token = TOKEN_RE.search(_get(f"{proxy}/main")[2]).group(1)

    async def connect():
        request = HTTPRequest(f"ws{proxy[4:]}/main/ws",
                              headers={"Origin": "http://elsewhere.example"})
        await websocket_connect(request, subprotocols=["bokeh", token])

    with pytest.raises(HTTPClientError) as err:
        run_async(connect)
    assert err.value.code == 403


@pytest.mark.ui
def test_slider_move_updates_the_page_through_the_proxy(deployment):
    from playwright.sync_api import sync_playwright

    proxy, upstreams, _ = deployment
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    before = {u: set(_sessions(u)) for u in upstreams}
    errors: list[str] = []
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1600, "height": 2000})
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(f"{proxy}/main", timeout=120_000)
            page.wait_for_function(
                "() => window.Bokeh && Bokeh.documents.length > 0"
                " && Bokeh.documents[0].is_idle === true", timeout=120_000)
            readout = page.locator(".fie-readout-pane").first
            old = readout.evaluate(JS_DEEP_TEXT)
            assert "v =" in old, old  # the readout is on the page, with the belt speed
            handle = page.locator(".fie-w-belt_speed .noUi-handle").first
            box = handle.bounding_box()
            x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
            page.mouse.move(x, y)
            page.mouse.down()
            page.mouse.move(x + 40, y, steps=8)
            page.mouse.up()
            # The server answers the release with a new solution and readout: only the
            # process holding this session's document can.
            deadline = time.monotonic() + 60
            while readout.evaluate(JS_DEEP_TEXT) == old:
                assert time.monotonic() < deadline, "the readout did not change after a move"
                page.wait_for_timeout(50)
        finally:
            browser.close()
    assert errors == []
    built = {u: set(_sessions(u)) - before[u] for u in upstreams}
    assert sum(len(s) for s in built.values()) == 1, built
    (session,) = set().union(*built.values())
    (owner,) = [u for u in upstreams if session in built[u]]
    # document_ready came over the websocket to the process that built the document.
    assert _sessions(owner)[session]["rendered"] is not None
