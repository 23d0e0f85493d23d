"""Serve the explorer and drive it in Debian's Chromium (Playwright, no downloaded browser).

A session-scoped fixture starts ``panel serve app/main.py`` on a free loopback port and waits
for its liveness endpoint; pages wait for the websocket and for BokehJS to be idle. Screens
go to ``artifacts/screenshots`` (or ``$SCREENSHOT_DIR``), printed at the end of the run.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator, Mapping
from pathlib import Path

import pytest
from uipage import server_faults

ROOT = Path(__file__).resolve().parents[2]
#: Debian's Chromium (never a browser downloaded by Playwright).
CHROMIUM = os.environ.get("CHROMIUM", shutil.which("chromium") or "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
#: Where the screenshots go.
SCREENSHOT_DIR = Path(os.environ.get("SCREENSHOT_DIR", ROOT / "artifacts" / "screenshots"))
#: Seconds to wait for the server to come up and for a page to be ready.
SERVER_TIMEOUT = 60.0
#: The shared server's log.
SERVER_LOG = SCREENSHOT_DIR.parent / "panel-serve.log"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def panel_server(app_path: str | Path, port: int, log: Path,
                 env: Mapping[str, str] | None = None) -> Iterator[subprocess.Popen]:
    """Serve ``app_path`` with ``panel serve`` on loopback ``port`` (output to ``log``),
    with ``env`` added to the environment; yields the process once its liveness endpoint
    answers, and stops it on exit."""
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "w") as out:
        proc = subprocess.Popen(
            [sys.executable, "-m", "panel", "serve", str(app_path), "--port", str(port),
             "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}",
             "--static-dirs", f"assets={ROOT / 'static'}", "--liveness"],
            cwd=ROOT, stdout=out, stderr=subprocess.STDOUT,
            env={**os.environ, **(env or {})},
        )
    try:
        deadline = time.monotonic() + SERVER_TIMEOUT
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2):
                    break
            except OSError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(f"panel serve did not start; see {log}") from None
                time.sleep(0.2)
        yield proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@pytest.fixture(scope="session")
def server() -> Iterator[str]:
    """URL of the app served by a `panel serve` subprocess on loopback."""
    port = free_port()
    with panel_server("app/main.py", port, SERVER_LOG):
        yield f"http://127.0.0.1:{port}/main"


@pytest.fixture(autouse=True)
def no_server_faults(request) -> Iterator[None]:
    """A test of the shared server fails where the server logged an exception meanwhile (a
    handler that raised leaves the page as it was, and the browser may say nothing)."""
    if "server" not in request.fixturenames:
        yield
        return
    request.getfixturevalue("server")  # started (its log begun) before the size is read
    start = SERVER_LOG.stat().st_size
    yield
    with open(SERVER_LOG, errors="replace") as log:
        log.seek(start)
        faults = server_faults(log.read())
    assert faults == [], f"the server raised (see {SERVER_LOG}): {faults}"


@pytest.fixture(scope="session")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


@pytest.fixture(scope="session")
def shots() -> Path:
    SCREENSHOT_DIR.mkdir(parents=True, exist_ok=True)
    return SCREENSHOT_DIR


def pytest_terminal_summary(terminalreporter) -> None:
    if SCREENSHOT_DIR.exists() and any(SCREENSHOT_DIR.glob("*.png")):
        terminalreporter.write_line(f"UI screenshots: {SCREENSHOT_DIR}")
