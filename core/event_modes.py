"""The modes of the non-smooth model as the event method integrates them, and their events.

Each mode is a smooth ODE (paper Eqs. 3-6, Eq. 14 in contact) integrated by
:mod:`core.event_method` until one of its events; here its right-hand side
(:func:`slip_rhs`), its event functions (:func:`slip_events`) and the end of stick inside a
deformable contact (:func:`stick_contact_end`).

* **slip** with a fixed ``s`` (``x'' = -x + s*a - phi``, paper Eq. 3 and Eq. 14 in contact):
  ``x' = v`` (relative velocity vanishes: stick if ``|x + phi| <= b``, else the sign of the
  relative velocity changes, ``docs/physics.md``); ``x = clearance`` with ``x' > 0`` (rigid
  impact, paper Eq. 8, or the start of a deformable contact); in a deformable contact,
  ``x' = 0`` (reversal of the overlap rate: the branch of the hysteresis law is updated with
  :func:`core.deformable.law.reverse`), ``x = clearance`` with ``x' < 0`` (separation), the force
  reaching the stop's strength (failure), the overlap reaching the limit overlap. A
  non-terminal event at ``x' = 0`` records every maximum of ``x`` as a point, so ``x_max``
  has the integration accuracy, and betrays a crossing of the stop that rose above it and
  fell back inside one step.
* the force of a contact has **kinks**: where a branch's curve is clipped to an envelope
  (Eq. 11; :func:`core.deformable.law.branch_kinks`) and at the face. A step across a kink does
  not see it in its error estimate: each separation speed was ~3e-7 relative off at rtol
  1e-8, and trains of contacts added those up in their phase (1e-3 of the scale by t = 40
  on random stops). A step that crosses a clip point is not kept: the solver steps to it
  in a segment of its own (the event ``kink``, :class:`core.numerics.events.Event`); past
  the face the force is ``phi_C`` continued, as in the exact method, so the step into
  separation is smooth. The error left grows with the contacts of a train (each one's
  timing error moves the next): up to 7e-5 of the scale by t = 40 at rtol 1e-8 on 120
  random stops, 3e-8 the median.
* **stick** (``x' = v``): in closed form, ``x = x_0 + v t``, up to ``x = b``, the stop, or in
  a deformable contact up to ``x + phi(x - clearance) = b`` (one monotone root by
  :func:`scipy.optimize.brentq`: along stick the overlap only grows, so the force follows
  one loading branch).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import brentq

from core.deformable.law import LIMIT_MARGIN, Branch, force_and_slope
from core.numerics.events import Event
from core.params import HystereticStop, RigidStop
from core.result import TransitionKind

#: An overlap within this fraction of the limit overlap ``D`` counts as reaching it (the
#: same for every method, :data:`core.deformable.law.LIMIT_MARGIN`).
LIMIT_OVERLAP_FRACTION = 1.0 - LIMIT_MARGIN
#: Relative tolerance of roots (event times, the stick-in-contact end point).
ROOT_RTOL = 4.0 * np.finfo(float).eps


def slip_rhs(s: int, a: float, c: float, stop: HystereticStop | None,
             branch: Branch | None) -> Callable:
    """Right-hand side ``f(t, (x, x'))`` of slip with sign ``s``: free (``branch`` None)
    or in a deformable contact on ``branch`` of the law (Eqs. 3 and 14)."""
    if branch is not None:
        kc = stop.k_c0 * stop.limit_overlap

        def fun(_t, y):
            d = y[0] - c
            if d > 0.0:
                p = force_and_slope(d, branch, stop)[0]
            else:
                # phi_C continued past the face, as the exact method does
                # (docs/contact-law.md): the step that crosses the face into separation
                # stays smooth; with the force cut to 0 it has a kink there.
                p = kc * d / (stop.limit_overlap - d)
            return np.array([y[1], -y[0] + s * a - p])

        return fun

    def fun_free(_t, y):
        return np.array([y[1], -y[0] + s * a])

    return fun_free


def slip_events(s: int, vb: float, c: float, stop: RigidStop | HystereticStop | None,
                branch: Branch | None, kink: float | None,
                acc: Callable[[float], float]) -> list[Event]:
    """Event functions of a slip segment with sign ``s`` on a belt at ``vb`` (see the
    module docstring): in a deformable contact on ``branch`` (else ``None``), with the next
    ``kink`` of its force to step to (or ``None``); ``acc(x)`` is the acceleration."""
    events = [
        Event("top", lambda _t, y: y[1], -1.0, terminal=False),
        Event("ur", lambda _t, y: y[1] - vb, 1.0 if s > 0 else -1.0),
        # where x' turns back from the belt's speed (SegmentIntegrator's speed watch: a step
        # whose speed passed it and came back, as on entering a contact just below it)
        Event("turn", lambda _t, y: acc(float(y[0])), -1.0 if s > 0 else 1.0,
              terminal=False),
    ]
    if stop is not None and branch is None:
        events.append(Event("stop", lambda _t, y: y[0] - c, 1.0))
    elif branch is not None:
        events += _contact_events(c, stop, branch, kink)
    return events


def _contact_events(c: float, stop: HystereticStop, branch: Branch,
                    kink: float | None) -> list[Event]:
    """The events that end slip inside a deformable contact: separation, reversal, the
    limit overlap, the next kink of the force, the stop's strength."""
    d_lim = stop.limit_overlap * LIMIT_OVERLAP_FRACTION
    events = [
        Event("separation", lambda _t, y: y[0] - c, -1.0),
        Event("reversal", lambda _t, y: y[1], -1.0 if branch.loading else 1.0),
        Event("limit", lambda _t, y: y[0] - c - d_lim, 1.0),
    ]
    if kink is not None:
        events.append(Event("kink", lambda _t, y: y[0] - kink,
                            1.0 if branch.loading else -1.0, kink=True))
    if math.isfinite(stop.strength):

        def fail(_t, y):
            d = y[0] - c
            phi = force_and_slope(d, branch, stop)[0] if d > 0.0 else 0.0
            return phi - stop.strength

        events.append(Event("failure", fail, 1.0))
    return events


def stick_contact_end(stop: HystereticStop, branch: Branch, x: float, b: float):
    """End of stick inside a deformable contact: ``x + phi = b`` (stick->slip), the force
    reaching the strength (``FAILURE``) or the limit overlap (``None``), whichever first.

    Along stick the overlap grows, so ``x + phi`` grows monotonically on the loading branch.
    """
    c, d_lim = stop.clearance, stop.limit_overlap
    x_hi = c + d_lim * LIMIT_OVERLAP_FRACTION

    def phi(xx: float) -> float:
        d = xx - c
        return force_and_slope(d, branch, stop)[0] if d > 0.0 else 0.0

    def g(xx: float) -> float:
        return xx + phi(xx) - b

    candidates = []
    if g(x) >= 0.0:
        return TransitionKind.STICK_SLIP, x
    if g(x_hi) > 0.0:
        candidates.append((brentq(g, x, x_hi, rtol=ROOT_RTOL), TransitionKind.STICK_SLIP))
    if math.isfinite(stop.strength):

        def gf(xx: float) -> float:
            return phi(xx) - stop.strength

        if gf(x) < 0.0 < gf(x_hi):
            candidates.append((brentq(gf, x, x_hi, rtol=ROOT_RTOL), TransitionKind.FAILURE))
    if not candidates:
        return None, x_hi
    x_e, kind = min(candidates, key=lambda p: p[0])
    return kind, x_e
