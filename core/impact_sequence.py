"""Closed form of an endless impact sequence at a rigid stop (paper §4.3-4.4, Eqs. A.5-A.6, A.12).

After an impact with approach speed ``w`` the mass leaves the stop at ``-r w`` on the slip
circle about ``(a, 0)``. When that arc comes back to the stop without reaching the belt
speed, symmetry of the circle about the ``x`` axis brings it back with speed ``r w``: the
impact speeds are ``w_h = r^h w`` for ever. With ``d = x_bar - a``:

* ``d < 0`` (**accumulation**, Zeno): each arc lies left of the stop and lasts
  ``2 atan(w_h / |d|)``; the impacts accumulate at ``t_acc = t_0 + sum_h 2 atan(w_h/|d|)``,
  after which the mass rests pressed on the stop.
* ``d >= 0`` (**grazing**): each arc lasts ``2 pi - 2 atan2(w_h, d)``; impacts go on for all
  time and the motion tends to the slip circle about ``(a, 0)`` that touches the stop.

The whole sequence is evaluated with numpy, so a million impacts cost milliseconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.result import Mode
from core.theory import accumulation_time

#: Impact speeds below this fraction of the problem's length scale are indistinguishable
#: from the limit (the state differs from it by less than this): the explicit sequence ends.
SPEED_FLOOR = 1e-15
#: Most arcs evaluated one by one; beyond, the accumulation sum uses its series tail.
MAX_ARCS = 1_000_000


@dataclass(frozen=True)
class ImpactSequence:
    """The impact sequence that starts with an impact at ``t_start`` of approach speed ``w``.

    ``t_impacts[k]`` is the time of impact ``k`` (``t_impacts[0] = t_start``) and
    ``speeds[k] = r^k w`` its approach speed, for the explicitly evaluated impacts.
    """

    t_start: float
    w: float
    r: float
    clearance: float
    a: float
    t_impacts: np.ndarray
    speeds: np.ndarray
    t_accumulation: float  # inf when grazing
    limit_follows: bool  # True when the limit follows the last explicit impact before t_end

    @property
    def zeno(self) -> bool:
        return self.clearance < self.a

    @property
    def t_limit(self) -> float:
        """Time after which the motion is its limit (rest, or the grazing circle)."""
        return self.t_accumulation if self.zeno else float(self.t_impacts[-1])


def impact_sequence(
    t_start: float, w: float, r: float, clearance: float, a: float, t_end: float, scale: float
) -> ImpactSequence:
    """Build the sequence up to ``t_end``, the speed floor or :data:`MAX_ARCS` impacts."""
    d = clearance - a
    floor = SPEED_FLOOR * scale
    # Number of impacts until the speed floor: r^k w < floor.
    n_floor = math.ceil(math.log(floor / w) / math.log(r)) + 1 if w > floor else 1
    n = max(1, min(n_floor, MAX_ARCS))
    if d >= 0.0:  # grazing arcs last at least pi: the horizon bounds their number
        n = min(n, int((t_end - t_start) / math.pi) + 2)
    k = np.arange(n, dtype=float)
    speeds = w * np.exp(k * math.log(r))
    rebound = speeds[1:]  # arc k starts with speed r^k w and ends with the same speed
    if d < 0.0:
        durations = 2.0 * np.arctan2(rebound, -d)
    else:
        durations = 2.0 * math.pi - 2.0 * np.arctan2(rebound, d)
    t_impacts = t_start + np.concatenate(([0.0], np.cumsum(durations)))
    inside = np.searchsorted(t_impacts, t_end, side="right")
    cut = max(1, int(inside))
    limit_follows = cut == n
    t_acc = math.inf
    if d < 0.0:
        t_acc = float(t_impacts[-1]) + accumulation_time(float(speeds[-1]) * r, r, -d)
    return ImpactSequence(
        t_start, w, r, clearance, a, t_impacts[:cut], speeds[:cut], t_acc, limit_follows
    )


def evaluate_sequence(
    seq: ImpactSequence, t: np.ndarray, belt_speed: float, side: np.ndarray | int = 1
) -> dict[str, np.ndarray]:
    """State and energy increments (from ``t_start``, before the first impact) at ``t``.

    At an impact time ``side = -1`` gives the state just before it (approach speed
    ``r^k w``) and ``side >= 0`` the state just after it (``-r^(k+1) w``). Samples after
    the explicit impacts take the limit: the mass at the stop (accumulation at rest) or
    the grazing circle about ``(a, 0)`` through ``(x_bar, 0)``.
    """
    r, a, xb = seq.r, seq.a, seq.clearance
    t = np.asarray(t, dtype=float)
    before = np.asarray(side) < 0
    last = len(seq.t_impacts) - 1
    k = np.searchsorted(seq.t_impacts, t, side="right") - 1  # last impact at or before t
    k = np.clip(k, 0, last)
    # Exactly at an impact, from the left: the arc that ends there (strictly before t).
    at_impact = before & (k > 0) & (seq.t_impacts[k] == t)
    k -= at_impact
    tau = t - seq.t_impacts[k]
    rebound = seq.speeds[k] * r
    beyond = (k == last) & seq.limit_follows
    if seq.zeno:
        rebound = np.where(beyond, 0.0, rebound)
        tau = np.where(beyond, 0.0, tau)
    d = xb - a
    cos_t, sin_t = np.cos(tau), np.sin(tau)
    x = a + d * cos_t - rebound * sin_t
    v = -d * sin_t - rebound * cos_t
    if np.any(at_impact):  # the state Newton's law acts on, exactly
        x[at_impact] = xb
        v[at_impact] = seq.speeds[k[at_impact] + 1]
    n_impacts = k + 1.0
    loss = 0.5 * seq.w**2 * -np.expm1(2.0 * n_impacts * math.log(r))
    mode = np.where(seq.zeno & (t >= seq.t_accumulation), Mode.CONTACT, Mode.SLIP)
    return {
        "x": x,
        "v": v,
        "mode": mode.astype(np.int8),
        "friction_work": a * (x - xb),
        "belt_input": a * belt_speed * (t - seq.t_start),
        "stop_loss": loss,
    }
