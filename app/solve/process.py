"""A solve in a child process: it holds neither the server's interpreter lock nor any
session's event loop, and a solve nobody waits for any more is stopped.

A deformable stop's integrated contact, ``event`` and ``switch`` hold the interpreter's lock
for as long as they integrate (seconds for a stiff, sharp stop at "precise"); run in a
thread of the server, they slow every other session's replies. Here such solves run in
worker processes started by the standard library's *forkserver* (:mod:`multiprocessing`,
public API only): the fork server imports :mod:`core` and what the server's main script
imports once, so a worker starts in milliseconds with everything loaded. A worker takes
one call after another and waits, idle, between them: a process per solve cost each
release ~20 ms (starting, ending, and a solve in a fresh process runs slower until the
pages it touches are its own; benchmarks/results/2026-11-28-solve-workers.md). Ending a
worker (``terminate``) is how a solve is cancelled; another takes its place. Workers are
daemons: they end with the server.

``FIE_SOLVE_PROCESSES=off`` in the environment solves in the calling thread instead (for a
platform without ``fork``, or to compare).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import sys
import threading
import time
import types
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

log = logging.getLogger(__name__)

#: The environment variable that turns the child processes off.
SWITCH = "FIE_SOLVE_PROCESSES"
#: How often [s] a waiting thread looks whether its solve was abandoned.
POLL_S = 0.02
#: How long [s] a finished or stopped child may take to exit before it is left to the OS.
JOIN_S = 2.0


class Abandoned(RuntimeError):
    """Nobody waits for the solve any more: its process was stopped."""


class Deadline:
    """A :func:`call`'s ``cancelled`` that is set ``seconds`` from now, or when ``also`` (a
    stop of its own, e.g. the session's) is set: the call's budget, whatever the solve.

    >>> Deadline(60.0).is_set(), Deadline(0.0).is_set()
    (False, True)
    """

    def __init__(self, seconds: float, also: threading.Event | Deadline | None = None
                 ) -> None:
        self.at, self.also = time.monotonic() + seconds, also

    def is_set(self) -> bool:
        return time.monotonic() >= self.at or (self.also is not None and self.also.is_set())

    def left(self) -> float:
        """Seconds until the deadline (negative past it)."""
        return self.at - time.monotonic()


@dataclass(frozen=True)
class Caller:
    """Calls ``fn`` for one solve: in a child process (``isolated``, by :func:`call`,
    abandoned when ``cancelled`` is set) or in the calling thread (where nothing stops it).

    ``fn`` is called by reference in the child: a module-level function (tests pass a
    probe in place of :func:`core.simulate`).

    >>> Caller(max)(2, 3), Caller(max, isolated=False).until(1.0).cancelled.is_set()
    (3, False)
    """

    fn: Callable[..., Any]
    isolated: bool = False
    cancelled: threading.Event | Deadline | None = None

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        if self.isolated:
            return call(self.fn, *args, cancelled=self.cancelled, **kwargs)
        return self.fn(*args, **kwargs)

    def until(self, seconds: float) -> Caller:
        """This caller, its calls also abandoned ``seconds`` from now."""
        return replace(self, cancelled=Deadline(seconds, self.cancelled))


def running() -> bool:
    """Whether solves now run in child processes (enabled, and the fork server is up)."""
    return enabled() and _ready.is_set()


def enabled() -> bool:
    """Whether solves run in child processes (:data:`SWITCH` is not ``off``)."""
    return (os.environ.get(SWITCH, "on").strip().lower() not in {"off", "0", "false", "no"}
            and "forkserver" in multiprocessing.get_all_start_methods())


#: The project's root: a child imports ``core`` and ``app`` from there.
PROJECT = str(Path(__file__).resolve().parents[2])


def _project_on_path() -> None:
    """Put :data:`PROJECT` on ``sys.path``, which a child copies when it starts (Bokeh runs
    the page's script with the path it puts there and restores the path afterwards)."""
    if PROJECT not in sys.path:
        sys.path.append(PROJECT)


_CONTEXT: Any = None
_CONTEXT_LOCK = threading.Lock()


def _main_imports() -> list[str]:
    """The modules the main script's names come from.

    A child runs the parent's main script again (as ``__mp_main__``) before it unpickles
    its work; under ``panel serve`` that script imports Panel, which took a child ~1 s.
    With those modules preloaded by the fork server the second run finds them imported.
    (Preloading ``__main__`` itself does not help: the fork server is never told its path.)
    """
    main = sys.modules.get("__main__")
    names = set()
    for value in vars(main).values() if main is not None else ():
        name = value.__name__ if isinstance(value, types.ModuleType) else getattr(
            value, "__module__", None)
        if isinstance(name, str) and not name.startswith(("__main__", "_")) and (
                name != "builtins"):
            names.add(name)
    return sorted(names)


def _context():
    """The forkserver context, its preloads set once: this module, ``core`` and what the
    main script imports, so that a child starts with all of it loaded."""
    global _CONTEXT
    with _CONTEXT_LOCK:
        if _CONTEXT is None:
            context = multiprocessing.get_context("forkserver")
            context.set_forkserver_preload([*_main_imports(), __name__, "core"])
            _CONTEXT = context
        return _CONTEXT


#: Idle workers kept at most (the integrating lane's threads call one each at a time).
IDLE_WORKERS = 2
#: Calls a worker takes before it is replaced: what a solve leaves allocated stays bounded.
CALLS_PER_WORKER = 100
#: How much lower a worker's scheduling priority is than the server's (``nice``): on a busy
#: machine the server's event loop, which answers every session's slider, gets a core before
#: a long solve does (Linux gives nice 5 about a third of nice 0's share of a shared core).
WORKER_NICE = 5


def _serve(tasks, answers) -> None:
    """A worker's loop, at :data:`WORKER_NICE`: receive ``(fn, args, kwargs)``, send back
    ``(True, value)`` or ``(False, error)``; end when the server closes its end of ``tasks``."""
    try:
        os.nice(WORKER_NICE)
    except OSError:  # not allowed here: the worker keeps the server's priority
        pass
    while True:
        try:
            fn, args, kwargs = tasks.recv()
        except (EOFError, OSError):
            return
        try:
            answer = (True, fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - the server raises it again
            answer = (False, exc)
        answers.send(answer)


class _Worker:
    """One worker process and the two pipes to it."""

    def __init__(self) -> None:
        context = _context()
        tasks_r, self.tasks = context.Pipe(duplex=False)
        self.answers, answers_w = context.Pipe(duplex=False)
        self.process = context.Process(target=_serve, args=(tasks_r, answers_w),
                                       daemon=True, name="fie-solve")
        self.process.start()
        # The worker holds the only other ends: its exit ends the pipes.
        tasks_r.close()
        answers_w.close()
        self.calls = 0

    def retire(self, stop: bool = False) -> None:
        """End the worker (at once with ``stop``), off the caller's path."""
        def end() -> None:
            for conn in (self.tasks, self.answers):
                conn.close()
            if stop:
                self.process.terminate()
            self.process.join(JOIN_S)
            if self.process.is_alive():
                self.process.kill()
                self.process.join(JOIN_S)

        threading.Thread(target=end, name="fie-solve-end", daemon=True).start()


_idle: list[_Worker] = []
_idle_lock = threading.Lock()


def _take() -> _Worker:
    with _idle_lock:
        while _idle:
            worker = _idle.pop()
            if worker.process.is_alive():
                return worker
            worker.retire()
    return _Worker()


def _give_back(worker: _Worker) -> None:
    """Keep ``worker`` for the next call, unless enough wait or it has taken its share."""
    with _idle_lock:
        if worker.calls < CALLS_PER_WORKER and len(_idle) < IDLE_WORKERS:
            _idle.append(worker)
            return
    worker.retire()


def _start_spare() -> None:
    """Start a worker in the background and keep it idle for the next call."""
    def start() -> None:
        try:
            _give_back(_Worker())
        except (OSError, RuntimeError) as exc:  # the next call starts one, or says why
            log.warning("no spare solver process: %s", exc)

    threading.Thread(target=start, name="fie-solve-spare", daemon=True).start()


_warmed = threading.Event()
#: Set once the fork server runs: until then a solve runs in the calling thread instead of
#: waiting ~2 s for it (the page's first solve comes before that).
_ready = threading.Event()


def warm_up(wait: bool = False) -> None:
    """Start the fork server, in the background unless ``wait``, so that the first solve
    does not pay for its imports (~2 s; once per process, later calls do nothing)."""
    if not enabled():
        return
    if _warmed.is_set():
        if wait:
            _ready.wait(JOIN_S * 10)
        return
    _warmed.set()

    def start() -> None:
        _project_on_path()
        try:
            worker = _Worker()  # starts the fork server, then waits for the first solve
        except (OSError, RuntimeError) as exc:  # no fork server here: threads it is
            log.warning("solves run in the server's threads: no child process (%s)", exc)
            return
        _give_back(worker)
        _ready.set()

    if wait:
        start()
    else:
        threading.Thread(target=start, name="fie-warm-up", daemon=True).start()


def call(fn: Callable[..., Any], *args: Any,
         cancelled: threading.Event | Deadline | None = None,
         **kwargs: Any) -> Any:
    """``fn(*args, **kwargs)`` in a child process; this thread waits without the
    interpreter's lock.

    ``fn`` and its arguments and answer must pickle (``fn`` by reference: a module-level
    function). With the processes turned off (:func:`enabled`), or before the fork server
    runs (:func:`warm_up`, which this starts), ``fn`` runs here.

    Raises
    ------
    Abandoned
        ``cancelled`` was set while the solve ran (the child was stopped).
    Exception
        What ``fn`` raised, raised again here.
    RuntimeError
        The child ended without an answer (killed, out of memory).
    """
    if not enabled():
        return fn(*args, **kwargs)
    if not _ready.is_set():
        warm_up()
        return fn(*args, **kwargs)
    _project_on_path()
    worker = _take()
    try:
        worker.tasks.send((fn, args, kwargs))
    except OSError:  # it had ended while idle: a new one
        worker.retire()
        worker = _Worker()
        worker.tasks.send((fn, args, kwargs))
    except BaseException:  # the call did not pickle: nothing was sent, the worker waits
        _give_back(worker)
        raise
    answered = False
    try:
        while not worker.answers.poll(POLL_S):
            if cancelled is not None and cancelled.is_set():
                raise Abandoned("the solve was abandoned")
        try:
            ok, value = worker.answers.recv()
        except EOFError:
            worker.process.join(JOIN_S)
            raise RuntimeError(f"the solver process ended without an answer (exit code "
                               f"{worker.process.exitcode})") from None
        answered = True
    finally:
        if answered:
            worker.calls += 1
            _give_back(worker)
        else:  # abandoned, or it died: it goes, another takes its place
            worker.retire(stop=True)
            _start_spare()
    if ok:
        return value
    raise value
