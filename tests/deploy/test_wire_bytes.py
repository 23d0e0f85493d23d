"""Bytes on the wire for a first and a repeat open of the page, measured in Chromium.

Before, a first open transferred 5.3 MB (MathJax, Bokeh's and Panel's bundles uncompressed,
Bootstrap's CSS twice). Served by scripts/serve.sh alone (gzip by Tornado,
app/serve_compressed.py) and through nginx with docs/nginx-example.conf (gzip by nginx,
long-lived caching of the versioned static files), a first open must stay within
:data:`FIRST_OPEN_LIMIT` and a repeat open (the browser's cache filled) within
:data:`REPEAT_OPEN_LIMIT`. The sizes are Chromium's own count of each response's bytes
received (CDP ``Network.loadingFinished``'s ``encodedDataLength``: headers and compressed
body).
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest
from processes import stop_group, wait_live

pytestmark = [pytest.mark.ui, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]
#: A first open on a classroom's Wi-Fi: at most this many bytes.
FIRST_OPEN_LIMIT = 1_500_000
#: A repeat open: the page itself and revalidations only.
REPEAT_OPEN_LIMIT = 200_000
STARTUP_TIMEOUT = 180.0
CHROMIUM = os.environ.get("CHROMIUM", shutil.which("chromium") or "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
JS_READY = """() => {
  const B = window.Bokeh;
  return !!B && B.documents.length > 0 && B.documents[0].is_idle === true;
}"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module", params=["direct", "nginx"])
def served(request, tmp_path_factory):
    """(kind, page URL, RUN_DIR, UPSTREAM_BASE_PORT) of scripts/serve.sh serving alone
    (one process) or through nginx (two)."""
    nginx = shutil.which("nginx") or Path("/usr/sbin/nginx").exists()
    if request.param == "nginx" and not nginx:
        pytest.fail("nginx is not installed: `make nginx`")
    run_dir = tmp_path_factory.mktemp(request.param)
    port, base_port = _free_port(), _free_port()
    while port in (base_port + 1, base_port + 2):  # nginx must not take a process's port
        base_port = _free_port()
    env = {k: v for k, v in os.environ.items() if k not in ("PROXY", "HTTP_GZIP")}
    env.update(VENV=sys.prefix, PORT=str(port), ADDRESS="127.0.0.1", WARM="0",
               RUN_DIR=str(run_dir), UPSTREAM_BASE_PORT=str(base_port))
    # Through nginx: the scale-out default, two processes (PROXY=auto picks nginx).
    env["NUM_PROCS"] = "2" if request.param == "nginx" else "1"
    log = run_dir / "serve.log"
    with open(log, "w") as out:
        proc = subprocess.Popen([str(ROOT / "scripts" / "serve.sh")], env=env, stdout=out,
                                stderr=subprocess.STDOUT, start_new_session=True)
    try:
        wait_live(f"http://127.0.0.1:{port}/liveness", proc, log, STARTUP_TIMEOUT)
        if request.param == "nginx":
            # nginx answers once one process does: wait for each (they start side by side).
            for upstream in (base_port + 1, base_port + 2):
                wait_live(f"http://127.0.0.1:{upstream}/liveness", proc, log, STARTUP_TIMEOUT)
        yield request.param, f"http://127.0.0.1:{port}/main", run_dir, base_port
    finally:
        stop_group(proc)


@pytest.mark.parametrize("served", ["nginx"], indirect=True)
def test_more_than_one_process_runs_behind_nginx_with_per_client_limits(served):
    _, _, run_dir, base_port = served
    for port in (base_port + 1, base_port + 2):  # one process per NUM_PROCS, each live
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=30) as r:
            assert r.status == 200
    conf = (run_dir / "nginx.conf").read_text()
    assert "limit_conn explorer_conn" in conf and "limit_req zone=explorer_pages" in conf


def _open(context, url: str) -> dict[str, int]:
    """Open ``url`` in a new page of ``context`` until the page is ready and the network
    idle; return {address: bytes received} of every request."""
    page = context.new_page()
    cdp = context.new_cdp_session(page)
    cdp.send("Network.enable")
    urls: dict[str, str] = {}
    sizes: dict[str, int] = {}
    cdp.on("Network.requestWillBeSent",
           lambda e: urls.__setitem__(e["requestId"], e["request"]["url"]))
    cdp.on("Network.loadingFinished",
           lambda e: sizes.__setitem__(e["requestId"], int(e["encodedDataLength"])))
    page.goto(url, wait_until="load", timeout=60_000)
    page.wait_for_function(JS_READY, timeout=60_000)
    page.wait_for_load_state("networkidle", timeout=60_000)
    page.close()
    return {urls.get(rid, rid): n for rid, n in sizes.items()}


def test_first_and_repeat_open_fit_a_classroom_wifi(served, capsys):
    from playwright.sync_api import sync_playwright

    _, url, _, _ = served
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            context = browser.new_context()
            first = _open(context, url)
            repeat = _open(context, url)
        finally:
            browser.close()
    with capsys.disabled():
        print(f"\n{url}: first open {sum(first.values())} B in {len(first)} requests, "
              f"repeat open {sum(repeat.values())} B")
    # Each bundle once: one address for Bootstrap's CSS, and no MathJax (the page has no TeX).
    assert len([u for u in first if "bootstrap.min.css" in u]) == 1
    assert not [u for u in first if "mathjax" in u]
    assert sum(first.values()) <= FIRST_OPEN_LIMIT, _largest(first)
    assert sum(repeat.values()) <= REPEAT_OPEN_LIMIT, _largest(repeat)


def _largest(sizes: dict[str, int]) -> list[tuple[str, int]]:
    return sorted(sizes.items(), key=lambda kv: -kv[1])[:5]
