"""The bounded stores of the server's solves, each least recently used first out and safe
to share between threads: solutions by what was solved, the reference solves runs are
measured against, regime maps.

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

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any

from core import Result, Status

#: Cached solves kept (shared by all sessions of the server process).
CACHE_ITEMS = 256
#: Reference solves kept (:func:`app.solve.measure.measure_run`: 45 ms on scene 10's stop,
#: as long as a switch solve at standard): two, so that a class's sessions on other
#: scenes do not hold more.
REFERENCE_ITEMS = 2


class Lru:
    """At most ``items`` values by key, the least recently used dropped first."""

    def __init__(self, items: int) -> None:
        self.items = items
        self._data: OrderedDict[Hashable, Any] = OrderedDict()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._data)

    def get(self, key: Hashable) -> Any:
        """The value of ``key`` (now the most recently used), or ``None``."""
        with self._lock:
            value = self._data.get(key)
            if value is not None:
                self._data.move_to_end(key)
            return value

    def put(self, key: Hashable, value: Any) -> None:
        """Keep ``value`` for ``key``, dropping the least recently used past ``items``."""
        with self._lock:
            self._data[key] = value
            self._data.move_to_end(key)
            while len(self._data) > self.items:
                self._data.popitem(last=False)

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
    """

    def __init__(self, items: int = CACHE_ITEMS, references: int = REFERENCE_ITEMS) -> None:
        self.solutions = Lru(items)
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
