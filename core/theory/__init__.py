"""Closed-form results of the paper for the rigid stop (Andreaus & Casini 2002, Secs. 3-4).

Everything here is a pure function of an :class:`~core.params.Oscillator`, an optional
:class:`~core.params.RigidStop` and the initial state ``(x0, v0)``, in the dimensionless
units of docs/physics.md, "Dimensionless form": time ``t = omega * tau``, lengths keep
their unit, and

    a = mu_k * u_s      (centre of the forward-slip circles)
    b = mu_s * u_s      (static friction limit)
    v = v_dr / omega    (belt speed, a length)

Forward slip (``x' < v``) runs clockwise on circles about ``(a, 0)`` in the phase plane
``(x, x')``; stick runs along the line ``x' = v`` while ``|x| <= b``; an impact at the stop
``x = x_bar`` maps ``x'`` to ``-r x'``. Every steady motion of the paper is made of these
three pieces, so its transition points and period follow from plane geometry. The module
derives them afresh instead of copying the printed formulas, whose symbols are garbled in
the extracted text; where the derivation disagrees with the print, the docstring says so.

Differences from the printed paper (docs/physics.md, "Misprints found"):

* Eq. (30): the first slip->stick point from rest is the ``-`` root,
  ``a - sqrt(a^2 - v^2)``.
* §4.1: the period of the fast-belt elastic impact cycle is ``2 arccos(1 - x_bar/a)``.
* Eq. (35): the critical clearance is ``x* = a + v sqrt(1 - r^2)``. After a stick->impact
  at speed ``v`` the rebound circle about ``(a, 0)`` has radius
  ``sqrt((x_bar - a)^2 + r^2 v^2)``; it reaches the stick line ``x' = v`` again iff that
  radius is at least ``v``, i.e. iff ``x_bar >= a + v sqrt(1 - r^2)``. This is also the
  condition under which the square root of Eq. (A.11) is real, and it gives ``x* = a`` for
  ``r = 1``, the elastic boundary between cases b and c (Eqs. 32-33). A value
  ``a + v / sqrt(1 - r^2)`` would be infinite for ``r = 1`` and contradict both.
* Eq. (A.9) is printed identical to Eq. (A.11). In case a the impact speed is not ``v`` but
  ``w = sqrt(v^2 + (b-a)^2 - (x_bar-a)^2)`` (Eq. A.7), so the stick onset is
  ``a - sqrt((x_bar-a)^2 + r^2 w^2 - v^2)``.
* Inelastic case a is periodic only while that square root is real. When ``x* > b`` there is
  a band ``b <= x_bar < x_a`` of case a in which the rebound circle misses the stick line
  and the motion grazes the stop instead (see :func:`classify`).
* §4.6: for natural initial conditions and ``x_bar < a - sqrt(a^2 - v^2)`` the stop is hit
  during the first slip, before any stick. With an elastic stop the steady motion is then
  the impact-slip cycle on the circle of radius ``a`` (as for a fast belt), not the case c
  cycle through ``(x_bar, +-v)``.
* Elastic case c (§4.2): the rebound circle through ``(x_bar, -v)`` comes back to the stop
  exactly on the stick line, at ``(x_bar, v)``; the paper counts one impact and one slip per
  period, and so does :func:`steady_prediction` (``('impact',)``), though the tangency
  lets a numerical solver see a zero-length stick there.
* Sec. 3.2: the steady ``x_max`` jumps at ``v = v*`` by ``sqrt((b-a)^2 + v*^2) - v*``; it is
  continuous there only when ``mu_s = mu_k``.

Layout: :mod:`~core.theory.impactless` (Sec. 3), :mod:`~core.theory.accumulation`
(the Zeno sum), :mod:`~core.theory.grid` (the one decision tree of the regimes,
vectorised), :mod:`~core.theory.regimes` (each regime's closed forms, :func:`classify`),
:mod:`~core.theory.appendix` (steady points and predictions), :mod:`~core.theory.values`.
"""

from core.theory.accumulation import accumulation_time
from core.theory.appendix import impact_sequence, steady_points, steady_prediction
from core.theory.grid import classify_grid
from core.theory.impactless import (
    critical_speed,
    first_stick_point,
    gamma0_radius,
    impactless_limit_cycle,
    is_fast_belt,
    x_max_impactless,
)
from core.theory.regimes import classify, x_star
from core.theory.values import LimitCycle, Prediction, Regime, RegimeGrid

__all__ = [
    "LimitCycle",
    "Prediction",
    "Regime",
    "RegimeGrid",
    "accumulation_time",
    "classify",
    "classify_grid",
    "critical_speed",
    "first_stick_point",
    "gamma0_radius",
    "impact_sequence",
    "impactless_limit_cycle",
    "is_fast_belt",
    "steady_points",
    "steady_prediction",
    "x_max_impactless",
    "x_star",
]
