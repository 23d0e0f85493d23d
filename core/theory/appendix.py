"""The paper's steady states from natural initial conditions (Appendix, Eqs. A.1-A.12;
docs/physics.md, "Closed-form results"): transition points, prediction, impact speeds."""

from __future__ import annotations

import math

import numpy as np

from core.params import Oscillator, RigidStop
from core.result import SteadyKind
from core.theory.regimes import analyse
from core.theory.values import Point, Prediction
from core.validation import check_integer

#: Most impact speeds :func:`impact_sequence` lists.
MAX_IMPACT_SPEEDS = 10_000_000


def steady_points(osc: Oscillator, stop: RigidStop | None) -> dict[str, Point]:
    """Named transition points ``(x, x')`` of the steady motion (Appendix, Eqs. A.1-A.12).

    For natural initial conditions. Keys, where they exist:

    * ``'P_impact_in'``, ``'P_impact_out'``: state just before / after the steady impact
      (A.1; A.2/A.7-A.8 for case a; A.3/A.10 for cases b and c).
    * ``'P_stick_start'``, ``'P_stick_end'``: ends of the steady stick segment (Eq. 24 for
      the limit cycle; A.9 rederived for case a; A.4/A.11 for case b, whose stick ends at
      the stop).
    * ``'P_limit'``: the point ``(x_bar, 0)`` that the impacts tend to in grazing and rest
      (A.5-A.6, A.12).

    Empty for pure slip and equilibrium (no finite set of cycle points).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> p = steady_points(osc, RigidStop(clearance=0.3, restitution=1.0))
    >>> [round(c, 12) for c in p["P_impact_in"]]
    [0.3, 0.173205080757]
    """
    return dict(analyse(osc, stop, 0.0, 0.0).points)


def steady_prediction(osc: Oscillator, stop: RigidStop | None) -> Prediction:
    """Closed-form steady state from natural initial conditions (Secs. 3-4).

    Periods are exact sums of stick times ``(x_end - x_start)/v`` and slip-arc angles;
    e.g. the fast-belt elastic cycle has ``2 arccos(1 - x_bar/a)`` (Sec. 4.1 with the
    missing factor 2 restored).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> pred = steady_prediction(osc, RigidStop(clearance=0.2, restitution=1.0))
    >>> pred.kind, round(pred.period, 12), pred.sequence
    ('periodic', 3.14159265359, ('impact',))
    """
    an = analyse(osc, stop, 0.0, 0.0)
    return Prediction(
        kind=an.kind.value,
        period=an.period,
        x_max=an.x_max,
        impact_speed=an.impact_speed,
        sequence=an.sequence,
        accumulation_time=an.accumulation_time,
    )


def impact_sequence(osc: Oscillator, stop: RigidStop | None, n: int) -> np.ndarray:
    """Approach speeds of the first ``n`` impacts from natural initial conditions.

    Where no stick separates the impacts (fast belt, Eqs. A.5-A.6; slow case c, A.12),
    ``w_h = r^h w_0`` with ``w_0`` the first approach speed (``sqrt(x_bar (2a - x_bar))``
    for a fast belt, ``v`` after a stick). Zeros mean the mass only touches the stop (or,
    after a rest, stays on it). In the periodic cases every impact is the steady one,
    ``w_h = w_0``. Empty when the stop is never reached.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> impact_sequence(osc, RigidStop(clearance=0.15, restitution=0.5), 3).round(12)
    array([0.1  , 0.05 , 0.025])
    """
    n = check_integer("n", n, 0, MAX_IMPACT_SPEEDS)
    an = analyse(osc, stop, 0.0, 0.0)
    if an.impactless or not math.isfinite(an.first_impact_speed):
        return np.zeros(0)
    w0 = an.first_impact_speed
    if an.kind is SteadyKind.PERIODIC:
        return np.full(n, w0)
    r = stop.restitution  # an impact happened, so stop is not None
    return w0 * r ** np.arange(n, dtype=float)
