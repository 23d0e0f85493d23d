"""One solve of the trade measurement (:mod:`app.solve.trade`) as a solver process runs it.

A solver process (:mod:`app.solve.process`) runs :func:`sampled` and sends back only what
the table needs: the positions at the compared times, the solve's wall time and the steady
state it found. A whole :class:`core.Result` of scene 10 to ``t_end = 5000`` pickles to
~8 MB; its positions at 1000 times to 8 kB. Only :mod:`numpy` and :mod:`core` are imported
here, which a solver process has loaded.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Sampled:
    """A solve at the compared times: wall time [s], positions, steady state, status."""

    seconds: float
    x: np.ndarray
    steady: Any
    status: str

    @property
    def verdict(self) -> str:
        """The steady state's kind, in words."""
        return self.steady.kind.value


def sampled(simulate: Callable[..., Any], osc: Any, stop: Any, t_end: float, x0: float,
            v0: float, t_eval: np.ndarray, method: str, options: dict[str, Any]) -> Sampled:
    """``simulate(osc, stop, t_end, x0, v0, t_eval=t_eval, method=method, **options)``
    (:func:`core.simulate`, passed by reference: tests put a probe in its place), timed,
    and its positions at ``t_eval``."""
    start = time.perf_counter()
    res = simulate(osc, stop, t_end, x0, v0, t_eval=t_eval, method=method, **options)
    seconds = time.perf_counter() - start
    return Sampled(seconds, positions_at(res, t_eval), res.steady, res.status.value)


def positions_at(res: Any, t_eval: np.ndarray) -> np.ndarray:
    """Positions of ``res`` at the times ``t_eval`` it was asked for (it adds its exact
    transition times to them)."""
    t = np.asarray(res.t)
    idx = np.clip(np.searchsorted(t, t_eval), 0, len(t) - 1)
    if np.array_equal(t[idx], t_eval):
        return np.asarray(res.x)[idx]
    return np.interp(t_eval, t, np.asarray(res.x))  # a result cut short: what it has
