"""Axis ranges computed on the server from the data it sends (all but the phase portrait's)."""

from __future__ import annotations

from typing import Any

import numpy as np
from bokeh.models import Range1d

from app.plots.columns import EMPTY_SPAN
from app.solve.solution import Solution

#: Fraction of the data span added to an axis range (half each side), and more for the
#: phase portrait's displacement (room for the theory points' labels).
RANGE_PADDING = 0.1
PHASE_X_PADDING = 0.15
#: A stop the motion does not reach is still shown (phase portrait, x(t)) when it lies
#: within this fraction of the motion's displacement span beyond it; a farther stop would
#: squeeze the motion into a corner (the readout then says the stop lies beyond x_max).
STOP_VIEW_REACH = 0.5


def data_bounds(arrays: tuple[Any, ...], padding: float) -> tuple[float, float]:
    """``(start, end)`` of an axis showing every finite value of ``arrays``, widened by
    ``padding`` times the span (half on each side, as ``DataRange1d.range_padding``).

    >>> data_bounds((np.array([0.0, 2.0]), [np.nan, 4.0]), 0.5)
    (-1.0, 5.0)
    >>> data_bounds(([3.0],), 0.1)
    (2.5, 3.5)
    """
    finite = [a[np.isfinite(a)] for a in (np.asarray(x, dtype=float).ravel() for x in arrays)]
    values = np.concatenate(finite) if finite else np.zeros(0)
    if len(values) == 0:
        return 0.0, 1.0
    lo, hi = float(values.min()), float(values.max())
    if hi - lo <= EMPTY_SPAN * max(abs(lo), abs(hi), 1.0):
        return lo - 0.5, hi + 0.5
    half = 0.5 * padding * (hi - lo)
    return lo - half, hi + half


def stop_in_view(x: Any, sol: Solution, length: float = 1.0) -> list[float]:
    """``[x_bar]`` if the stop should widen the displacement axes, else ``[]``: always when
    the motion reaches it, and when it lies within :data:`STOP_VIEW_REACH` of the motion's
    span beyond it; ``x`` and the answer in the page's units, ``length`` times the
    core's.

    >>> from types import SimpleNamespace as NS
    >>> stop_in_view([0.0, 0.2], NS(stop=NS(clearance=0.25)))
    [0.25]
    >>> stop_in_view([0.0, 0.2], NS(stop=NS(clearance=0.5)))
    []
    >>> stop_in_view([0.0, 0.2], NS(stop=None))
    []
    """
    if sol.stop is None:
        return []
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    if len(x) == 0:
        return []
    clearance = float(sol.stop.clearance) * length
    lo, hi = float(x.min()), float(x.max())
    return [clearance] if clearance <= hi + STOP_VIEW_REACH * (hi - lo) else []


def set_range(rng: Range1d, arrays: tuple[Any, ...], padding: float) -> None:
    """Show ``arrays`` in ``rng``; the reset tool returns to the same view."""
    start, end = data_bounds(arrays, padding)
    if (rng.start, rng.end, rng.reset_start, rng.reset_end) != (start, end, start, end):
        # Setting equal values sends nothing but still costs Bokeh's checks and change
        # bookkeeping; most ranges of a release (time axes, a fixed map) stay as they are.
        rng.update(start=start, end=end, reset_start=start, reset_end=end)

