"""A solve in a child process of its own: it holds neither the server's interpreter lock nor
any session's event loop, and a solve nobody waits for any more is stopped.

A deformable stop's integrated contact, ``event`` and ``switch`` hold the interpreter's lock
for as long as they integrate (seconds for a stiff, sharp stop at "precise"); run in a
thread of the server, they slow every other session's replies. Here each such solve gets a
process started by the standard library's *forkserver* (:mod:`multiprocessing`, public
API only): the fork server imports the server's main module and :mod:`core` once, so a
child starts in milliseconds with everything loaded, and ending it (``terminate``) is how a
solve is cancelled. Children are daemons: they end with the server.

``FIE_SOLVE_PROCESSES=off`` in the environment solves in the calling thread instead (for a
platform without ``fork``, or to compare).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import sys
import threading
from collections.abc import Callable
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


def running() -> bool:
    """Whether solves now run in child processes (enabled, and the fork server is up)."""
    return enabled() and _ready.is_set()


def enabled() -> bool:
    """Whether solves run in child processes (:data:`SWITCH` is not ``off``)."""
    return (os.environ.get(SWITCH, "on").strip().lower() not in {"off", "0", "false", "no"}
            and "forkserver" in multiprocessing.get_all_start_methods())


#: The project's root: a child imports ``core`` and ``app`` from there.
PROJECT = str(Path(__file__).resolve().parent.parent)


def _project_on_path() -> None:
    """Put :data:`PROJECT` on ``sys.path``, which a child copies when it starts (Bokeh runs
    the page's script with the path it puts there and restores the path afterwards)."""
    if PROJECT not in sys.path:
        sys.path.append(PROJECT)


_CONTEXT: Any = None
_CONTEXT_LOCK = threading.Lock()


def _context():
    """The forkserver context, its preloads set once (``__main__`` first: a child then
    finds the server's main module imported and does not run it again)."""
    global _CONTEXT
    with _CONTEXT_LOCK:
        if _CONTEXT is None:
            context = multiprocessing.get_context("forkserver")
            context.set_forkserver_preload(["__main__", __name__, "core"])
            _CONTEXT = context
        return _CONTEXT


def _child(send, fn: Callable[..., Any], args: tuple, kwargs: dict) -> None:
    """The child's work: call ``fn`` and send back ``(True, value)`` or ``(False, error)``."""
    try:
        answer = (True, fn(*args, **kwargs))
    except Exception as exc:  # noqa: BLE001 - the parent raises it again
        answer = (False, exc)
    send.send(answer)
    send.close()


def _nothing() -> None:
    """A child that does nothing (starts the fork server)."""


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
            process = _context().Process(target=_nothing, daemon=True, name="fie-warm-up")
            process.start()
            process.join(JOIN_S * 10)
        except (OSError, RuntimeError) as exc:  # no fork server here: threads it is
            log.warning("solves run in the server's threads: no child process (%s)", exc)
            return
        _ready.set()

    if wait:
        start()
    else:
        threading.Thread(target=start, name="fie-warm-up", daemon=True).start()


def call(fn: Callable[..., Any], *args: Any, cancelled: threading.Event | None = None,
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
    context = _context()
    receive, send = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(send, fn, args, kwargs), daemon=True,
                              name="fie-solve")
    process.start()
    send.close()  # the child holds the only writing end: its exit ends the pipe
    try:
        while not receive.poll(POLL_S):
            if cancelled is not None and cancelled.is_set():
                raise Abandoned("the solve was abandoned")
        try:
            ok, value = receive.recv()
        except EOFError:
            process.join(JOIN_S)
            raise RuntimeError(f"the solver process ended without an answer (exit code "
                               f"{process.exitcode})") from None
    finally:
        receive.close()
        if cancelled is not None and cancelled.is_set():
            process.terminate()
        process.join(JOIN_S)
        if process.is_alive():
            process.kill()
    if ok:
        return value
    raise value
