"""The impactless motion (paper Sec. 3; docs/physics.md, "Exact solution"): critical
speed, the stick-slip limit cycle, the first stick point and the impactless maximum."""

from __future__ import annotations

import math

from core.params import Oscillator
from core.scene_checks import check_oscillator, check_state
from core.theory.values import LimitCycle, Point

# --------------------------------------------------------------------------- impactless


def critical_speed(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> float:
    """Critical belt speed ``v* = sqrt((x0 - a)^2 + v0^2)`` (Eq. 25).

    It is the radius of the slip circle about ``(a, 0)`` through the start.

    Parameters
    ----------
    osc : Oscillator
    x0, v0 : float
        Initial displacement (a length) and velocity (a length, dimensionless time).

    Returns
    -------
    float
        ``v*`` (a length).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> round(critical_speed(osc), 12)
    0.2
    """
    x0, v0 = check_state(osc, x0, v0)
    return math.hypot(x0 - osc.a, v0)


def is_fast_belt(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> bool:
    """True for a fast belt, ``v > v*`` (Sec. 3.2): pure slip, no steady stick.

    ``v = v*`` counts as slow: the slip circle then touches the stick line and sticks.

    Examples
    --------
    >>> is_fast_belt(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25))
    True
    """
    return osc.v > critical_speed(osc, x0, v0)


def gamma0_radius(osc: Oscillator) -> float:
    """Radius ``v`` of the region Gamma_0 of Eq. (21), the open disc about ``(a, 0)``.

    Starts inside Gamma_0 are fast-belt starts: their slip circle never reaches ``x' = v``.

    Examples
    --------
    >>> gamma0_radius(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1))
    0.1
    """
    check_oscillator(osc)
    return osc.v


def impactless_limit_cycle(osc: Oscillator) -> LimitCycle:
    """The stick-slip limit cycle Gamma_LC of the impactless slow-belt motion (Eqs. 23-24).

    A stick segment at ``x' = v`` from ``(2a - b, v)`` to ``(b, v)``, then a clockwise slip
    arc about ``(a, 0)`` of radius ``R = sqrt((b-a)^2 + v^2)`` back to the segment's start.
    Measured clockwise from ``(b, v)`` to ``(2a - b, v)`` the arc spans ``pi + 2 beta`` with
    ``beta = atan2(v, b - a)``.

    Degenerate cases: ``mu_s = mu_k`` gives a zero-length stick and a full circle (period
    ``2 pi``); ``v = 0`` gives ``period = inf`` (the mass never leaves the stick).

    Examples
    --------
    >>> lc = impactless_limit_cycle(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1))
    >>> round(lc.x_max, 12), [round(c, 12) for c in lc.stick_start]
    (0.341421356237, [0.1, 0.1])
    """
    check_oscillator(osc)
    a, b, v = osc.a, osc.b, osc.v
    radius = math.hypot(b - a, v)
    slip_time = math.pi + 2.0 * math.atan2(v, b - a)
    stick_time = 2.0 * (b - a) / v if v > 0 else math.inf
    return LimitCycle(
        centre=(a, 0.0),
        radius=radius,
        stick_start=(2.0 * a - b, v),
        stick_end=(b, v),
        x_max=a + radius,
        stick_time=stick_time,
        slip_time=slip_time,
        period=stick_time + slip_time,
    )


def first_stick_point(osc: Oscillator) -> Point | None:
    """First slip->stick point from natural initial conditions (Eq. 30, minus root).

    From rest at the origin the mass slips on the circle about ``(a, 0)`` of radius ``a``;
    it first reaches ``x' = v`` at ``x = a - sqrt(a^2 - v^2)``. The extracted text prints
    ``+``, the far intersection, which the motion would reach only after passing the top.

    Returns
    -------
    (float, float) or None
        ``(a - sqrt(a^2 - v^2), v)`` when ``v <= a`` (slow belt), else None.

    Examples
    --------
    >>> x, xd = first_stick_point(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.12))
    >>> round(x, 12), xd
    (0.04, 0.12)
    """
    check_oscillator(osc)
    a, v = osc.a, osc.v
    if v > a:
        return None
    return (a - math.sqrt((a - v) * (a + v)), v)


def x_max_impactless(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> float:
    """Maximum displacement of the impactless steady motion (Sec. 3.2).

    * fast belt: ``a + sqrt((x0 - a)^2 + v0^2)`` (the slip circle through the start);
    * slow belt, ``v > 0``: the limit cycle's ``a + sqrt((b - a)^2 + v^2)``, whatever
      the start;
    * ``v = 0``: the position where the Coulomb-damped oscillation comes to rest.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> round(x_max_impactless(osc), 12)              # 2a from rest at the origin
    0.4
    >>> round(x_max_impactless(osc, x0=0.1), 12)      # the slip circle through (0.1, 0)
    0.3
    """
    x0, v0 = check_state(osc, x0, v0)
    if is_fast_belt(osc, x0, v0):
        return osc.a + critical_speed(osc, x0, v0)
    if osc.v > 0:
        return impactless_limit_cycle(osc).x_max
    return rest_position_still_belt(osc, x0, v0)


def rest_position_still_belt(osc: Oscillator, x0: float, v0: float) -> float:
    """Where the mass stops on a belt at rest (``v = 0``), or ``a + R`` if it never does.

    Each half swing is a half circle about ``(-s a, 0)`` with ``s`` the sign of ``x'``; it
    ends at ``x' = 0``, where the mass sticks iff ``|x| <= b``. Each half swing shrinks the
    amplitude by ``2a``, so the loop ends after at most ``|x0|/(2a) + 2`` swings when
    ``a > 0``; without kinetic friction the first turning point decides.
    """
    a, b = osc.a, osc.b
    if v0 == 0.0 and abs(x0) <= b:
        return x0
    if v0 != 0.0:  # move to the first turning point
        centre = -a if v0 > 0 else a
        radius = math.hypot(x0 - centre, v0)
        x = centre + radius if v0 > 0 else centre - radius
    else:
        x = x0
    while abs(x) > b:
        if a == 0.0:  # frictionless swings never end: report the amplitude
            return abs(x)
        x = 2.0 * a - x if x > 0 else -2.0 * a - x
    return x
