"""What the motion settles to: one steady-state detector and one rule for rest at the stop.

For every method (exact, hysteretic, switch, event; docs/physics.md, "Steady states"):

* :class:`FixedPointDetector` finds a periodic steady state as a fixed point of the
  friction-impact map (Eq. 20): a transition state that repeats an earlier one of the same
  kind, with a period the times can resolve (``> 0``);
* :func:`fold_times` tiles the rest of the horizon with the cycle found: a time after the
  cycle maps into the stored period, with the number of whole periods it moved;
* :func:`pressed_on_stop`, :func:`rest_force` and :func:`comes_to_rest` decide whether a
  mass that has come to rest at the stop stays there, and with what force;
  :func:`pressed_steady` labels a pressed mass's motion when no fixed point is found: rest
  where its swing at the horizon (:class:`SwingProbe`) is within what the rule for rest
  lets rest, else an oscillation on the stop with that swing and its decay.

The rule: at the stop ``x = x_bar`` with ``x' = 0`` the mass moves backwards relative to
a moving belt, so kinetic friction ``+a`` acts and the net force without the stop is
``a - x_bar``. The mass stays pressed on the stop iff that force does not pull it away,
``a >= x_bar``. The same inequality decides whether the rebounds of an impact sequence
come back to the stop ever faster (accumulation, ``x_bar < a``) or not (grazing).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from core.deformable.law import ElasticLimit
from core.params import Oscillator
from core.result import Steady, SteadyKind, Transition, TransitionKind

#: Two transition states closer than this (relative to the problem's length scale) are the
#: same point of the friction-impact map. The exact solution repeats to a few ulps; 1e-11
#: leaves room for the rounding of long transients without merging distinct states.
FIXED_POINT_RTOL = 1e-11
#: Relative change per cycle of the amplitude of an oscillation on the stop below which it
#: is steady rather than dying out: an amplitude shrinking that slowly keeps 99 % of itself
#: for 1e4 cycles, more than any horizon offers (t_end <= 1e4, periods ~1), and solves at
#: rtol 1e-8 to 1e-11 leave retracing loops drifting by ~4e-9 per cycle. (The passive law's
#: loops are labelled by the law, :func:`pressed_steady`'s ``lossless``: with their curve
#: kept over reversals they drift by the integration's ~1e-8 per cycle at rtol 1e-8.)
SWING_STEADY = 1e-6
#: Swings (two a cycle) whose change the label of an oscillation on the stop is read from:
#: four cycles, three ratios of successive cycles.
SWING_WINDOW = 8
#: Points per cycle on which the swing at the horizon is measured: the half range of
#: samples of a sine misses its amplitude by at most ``1 - cos(pi / 256) = 7.5e-5`` of it.
SWING_POINTS = 256
#: Cycles an oscillation must have run past its last stored reversals for its decay to be
#: read from the amplitude there and at the horizon (a reduced model carried it on) rather
#: than from those reversals: the amplitudes then differ by far more than their sampling.
SWING_SPAN_CYCLES = 8
#: ... over enough cycles for the amplitude to change by this fraction: its sampling
#: (:data:`SWING_POINTS`) then moves the rate read by ~2e-3 of itself.
SWING_SPAN_CHANGE = 0.1
#: How many earlier transitions of the same kind are compared with each new one.
FIXED_POINT_LOOKBACK = 64
#: A cycle must last more than this many ulps of the time it closes at (a shorter one is a
#: bounce below the resolution of time and cannot be tiled).
PERIOD_ULPS = 1024
#: Times within this fraction of a period of a cycle boundary are put on it (rounding of
#: the repeated transition times is ~1e-16 of the horizon; 1e-9 of a period moves a time
#: by nanoseconds of dimensionless time).
TILE_SNAP = 1e-9

#: An impact whose bounce would rise less than this fraction of the stop's length scale
#: off the stop (height ``w^2 / (2 |a - x_bar|)``) cannot be told from rest: one ulp of
#: ``x`` at a turning point next to the stop already gives a speed of that order. The
#: threshold on the speed is ``REST_SPEED * sqrt(|a - x_bar| * L)``; 1e-7 is the square
#: root of ~500 ulps of position.
REST_SPEED = 1e-7


#: Contacts of a regular train (one reversal each, nothing else between them) its label is
#: read from: two flights to measure the period by, three speeds to see them fall.
TRAIN_CONTACTS = 3
#: The transitions of one contact of a regular train, in order.
TRAIN_CYCLE = (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION)


def pressed_on_stop(osc: Oscillator, clearance: float) -> bool:
    """True when a mass at rest at the stop stays pressed on it: ``a >= x_bar``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> pressed_on_stop(osc, 0.1), pressed_on_stop(osc, 0.3)
    (True, False)
    """
    return osc.a >= clearance


def rest_force(osc: Oscillator, clearance: float) -> float:
    """Contact force over ``k`` (a length) of the mass resting on the stop.

    On a moving belt kinetic friction presses it: ``a - x_bar``. On a still belt static
    friction is indeterminate and the least force it allows, ``max(-x_bar - b, 0)``, is
    reported. Zero when the mass is not pressed.

    Examples
    --------
    >>> round(rest_force(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5), 0.05), 12)
    0.15
    """
    if osc.v > 0.0:
        return max(osc.a - clearance, 0.0)
    return max(-clearance - osc.b, 0.0)


def comes_to_rest(osc: Oscillator, clearance: float, speed: float) -> bool:
    """True when an impact at ``speed`` leaves the mass at rest at the stop to the
    resolution of the numbers: it is pressed on the stop and the bounce it starts would
    rise less than ``REST_SPEED**2`` of the stop's length scale (see :data:`REST_SPEED`).

    Examples
    --------
    >>> osc = Oscillator(mu_s=1.0, mu_k=1.0, belt_speed=0.0)
    >>> comes_to_rest(osc, 0.0, 1e-20), comes_to_rest(osc, 0.0, 1e-3)
    (True, False)
    """
    if not pressed_on_stop(osc, clearance):
        return False
    if speed == 0.0:
        return True
    d = abs(osc.a - clearance)
    scale = max(abs(clearance), d)
    return speed <= REST_SPEED * math.sqrt(d * scale)


@dataclass(frozen=True)
class SwingProbe:
    """How far a motion on the stop swings at the horizon, against the rule for rest.

    ``evaluate(t) -> (x, x')`` is the solution; ``rest_amplitude`` and ``rest_velocity``
    the rule's thresholds on the swing of the position and of the velocity (the solver's
    :func:`core.deformable.rest.rest_swing`: 10 and 100 ``rtol`` of the length scale,
    docs/contact-law.md)."""

    evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    t_end: float
    rest_amplitude: float
    rest_velocity: float

    def swing(self, t1: float, cycle: float) -> tuple[float, float]:
        """Half the range of ``x`` and of ``x'`` over the cycle that ends at ``t1``."""
        t = np.linspace(max(t1 - cycle, 0.0), t1, SWING_POINTS + 1)
        x, v = self.evaluate(t)
        return 0.5 * float(np.ptp(x)), 0.5 * float(np.ptp(v))

    def at_rest(self, amplitude: float, velocity: float) -> bool:
        return amplitude <= self.rest_amplitude and velocity <= self.rest_velocity


def _oscillation(probe: SwingProbe, reversals: list[Transition], ratio: float,
                 x_max: float) -> Steady | None:
    """The oscillation on the stop that the reversals end on, as it is at the horizon, or
    ``None`` if its swing there is within what the rule for rest lets rest.

    Its decay is the ratio of successive cycles' amplitudes: the reversals' ``ratio``
    where they reach the horizon, else (a reduced model carried the loops on) read from
    the amplitude of their last cycle and the one at the horizon, over the cycles between."""
    cycle = reversals[-1].t - reversals[-3].t
    if not cycle > 0.0:
        return None
    amp, vel = probe.swing(probe.t_end, cycle)
    if probe.at_rest(amp, vel):
        return None
    cycles = (probe.t_end - reversals[-1].t) / cycle
    if cycles >= SWING_SPAN_CYCLES:
        # Back from the horizon by as many cycles as shrink it by SWING_SPAN_CHANGE at the
        # reversals' rate (the rate at the horizon, not averaged over the model's run: on
        # loops dying like 1/k, from a switch at t ~ 100 to t_end = 1600 that average was
        # 1.6 times the rate at the end), all the cycles since them at most.
        back = cycles if not ratio < 1.0 else min(
            cycles, max(SWING_SPAN_CYCLES, SWING_SPAN_CHANGE / (1.0 - ratio)))
        then = probe.swing(probe.t_end - back * cycle, cycle)[0]
        ratio = (amp / then) ** (1.0 / back) if then > 0.0 else ratio
    return Steady(SteadyKind.OSCILLATION, period=cycle, transitions_per_period=2,
                  sequence=("reversal", "reversal"), x_max=x_max, decay_rate=ratio,
                  amplitude=amp, velocity_amplitude=vel,
                  rest_amplitude=probe.rest_amplitude, rest_velocity=probe.rest_velocity)


def pressed_steady(tail: list[Transition], lossless: bool = False,
                   probe: SwingProbe | None = None) -> Steady:
    """Steady state of a mass the belt presses on the stop (``x_bar < a``), read off the
    latest transitions when no fixed point was found.

    No slip circle misses or grazes the stop then (the circles about ``(a, 0)`` all cross
    it), so neither pure slip nor grazing can be the limit: the motion ends at rest on the
    stop, or goes on as a train of contacts, or as an oscillation on the stop. A train is
    labelled with the measured ratio of successive approach speeds; a sustained oscillation
    whose swings shrink is rest approached, with the measured ratio of successive swings
    (over whole cycles), and one whose swings keep their size (:data:`SWING_STEADY` per
    cycle) is periodic.

    ``probe``: the solution at the horizon. Shrinking loops are rest only where their
    swing there is within what the rule for rest lets rest; else they are an oscillation
    on the stop, with that swing and its decay (:class:`SwingProbe`). Without it they are
    rest approached.

    ``lossless``: the contact law dissipates nothing on loops made of overlap reversals
    alone (the passive law retraces its curve there, docs/contact-law.md). Such loops are
    periodic whatever their measured change, which is then the numbers' drift.
    """
    speeds = [tr.v for tr in tail if tr.kind is TransitionKind.CONTACT]
    if len(speeds) >= 2 and any(tr.kind is TransitionKind.SEPARATION for tr in tail[-4:]):
        ratio = float(np.median(np.array(speeds[1:]) / np.array(speeds[:-1])))
        return Steady(
            SteadyKind.CONTACT_TRAIN,
            impact_speed=speeds[-1],
            decay_rate=ratio,
            x_max=max(tr.x for tr in tail),
        )
    reversals = [tr for tr in tail if tr.kind is TransitionKind.REVERSAL]
    xs = [tr.x for tr in reversals]
    swings = np.abs(np.diff(xs))
    n = min(SWING_WINDOW, len(swings) - len(swings) % 2)
    if n >= 4 and np.all(swings[-n:] > 0.0):
        # One amplitude a cycle, from its two swings: the paper's loops creep, so their
        # swings alternate in size, and a ratio of single swings read growth every other
        # reversal (k_c0 = 1e4, beta = 1000, D = 1e-3: +0.65 % while the loops die like 1/k).
        amps = swings[-n:][0::2] + swings[-n:][1::2]
        ratio = float(np.median(amps[1:] / amps[:-1]))
        retrace = lossless and all(tr.kind is TransitionKind.REVERSAL for tr in tail[-n - 1:])
        if ratio < 1.0 - SWING_STEADY and not retrace:
            swinging = None if probe is None else _oscillation(probe, reversals, ratio, max(xs))
            if swinging is not None:
                return swinging
            return Steady(SteadyKind.REST, x_max=max(xs), impact_speed=0.0,
                          decay_rate=math.sqrt(ratio))
        if ratio <= 1.0 + SWING_STEADY or retrace:
            # Loops that keep their size: a sustained oscillation on the stop, one cycle
            # every two reversals.
            last = reversals[-5:]
            return Steady(SteadyKind.PERIODIC, period=0.5 * (last[-1].t - last[0].t),
                          transitions_per_period=2, sequence=("reversal", "reversal"),
                          x_max=max(xs), t_reached=last[0].t)
    if tail and tail[-1].kind is TransitionKind.REDUCED:
        swinging = None
        if probe is not None and len(reversals) >= 3:
            swinging = _oscillation(probe, reversals, math.nan, max(tr.x for tr in tail))
        if swinging is not None:
            return swinging
        return Steady(SteadyKind.REST, x_max=tail[-1].x, impact_speed=0.0)
    return Steady(SteadyKind.NONE)


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


@dataclass(frozen=True)
class Cycle:
    """A periodic steady state found by :class:`FixedPointDetector`.

    ``t_then``/``t_now`` are the times of the two equal transition states (``period =
    t_now - t_then > 0``); ``tag_then``/``tag_now`` the caller's tags stored with them
    (e.g. the row of a segment table); ``n_transitions`` the transitions per period.
    """

    t_then: float
    t_now: float
    tag_then: int
    tag_now: int
    n_transitions: int

    @property
    def period(self) -> float:
        return self.t_now - self.t_then


class FixedPointDetector:
    """Fixed point of the friction-impact map ``P^j`` (Eq. 20) from transition states.

    Feed every transition state with :meth:`add`; it returns the :class:`Cycle` when the
    state repeats an earlier one of the same kind, else ``None``. A repeat must hold to
    ``FIXED_POINT_RTOL * scale`` and also to ``FIXED_POINT_RTOL`` of the cycle's own size
    (a sequence converging on a point, as in an accumulation, has consecutive states that
    come within any absolute tolerance without ever repeating), and its period must be
    resolvable in time (more than :data:`PERIOD_ULPS` ulps).

    ``rtol`` replaces ``FIXED_POINT_RTOL`` for states known only to a tolerance: the
    transition states of a numerical method repeat to about its own accuracy, never to
    the few ulps of the exact solution. Such states cannot tell a cycle from a converging
    sequence by the cycle's own size either (a cycle of one impact has the size of its
    own drift); ``min_cycle_size`` (e.g. ``scale``) is then the size the repeat is
    measured against, and an accumulation must be recognised by the caller.

    A deformable stop adds the contact force ``phi`` (over ``k``, a length times the stop's
    stiffness ratio) to the state; it must repeat to ``phi_scale`` times the tolerance.

    Examples
    --------
    >>> det = FixedPointDetector(scale=1.0)
    >>> det.add(TransitionKind.IMPACT, 1.0, 0.3, 0.2) is None
    True
    >>> det.add(TransitionKind.IMPACT, 3.5, 0.3, 0.2).period
    2.5
    """

    def __init__(
        self,
        scale: float,
        rtol: float = FIXED_POINT_RTOL,
        min_cycle_size: float = 0.0,
        phi_scale: float = 1.0,
    ) -> None:
        if not rtol > 0.0:
            raise ValueError(f"rtol must be > 0, got {rtol!r}")
        self.rtol = rtol
        self.tol = rtol * scale
        self.min_cycle_size = min_cycle_size
        self.phi_tol = self.tol * phi_scale
        self.phis: list[float] = []
        #: For each state, how many transitions back each earlier state it repeats lies.
        self.repeats: list[frozenset[int]] = []
        self.states: list[tuple[float, float, float, int]] = []  # (t, x, v, tag)
        self.by_kind: dict[str, list[int]] = {}

    def add(
        self, kind: TransitionKind, t: float, x: float, v: float, tag: int = 0, phi: float = 0.0
    ) -> Cycle | None:
        """Record the state ``(x, v, phi)`` of a transition of ``kind`` at ``t``; the cycle
        it closes with the closest earlier state it repeats, or ``None``."""
        seen = self.by_kind.setdefault(kind.value, [])
        matches = self._matches(seen, t, x, v, phi)
        n_now = len(self.states)
        self.states.append((t, x, v, tag))
        self.phis.append(phi)
        seen.append(n_now)
        self.repeats.append(frozenset(n_now - i for i, _ in matches))
        if not matches:
            return None
        j = min(matches, key=lambda m: m[1])[0]
        t_then, _, _, tag_then = self.states[j]
        return Cycle(t_then, t, tag_then, tag, n_now - j)

    def _matches(
        self, seen: list[int], t: float, x: float, v: float, phi: float
    ) -> list[tuple[int, float]]:
        """The earlier states ``(index, gap)`` that ``(x, v, phi)`` at ``t`` repeats."""
        shortest = PERIOD_ULPS * math.ulp(max(abs(t), 1.0))
        found = []
        for i in seen[-FIXED_POINT_LOOKBACK:]:
            ti, xi, vi, _ = self.states[i]
            gap = abs(xi - x) + abs(vi - v)
            near = abs(xi - x) <= self.tol and abs(vi - v) <= self.tol
            near = near and abs(self.phis[i] - phi) <= self.phi_tol
            if near and t - ti > shortest:
                size = max(abs(st[1] - x) + abs(st[2] - v) for st in self.states[i:])
                if gap <= self.rtol * max(size, self.min_cycle_size):
                    found.append((i, gap))
        return found


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
