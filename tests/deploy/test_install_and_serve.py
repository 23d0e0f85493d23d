"""The Docker image's install and start steps, run without Docker.

The Dockerfile runs scripts/install.sh and scripts/serve.sh. Here the same scripts install the
project into a fresh virtual environment and start `panel serve` from it on a free loopback
port; then the liveness endpoint (the image's HEALTHCHECK) and the /main page are checked, and,
where Chromium is installed, the page is rendered in headless Chromium.

pip's cache is used, so after the first run the install takes well under a minute.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from processes import stop_group, wait_live

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
# The real app; DEPLOY_TEST_APP_PATH may point elsewhere while developing the scripts.
APP_PATH = os.environ.get("DEPLOY_TEST_APP_PATH", str(ROOT / "app" / "main.py"))
STARTUP_TIMEOUT = 120.0
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str, timeout: float = 10.0) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url, timeout=timeout) as resp:
            return resp.status, resp.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as exc:
        return exc.code, exc.read().decode("utf-8", "replace")


def _chromium() -> str | None:
    for candidate in ("/usr/bin/chromium", shutil.which("chromium")):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    return None


@pytest.fixture(scope="module")
def fresh_venv(tmp_path_factory) -> Path:
    venv = tmp_path_factory.mktemp("deploy") / "venv"
    env = {k: v for k, v in os.environ.items() if k not in ("VENV", "EXTRAS", "VIRTUAL_ENV")}
    env["PYTHON"] = sys.executable
    proc = subprocess.run(
        [str(ROOT / "scripts" / "install.sh"), str(venv)],
        cwd=tmp_path_factory.getbasetemp(),  # the script must not depend on the caller's cwd
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert proc.returncode == 0, f"install.sh failed:\n{proc.stdout}\n{proc.stderr}"
    assert (venv / "bin" / "panel").exists()
    # The project itself is installed (found from any directory), not only its dependencies.
    code = "import importlib.util as u, panel; assert u.find_spec('core') and u.find_spec('app')"
    check = subprocess.run(
        [str(venv / "bin" / "python"), "-c", code],
        cwd=tmp_path_factory.getbasetemp(),
        capture_output=True,
        text=True,
    )
    assert check.returncode == 0, check.stderr
    return venv


@pytest.fixture(scope="module")
def server(fresh_venv, tmp_path_factory):
    assert Path(APP_PATH).is_file(), f"no app at {APP_PATH}"
    port = _free_port()
    log_path = tmp_path_factory.getbasetemp() / "serve.log"
    env = dict(os.environ)
    env.update(
        VENV=str(fresh_venv),
        APP_PATH=APP_PATH,
        PORT=str(port),
        ADDRESS="127.0.0.1",
        NUM_PROCS="1",
        SESSION_LIFETIME_MS="5000",
        CHECK_UNUSED_MS="2000",
    )
    with open(log_path, "w") as log:
        proc = subprocess.Popen(
            [str(ROOT / "scripts" / "serve.sh")],
            cwd=tmp_path_factory.getbasetemp(),
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
    base = f"http://127.0.0.1:{port}"
    try:
        wait_live(f"{base}/liveness", proc, log_path, STARTUP_TIMEOUT)
        yield base, log_path
    finally:
        stop_group(proc)


def test_serve_runs_the_panel_from_the_fresh_venv(server, fresh_venv):
    _, log_path = server
    log = log_path.read_text()
    # `panel serve` with gzip (app/serve_compressed.py), by the fresh venv's Python.
    assert f"{fresh_venv}/bin/python -m app.serve_compressed (panel serve, gzip)" in log
    for flag in ("--num-procs", "--check-unused-sessions", "--unused-session-lifetime",
                 "--allow-websocket-origin", "--liveness", "--warm"):
        assert flag in log


def test_liveness(server):
    base, _ = server
    status, body = _get(f"{base}/liveness")
    assert status == 200
    assert "true" in body
    # With ?endpoint= Panel builds the app's document once: the app itself runs.
    status, body = _get(f"{base}/liveness?endpoint=/main")
    assert status == 200, body


def test_main_page_has_bokeh_content(server):
    base, _ = server
    status, html = _get(f"{base}/main")
    assert status == 200
    assert "bokeh" in html.lower() and ".js" in html
    assert "embed_items" in html or "embed_document" in html
    assert "data-root-id" in html


@pytest.mark.ui
def test_page_renders_in_headless_chromium(server, tmp_path):
    executable = _chromium()
    if executable is None:
        pytest.skip("chromium is not installed")
    sync_api = pytest.importorskip("playwright.sync_api")
    base, log_path = server
    errors: list[str] = []
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(f"{base}/main", wait_until="load", timeout=60_000)
            page.wait_for_function(
                "() => window.Bokeh !== undefined && Bokeh.documents.length > 0"
                " && Bokeh.documents[0].roots().length > 0",
                timeout=60_000,
            )
            # Bokeh's canvas (plots) and widgets are drawn inside shadow roots, which
            # Playwright's CSS locators pierce.
            page.locator("canvas").first.wait_for(state="attached", timeout=60_000)
            page.wait_for_timeout(1000)  # let late errors surface
            page.screenshot(path=str(tmp_path / "main.png"))
        finally:
            browser.close()
    assert not errors, f"console errors: {errors}\nserver log:\n{log_path.read_text()}"
