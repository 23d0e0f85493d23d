"""The switch model of friction (paper Eq. 7): its acceleration and the width of its band.

The switch model (state ``(x, x')``, relative velocity ``u_r = v - x'``, applied force over
``k`` ``F = -x - phi``):

* ``|u_r| > eta`` (slip): ``x'' = F + s*a`` with ``s = sign(u_r)`` (paper Eq. 3);
* ``|u_r| <= eta`` and ``|F| <= b`` (stick): ``x'' = 0``, the belt's acceleration;
* ``|u_r| <= eta`` and ``|F| > b`` (stick->slip transition): ``x'' = F - b sign(F)``, static
  friction at its limit against the applied force, which takes the mass out of the band.

The band's half-width ``eta`` is checked against what the steps resolve
(:func:`eta_bounds`, :func:`check_eta`); :mod:`core.switch` integrates the model.
"""

from __future__ import annotations

import math

from core.deformable.law import LIMIT_MARGIN, Branch, force_and_slope
from core.params import HystereticStop, Oscillator
from core.validation import check_range

#: Default stick-band half-width relative to the belt speed, ``eta = ETA_REL * v``
#: (``eta << v``, ``docs/physics.md``); on a still belt relative to ``max(a, b)``.
ETA_REL = 1e-4
#: Widest stick band, relative to the belt speed (:func:`check_eta`).
ETA_MAX_REL = 0.1
#: Narrowest stick band, relative to the speed the steps resolve (``rtol v``, on a still
#: belt ``rtol max(a, b, u_s)``): a narrower band is missed by the located steps. At
#: rtol 1e-6, atol 1e-9, ``v = 0.1``, a band of 1e-10 (1e-3 of that speed) let the mass slip
#: through it, and the model reported pure slip for a stick-slip cycle (0.24 off in x); at
#: 1e-2 of it and above the model followed the exact motion (tests/core/test_exact.py).
ETA_MIN_PER_TOL = 1e-2
#: An overlap within this fraction of the limit overlap ``D`` counts as reaching it (the
#: same for every method, :data:`core.deformable.law.LIMIT_MARGIN`).
LIMIT_OVERLAP_FRACTION = 1.0 - LIMIT_MARGIN


def switch_rhs(osc: Oscillator, eta: float, stop: HystereticStop | None, branch: Branch | None):
    """The switch model's acceleration ``f(x, x')`` (paper Eq. 7 with Eq. 14 in contact).

    Parameters
    ----------
    osc : Oscillator
    eta : float
        Half-width of the stick band ``|v - x'| <= eta``.
    stop : HystereticStop or None
        Deformable stop whose contact force enters the applied force, or ``None``.
    branch : Branch or None
        Branch of the contact law held over the step.

    Returns
    -------
    callable
        ``f(x, v) -> x''``.

    Examples
    --------
    >>> f = switch_rhs(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1), 1e-5, None, None)
    >>> f(0.0, 0.0), f(0.1, 0.1), f(0.4, 0.1)   # slip, stick, stick->slip
    (0.2, 0.0, -0.10000000000000003)
    """
    a, b, vb = osc.a, osc.b, osc.v
    if stop is None or branch is None:

        def rhs(x: float, v: float) -> float:
            ur = vb - v
            if ur > eta:
                return a - x
            if ur < -eta:
                return -a - x
            if x < -b:
                return -x - b
            if x > b:
                return b - x
            return 0.0

        return rhs

    c = stop.clearance
    d_lim = stop.limit_overlap * LIMIT_OVERLAP_FRACTION

    def rhs_contact(x: float, v: float) -> float:
        d = x - c
        if d > 0.0:
            if d >= d_lim:
                return -math.inf
            force = -x - force_and_slope(d, branch, stop)[0]
        else:
            force = -x
        ur = vb - v
        if ur > eta:
            return force + a
        if ur < -eta:
            return force - a
        if force > b:
            return force - b
        if force < -b:
            return force + b
        return 0.0

    return rhs_contact


def band_edge(vb: float, eta: float, s: int) -> float:
    """The velocity where slip with sign ``s`` enters the stick band ``|vb - x'| <= eta``,
    rounded so that the band test holds for it (``vb - (vb - eta)`` may round above ``eta``).

    >>> v = band_edge(1e-5, 1e-9, 1); abs(1e-5 - v) <= 1e-9
    True
    """
    v = vb - s * eta
    while abs(vb - v) > eta:
        v = math.nextafter(v, vb)
    return v


def default_eta(osc: Oscillator) -> float:
    """The default stick band: :data:`ETA_REL` times the belt speed (on a still belt times
    ``max(a, b, u_s)``), before :func:`eta_bounds`."""
    scale = osc.v if osc.v > 0.0 else max(osc.a, osc.b, osc.u_s)
    return ETA_REL * scale


def eta_bounds(osc: Oscillator, rtol: float = 1e-6) -> tuple[float, float]:
    """The stick band's half-widths the switch model takes at the tolerance ``rtol``: at most
    :data:`ETA_MAX_REL` times the belt speed (the model needs ``eta << v``, docs/physics.md, "The
    switch model": a band that reaches ``x' = 0`` holds a mass at rest in "stick"; ``eta = v`` gave
    ``x_max = 0`` where the exact motion grazes the stop), at most 1 on a still belt; at least
    :data:`ETA_MIN_PER_TOL` times the speed the steps resolve.

    >>> [f"{e:.3g}" for e in eta_bounds(Oscillator(0.3, 0.2, 0.1))]
    ['1e-09', '0.01']
    """
    scale = osc.v if osc.v > 0.0 else max(osc.a, osc.b, osc.u_s)
    return ETA_MIN_PER_TOL * rtol * scale, ETA_MAX_REL * osc.v if osc.v > 0.0 else 1.0


def check_eta(eta: float, osc: Oscillator, rtol: float = 1e-6) -> float:
    """The stick band's half-width ``eta``, within :func:`eta_bounds`.

    >>> check_eta(0.1, Oscillator(0.3, 0.2, 0.1))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: eta must lie in [1e-09, 0.01] (at most a tenth of the belt speed ...); got 0.1
    """
    eta = check_range("eta", eta, 0.0, low_open=True)
    low, high = eta_bounds(osc, rtol)
    if not low <= eta <= high:
        limit = (f"at most a tenth of the belt speed v = {osc.v:g}: the stick band "
                 "|v - x'| <= eta must stay clear of x' = 0; " if osc.v > 0.0 else "")
        why = (f" ({limit}at least {ETA_MIN_PER_TOL:g} rtol "
               f"{'v' if osc.v > 0.0 else 'max(a, b, u_s)'} at rtol = {rtol:g}: a narrower "
               "band is missed by the located steps)")
        raise ValueError(f"eta must lie in [{low:.3g}, {high:.3g}]{why}; got {eta:g}")
    return eta
