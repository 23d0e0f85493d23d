"""The steady state read off the last transitions of a motion, for every method.

A fixed point of the friction-impact map ``P^j`` (:class:`~core.steady.fixed_point.
FixedPointDetector`) at the tolerance of the method; else a quiet end (equilibrium, a
slip circle), the law's label of a train of contacts, the pressed mass's rule
(:func:`~core.steady.pressed.pressed_steady`) or an asymptotic approach (grazing, rest;
docs/physics.md, "Steady states").
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from core.deformable.law import ElasticLimit
from core.result import Mode, Steady, SteadyKind, Transition, TransitionKind
from core.steady.fixed_point import FIXED_POINT_RTOL, FixedPointDetector
from core.steady.pressed import SwingProbe, pressed_steady
from core.steady.train import impacts_lose, train_loses, train_steady
from core.transitions import IMPACT_KINDS

#: How many of the most recent transitions are kept for the steady-state search.
STEADY_WINDOW = 96
#: Largest number of transitions per period searched for a fixed point of ``P^j``.
STEADY_MAX_J = 32
#: A steady state needs the fixed point to repeat over this many consecutive periods.
STEADY_PERIODS = 2
#: At least this many transitions of falling speed (impacts, contacts) make an asymptotic
#: approach (grazing, or rest at a deformable stop) recognisable.
ASYMPTOTIC_MIN = 6
#: Default steady-state tolerance relative to the state scale, per unit of ``rtol``: the
#: transition states of a method with relative tolerance ``rtol`` scatter by a few hundred
#: ``rtol`` after a long horizon (global error grows with the number of steps).
STEADY_TOL_PER_RTOL = 1e3
#: Floor of the relative steady-state tolerance (a few thousand ulps).
STEADY_TOL_FLOOR = 1e-12
#: A period ``d`` that divides the ``j`` found is the period when its states repeat within
#: this factor of how well those ``j`` apart do (or of the tolerance).
SUB_PERIOD_FACTOR = 10.0
#: The kinds of transition an asymptotic approach to grazing is made of.
APPROACH_KINDS = frozenset({
    TransitionKind.IMPACT,
    TransitionKind.CONTACT,
    TransitionKind.SEPARATION,
    TransitionKind.REVERSAL,
})

XMax = Callable[[float, float], float]


def method_rtol(rtol: float, model_rtol: float = 0.0) -> float:
    """Relative tolerance of a fixed point for a method solved at ``rtol``: its transition
    states scatter by :data:`STEADY_TOL_PER_RTOL` ``rtol``, by the model's own error
    ``model_rtol`` (located anew at every transition, it does not grow with the horizon),
    and by no less than :data:`STEADY_TOL_FLOOR`.

    >>> method_rtol(1e-8)
    1e-05
    """
    return max(STEADY_TOL_PER_RTOL * rtol, model_rtol, STEADY_TOL_FLOOR)


def steady_from_transitions(
    tail: Sequence[Transition],
    *,
    scale: float,
    rtol: float,
    t_end: float,
    final_mode: int,
    final_v: float,
    x_max_between: XMax | None = None,
    pressed: bool = False,
    limit: ElasticLimit | None = None,
    lossless: bool = False,
    probe: SwingProbe | None = None,
) -> Steady:
    """The steady state read off the most recent transitions (``docs/physics.md``).

    Parameters
    ----------
    tail : sequence of Transition
        The most recent transitions, oldest first.
    scale : float
        Length scale of the states ``(x, x')``.
    rtol : float
        Tolerance, relative to ``scale``, of a fixed point of the friction-impact map
        ``P^j`` (:class:`~core.steady.fixed_point.FixedPointDetector`).
    t_end : float
        The horizon.
    final_mode, final_v : int, float
        Mode and velocity at ``t_end`` (for motions without transitions).
    x_max_between : callable, optional
        ``x_max_between(t0, t1)``: maximum displacement over a time interval.
    pressed : bool
        The belt presses the mass on the stop (:func:`core.steady.pressed_on_stop`). No
        slip circle grazes the stop then, so impacts of vanishing speed are rest at the
        stop and, without a fixed point, :func:`core.steady.pressed_steady` decides.
    limit, lossless : optional
        A deformable stop's law: its elastic limit (:func:`core.steady.train_steady`)
        and whether it retraces its loops (:func:`core.steady.pressed_steady`).
    probe : SwingProbe, optional
        The solution at the horizon, for :func:`core.steady.pressed_steady` to tell rest
        from loops still swinging there.

    Returns
    -------
    Steady
    """
    tail = list(tail)

    def xmax(t0: float, t1: float) -> float:
        return x_max_between(t0, t1) if x_max_between is not None else math.nan

    marked = _final_mark(tail)
    if marked is not None:
        return marked
    t_last = tail[-1].t if tail else 0.0
    if not tail or t_end - t_last > 2.0 * math.pi:
        # no transition for more than a full slip circle: nothing will happen any more
        quiet = _quiet_steady(tail, t_last, t_end, final_mode, final_v, xmax, pressed)
        if quiet is not None:
            return quiet
    train = train_steady(tail, limit) if limit is not None else None
    if train is not None:
        return train
    periodic = _periodic_tail(tail, scale, rtol, xmax, pressed, limit)
    if periodic is not None:
        return periodic
    if pressed:
        return pressed_steady(tail, lossless=lossless, probe=probe)
    return _approach(tail, limit)


def _final_mark(tail: list[Transition]) -> Steady | None:
    """Rest at the stop, or no steady state after a failure, where the transitions record
    one (the latest of the two counts)."""
    for tr in reversed(tail):
        if tr.kind is TransitionKind.REST:
            return Steady(SteadyKind.REST, x_max=tr.x, impact_speed=0.0, t_reached=tr.t)
        if tr.kind is TransitionKind.FAILURE:
            return Steady(SteadyKind.NONE)
    return None


def _quiet_steady(
    tail: list[Transition],
    t_last: float,
    t_end: float,
    final_mode: int,
    final_v: float,
    xmax: XMax,
    pressed: bool,
) -> Steady | None:
    """The steady state of a motion without transitions over the last full slip circle
    (from ``t_last`` to ``t_end``), or ``None`` if its final mode does not tell."""
    if final_mode == Mode.STICK and final_v == 0.0:
        return Steady(SteadyKind.EQUILIBRIUM, x_max=xmax(t_last, t_end), t_reached=t_last)
    if final_mode == Mode.SLIP and tail and tail[-1].kind in IMPACT_KINDS and not pressed:
        # impacts died out on a slip circle that touches the stop: grazing (paper §4),
        # reached at a plastic impact (the mass leaves at zero speed), else approached
        plastic = tail[-1].v_after == 0.0
        return Steady(SteadyKind.GRAZING, impact_speed=0.0,
                      period=2.0 * math.pi if plastic else math.nan,
                      t_reached=tail[-1].t if plastic else math.nan)
    if final_mode == Mode.SLIP:
        return Steady(
            SteadyKind.PURE_SLIP,
            period=2.0 * math.pi,
            x_max=xmax(max(t_last, t_end - 2.0 * math.pi), t_end),
            t_reached=t_last,
        )
    if final_mode == Mode.CONTACT:
        return Steady(SteadyKind.REST, t_reached=math.nan, x_max=xmax(t_last, t_end))
    return None


def _fundamental(tail: list[Transition], j: int, tol: float,
                 periods: int = STEADY_PERIODS) -> int:
    """The shortest period ``d`` dividing ``j`` (transitions) whose states repeat about as
    well as those ``j`` apart over the last ``periods`` periods.

    The states of a numerical method repeat to its accuracy only: a cycle whose states
    scatter about the tolerance can pass the repeat test ``3 j`` transitions apart and not
    ``j`` apart (the switch model at its default band: a stick-slip cycle reported with
    three times its period). A true period-3 orbit's states one cycle apart differ by the
    orbit's geometry, far more than this factor."""
    span = periods * j

    def worst(d: int) -> float:
        if any(tail[-1 - i].kind is not tail[-1 - i - d].kind for i in range(span)):
            return math.inf
        return max(max(abs(tail[-1 - i].x - tail[-1 - i - d].x),
                       abs(tail[-1 - i].v - tail[-1 - i - d].v)) for i in range(span))

    bound = SUB_PERIOD_FACTOR * max(worst(j), tol)
    for d in range(1, j):
        if j % d == 0 and worst(d) <= bound:
            return d
    return j


def _repeat(tail: list[Transition], scale: float,
            rtol: float) -> tuple[FixedPointDetector, int, int] | None:
    """The detector that saw the tail repeat, the transitions ``j`` per period and over
    how many periods, or ``None``.

    Repeats to the tolerance over :data:`STEADY_PERIODS` periods, or to rounding over one:
    a cycle through a state the motion is reset to (a stick that carries the mass onto the
    stop at the belt's speed) repeats it to the bit, as the exact method's detector sees
    after one period (a 41-time-unit cycle twice in t_end = 100: "periodic" by exact,
    "none" by event)."""
    for tol, periods in ((rtol, STEADY_PERIODS), (FIXED_POINT_RTOL, 1)):
        det = FixedPointDetector(scale, rtol=tol, min_cycle_size=scale)
        for i, tr in enumerate(tail):
            det.add(tr.kind, tr.t, tr.x, tr.v, i)
        j = _repeat_period(tail, det, periods)
        if j is not None:
            return det, j, periods
    return None


def _periodic_tail(
    tail: list[Transition], scale: float, rtol: float, xmax: XMax, pressed: bool,
    limit: ElasticLimit | None = None,
) -> Steady | None:
    """The periodic steady state (or its grazing limit) the transitions end on, or ``None``.

    Every transition goes through :class:`~core.steady.fixed_point.FixedPointDetector`;
    the tail is periodic when each transition of its last ``STEADY_PERIODS`` periods of
    ``j`` transitions repeats the state ``j`` transitions earlier (the smallest such
    ``j``). Not a period: reversals alone (loops on the stop, which
    :func:`core.steady.pressed_steady` labels from their swings: one reversal is half a
    loop, and loops that die out come within a tolerance of each other), nor a train of
    contacts the law makes lose energy (:func:`core.steady.train_loses`), nor inelastic
    rigid impacts with nothing but slip on one circle between them
    (:func:`core.steady.impacts_lose`).
    """
    found = _repeat(tail, scale, rtol)
    if found is None:
        return None
    det, j, periods = found
    k = _first_repeat(det, len(tail) - 1 - periods * j, j)
    j = _fundamental(tail, j, det.tol, periods)
    period = tail[-1].t - tail[-1 - j].t
    last = tail[-j:]
    if all(tr.kind is TransitionKind.REVERSAL for tr in last):
        return None
    if limit is not None and train_loses(last, limit):
        return None
    speeds = [tr.v for tr in last if tr.kind in IMPACT_KINDS]
    if speeds and max(speeds) <= det.tol:
        # impacts of vanishing speed: the grazing limit, reached to the tolerance, or, on a
        # stop the belt presses the mass on (no slip circle touches it), rest there
        if pressed:
            return Steady(SteadyKind.REST, x_max=last[-1].x, impact_speed=0.0, t_reached=math.nan)
        return Steady(SteadyKind.GRAZING, impact_speed=0.0, t_reached=math.nan)
    if impacts_lose(last):
        return None
    return Steady(
        SteadyKind.PERIODIC,
        period=period,
        transitions_per_period=j,
        sequence=tuple(tr.kind.value for tr in last),
        x_max=xmax(tail[-1].t - period, tail[-1].t),
        impact_speed=max(speeds) if speeds else math.nan,
        t_reached=tail[k].t,
    )


def _first_repeat(det: FixedPointDetector, k: int, j: int) -> int:
    """The earliest transition, back from the ``k``-th, from which every one repeats the
    state ``j`` transitions before it: where the cycle was reached."""
    while k - j >= 0 and j in det.repeats[k]:
        k -= 1
    return k


def _repeat_period(tail: list[Transition], det: FixedPointDetector, periods: int) -> int | None:
    """The fewest transitions ``j`` per period such that each transition of the last
    ``periods`` periods repeats (``det``) the state ``j`` earlier, or ``None``."""
    n = len(tail)
    for j in range(1, min(STEADY_MAX_J, n // (periods + 1)) + 1):
        if all(j in det.repeats[n - 1 - i] for i in range(periods * j)) and (
                tail[-1].t - tail[-1 - j].t > 0.0):
            return j
    return None


def _approach(tail: list[Transition], limit: ElasticLimit | None) -> Steady:
    """The limit the transitions approach without reaching it (:func:`_falling_contacts`):
    rest, or grazing (on a deformable stop at the law's elastic speed), else none."""
    falling = _falling_contacts(tail)
    if falling == "rest":
        return Steady(SteadyKind.REST, impact_speed=0.0, t_reached=math.nan)
    if falling == "grazing" and limit is None:
        return Steady(SteadyKind.GRAZING, impact_speed=0.0, t_reached=math.nan)
    if falling == "grazing":
        # a deformable stop's contacts, not a regular train: they fall towards the elastic
        # speed only while above it (slower ones are elastic, docs/contact-law.md)
        speeds = [tr.v for tr in tail[-ASYMPTOTIC_MIN:] if tr.kind is TransitionKind.CONTACT]
        if 0.0 < limit.w_inf < min(speeds, default=0.0):
            return Steady(SteadyKind.GRAZING, impact_speed=limit.w_inf, t_reached=math.nan)
    return Steady(SteadyKind.NONE)


def _falling_contacts(tail: list[Transition]) -> str | None:
    """``"grazing"`` when the last transitions are impacts (or contacts) with falling speed,
    ``"rest"`` when they are only overlap reversals of falling amplitude (a mass pressed on a
    deformable stop), else ``None``."""
    recent = tail[-ASYMPTOTIC_MIN:]
    if len(recent) < ASYMPTOTIC_MIN:
        return None
    if all(tr.kind is TransitionKind.REVERSAL for tr in recent):
        xs = [tr.x for tr in recent]
        upper, lower = xs[0::2], xs[1::2]
        shrink = _monotone(upper) and _monotone(lower) and _shrinking(upper, lower)
        return "rest" if shrink else None
    return "grazing" if _speeds_fall(tail, recent) else None


def _speeds_fall(tail: list[Transition], recent: list[Transition]) -> bool:
    """The recent transitions are impacts or contacts (with their separations and
    reversals), and the speeds of the last impacts fall at each one."""
    impacts = [tr for tr in tail if tr.kind in IMPACT_KINDS or tr.kind is TransitionKind.CONTACT]
    if not {tr.kind for tr in recent} <= APPROACH_KINDS or len(impacts) < ASYMPTOTIC_MIN // 2:
        return False
    speeds = [tr.v for tr in impacts[-ASYMPTOTIC_MIN // 2 :]]
    return all(s1 < s0 for s0, s1 in zip(speeds, speeds[1:], strict=False))


def _monotone(seq: list[float]) -> bool:
    d = np.diff(seq)
    return bool(np.all(d >= 0.0) or np.all(d <= 0.0))


def _shrinking(upper: list[float], lower: list[float]) -> bool:
    m = min(len(upper), len(lower))
    gaps = [abs(u - w) for u, w in zip(upper[:m], lower[:m], strict=False)]
    return all(g1 <= g0 for g0, g1 in zip(gaps, gaps[1:], strict=False))
