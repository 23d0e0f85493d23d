"""Waiting for and stopping the servers the deployment tests start (each in a process group
of its own)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
import urllib.request
from pathlib import Path

import pytest


def stop_group(proc: subprocess.Popen, timeout: float = 15.0) -> None:
    """End ``proc``'s process group (started with ``start_new_session=True``): SIGTERM,
    then SIGKILL if it is still running after ``timeout`` seconds."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def wait_live(url: str, proc: subprocess.Popen, log: Path, timeout: float) -> None:
    """Wait until ``url`` answers 200; fail the test (with ``log``) if ``proc`` exits first
    or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while True:
        if proc.poll() is not None:
            pytest.fail(f"{proc.args[0]} exited with {proc.returncode}:\n{log.read_text()}")
        try:
            with urllib.request.urlopen(url, timeout=2) as reply:
                if reply.status == 200:
                    return
        except OSError:
            pass
        if time.monotonic() > deadline:
            pytest.fail(f"no answer from {url} after {timeout} s:\n{log.read_text()}")
        time.sleep(0.5)


#: The session token a served page carries (Bokeh's autoload script).
TOKEN_RE = re.compile(r'"token"\s*:\s*"([^"]+)"')


async def open_session(base: str, headers: dict[str, str] | None = None) -> str:
    """Open ``base``/main as a browser does: the page, its websocket and the document
    (PULL-DOC), then close the websocket as a closed tab does; return the session's id.
    ``headers`` go with both requests; the cookies the page sets go with the websocket, as
    in a browser (a proxy's sticky cookie)."""
    import asyncio

    from bokeh.protocol import Protocol
    from bokeh.protocol.receiver import Receiver
    from bokeh.util.token import get_session_id
    from tornado.httpclient import AsyncHTTPClient, HTTPRequest
    from tornado.websocket import websocket_connect

    headers = dict(headers or {})
    resp = await AsyncHTTPClient().fetch(f"{base}/main", headers=headers, request_timeout=120)
    token = TOKEN_RE.search(resp.body.decode()).group(1)
    cookies = [c.split(";", 1)[0] for c in resp.headers.get_list("Set-Cookie")]
    if cookies:
        headers["Cookie"] = "; ".join(cookies)
    request = HTTPRequest(f"ws{base[4:]}/main/ws", headers={**headers, "Origin": base},
                          request_timeout=120)
    ws = await websocket_connect(request, subprotocols=["bokeh", token],
                                 max_message_size=64 * 1024 * 1024)
    protocol = Protocol()
    receiver = Receiver(protocol)

    async def read(kind: str):
        while True:
            fragment = await asyncio.wait_for(ws.read_message(), 120)
            assert fragment is not None, "the websocket was closed"
            msg = await receiver.consume(fragment)
            if msg is not None and msg.msgtype == kind:
                return msg

    try:
        await read("ACK")
        pull = protocol.create("PULL-DOC-REQ")
        for part in (pull.header_json, pull.metadata_json, pull.content_json):
            await ws.write_message(part)
        reply = await read("PULL-DOC-REPLY")
        assert reply.content["doc"]["roots"], "an empty document"
    finally:
        ws.close()
    return get_session_id(token)
