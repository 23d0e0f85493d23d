"""scripts/serve.sh for a classroom: the origin rule, signed session ids, and closed tabs'
sessions discarded within 10 s.

- On an address for other machines (the image's 0.0.0.0) the server does not start without
  ALLOW_WEBSOCKET_ORIGIN: before, the image's default (localhost:5006) served students a
  blank page. The message says what to set, with an example.
- ``*`` is accepted, with a warning in the log.
- Bokeh's own BOKEH_ALLOW_WS_ORIGIN, which inside the server would replace the list the
  script passes, never reaches the server: alone it is taken as ALLOW_WEBSOCKET_ORIGIN under
  the same rules, beside a different one the script refuses to start.
- With BOKEH_SECRET_KEY set, session ids are signed: a page opens (its websocket is
  accepted and the document arrives), and a session id the server did not sign is refused,
  on the page and on the websocket.
- A closed tab's session is discarded: SESSION_LIFETIME_MS + CHECK_UNUSED_MS <= 8 s by
  default (10 s, less the time a class's discards take), and the session does go (Panel's
  record of it, /rest/session_info).
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import secrets
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from processes import open_session, stop_group, wait_live

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
SERVE = ROOT / "scripts" / "serve.sh"
STARTUP_TIMEOUT = 180.0
#: A closed tab's session must be gone this long after its websocket closed [ms].
DISCARD_WITHIN_MS = 10_000
#: Of which the defaults leave this much for the discard itself: a class's sessions are
#: discarded one after another by a server that is busy meanwhile (with 7 s + 3 s, 20
#: sessions on one process were gone 9.7 s after their close: 0.3 s to spare).
DISCARD_MARGIN_MS = 2_000
#: Bound of the wait for the discard in the test (a loaded machine's event loop can be late).
DISCARD_WAIT_S = 60.0


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url, timeout=60) as resp:
            return resp.status, resp.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as exc:
        return exc.code, exc.read().decode("utf-8", "replace")


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("ALLOW_WEBSOCKET_ORIGIN", "BOKEH_ALLOW_WS_ORIGIN", "BOKEH_SECRET_KEY",
                        "SESSION_LIFETIME_MS", "CHECK_UNUSED_MS", "PROXY", "PYTHONMALLOC",
                        "ALLOCATOR", "LD_PRELOAD")}
    return {**env, "VENV": sys.prefix, "WARM": "0", **extra}


def test_a_server_for_other_machines_refuses_to_start_without_origins():
    result = subprocess.run([str(SERVE)], env=_env(ADDRESS="0.0.0.0", PORT=str(_free_port())),
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert "ALLOW_WEBSOCKET_ORIGIN is not set" in result.stderr
    assert "-e ALLOW_WEBSOCKET_ORIGIN=explorer.school.example:" in result.stderr  # an example
    assert "panel serve" not in result.stdout  # nothing was started


def test_loopback_needs_no_origins():
    # A laptop's server: the default origins are localhost's. NUM_PROCS is checked after the
    # origins, so a bad value ends the script before anything starts.
    result = subprocess.run([str(SERVE)], env=_env(ADDRESS="127.0.0.1", NUM_PROCS="x"),
                            capture_output=True, text=True, timeout=60)
    assert "ALLOW_WEBSOCKET_ORIGIN" not in result.stderr
    assert "NUM_PROCS must be a whole number >= 0, got 'x'" in result.stderr


def _started(tmp_path, **env: str) -> subprocess.CompletedProcess:
    """scripts/serve.sh with ``env``, its server a stand-in that prints the environment's
    BOKEH_ALLOW_WS_ORIGIN and its arguments (a virtual environment of one script)."""
    stub = tmp_path / "venv" / "bin"
    stub.mkdir(parents=True, exist_ok=True)
    for name in ("python", "panel"):
        (stub / name).write_text('#!/bin/sh\necho "server env: ${BOKEH_ALLOW_WS_ORIGIN-unset}"\n'
                                 'echo "allocator: ${PYTHONMALLOC-unset}"\n'
                                 'echo "preloaded: ${LD_PRELOAD-none}"\n'
                                 'echo "server args: $*"\n')
        (stub / name).chmod(0o755)
    full = {**_env(**env), "VENV": str(tmp_path / "venv")}
    return subprocess.run([str(SERVE)], env=full, capture_output=True, text=True, timeout=60)


def test_the_allocator_is_jemalloc_where_installed_else_as_asked(tmp_path):
    """jemalloc gives a class's memory back once it has left; Python's allocator keeps it
    (docs/deploy.md, "Memory"). `make test` installs jemalloc (`make jemalloc`)."""
    import glob

    libs = glob.glob("/usr/lib/*/libjemalloc.so.2") + glob.glob("/usr/lib/libjemalloc.so.2")
    assert libs, "jemalloc is not installed: make jemalloc (apt-get install -y libjemalloc2)"
    auto = _started(tmp_path)
    assert "allocator: malloc" in auto.stdout and f"preloaded: {libs[0]}" in auto.stdout
    assert "serve.sh: allocator jemalloc" in auto.stderr
    assert _started(tmp_path, ALLOCATOR="jemalloc").stdout == auto.stdout
    for asked in ("pymalloc", "malloc"):
        out = _started(tmp_path, ALLOCATOR=asked).stdout
        assert f"allocator: {asked}" in out and "preloaded: none" in out
    bad = _started(tmp_path, ALLOCATOR="tcmalloc")
    assert bad.returncode == 2
    assert ("ALLOCATOR must be auto, jemalloc, pymalloc or malloc, got 'tcmalloc'"
            in bad.stderr)


def test_bokeh_s_origin_variable_never_reaches_the_server(tmp_path):
    same = "explorer.school.example:5006"
    result = _started(tmp_path, ADDRESS="0.0.0.0", ALLOW_WEBSOCKET_ORIGIN=same,
                      BOKEH_ALLOW_WS_ORIGIN=same)
    assert result.returncode == 0, result.stderr
    assert "server env: unset" in result.stdout
    assert f"--allow-websocket-origin {same}" in result.stdout


def test_bokeh_s_origin_variable_alone_follows_the_rules(tmp_path):
    result = _started(tmp_path, ADDRESS="0.0.0.0", BOKEH_ALLOW_WS_ORIGIN="*")
    assert result.returncode == 0, result.stderr
    assert "WARNING: ALLOW_WEBSOCKET_ORIGIN=* accepts websockets from any origin" in \
        result.stderr
    assert "server env: unset" in result.stdout
    assert "--allow-websocket-origin *" in result.stdout


def test_a_different_bokeh_origin_variable_is_refused(tmp_path):
    result = _started(tmp_path, ADDRESS="0.0.0.0",
                      ALLOW_WEBSOCKET_ORIGIN="explorer.school.example:5006",
                      BOKEH_ALLOW_WS_ORIGIN="*")
    assert result.returncode == 2
    assert "BOKEH_ALLOW_WS_ORIGIN=* and" in result.stderr
    assert "Set ALLOW_WEBSOCKET_ORIGIN only" in result.stderr
    assert "server args" not in result.stdout  # nothing was started


@pytest.fixture(scope="module")
def signed_server(tmp_path_factory):
    """(base URL, log) of scripts/serve.sh with a secret key and ALLOW_WEBSOCKET_ORIGIN=*,
    the session lifetimes left at their defaults."""
    port = _free_port()
    log = tmp_path_factory.mktemp("signed") / "serve.log"
    env = _env(ADDRESS="127.0.0.1", PORT=str(port), ALLOW_WEBSOCKET_ORIGIN="*",
               BOKEH_SECRET_KEY=secrets.token_urlsafe(32))
    with open(log, "w") as out:
        proc = subprocess.Popen([str(SERVE), "--rest-session-info", "--session-history", "10"],
                                env=env, stdout=out, stderr=subprocess.STDOUT,
                                start_new_session=True)
    base = f"http://127.0.0.1:{port}"
    try:
        wait_live(f"{base}/liveness", proc, log, STARTUP_TIMEOUT)
        yield base, log
    finally:
        stop_group(proc)


async def _websocket(base: str, token: str):
    from tornado.httpclient import HTTPRequest
    from tornado.websocket import websocket_connect

    request = HTTPRequest(f"ws{base[4:]}/main/ws", headers={"Origin": base},
                          request_timeout=120)
    return await websocket_connect(request, subprotocols=["bokeh", token],
                                   max_message_size=64 * 1024 * 1024)


async def _open_and_close(base: str) -> str:
    """Open /main as a browser does (the page, its websocket, the document), close the
    websocket as a closed tab does; return the session's id."""
    return await open_session(base)


def _session(base: str, session_id: str) -> dict:
    """Panel's record of one session: launched, rendered, ended (None while it lives)."""
    status, body = _get(f"{base}/rest/session_info")
    assert status == 200, body
    info = json.loads(body)
    return info.get("session_info", info)["sessions"][session_id]


def test_star_is_accepted_with_a_warning(signed_server):
    base, log = signed_server
    assert _get(f"{base}/liveness")[0] == 200
    assert "WARNING: ALLOW_WEBSOCKET_ORIGIN=* accepts websockets from any origin" in \
        log.read_text()


def test_with_a_secret_a_page_opens_and_its_session_is_discarded_once_closed(signed_server,
                                                                            run_async):
    base, log = signed_server
    assert "--session-ids signed" in log.read_text()
    command = next(line for line in log.read_text().splitlines()
                   if line.startswith("serve.sh:") and "--unused-session-lifetime" in line)
    lifetime = int(re.search(r"--unused-session-lifetime (\d+)", command).group(1))
    check = int(re.search(r"--check-unused-sessions (\d+)", command).group(1))
    # The defaults: discarded within 10 s, a class's discards included.
    assert lifetime + check <= DISCARD_WITHIN_MS - DISCARD_MARGIN_MS
    session_id = run_async(lambda: _open_and_close(base))
    closed = time.monotonic()
    while _session(base, session_id)["ended"] is None:
        assert time.monotonic() - closed < DISCARD_WAIT_S, "the closed session was kept"
        time.sleep(0.5)
    print(f"closed session discarded after {time.monotonic() - closed:.1f} s")


def test_a_forged_session_id_is_refused(signed_server, run_async):
    from bokeh.util.token import generate_jwt_token, generate_session_id

    base, _ = signed_server
    status, _ = _get(f"{base}/main?bokeh-session-id=forged-by-a-student")
    assert status == 403
    # A well-formed id signed with another key: refused on the page and on the websocket.
    other = secrets.token_urlsafe(32)
    forged = generate_session_id(secret_key=other.encode(), signed=True)
    assert _get(f"{base}/main?bokeh-session-id={forged}")[0] == 403
    token = generate_jwt_token(forged, secret_key=other.encode(), signed=True)

    async def connect():
        ws = await _websocket(base, token)
        return await asyncio.wait_for(ws.read_message(), 60)

    try:
        message = run_async(connect)
    except Exception as exc:  # the handshake refused
        message = exc
    assert message is None or isinstance(message, Exception), "a forged token was served"
