"""The server's garbage-collector policy: long-lived objects kept out of full collections.

A full (generation 2) collection of CPython scans every tracked object, about 0.5 µs each
on the test machine. The imports alone leave about 160,000 of them and each session's page
adds about 50,000, so a full collection stalled the server for 100-150 ms with one session
and 440 ms with fifteen (``benchmarks/gc_pause.py``), now and then in the middle of a
slider release. None of those objects needs scanning while its session lives:

* once a page has loaded, everything alive is frozen (:func:`gc.freeze`), and the
  collections Python and Panel run by themselves scan only what was made since;
* an ended session's reference cycles are frozen with the rest, so they are freed by an
  explicit collection of everything (unfreeze, collect, freeze in one go, so that no page
  load freezes them again half-way): a second after the last session of a process has
  ended, or after :data:`COLLECT_AFTER_ENDS` sessions (or a quarter of those still open, if
  more) have ended since the last one. That collection scans every live session's objects
  (about 25 ms per session), so it is not run for every student who leaves; until it runs,
  each ended session keeps about 3.4 MiB (``benchmarks/results/2026-11-27-memory.md``).

Before, every session's end unfroze everything until a refreeze after Panel's own
collection; a page loading in that window froze the ended session's cycles before the
collection reached them, and as sessions kept ending and starting they were never freed
(about 100 MiB kept per class of 30).
"""

from __future__ import annotations

import asyncio
import ctypes
import ctypes.util
import gc
from typing import Any

import panel as pn

#: Sessions that may end, their cycles kept, before a collection frees them (at least:
#: a quarter of the sessions still open if that is more).
COLLECT_AFTER_ENDS = 8
#: Delay [s] from a session's end to the collection: the rest of a burst of ends (a class
#: leaving) is collected with it, and the session's own clean-up tasks have run.
COLLECT_DELAY_S = 1.0

_pending: dict[str, Any] = {"ended": 0, "handle": None}


def keep_long_lived_out_of_collections() -> None:
    """Freeze the live objects when this session's page has loaded; count its end towards
    the next collection (call while the session's page is built)."""
    pn.state.onload(freeze_live_objects)
    pn.state.on_session_destroyed(session_ended)


def freeze_live_objects() -> None:
    """Move every object the collector tracks to the permanent generation."""
    gc.freeze()


def session_ended(session_context: Any) -> None:
    """Count an ended session; schedule the collection of the ended sessions once enough
    have ended, or none is left (one per burst of ends)."""
    _pending["ended"] += 1
    live = live_sessions(session_context)
    if live and _pending["ended"] < max(COLLECT_AFTER_ENDS, live // 4):
        return  # kept, frozen, until the next collection
    try:
        loop = asyncio.get_running_loop()
    except RuntimeError:  # no event loop (a script): collect now
        collect_ended_sessions()
        return
    if _pending["handle"] is not None:
        _pending["handle"].cancel()
    _pending["handle"] = loop.call_later(COLLECT_DELAY_S, collect_ended_sessions)


def collect_ended_sessions() -> None:
    """Free the cycles of every ended session (a full collection of everything), then
    freeze what is left."""
    _pending["handle"] = None
    _pending["ended"] = 0
    gc.unfreeze()
    gc.collect()
    gc.freeze()
    give_back_freed_memory()


#: jemalloc's index for "every arena" in its ``arena.<i>.purge`` control (jemalloc 5).
JEMALLOC_ALL_ARENAS = 4096


def _jemalloc_purge() -> Any:
    """A call that purges every jemalloc arena, or None where jemalloc is not the C heap
    (``scripts/serve.sh`` preloads it, ``ALLOCATOR``)."""
    try:
        mallctl = ctypes.CDLL(None).mallctl
    except (OSError, AttributeError):
        return None
    mallctl.argtypes = [ctypes.c_char_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
                        ctypes.c_size_t]
    mallctl.restype = ctypes.c_int
    name = f"arena.{JEMALLOC_ALL_ARENAS}.purge".encode()
    return lambda: mallctl(name, None, None, None, 0) == 0


def _libc_malloc_trim() -> Any:
    """glibc's ``malloc_trim(0)``, or None (another C library, or none found)."""
    try:
        name = ctypes.util.find_library("c")
        trim = ctypes.CDLL(name).malloc_trim if name else None
    except (OSError, AttributeError):
        return None
    if trim is None:
        return None
    trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    return lambda: trim(0) >= 0  # 1: pages given back, 0: none to give


#: The C heap's call that gives its free pages back, and the heap's name.
HEAP, _GIVE_BACK = next(((heap, call) for heap, call in (("jemalloc", _jemalloc_purge()),
                                                         ("glibc", _libc_malloc_trim()))
                         if call is not None), ("unknown", None))


def give_back_freed_memory() -> bool:
    """Return the C heap's free pages to the system (jemalloc's purge of every arena, or
    glibc's ``malloc_trim(0)``); False where the C heap has no such call or it failed.

    With Python's own allocator (``ALLOCATOR=pymalloc``) that is the larger blocks only
    (arrays, serialised messages): Python keeps each 1 MiB arena that one surviving object
    sits in. With ``PYTHONMALLOC=malloc`` (``ALLOCATOR=jemalloc``, the default where
    jemalloc is installed, or ``malloc``) it is every object, and a process comes back to
    near its idle size after a class has left (docs/deploy.md, "Memory").
    """
    return _GIVE_BACK is not None and bool(_GIVE_BACK())


def ended_since_collection() -> int:
    """Sessions ended since the last collection of ended sessions."""
    return _pending["ended"]


def collection_scheduled() -> bool:
    """Whether a collection of ended sessions is scheduled on the event loop."""
    return _pending["handle"] is not None


def cancel_collection() -> None:
    """Cancel the scheduled collection, if any, and count ended sessions afresh (their
    cycles stay frozen until a later collection)."""
    if _pending["handle"] is not None:
        _pending["handle"].cancel()
    _pending["handle"] = None
    _pending["ended"] = 0


def live_sessions(session_context: Any) -> int | None:
    """Sessions still open in this process (Bokeh's ``ServerContext.sessions``; the ended
    one is no longer listed), or None where unknown (a script, a test)."""
    try:
        return len(session_context.server_context.sessions)
    except AttributeError:
        return None
