"""The server's garbage-collector policy: long-lived objects kept out of full collections.

A full (generation 2) collection of CPython scans every tracked object, about 0.5 µs each
on the test machine. The imports alone leave about 160,000 of them and each session's page
adds about 50,000, so a full collection stalled the server for 100-150 ms with one session
and 440 ms with fifteen (``benchmarks/gc_pause.py``), now and then in the middle of a
slider release. None of those objects needs scanning while its session lives:

* once a page has loaded, everything alive is frozen (:func:`gc.freeze`);
* when a session ends everything is unfrozen, so that the full collection Panel runs a few
  seconds later (``panel.io.document``, debounced by ``GC_DEBOUNCE``) frees that session's
  reference cycles; shortly after it, what survived is frozen again. A page that loads in
  between does not freeze: it would freeze the ended session's cycles before that
  collection reached them, and while sessions keep ending and starting (a class arriving
  as another leaves) they would never be freed (about 100 MiB kept per class of 30,
  ``benchmarks/results/2026-11-27-memory.md``). The refreeze itself collects first unless a
  full collection has run since the last session ended.

Objects made after the last freeze (each release's arrays, the models' new data) are
collected as usual. Garbage frozen by mistake (a cycle dropped between a freeze and the
next session's end) lives only until the refreeze after that session's end.
"""

from __future__ import annotations

import asyncio
import gc
from typing import Any

import panel as pn
import panel.io.document

#: Delay [s] from a session's end to the refreeze: after Panel's own collection.
REFREEZE_DELAY_S = getattr(panel.io.document, "GC_DEBOUNCE", 5) + 2.0

_refreeze: dict[str, Any] = {"handle": None}
#: Whether a full collection has run since the last session ended (gc.callbacks).
_collected: dict[str, bool] = {"since_unfreeze": True}


def _note_full_collection(phase: str, info: dict[str, Any]) -> None:
    if phase == "stop" and info.get("generation") == 2:
        _collected["since_unfreeze"] = True


if _note_full_collection not in gc.callbacks:
    gc.callbacks.append(_note_full_collection)


def keep_long_lived_out_of_collections() -> None:
    """Freeze the live objects when this session's page has loaded; unfreeze them when the
    session ends (call while the session's page is built)."""
    pn.state.onload(freeze_live_objects)
    pn.state.on_session_destroyed(unfreeze_objects)


def freeze_live_objects() -> None:
    """Move every object the collector tracks to the permanent generation, unless a
    refreeze is pending (a session has ended and its cycles are not yet collected)."""
    if _refreeze["handle"] is None:
        gc.freeze()


def unfreeze_objects(session_context: Any) -> None:
    """Return the frozen objects to the oldest generation (a session ended) and schedule
    the refreeze (one per burst of session ends)."""
    gc.unfreeze()
    _collected["since_unfreeze"] = False
    try:
        loop = asyncio.get_running_loop()
    except RuntimeError:  # no event loop (a script): nothing to schedule
        return
    if _refreeze["handle"] is not None:
        _refreeze["handle"].cancel()
    _refreeze["handle"] = loop.call_later(REFREEZE_DELAY_S, _refreeze_now)


def _refreeze_now() -> None:
    _refreeze["handle"] = None
    if not _collected["since_unfreeze"]:
        gc.collect()
    gc.freeze()
