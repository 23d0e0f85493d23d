"""The cycle a steady motion repeats: where it starts, how long it lasts, what it is made of.

For every method and every label (docs/physics.md, "Steady states"): a periodic steady
state repeats its fixed point's cycle exactly (paper Eq. 20); a grazing motion or a pure
slip circle repeats, from the time its transitions have settled, the last interval
between two transitions of one kind or one turn of the circle (:func:`steady_cycle`).
:func:`fold_times` tiles the rest of the horizon with a cycle; :func:`cycle_transitions`
lists the transitions of one period, or of the limit a grazing motion approaches.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from core.params import HystereticStop, RigidStop
from core.result import Result, SteadyKind, Transition, TransitionKind

#: Duration of one turn of a slip circle (dimensionless time, paper Eq. 7): the cycle of a
#: motion that settles on a circle without a transition to measure it by.
TURN = 2.0 * math.pi
#: Times within this fraction of a period of a cycle boundary are put on it (rounding of
#: the repeated transition times is ~1e-16 of the horizon; 1e-9 of a period moves a time
#: by nanoseconds of dimensionless time).
TILE_SNAP = 1e-9


def fold_times(
    t: np.ndarray, side: np.ndarray, t_from: float, cycle_t0: float, period: float
) -> tuple[np.ndarray, np.ndarray]:
    """Tile the horizon after ``t_from`` with the period ``[cycle_t0, cycle_t0 + period)``.

    Returns the times mapped into the stored motion and how many whole periods each was
    moved by (0 for times before the tiling). A time on a cycle boundary maps onto the
    cycle's start exactly (its right limit) or, for ``side = -1``, onto ``t_from``, the
    end of the stored motion (its left limit), never a rounding error beside them.

    Examples
    --------
    >>> folded, n = fold_times(np.array([1.0, 7.0, 9.0]), np.array([1, 1, -1]), 5.0, 3.0, 2.0)
    >>> folded.tolist(), n.tolist()
    ([1.0, 3.0, 5.0], [0.0, 2.0, 2.0])
    """
    late = (t > t_from) | ((t == t_from) & (side >= 0))
    tl = t[late]
    k = np.floor((tl - t_from) / period)
    shift = tl - t_from - k * period
    snap = TILE_SNAP * period
    wrap = shift >= period - snap
    k += wrap
    boundary = wrap | (shift <= snap)
    shift[boundary] = 0.0
    # Left limit at a boundary: the end of the previous period, where the stored motion
    # itself ends, rather than the transient's arrival at the cycle's start.
    end = boundary & (side[late] < 0)
    k -= end
    mapped = cycle_t0 + shift
    mapped[end] = t_from
    folded = np.array(t, dtype=float, copy=True)
    folded[late] = mapped
    n = np.zeros_like(folded)
    n[late] = k + 1.0
    return folded, n


class SteadyCycle(NamedTuple):
    """A cycle the motion repeats from ``t0`` on, every ``period``."""

    t0: float
    period: float


def settled_time(result: Result, step: tuple[float, float]) -> float:
    """Time of the first transition from which every later transition of the last one's
    kind lies within half a ``step`` (``(dx, dv)``, per axis of the phase plane) of the
    last one; ``inf`` when the last one is new and no steady state was found, and 0 for a
    motion without transitions that settles.

    >>> from core import Oscillator, simulate
    >>> res = simulate(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=2.0), t_end=20.0)
    >>> settled_time(res, (0.01, 0.01))
    0.0
    """
    trs = result.transitions
    if not trs:
        return math.inf if result.steady.kind is SteadyKind.NONE else 0.0
    last = trs[-1]
    same = [tr for tr in trs if tr.kind is last.kind]
    x = np.array([tr.x for tr in same])
    v = np.array([tr.v for tr in same])
    far = np.hypot((x - last.x) / step[0], (v - last.v) / step[1]) >= 0.5
    beyond = np.flatnonzero(far)
    first = int(beyond[-1]) + 1 if len(beyond) else 0
    if result.steady.kind is SteadyKind.NONE and first == len(same) - 1:
        return math.inf  # the last one is new: no sign of settling
    return same[first].t


def steady_cycle(result: Result, t_end: float, step: tuple[float, float]
                 ) -> SteadyCycle | None:
    """The cycle ``(t0, period)`` the motion repeats from ``t0`` on, to the horizon.

    Periodic: the steady state's cycle, exactly (paper Eq. 20). Grazing or a pure slip
    circle: from the time the transitions have settled within half a ``step``
    (:func:`settled_time`), the last interval between two transitions of one kind, or one
    :data:`TURN` of a slip circle; its later periods then trace the cycle's orbit in the
    phase plane to within that bound. ``None`` otherwise, or when the cycle does not close
    before ``t_end``.

    >>> from core import Oscillator, RigidStop, simulate
    >>> res = simulate(Oscillator(0.3, 0.2, 0.5), RigidStop(0.3, 1.0), t_end=50.0)
    >>> cycle = steady_cycle(res, 50.0, (0.01, 0.01))
    >>> cycle.period == res.steady.period
    True
    """
    steady = result.steady
    if steady.kind is SteadyKind.PERIODIC:
        if (math.isfinite(steady.period) and steady.period > 0
                and math.isfinite(steady.t_reached)
                and steady.t_reached + steady.period < t_end):
            return SteadyCycle(steady.t_reached, steady.period)
        return None
    if steady.kind not in (SteadyKind.GRAZING, SteadyKind.PURE_SLIP):
        return None
    t0 = settled_time(result, step)
    trs = result.transitions
    same = [tr.t for tr in trs if trs and tr.kind is trs[-1].kind and tr.t >= t0]
    period = same[-1] - same[-2] if len(same) >= 2 else TURN
    if not math.isfinite(t0) or t0 + period >= t_end or period <= 0:
        return None
    return SteadyCycle(t0, period)


def first_cycle_end(result: Result, t_end: float, step: tuple[float, float]) -> float:
    """Time at which the motion has run through its first steady cycle, from where it only
    retraces itself. Periodic: the end of the first period; a mass that comes to rest: the
    time it stops; otherwise (grazing, a pure slip circle, nothing found) one more
    :data:`TURN` after the transitions have settled within half a ``step``
    (:func:`settled_time`). Within ``[0, t_end]``."""
    steady = result.steady
    kind = steady.kind
    if kind is SteadyKind.PERIODIC and math.isfinite(steady.period) and math.isfinite(
            steady.t_reached):
        t_draw = steady.t_reached + steady.period
    elif kind in (SteadyKind.REST, SteadyKind.EQUILIBRIUM) and math.isfinite(
            steady.t_reached):
        # (no transition at all when the mass starts at rest)
        t_draw = max([steady.t_reached, *(tr.t for tr in result.transitions[-1:])])
    else:
        t_draw = settled_time(result, step) + TURN
    return float(min(t_end, max(t_draw, 0.0)))


def cycle_transitions(result: Result,
                      stop: RigidStop | HystereticStop | None = None) -> list[Transition]:
    """The transitions of one steady period: the ``transitions_per_period`` stored after
    ``steady.t_reached`` (periodic). A grazing motion gets its limit, at time ``nan``: on
    a rigid stop one impact of speed 0 at ``steady.x_max``; on a deformable ``stop`` whose
    law turns slow contacts elastic, the contact at the elastic speed
    ``steady.impact_speed``, its reversal at ``steady.x_max`` and its separation
    (:func:`core.steady.train_steady`). Empty for the other labels."""
    steady = result.steady
    if steady.kind is SteadyKind.GRAZING and isinstance(stop, HystereticStop) and (
            steady.impact_speed > 0.0 and math.isfinite(steady.x_max)):
        w, c, peak = steady.impact_speed, stop.clearance, steady.x_max
        return [Transition(TransitionKind.CONTACT, math.nan, c, w, w),
                Transition(TransitionKind.REVERSAL, math.nan, peak, 0.0, 0.0),
                Transition(TransitionKind.SEPARATION, math.nan, c, -w, -w)]
    if steady.kind is SteadyKind.GRAZING:
        return [Transition(TransitionKind.IMPACT, math.nan, float(steady.x_max), 0.0, 0.0)]
    if steady.kind is not SteadyKind.PERIODIC:
        return []
    stored = result.transitions
    times = np.fromiter((tr.t for tr in stored), float, len(stored))
    i0 = int(np.searchsorted(times, steady.t_reached, side="right"))
    return list(stored[i0 : i0 + steady.transitions_per_period])
