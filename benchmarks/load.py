"""Classroom load test: N concurrent sessions moving sliders against one Panel server.

Bounded in count and time, loopback only. For each N (default 10, 30, 60) the harness

1. opens N sessions the way a browser does: GET /main (the server builds the session's
   document and returns the page with a session token), then the Bokeh websocket, PULL-DOC,
   and the ``document_ready`` event a browser sends once the page has rendered (Panel runs
   its onload callbacks on it);
2. in every session moves the app's sliders MOVES times, with a think time between moves,
   all sessions at once. A move sends what a browser sends at the end of a drag: a patch
   setting the slider's ``value`` and ``value_throttled``. The latency of a move is the time
   from sending it to receiving the server's patch that changes a ColumnDataSource (the plot's
   new data); if a move brings no data change, the last patch before a quiet period counts;
3. closes the sessions as closed tabs do and measures how long until the server has
   discarded them all (``gone``: Panel's /rest/session_info, asked every 0.25 s; by default
   the server runs with the classroom's session lifetime and check interval, those of
   scripts/serve.sh, so ``gone`` is what a class's server does); a round whose sessions are
   not all gone within --gone-limit-s (10 s) counts an error;
4. reads the server's resident memory (VmRSS of the server process and its children, from
   /proc) before, at the peak and after the sessions closed and the server discarded them.

The sessions are Bokeh protocol clients (one asyncio loop in this process), not browsers:
they cost the server what a browser session costs it (documents, patches, callbacks) without
running 60 Chromiums on the same cores. Browser-side rendering time is not included.

    python benchmarks/load.py                       # starts scripts/serve.sh on a free port
    python benchmarks/load.py --sessions 10 --moves 3
    python benchmarks/load.py --url http://127.0.0.1:5006/main --server-pid 1234
    # behind a proxy (scripts/serve-behind-nginx.sh): the proxy's URL, every process's pid and
    # address (for memory, CPU and session counts)
    python benchmarks/load.py --url http://127.0.0.1:8086/main --server-pid 11 --server-pid 12 \
        --backend http://127.0.0.1:5107 --backend http://127.0.0.1:5108

A session keeps the cookies the page set (a proxy's sticky-session cookie) for its websocket,
as a browser does.

With ``--measure-clicks K`` one more session (not counted in the table's moves) opens
``--measure-query`` (default scene 10 to t_end = 5000) and, while the others move, clicks
"Measure the trade" every ``--measure-every`` seconds, K times at most: clicks a page sends
itself, whether the button is disabled or not. The other sessions' move latencies then say
what one such student costs the class:

    python benchmarks/load.py --sessions 10 --moves 10 --measure-clicks 30 --measure-every 0.2
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import random
import re
import signal
import socket
import statistics
import subprocess
import sys
import time
import urllib.parse
from dataclasses import dataclass, field
from pathlib import Path

from bokeh.client.websocket import WebSocketClientConnectionWrapper
from bokeh.protocol import Protocol
from bokeh.protocol.messages.patch_doc import patch_doc
from bokeh.protocol.receiver import Receiver
from bokeh.util.token import generate_jwt_token, generate_session_id
from tornado.httpclient import AsyncHTTPClient, HTTPRequest
from tornado.websocket import WebSocketClosedError, websocket_connect

ROOT = Path(__file__).resolve().parents[1]
LOOPBACK = {"127.0.0.1", "localhost", "::1"}
TOKEN_RE = re.compile(r'"token"\s*:\s*"([^"]+)"')
DATA_EVENT_KINDS = {"ColumnDataChanged", "ColumnsStreamed", "ColumnsPatched"}
SLIDER_TYPES = {"Slider"}  # bokeh.models.Slider, which Panel's (Editable)FloatSlider renders
MEASURE_CLASS = "fie-measure"  # the css class of the "Measure the trade" button
PROTOCOL = Protocol()


# --------------------------------------------------------------------------------------------
# Server process: start, memory, session count
# --------------------------------------------------------------------------------------------


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _children(pid: int) -> list[int]:
    kids: list[int] = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                kids.extend(int(p) for p in f.read().split())
    except OSError:
        pass
    return kids


def rss_mib(pid: int) -> float:
    """VmRSS of pid and all its descendants, in MiB (0 if gone)."""
    total_kib = 0
    stack = [pid]
    while stack:
        p = stack.pop()
        try:
            with open(f"/proc/{p}/status") as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        total_kib += int(line.split()[1])
                        break
        except OSError:
            continue
        stack.extend(_children(p))
    return total_kib / 1024


def cpu_s(pid: int) -> float:
    """User + system CPU seconds of pid and its descendants (live ones)."""
    tick = os.sysconf("SC_CLK_TCK")
    total = 0
    stack = [pid]
    while stack:
        p = stack.pop()
        try:
            with open(f"/proc/{p}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            total += int(fields[11]) + int(fields[12])  # utime, stime
        except (OSError, IndexError, ValueError):
            continue
        stack.extend(_children(p))
    return total / tick


def system_busy_s() -> float:
    """CPU seconds all cores have spent busy since boot (from /proc/stat)."""
    with open("/proc/stat") as f:
        fields = [int(x) for x in f.readline().split()[1:]]
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    return (sum(fields[:8]) - idle) / os.sysconf("SC_CLK_TCK")


class Server:
    """A server started by scripts/serve.sh, or one already running (url + pids), possibly a
    proxy in front of several processes (backends)."""

    def __init__(self, args: argparse.Namespace):
        self.args = args
        self.proc: subprocess.Popen | None = None
        if args.url:
            self.url = args.url
            self.pids = list(args.server_pid or [])
        else:
            port = args.port or free_port()
            self.url = f"http://127.0.0.1:{port}/main"
            env = dict(os.environ)
            env.update(
                APP_PATH=args.app,
                PORT=str(port),
                ADDRESS="127.0.0.1",
                NUM_PROCS=str(args.num_procs),
                SESSION_LIFETIME_MS=str(args.session_lifetime_ms),
                CHECK_UNUSED_MS=str(args.check_unused_ms),
                LOG_LEVEL="warning",
                WARM="1",
            )
            self.log_path = Path(args.log)
            self.log = open(self.log_path, "w")  # noqa: SIM115  (closed in stop())
            self.proc = subprocess.Popen(
                # Panel's /rest/session_info counts live sessions (needs a session history).
                [str(ROOT / "scripts" / "serve.sh"),
                 "--rest-session-info", "--session-history", "1000"],
                env=env,
                stdout=self.log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
            self.pids = [self.proc.pid]
        parts = urllib.parse.urlsplit(self.url)
        if parts.hostname not in LOOPBACK:
            raise SystemExit(f"refusing {self.url}: this harness only loads loopback servers")
        self.base = f"{parts.scheme}://{parts.netloc}"
        # Where to ask for session counts: each process behind a proxy, or the server itself.
        self.backends = list(args.backend or [self.base])
        for backend in self.backends:
            if urllib.parse.urlsplit(backend).hostname not in LOOPBACK:
                raise SystemExit(f"refusing {backend}: this harness only loads loopback servers")
        self.app_path = parts.path or "/main"

    async def wait_live(self, timeout: float) -> None:
        client = AsyncHTTPClient()
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc is not None and self.proc.poll() is not None:
                raise SystemExit(f"server exited:\n{self.log_path.read_text()}")
            try:
                resp = await client.fetch(
                    f"{self.base}/liveness", request_timeout=2, raise_error=False
                )
                if resp.code == 200:
                    return
            except OSError:
                pass
            await asyncio.sleep(0.5)
        raise SystemExit(f"no /liveness at {self.base} after {timeout} s")

    async def live_sessions(self) -> int | None:
        """Sessions Panel counts as rendered and not yet discarded, summed over the backends
        (None: not known).

        Needs `panel serve --rest-session-info --session-history N`.
        """
        counts = [await self._live_sessions(backend) for backend in self.backends]
        return None if None in counts else sum(counts)

    async def _live_sessions(self, base: str) -> int | None:
        try:
            resp = await AsyncHTTPClient().fetch(
                f"{base}/rest/session_info", request_timeout=5, raise_error=False
            )
            if resp.code != 200:
                return None
            info = json.loads(resp.body)
            info = info.get("session_info", info)
            if not info["total"]:
                return None  # the server does not keep a session history
            return int(info["live"])
        except Exception:  # noqa: BLE001  (busy server, time-out, no endpoint: not known)
            return None

    def rss(self) -> float:
        return sum(rss_mib(p) for p in self.pids) if self.pids else float("nan")

    def cpu(self) -> float:
        return sum(cpu_s(p) for p in self.pids) if self.pids else float("nan")

    def log_errors(self) -> list[str]:
        """Errors the server has logged so far (callbacks that raised, ...)."""
        if self.proc is None:
            return []
        return [line.strip() for line in self.log_path.read_text(errors="replace").splitlines()
                if " ERROR" in line or "Traceback" in line or "Exception" in line]

    def stop(self) -> None:
        if self.proc is None or self.proc.poll() is not None:
            return
        os.killpg(self.proc.pid, signal.SIGTERM)
        try:
            self.proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()
        self.log.close()


# --------------------------------------------------------------------------------------------
# One client session
# --------------------------------------------------------------------------------------------


@dataclass
class Move:
    latency: float | None  # s until the data patch (or the settled patch) arrived
    first: float | None  # s until the first patch of any kind arrived
    patches: int
    error: str | None = None
    had_data: bool = False
    slider: str = ""  # the moved slider's title
    sent: float = 0.0  # when it was sent, s since the round's moves started


@dataclass
class SessionResult:
    open_s: float | None = None
    moves: list[Move] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    sliders: int = 0


#: Seconds without a patch after which a move that brought patches but no data change is
#: over (the app answered with text only: e.g. a restitution where the run has no impact).
NO_DATA_QUIET_S = 2.0


def settle_wait(arrivals: list[tuple[float, bool]], now: float, deadline: float,
                quiet: float) -> float | None:
    """Seconds to wait for a move's next patch, or None once the move is over: ``quiet`` s
    without a patch after its data patch; ``max(quiet, NO_DATA_QUIET_S)`` s without one
    after patches without data; or the ``deadline``. ``arrivals``: (time, changed data).

    >>> settle_wait([(10.0, False)], 10.5, 40.0, 0.3)   # no data yet: wait out the quiet
    1.5
    >>> settle_wait([(10.0, False)], 12.1, 40.0, 0.3) is None
    True
    """
    if now >= deadline:
        return None
    if not arrivals:
        return deadline - now
    have_data = any(is_data for _, is_data in arrivals)
    left = (quiet if have_data else max(quiet, NO_DATA_QUIET_S)) - (now - arrivals[-1][0])
    return min(left, deadline - now) if left > 0 else None


class Session:
    """One client session speaking the Bokeh protocol on the raw JSON.

    The document is not rebuilt as Python models here: a Panel page has about a thousand
    models, and deserialising them for 60 sessions would spend the CPU the server is measured
    on. Sliders are found by their model type in the document JSON, moves are sent as the
    JSON patches BokehJS sends, and the server's patches are inspected, not applied.
    """

    def __init__(self, server: Server, rng: random.Random, args: argparse.Namespace,
                 query: str = ""):
        self.server = server
        self.query = query  # the page's address query, e.g. "scene=10&tend=5000"
        self.rng = rng
        self.args = args
        self.ws = None
        self.conn: WebSocketClientConnectionWrapper | None = None
        self.receiver = Receiver(PROTOCOL)
        self.result = SessionResult()
        self.sliders: dict[str, dict] = {}  # id -> attributes (start, end, step, value, ...)
        self.models = 0  # models of the document pulled at the opening
        self.arrivals: list[tuple[float, bool]] = []  # (time, changed a ColumnDataSource)
        self.arrived = asyncio.Event()
        self.replies: dict[str, asyncio.Future] = {}
        self.reader: asyncio.Task | None = None
        self.closing = False
        self.acked = asyncio.Event()
        self.measure_button: str | None = None  # the "Measure the trade" button's model id
        self.clicks = 0

    # ---- wire ----------------------------------------------------------------------------

    async def _send(self, msg) -> None:
        # The wrapper's write lock keeps the frames of one message together.
        try:
            await msg.send(self.conn)
        except WebSocketClosedError:
            if not self.closing:
                self.result.errors.append("websocket closed by the server")

    async def _send_events(self, events: list[dict]) -> None:
        await self._send(patch_doc(patch_doc.create_header(), {}, {"events": events}))

    async def _request(self, msg, timeout: float):
        fut = asyncio.get_running_loop().create_future()
        self.replies[msg.header["msgid"]] = fut
        await self._send(msg)
        return await asyncio.wait_for(fut, timeout)

    async def _read_loop(self) -> None:
        try:
            await self._read_messages()
        except Exception as exc:  # noqa: BLE001
            if not self.closing:
                self.result.errors.append(f"reading: {type(exc).__name__}: {exc}")
            for fut in self.replies.values():
                if not fut.done():
                    fut.set_exception(exc)

    async def _read_messages(self) -> None:
        while True:
            fragment = await self.ws.read_message()
            if fragment is None:
                if not self.closing:
                    self.result.errors.append("websocket closed by the server")
                return
            msg = await self.receiver.consume(fragment)
            if msg is None:
                continue
            reqid = msg.header.get("reqid")
            if msg.msgtype == "ACK":
                self.acked.set()
            elif msg.msgtype == "PATCH-DOC":
                self._patched(msg.content.get("events", []))
            elif msg.msgtype == "ERROR":
                self.result.errors.append(f"server error: {msg.content.get('text', msg.content)}")
            if reqid in self.replies:
                fut = self.replies.pop(reqid)
                if not fut.done():
                    fut.set_result(msg)

    def _patched(self, events: list[dict]) -> None:
        now = time.perf_counter()
        is_data = False
        for ev in events:
            kind = ev.get("kind")
            if kind in DATA_EVENT_KINDS or (kind == "ModelChanged" and ev.get("attr") == "data"):
                is_data = True
            elif kind == "ModelChanged":
                model_id = (ev.get("model") or {}).get("id")
                if model_id in self.sliders and isinstance(ev.get("new"), (int, float, bool)):
                    self.sliders[model_id][ev["attr"]] = ev["new"]
        self.arrivals.append((now, is_data))
        self.arrived.set()

    # ---- life cycle ----------------------------------------------------------------------

    async def open(self) -> None:
        t0 = time.perf_counter()
        timeout = self.args.request_timeout
        http = AsyncHTTPClient()
        query = f"?{self.query}" if self.query else ""
        resp = await http.fetch(self.server.base + self.server.app_path + query,
                                request_timeout=timeout)
        match = TOKEN_RE.search(resp.body.decode("utf-8", "replace"))
        token = match.group(1) if match else generate_jwt_token(generate_session_id())
        ws_url = "ws" + self.server.base[4:] + self.server.app_path + "/ws"
        headers = {"Origin": self.server.base}
        # The cookies the page set go with the websocket, as in a browser: a proxy's sticky
        # cookie sends it to the process that built the session.
        cookies = [c.split(";", 1)[0] for c in resp.headers.get_list("Set-Cookie")]
        if cookies:
            headers["Cookie"] = "; ".join(cookies)
        request = HTTPRequest(ws_url, headers=headers, request_timeout=timeout)
        self.ws = await websocket_connect(
            request, subprotocols=["bokeh", token], max_message_size=64 * 1024 * 1024
        )
        self.conn = WebSocketClientConnectionWrapper(self.ws)
        self.reader = asyncio.ensure_future(self._read_loop())
        # The server reads messages only after it has sent its ACK; then pull the document.
        await asyncio.wait_for(self.acked.wait(), timeout)
        reply = await self._request(PROTOCOL.create("PULL-DOC-REQ"), timeout)
        if reply.msgtype != "PULL-DOC-REPLY":
            raise RuntimeError(f"PULL-DOC answered with {reply.msgtype}")
        self.models = len({obj["id"] for obj in _objects(reply.content["doc"])})
        # Only sliders a student can reach: inside no hidden layout (e.g. the SI-unit set).
        for obj in _visible_objects(reply.content["doc"]):
            if obj.get("name") in SLIDER_TYPES:
                self.sliders[obj["id"]] = dict(obj.get("attributes") or {})
            elif MEASURE_CLASS in ((obj.get("attributes") or {}).get("css_classes") or []):
                self.measure_button = obj["id"]
        # What BokehJS sends once the page is rendered; Panel runs onload callbacks on it.
        await self._send_events([{
            "kind": "MessageSent",
            "msg_type": "bokeh_event",
            "msg_data": {"type": "event", "name": "document_ready", "values": {"type": "map"}},
        }])
        self.result.open_s = time.perf_counter() - t0
        self.result.sliders = len(self.movable())

    def movable(self) -> list[str]:
        found = []
        for model_id, a in self.sliders.items():
            start, end = a.get("start"), a.get("end")
            if not isinstance(start, (int, float)) or not isinstance(end, (int, float)):
                continue
            if a.get("disabled") or a.get("visible") is False or end <= start:
                continue
            label = str(a.get("title") or a.get("name") or "")
            if self.args.slider and not any(s in label for s in self.args.slider):
                continue
            if any(s == label for s in self.args.exclude_slider):
                continue
            found.append(model_id)
        return sorted(found)

    async def move(self, model_id: str) -> Move:
        a = self.sliders[model_id]
        start, end = float(a["start"]), float(a["end"])
        step = float(a.get("step") or 1.0)
        if step <= 0 or step > end - start:
            step = (end - start) / 100
        n_steps = max(1, int((end - start) / step))
        old = a.get("value", start)
        new = old
        while new == old:
            new = min(start + step * self.rng.randint(0, n_steps), end)
        a["value"] = new
        self.arrivals.clear()
        self.arrived.clear()
        t0 = time.perf_counter()
        # A slider released after a drag: BokehJS sends value, then value_throttled.
        ref = {"id": model_id}
        await self._send_events([
            {"kind": "ModelChanged", "model": ref, "attr": "value", "new": new},
            {"kind": "ModelChanged", "model": ref, "attr": "value_throttled", "new": new},
        ])
        deadline = t0 + self.args.move_timeout
        quiet = self.args.quiet_ms / 1000
        while (wait := settle_wait(self.arrivals, time.perf_counter(), deadline,
                                   quiet)) is not None:
            self.arrived.clear()
            try:
                await asyncio.wait_for(self.arrived.wait(), max(wait, 0.001))
            except TimeoutError:
                pass
        if not self.arrivals:
            label = str(a.get("title") or a.get("name") or model_id)
            return Move(None, None, 0, error=f"timeout: no update after moving {label!r} to {new}")
        first = self.arrivals[0][0] - t0
        data = [t for t, is_data in self.arrivals if is_data]
        latency = (data[0] if data else self.arrivals[-1][0]) - t0
        return Move(latency, first, len(self.arrivals), had_data=bool(data),
                    slider=str(a.get("title") or a.get("name") or model_id), sent=t0)

    async def run_moves(self, start: asyncio.Event) -> None:
        await start.wait()
        sliders = self.movable()
        if not sliders:
            self.result.errors.append("no slider found in the document")
            return
        for _ in range(self.args.moves):
            await asyncio.sleep(self.rng.uniform(0.5, 1.5) * self.args.think_s)
            mv = await self.move(self.rng.choice(sliders))
            self.result.moves.append(mv)
            if mv.error:
                self.result.errors.append(mv.error)

    async def click_measure(self, done: asyncio.Event) -> None:
        """Click "Measure the trade" every --measure-every s until ``done`` (the other
        sessions' moves ended), --measure-clicks times at most: the ButtonClick event
        BokehJS sends, whatever the button's state."""
        if self.measure_button is None:
            self.result.errors.append("no 'Measure the trade' button in the document")
            return
        for _ in range(self.args.measure_clicks):
            if done.is_set():
                return
            await self._send_events([{
                "kind": "MessageSent",
                "msg_type": "bokeh_event",
                "msg_data": {"type": "event", "name": "button_click", "values": {
                    "type": "map", "entries": [["model", {"id": self.measure_button}]]}},
            }])
            self.clicks += 1
            try:
                await asyncio.wait_for(done.wait(), self.args.measure_every)
            except TimeoutError:
                pass

    async def close(self) -> None:
        self.closing = True
        if self.ws is not None:
            self.ws.close()
        if self.reader is not None:
            self.reader.cancel()


def _objects(node):
    """Every serialised model ({"type": "object", "id": ...}) in a JSON document, nested or not."""
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            if item.get("type") == "object" and "id" in item:
                yield item
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)


def _visible_objects(doc: dict):
    """The models reachable from the document's roots without passing a visible=False model.

    A model is serialised in full once and referenced as {"id": ...} elsewhere, so the walk
    follows references through an id -> model table.
    """
    by_id = {obj["id"]: obj for obj in _objects(doc)}
    seen: set[str] = set()
    stack = list(doc.get("roots", []))
    while stack:
        item = stack.pop()
        if isinstance(item, list):
            stack.extend(item)
            continue
        if not isinstance(item, dict):
            continue
        if "id" in item and set(item) <= {"id"}:  # a reference
            item = by_id.get(item["id"], {})
        if item.get("type") == "object" and "id" in item:
            if item["id"] in seen:
                continue
            seen.add(item["id"])
            attrs = item.get("attributes") or {}
            if attrs.get("visible") is False:
                continue
            yield item
            stack.extend(attrs.values())
        else:
            stack.extend(item.values())


# --------------------------------------------------------------------------------------------
# One round: N sessions
# --------------------------------------------------------------------------------------------


async def wait_gone(live_sessions, live0: int, limit_s: float,
                    poll_s: float = 0.25) -> tuple[float | None, int | None]:
    """Seconds from now until ``live_sessions()`` (an awaitable count, None when unknown)
    is back to ``live0``, and the last count; None for the seconds if it was not within
    ``limit_s`` (or the count is not known)."""
    t0 = time.perf_counter()
    while True:
        live = await live_sessions()
        if live is not None and live <= live0:
            return time.perf_counter() - t0, live
        if live is None or time.perf_counter() - t0 >= limit_s:
            return None, live
        await asyncio.sleep(poll_s)


def pct(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    if len(values) == 1:
        return values[0]
    return statistics.quantiles(values, n=100, method="inclusive")[q - 1]


async def run_round(server: Server, n: int, args: argparse.Namespace, seed: int) -> dict:
    rng = random.Random(seed)
    live0 = await server.live_sessions()
    baseline = server.rss()
    sessions = [Session(server, random.Random(rng.random()), args) for _ in range(n)]
    peak = baseline
    stop_sampling = asyncio.Event()

    async def sample() -> None:
        nonlocal peak
        while not stop_sampling.is_set():
            peak = max(peak, server.rss())
            try:
                await asyncio.wait_for(stop_sampling.wait(), 0.25)
            except TimeoutError:
                pass

    sampler = asyncio.ensure_future(sample())
    log_errors0 = len(server.log_errors())
    cpu0 = server.cpu()
    busy0, own0 = system_busy_s(), time.process_time()
    t_start = time.perf_counter()
    open_errors: list[str] = []

    async def open_one(i: int, s: Session) -> None:
        # A class does not click the link in the same millisecond: spread over --ramp-s.
        await asyncio.sleep(args.ramp_s * i / max(n, 1))
        try:
            await s.open()
        except Exception as exc:  # noqa: BLE001  (every failure is counted, none is fatal)
            open_errors.append(f"open: {type(exc).__name__}: {exc}")
            if os.environ.get("LOAD_DEBUG"):
                import traceback
                traceback.print_exc()

    measurer = (Session(server, random.Random(rng.random()), args, args.measure_query)
                if args.measure_clicks else None)
    await asyncio.gather(*(open_one(i, s) for i, s in enumerate(sessions)))
    if measurer is not None:
        await open_one(0, measurer)
    opened = [s for s in sessions if s.result.open_s is not None]
    t_opened = time.perf_counter()
    await asyncio.sleep(1.0)  # let onload work finish before the moves start
    cpu_opened = server.cpu()
    rss_open = server.rss()
    live_open = await server.live_sessions()
    start, moved = asyncio.Event(), asyncio.Event()
    movers = asyncio.gather(*(s.run_moves(start) for s in opened))
    clicker = (asyncio.ensure_future(measurer.click_measure(moved))
               if measurer is not None and measurer.result.open_s is not None else None)
    t_moves0 = time.perf_counter()
    start.set()
    try:
        await asyncio.wait_for(movers, args.round_timeout)
        timed_out = False
    except TimeoutError:
        timed_out = True
    moved.set()
    if clicker is not None:
        await clicker
    t_moved = time.perf_counter()
    cpu_moved = server.cpu()
    # CPU used by neither the server nor this client (other work on the machine), in cores.
    others = (system_busy_s() - busy0) - (cpu_moved - cpu0) - (time.process_time() - own0)
    others_cores = max(others, 0.0) / (t_moved - t_start)
    stop_sampling.set()
    await sampler
    rss_peak = max(peak, server.rss())

    for s in sessions + ([measurer] if measurer is not None else []):
        await s.close()
    # How long until the server has discarded the closed sessions (bounded: lifetime + check
    # interval + margin, at least the goal).
    wait_limit = (args.session_lifetime_ms + 2 * args.check_unused_ms) / 1000 + 15
    t_closed = time.perf_counter()
    gone_s, live_after = await wait_gone(server.live_sessions, live0 or 0,
                                         max(wait_limit, args.gone_limit_s))
    if live_after is None:  # no session info: just wait out the lifetime
        await asyncio.sleep(wait_limit)
    await asyncio.sleep(args.after_s)
    rss_after = server.rss()

    moves = [m for s in opened for m in s.result.moves]
    # Latency of moves that changed the plots; moves that changed no data (the animation's
    # speed, a value the app clamps back, ...) are counted apart with their first answer.
    lat = [m.latency * 1000 for m in moves if m.latency is not None and m.had_data]
    nodata_first = [m.first * 1000 for m in moves if m.first is not None and not m.had_data]
    first = [m.first * 1000 for m in moves if m.first is not None]
    errors = open_errors + [e for s in sessions for e in s.result.errors]
    if measurer is not None:
        errors += [f"measuring session: {e}" for e in measurer.result.errors]
    errors += [f"server log: {e}" for e in server.log_errors()[log_errors0:]]
    if timed_out:
        errors.append(f"round timed out after {args.round_timeout} s")
    if live_after is not None and (gone_s is None or gone_s > args.gone_limit_s):
        waited = max(wait_limit, args.gone_limit_s)
        late = (f"gone only after {gone_s:.1f} s" if gone_s is not None
                else f"still live ({live_after}) after {waited:.0f} s")
        errors.append(f"closed sessions {late} (limit {args.gone_limit_s:g} s)")
    open_s = [s.result.open_s * 1000 for s in opened]
    return {
        "n": n,
        "measure_clicks": measurer.clicks if measurer is not None else 0,
        "opened": len(opened),
        "sliders": max((s.result.sliders for s in opened), default=0),
        "moves": len(moves),
        "moves_with_data": sum(m.had_data for m in moves),
        "server_cpu_open_s": cpu_opened - cpu0,
        "server_cpu_moves_s": cpu_moved - cpu_opened,
        "server_busy": (cpu_moved - cpu0) / (t_moved - t_start),
        "other_cores": others_cores,
        "open_p50_ms": pct(open_s, 50),
        "open_p95_ms": pct(open_s, 95),
        "open_all_s": t_opened - t_start,
        "first_p50_ms": pct(first, 50),
        "nodata_first_p50_ms": pct(nodata_first, 50),
        "lat_p50_ms": pct(lat, 50),
        "lat_p95_ms": pct(lat, 95),
        "lat_p99_ms": pct(lat, 99),
        "lat_max_ms": max(lat) if lat else float("nan"),
        "errors": len(errors),
        "error_samples": sorted(set(errors))[:5],
        "moves_s": t_moved - t_opened,
        "rss_base_mib": baseline,
        "rss_open_mib": rss_open,
        "rss_peak_mib": rss_peak,
        "rss_per_session_mib": (rss_peak - baseline) / max(len(opened), 1),
        "rss_after_mib": rss_after,
        "live_open": live_open,
        "live_after": live_after,
        "gone_s": gone_s,
        "cleanup_s": time.perf_counter() - t_closed,
        # Each move (in --json): its slider, when it was sent [s after the moves began],
        # its latency to the data patch [ms] (None: no answer) and whether data came.
        "moves_start_epoch": round(time.time() - (time.perf_counter() - t_moves0), 3),
        "move_log": [
            {"slider": m.slider, "sent_s": round(m.sent - t_moves0, 3),
             "ms": None if m.latency is None else round(m.latency * 1000, 1),
             "data": m.had_data}
            for m in moves],
    }


def print_table(rows: list[dict]) -> None:
    cols = [
        ("N", 4, lambda r: f"{r['n']}"),
        ("clicks", 6, lambda r: f"{r.get('measure_clicks', 0)}"),
        ("open", 5, lambda r: f"{r['opened']}"),
        ("moves", 7, lambda r: f"{r['moves_with_data']}/{r['moves']}"),
        ("err", 4, lambda r: f"{r['errors']}"),
        ("open p50", 9, lambda r: f"{r['open_p50_ms'] / 1000:.1f}s"),
        ("p95", 6, lambda r: f"{r['open_p95_ms'] / 1000:.1f}s"),
        ("move p50", 9, lambda r: f"{r['lat_p50_ms']:.0f}ms"),
        ("p95", 7, lambda r: f"{r['lat_p95_ms']:.0f}ms"),
        ("p99", 7, lambda r: f"{r['lat_p99_ms']:.0f}ms"),
        ("max", 7, lambda r: f"{r['lat_max_ms']:.0f}ms"),
        ("cpu/open", 9, lambda r: f"{r['server_cpu_open_s'] / max(r['opened'], 1):.2f}s"),
        ("cpu/move", 9, lambda r: f"{r['server_cpu_moves_s'] / max(r['moves'], 1):.2f}s"),
        ("RSS base", 9, lambda r: f"{r['rss_base_mib']:.0f}M"),
        ("peak", 6, lambda r: f"{r['rss_peak_mib']:.0f}M"),
        ("/sess", 6, lambda r: f"{r['rss_per_session_mib']:.1f}M"),
        ("after", 6, lambda r: f"{r['rss_after_mib']:.0f}M"),
        ("live", 7, lambda r: f"{r['live_open']}>{r['live_after']}"),
        ("gone", 6, lambda r: "n/a" if r.get("gone_s") is None else f"{r['gone_s']:.1f}s"),
        ("srv cpu", 7, lambda r: f"{r['server_busy']:.2f}"),
        ("others", 6, lambda r: f"{r['other_cores']:.2f}"),
    ]
    print(" ".join(f"{name:>{w}}" for name, w, _ in cols))
    print(" ".join("-" * w for _, w, _ in cols))
    for r in rows:
        print(" ".join(f"{fmt(r):>{w}}" for _, w, fmt in cols))
    for r in rows:
        for e in r["error_samples"]:
            print(f"  N={r['n']}: {e[:300]}")


async def main_async(args: argparse.Namespace) -> list[dict]:
    server = Server(args)
    rows: list[dict] = []
    deadline = time.monotonic() + args.max_seconds
    try:
        await server.wait_live(args.startup_timeout)
        # Warm the app once (first-run imports, JIT-like caches) before the baseline.
        warm = Session(server, random.Random(0), args)
        await warm.open()
        await warm.close()
        args.page_models = warm.models
        await asyncio.sleep((args.session_lifetime_ms + 2 * args.check_unused_ms) / 1000 + 2)
        print(f"server {server.url} pids {server.pids}: {server.rss():.0f} MiB RSS after warm-up",
              file=sys.stderr)
        for i, n in enumerate(args.sessions):
            if time.monotonic() > deadline:
                print(f"stopping: --max-seconds {args.max_seconds} reached", file=sys.stderr)
                break
            row = await run_round(server, n, args, seed=args.seed + i)
            rows.append(row)
            print(f"N={n}: done in {row['moves_s']:.0f} s, {row['errors']} errors",
                  file=sys.stderr)
            if args.json:  # written after every round, so a stopped run keeps its rounds
                Path(args.json).write_text(json.dumps(rows, indent=2))
    finally:
        server.stop()
    return rows


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sessions", type=lambda s: [int(x) for x in s.split(",")],
                   default=[10, 30, 60], help="comma-separated session counts (default 10,30,60)")
    p.add_argument("--moves", type=int, default=5, help="slider moves per session (default 5)")
    p.add_argument("--ramp-s", type=float, default=20.0,
                   help="spread the N session openings over this many seconds (default 20)")
    p.add_argument("--think-s", type=float, default=1.0,
                   help="mean pause between a session's moves, s (default 1)")
    p.add_argument("--slider", action="append", default=[],
                   help="only move sliders whose title contains this (repeatable)")
    p.add_argument("--exclude-slider", action="append",
                   default=["speed", "time (drag to scrub)"],
                   help="never move sliders with this title (default: the animation's "
                        "'speed' and time scrub, which only drive the animation in the "
                        "browser and get no answer from the server)")
    p.add_argument("--app", default=str(ROOT / "app" / "main.py"), help="app to serve")
    p.add_argument("--url", help="use a running loopback server, e.g. http://127.0.0.1:5006/main")
    p.add_argument("--server-pid", type=int, action="append",
                   help="its process id, for memory and CPU (with --url); repeat it for each "
                        "process behind a proxy")
    p.add_argument("--backend", action="append",
                   help="with --url of a proxy: a process's own base URL, e.g. "
                        "http://127.0.0.1:5107, asked for its session count (repeatable)")
    p.add_argument("--port", type=int, help="port for the started server (default: free)")
    p.add_argument("--num-procs", type=int, default=1)
    # The classroom's defaults (scripts/serve.sh): a closed tab's session is gone within 10 s.
    p.add_argument("--session-lifetime-ms", type=int, default=6000,
                   help="the started server's unused-session lifetime (default 6000, "
                        "scripts/serve.sh's)")
    p.add_argument("--check-unused-ms", type=int, default=2000,
                   help="how often it looks for unused sessions (default 2000, serve.sh's)")
    p.add_argument("--gone-limit-s", type=float, default=10.0,
                   help="a round whose closed sessions are not all discarded this long after "
                        "the close counts an error (default 10)")
    p.add_argument("--after-s", type=float, default=10.0,
                   help="s from the sessions' discard to reading memory 'after' (default 10: "
                        "the server collects their cycles ~7 s after the last one ends)")
    p.add_argument("--move-timeout", type=float, default=30.0, help="s per move before an error")
    p.add_argument("--quiet-ms", type=float, default=300.0,
                   help="a move has settled after this long without a patch")
    p.add_argument("--request-timeout", type=float, default=300.0)
    p.add_argument("--round-timeout", type=float, default=300.0, help="s for one N's moves")
    p.add_argument("--startup-timeout", type=float, default=120.0)
    p.add_argument("--max-seconds", type=float, default=1200.0, help="stop starting new rounds")
    p.add_argument("--measure-clicks", type=int, default=0,
                   help="one more session clicks 'Measure the trade' this many times at most "
                        "while the others move (default 0: none)")
    p.add_argument("--measure-every", type=float, default=0.2,
                   help="s between its clicks (default 0.2)")
    p.add_argument("--measure-query", default="scene=10&tend=5000",
                   help="that session's page query (default scene=10&tend=5000)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--log", default="/tmp/load-server.log", help="server log file")
    p.add_argument("--json", help="also write the results to this JSON file")
    args = p.parse_args(argv)
    if max(args.sessions) > 200:
        p.error("at most 200 sessions per round")
    if args.moves > 50:
        p.error("at most 50 moves per session")
    if not 0 <= args.measure_clicks <= 1000 or args.measure_every <= 0:
        p.error("--measure-clicks must be in [0, 1000] and --measure-every > 0")
    if args.url and not args.server_pid:
        print("no --server-pid: memory is not measured", file=sys.stderr)
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    AsyncHTTPClient.configure(None, max_clients=max(args.sessions) + 10)
    rows: list[dict] = []
    try:
        rows = asyncio.run(main_async(args))
    except Exception as exc:  # noqa: BLE001
        print(f"run stopped: {type(exc).__name__}: {exc}", file=sys.stderr)
        if args.json and Path(args.json).exists():
            rows = json.loads(Path(args.json).read_text())
    target = (f"server {args.url} ({len(args.server_pid or [])} pids)" if args.url
              else f"--num-procs {args.num_procs}")
    print(f"\n{args.moves} moves per session (think time ~{args.think_s} s), openings spread "
          f"over {args.ramp_s} s, {target}, unused-session lifetime "
          f"{args.session_lifetime_ms} ms.\n"
          "open: GET page -> document pulled; move: slider release -> plot data patch "
          "received;\ncpu/open, cpu/move: server CPU seconds per session opened / per move; "
          "RSS: server resident memory\n(base before, peak with N open, per session = "
          "(peak - base)/N, after = once the server discarded them);\n"
          "moves: with a data patch / all; live: Panel's live sessions while open > after;\n"
          "gone: s from the sessions' close until the server had discarded them all;\n"
          "srv cpu: server CPU (cores) during the round; others: cores used by other processes "
          f"on this machine ({os.cpu_count()} cores) during it;\nclicks: 'Measure the trade' "
          f"clicks sent by one more session ({args.measure_query}), every "
          f"{args.measure_every} s while the others moved.\n")
    print_table(rows)
    print(f"\na new session's default page: {getattr(args, 'page_models', 'n/a')} Bokeh models")
    return 0 if rows and all(r["errors"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
