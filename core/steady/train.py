"""Trains of contacts and impacts whose label the contact law decides, not a tolerance.

A regular train of contacts on a deformable stop (:func:`train_contacts`) is periodic when
its contacts are elastic and approaches grazing when the law makes them lose energy
(:func:`train_steady`); a cycle of such contacts, or of inelastic rigid impacts alone,
is no fixed point however small its loss (:func:`train_loses`, :func:`impacts_lose`).
"""

from __future__ import annotations

import math

from core.deformable.law import ElasticLimit
from core.result import Steady, SteadyKind, Transition, TransitionKind

#: Contacts of a regular train (one reversal each, nothing else between them) its label is
#: read from: two flights to measure the period by, three speeds to see them fall.
TRAIN_CONTACTS = 3
#: The transitions of one contact of a regular train, in order.
TRAIN_CYCLE = (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION)


def train_contacts(tail: list[Transition]) -> list[Transition]:
    """The contacts of the regular train of a deformable stop the transitions end on: each
    contact one reversal and a separation, nothing else between them (no stick, no sign
    change: each contact starts with the law fresh and the belt pushing, each flight is the
    slip circle through the face). A ``reduced`` mark (a model laid contacts out) is
    skipped. Empty when the tail does not end on such a train."""
    tail = [tr for tr in tail if tr.kind is not TransitionKind.REDUCED]
    last = max((k for k, tr in enumerate(tail) if tr.kind is TransitionKind.CONTACT),
               default=None)
    if last is None:
        return []
    after = tuple(tr.kind for tr in tail[last:])
    if after != TRAIN_CYCLE[: len(after)]:
        return []
    k, found = last, [tail[last]]
    while k >= 3 and tuple(tr.kind for tr in tail[k - 3 : k]) == TRAIN_CYCLE:
        k -= 3
        found.append(tail[k])
    return found[::-1]


def train_loses(cycle: list[Transition], limit: ElasticLimit) -> bool:
    """True when a cycle of transitions is contacts of a regular train that the contact law
    makes lose energy (approach speeds between ``w_inf`` and ``w_deep``,
    :class:`core.deformable.law.ElasticLimit`): its speeds fall at every contact, so it is no
    fixed point, however small the fall is against a tolerance."""
    kinds = {tr.kind for tr in cycle}
    speeds = [tr.v for tr in cycle if tr.kind is TransitionKind.CONTACT]
    return (bool(speeds) and kinds <= set(TRAIN_CYCLE)
            and all(limit.w_inf < w < limit.w_deep for w in speeds))


def impacts_lose(cycle: list[Transition]) -> bool:
    """True when a cycle of transitions is rigid impacts alone, some of them inelastic: no
    fixed point, however small its loss is against a tolerance.

    Between such impacts the mass slips on circles about one centre ``(s a, 0)`` (a stick or
    a change of slip direction is a transition of its own), where friction is the constant
    ``s a`` and its work ``s a dx``. Over a closed cycle ``x`` returns, so friction does no
    net work, while each impact with ``|x'(+)| < x'(-)`` takes
    ``(x'(-)^2 - x'(+)^2) / 2``: the mechanical energy falls every cycle and the approach
    speeds fall as ``r^h`` (docs/physics.md, Zeno and grazing sums). Only a stick or slip on
    the other circle can feed the energy back, so only a cycle containing one can repeat.

    Examples
    --------
    >>> hit = Transition(TransitionKind.IMPACT, 1.0, 0.1, 0.05, -0.0499)
    >>> impacts_lose([hit]), impacts_lose([hit._replace(v_after=-0.05)])
    (True, False)
    """
    return bool(cycle) and all(
        tr.kind is TransitionKind.IMPACT for tr in cycle
    ) and any(-tr.v_after < tr.v for tr in cycle)


def train_steady(tail: list[Transition], limit: ElasticLimit) -> Steady | None:
    """Steady state of a regular train of contacts (:func:`train_contacts`) read off the
    contact law (:class:`core.deformable.law.ElasticLimit`), whatever a tolerance says:

    * contacts slower than ``w_inf`` are elastic, so each flight returns at the speed it
      left with: periodic from the first of them (a measured change of the speeds is the
      integration's drift);
    * contacts between ``w_inf`` and ``w_deep`` lose energy: on a stop the belt does not
      press the mass on (``x_bar > a``) the speeds fall towards ``w_inf`` and the motion
      tends to the train of elastic contacts at ``w_inf`` ("grazing approached"), whose
      speed, peak, period and force the label states. On a pressed stop ``None``
      (:func:`pressed_steady` labels the train).

    ``None`` also for fewer than :data:`TRAIN_CONTACTS` contacts or other speeds.
    """
    contacts = train_contacts(tail)
    if len(contacts) < TRAIN_CONTACTS:
        return None
    w = contacts[-1].v
    if w <= limit.w_inf:
        first = len(contacts) - 1
        while first > 0 and contacts[first - 1].v <= limit.w_inf:
            first -= 1
        last = contacts[-1].t
        peak = max(tr.x for tr in tail if contacts[-2].t <= tr.t <= last)
        return Steady(SteadyKind.PERIODIC, period=last - contacts[-2].t,
                      transitions_per_period=len(TRAIN_CYCLE),
                      sequence=tuple(k.value for k in TRAIN_CYCLE), x_max=peak,
                      impact_speed=w, t_reached=contacts[first].t)
    gap = limit.clearance - limit.a
    if w < limit.w_deep and gap > 0.0:
        flight = 2.0 * math.pi - 2.0 * math.atan(limit.w_inf / gap)
        return Steady(SteadyKind.GRAZING, period=flight + limit.duration,
                      x_max=limit.clearance + limit.r_inf, impact_speed=limit.w_inf)
    return None
