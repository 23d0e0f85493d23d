"""The bounded stores of the server's solves, each least recently used first out and safe
to share between threads: solutions by what was solved, the reference solves runs are
measured against, regime maps. Each is bounded in entries and, where an entry's size
varies (a solution: ~0.2 MiB for a rigid scene's run, over 1 MiB for a deformable stop's
long run), in bytes.

One :class:`SolveCache` serves a :class:`app.solve.pool.Solver` (the server's is shared by
all its sessions); a test gives its solver one of its own, so that no other test's answer
is found in it.

>>> kept = Lru(2)
>>> kept.put("a", 1); kept.put("b", 2); kept.get("a"); kept.put("c", 3)
1
>>> kept.get("b") is None, len(kept)
(True, 2)
"""

from __future__ import annotations

import dataclasses
import sys
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Mapping
from typing import Any

import numpy as np

from core import Result, Status

#: Cached solves kept (shared by all sessions of the server process) ...
CACHE_ITEMS = 256
#: ... and their bytes at most (:func:`estimated_bytes`): what a server process keeps
#: after a class has left, beside its idle size (~140 MiB for the page process).
CACHE_BYTES = 32 * 2**20
#: Reference solves kept (:func:`app.solve.measure.measure_run`: 45 ms on scene 10's stop,
#: as long as a switch solve at standard): two, so that a class's sessions on other
#: scenes do not hold more.
REFERENCE_ITEMS = 2


class Lru:
    """At most ``items`` values by key (and at most ``max_bytes`` of them by
    :func:`estimated_bytes`, if given), the least recently used dropped first."""

    def __init__(self, items: int, max_bytes: int | None = None) -> None:
        self.items = items
        self.max_bytes = max_bytes
        self._data: OrderedDict[Hashable, Any] = OrderedDict()
        self._sizes: dict[Hashable, int] = {}
        self._bytes = 0
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._data)

    @property
    def bytes(self) -> int:
        """Estimated bytes of the values kept (0 when the store has no byte bound)."""
        return self._bytes

    def get(self, key: Hashable) -> Any:
        """The value of ``key`` (now the most recently used), or ``None``."""
        with self._lock:
            value = self._data.get(key)
            if value is not None:
                self._data.move_to_end(key)
            return value

    def put(self, key: Hashable, value: Any) -> None:
        """Keep ``value`` for ``key``, dropping the least recently used past ``items`` (or
        ``max_bytes``); a value larger than ``max_bytes`` alone is not kept."""
        size = estimated_bytes(value) if self.max_bytes is not None else 0
        with self._lock:
            self._forget(key)
            if self.max_bytes is not None and size > self.max_bytes:
                return
            self._data[key] = value
            self._sizes[key] = size
            self._bytes += size
            while len(self._data) > self.items or (
                    self.max_bytes is not None and self._bytes > self.max_bytes):
                self._forget(next(iter(self._data)))

    def _forget(self, key: Hashable) -> None:
        if key in self._data:
            del self._data[key]
            self._bytes -= self._sizes.pop(key)

    def get_or_make(self, key: Hashable, make: Callable[[], Any]) -> Any:
        """The value of ``key``, or ``make()``'s, kept (made outside the lock: two threads
        may make the same value once each)."""
        value = self.get(key)
        if value is None:
            value = make()
            self.put(key, value)
        return value


class SolveCache:
    """Solutions by ``(key, preview)`` and the reference solves of their measurements.

    Parameters
    ----------
    items : int
        Solutions kept.
    references : int
        Reference solves kept.
    max_bytes : int
        Bytes of solutions kept (:func:`estimated_bytes`).
    """

    def __init__(self, items: int = CACHE_ITEMS, references: int = REFERENCE_ITEMS,
                 max_bytes: int = CACHE_BYTES) -> None:
        self.solutions = Lru(items, max_bytes)
        self.references = Lru(references)

    def get(self, key: tuple, preview: bool) -> Any:
        """The solution kept for ``key`` (a preview or not), or ``None``."""
        return self.solutions.get((key, preview))

    def keep(self, key: tuple, preview: bool, solution: Any) -> None:
        """Keep ``solution``, unless the core cut it short at its budget (asking again may
        get further)."""
        result = solution.result
        if result is None or result.status is not Status.TIME_BUDGET:
            self.solutions.put((key, preview), solution)

    def reference(self, inputs: tuple, make: Callable[[], Result]) -> Result:
        """The reference solve of ``inputs`` ``(osc, stop, t_end, x0, v0)``, or
        ``make()``'s, kept for the other methods and presets of the same scene."""
        return self.references.get_or_make(inputs, make)


#: Elements of a long sequence whose sizes are measured; the rest are taken to be alike.
_SIZE_SAMPLE = 16
#: An array's own size without its data.
_ARRAY_HEADER = sys.getsizeof(np.empty(0))


def estimated_bytes(value: Any, _depth: int = 0) -> int:
    """The memory ``value`` holds, estimated: arrays by their bytes; dataclasses, mappings,
    sequences and other objects by their parts (a long sequence from its first
    :data:`_SIZE_SAMPLE` elements); anything else by :func:`sys.getsizeof`. A part shared
    by two values counts in each.

    >>> estimated_bytes(np.zeros(1000)) >= 8000
    True
    """
    if isinstance(value, np.ndarray):
        return value.nbytes + _ARRAY_HEADER
    if _depth > 6:
        return sys.getsizeof(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        parts: Any = [getattr(value, f.name) for f in dataclasses.fields(value)]
    elif isinstance(value, Mapping):
        parts = [*value.keys(), *value.values()]
    elif isinstance(value, (list, tuple, set, frozenset)):
        parts = list(value)
    elif hasattr(value, "__dict__") and not callable(value):
        parts = list(vars(value).values())
    else:
        return sys.getsizeof(value)
    own = sys.getsizeof(value)
    if len(parts) > _SIZE_SAMPLE:
        sample = sum(estimated_bytes(p, _depth + 1) for p in parts[:_SIZE_SAMPLE])
        return own + sample * len(parts) // _SIZE_SAMPLE
    return own + sum(estimated_bytes(p, _depth + 1) for p in parts)
