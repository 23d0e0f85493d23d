"""The budget of a sweep of the page (:mod:`app.bifurcation`): its wall time, and the work
a page may ask for.

A sweep runs chunk by chunk in the solver's workers; without a budget a deformable stop's
diagram of 200,000 points (~0.1 s each) would keep a worker for hours while its tab is
open. So a sweep stops at :data:`SWEEP_BUDGET_S` with the values it has, and says so; and
before it starts its cost is estimated, points times the cost of a point
(:func:`point_cost_s`), and a sweep estimated past the budget is refused with the number of
points that fit.

>>> max_points(closed=False, t_end=80.0)  # a deformable stop to t = 80
937
>>> budget_note(estimate_s(1000, closed=True, t_end=200.0))
'about 0.025 s; at most 120 s: stops with what it has'
"""

from __future__ import annotations

import math

#: Wall-time budget [s] of one sweep (a bifurcation diagram or a simulated regime map),
#: from its start to its last chunk: past it the sweep stops with the values it has.
SWEEP_BUDGET_S = 120.0
#: Estimated wall time [s] of one point of a closed-form sweep (no stop or a rigid stop,
#: the exact method; its horizon is fixed): the slowest measured, 22.6 us per point
#: (benchmarks/results/sweep_speed_2026-11-23.md), rounded up.
CLOSED_POINT_S = 25e-6
#: Estimated wall time [s] of an integrated sweep's point per unit of simulated time (a
#: deformable stop, or the event or switch method: each point is a core.simulate): the
#: largest measured on scenes 2b, 10, 11 (deformable), 5a and 7c (event, switch) at their
#: horizons was 1.55 ms (0.10-1.55 ms; 6-124 ms per point), rounded up.
INTEGRATED_S_PER_TIME = 1.6e-3


def point_cost_s(*, closed: bool, t_end: float) -> float:
    """Estimated wall time [s] of one point of a sweep to ``t_end``."""
    return CLOSED_POINT_S if closed else INTEGRATED_S_PER_TIME * t_end


def estimate_s(points: int, *, closed: bool, t_end: float) -> float:
    """Estimated wall time [s] of a sweep of ``points`` points."""
    return points * point_cost_s(closed=closed, t_end=t_end)


def max_points(*, closed: bool, t_end: float) -> int:
    """Most points whose estimated sweep fits :data:`SWEEP_BUDGET_S`."""
    return max(int(math.floor(SWEEP_BUDGET_S / point_cost_s(closed=closed, t_end=t_end))), 0)


def check_cost(points: int, *, closed: bool, t_end: float) -> None:
    """A ``ValueError`` naming the points allowed for this run if ``points`` points are
    estimated to take longer than :data:`SWEEP_BUDGET_S`."""
    most = max_points(closed=closed, t_end=t_end)
    if points > most:
        raise ValueError(
            f"points must be at most {most} for this run (about "
            f"{point_cost_s(closed=closed, t_end=t_end):.2g} s each to t = {t_end:g}: the "
            f"sweep's budget of {SWEEP_BUDGET_S:g} s); got {points}. Fewer points, a "
            "narrower range or a shorter horizon t_end fit.")


def budget_note(estimate: float, partial: bool = True) -> str:
    """What a sweep's card says of its time before it starts (``partial``: what it has
    when stopped is shown)."""
    stops = ": stops with what it has" if partial else ""
    return f"about {estimate:.2g} s; at most {SWEEP_BUDGET_S:g} s{stops}"


def cut_note(done: int, total: int) -> str:
    """What a sweep's card says when the budget stopped it."""
    return (f"Stopped at the sweep's budget of {SWEEP_BUDGET_S:g} s after {done} of {total} "
            "values: the diagram shows what it has. Fewer points or a shorter horizon "
            "t_end finish within it.")
