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

The whole sequence is evaluated with numpy, so a million impacts cost milliseconds. Past
:data:`MAX_ARCS` explicit impacts (``r`` within ~3e-5 of 1) the impact at or before a time is
found by bisection on its index, with the time left to the accumulation summed in closed
form (:func:`core.theory.accumulation.accumulation_times`): the motion is exact up to the
speed floor, never the limit drawn early.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.result import Mode
from core.theory import accumulation_time
from core.theory.accumulation import accumulation_times

#: Impact speeds below this fraction of the problem's length scale are indistinguishable
#: from the limit (the state differs from it by less than this): the explicit sequence ends.
SPEED_FLOOR = 1e-15
#: Most arcs evaluated one by one; beyond, the accumulation sum uses its series tail.
MAX_ARCS = 1_000_000


@dataclass(frozen=True)
class ImpactSequence:
    """The impact sequence that starts with an impact at ``t_start`` of approach speed ``w``.

    ``t_impacts[k]`` is the time of impact ``k`` (``t_impacts[0] = t_start``) and
    ``speeds[k] = r^k w`` its approach speed, for the explicitly evaluated impacts;
    ``n_floor`` impacts are faster than the speed floor (more than the explicit ones when
    :data:`MAX_ARCS` cut them short).
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
    n_floor: int = 1

    @property
    def truncated(self) -> bool:
        """True when impacts above the speed floor follow the explicit ones before the
        horizon (:data:`MAX_ARCS` reached): :func:`tail_impacts` places them."""
        return self.limit_follows and len(self.t_impacts) < self.n_floor

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
        t_start, w, r, clearance, a, t_impacts[:cut], speeds[:cut], t_acc, limit_follows,
        n_floor,
    )


def tail_impacts(seq: ImpactSequence, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index ``h`` and time of the last impact at or before each ``t``, for times after the
    explicit impacts of a truncated sequence; ``h`` stops at the last impact above the
    speed floor, ``n_floor - 1``.

    Impact ``h`` (approach speed ``w r^h``) comes at ``T(h)``: for an accumulation
    ``t_acc - R(h)`` with ``R(h) = sum_{j>h} 2 atan(w r^j / |d|)`` the time still to go
    (:func:`core.theory.accumulation.accumulation_times`); when grazing, each arc lasts
    ``2 pi - 2 atan(w r^j / d)``, so ``T(h) = T(last) + 2 pi (h - last) - (R(last) - R(h))``
    (``pi`` an arc for ``d = 0``). ``T`` increases with ``h``: bisection on the integer.
    """
    t = np.asarray(t, dtype=float)
    r, w, d = seq.r, seq.w, seq.clearance - seq.a
    last = len(seq.t_impacts) - 1
    t_last = float(seq.t_impacts[-1])
    log_r = math.log(r)

    def remaining(h: np.ndarray) -> np.ndarray:
        return accumulation_times(w * np.exp((h + 1.0) * log_r), r, abs(d))

    if d < 0.0:
        def time_of(h):
            return seq.t_accumulation - remaining(h)
    elif d > 0.0:
        r_last = float(remaining(np.array([float(last)]))[0])

        def time_of(h):
            return t_last + 2.0 * math.pi * (h - last) - (r_last - remaining(h))
    else:
        def time_of(h):
            return t_last + math.pi * (h - last)

    top = float(seq.n_floor - 1)
    lo = np.full(t.shape, float(last))
    hi = np.full(t.shape, top)
    if d >= 0.0:  # every arc lasts at least pi
        hi = np.minimum(hi, last + np.floor((t - t_last) / math.pi) + 1.0)
    hi_ok = time_of(hi) <= t
    while True:
        open_ = ~hi_ok & (hi - lo > 1.0)
        if not np.any(open_):
            break
        mid = np.floor(0.5 * (lo + hi))
        ok = np.zeros(t.shape, bool)
        ok[open_] = time_of(mid[open_]) <= t[open_]
        lo = np.where(open_ & ok, mid, lo)
        hi = np.where(open_ & ~ok, mid, hi)
    h = np.where(hi_ok, hi, lo)
    t_h = np.where(h == last, t_last, time_of(h))
    return h, np.minimum(t_h, t)


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
    n_impacts = k + 1.0
    beyond = (k == last) & seq.limit_follows
    if seq.truncated:
        # past MAX_ARCS: the impacts above the speed floor, placed in closed form
        late = beyond & (t > seq.t_impacts[last])
        if seq.zeno:
            late &= t < seq.t_accumulation
        if np.any(late):
            h, t_h = tail_impacts(seq, t[late])
            tau[late] = t[late] - t_h
            rebound[late] = w_late = seq.w * np.exp((h + 1.0) * math.log(r))
            n_impacts[late] = h + 1.0
            beyond[late] = h >= seq.n_floor - 1
            if seq.zeno:  # an arc from the stop and back lasts 2 atan(w / |d|)
                tau[late] = np.minimum(tau[late], 2.0 * np.arctan2(w_late, a - xb))
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
    at_rest = seq.zeno & (t >= seq.t_accumulation)
    # at rest every impact has taken its share: the whole kinetic energy w^2/2 (a sum
    # stopped at the explicit impacts leaves out (r^n w)^2/2, 7e-4 of 1.25e-3 at r = 1 - 1e-6)
    n_impacts = np.where(at_rest, np.inf, n_impacts)
    loss = 0.5 * seq.w**2 * -np.expm1(2.0 * n_impacts * math.log(r))
    mode = np.where(at_rest, Mode.CONTACT, Mode.SLIP)
    return {
        "x": x,
        "v": v,
        "mode": mode.astype(np.int8),
        "friction_work": a * (x - xb),
        "belt_input": a * belt_speed * (t - seq.t_start),
        "stop_loss": loss,
    }
