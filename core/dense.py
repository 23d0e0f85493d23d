"""Build a :class:`~core.result.Result` from the dense output of a numerical integrator.

This module is longer than the project's ~500 lines because it is the one place where every
numerical method's step points become a result (transitions, steady state, samples).

The transitions go to the project's one log (:class:`core.transitions.TransitionLog`); the
steady state read off them (:func:`steady_from_transitions`) finds fixed points with the
project's one detector (:class:`core.steady.FixedPointDetector`) at the tolerance of the
numerical method.

The numerical methods (the switch model of :mod:`core.switch`, the event-driven
``solve_ivp`` method of :mod:`core.event_method`, and any other stepper) produce the state at
their own step points, which are irregular and may be many. This module turns those points
into the result every method returns:

* uniform samples over ``[0, t_end]`` (``n_samples`` of them) merged with the stored
  transitions' points, interpolated by cubic Hermite polynomials on each step (position with
  the velocity as derivative, velocity with the acceleration as derivative, ``docs/physics.md``);
* the mode at each sample, the energy terms (:class:`~core.result.Energy`), the contact
  force and overlap;
* the transition list capped at ``transition_cap`` with all transitions counted;
* the steady state (``docs/physics.md``): a fixed point of the friction-impact map ``P^j``
  found on the transition sequence, to a tolerance the caller derives from its own accuracy.

Conventions of the dense arrays
-------------------------------
``t`` is non-decreasing; a repeated time marks a jump (a rigid impact, paper Eq. 8): the
first point holds the state just before it, the last the state just after. ``mode[i]`` and
``acc[i]`` belong to the interval that *starts* at point ``i`` (right limits); where the
acceleration jumps (a friction transition) an integrator that knows both limits repeats the
point with the left limit first, so that the velocity interpolant on each side is right.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from core.deformable.law import ElasticLimit, elastic_limit, stored_energy
from core.deformable.rest import rest_swing_of
from core.numerics.dense_output import PointTrack
from core.numerics.hermite import hermite_eval, hermite_max, linear_eval
from core.result import (
    DenseSolution,
    Energy,
    Mode,
    Result,
    Status,
    Steady,
    SteadyKind,
    Transition,
    TransitionKind,
)
from core.solve_inputs import SolveInputs, StopFacts
from core.steady import (
    FIXED_POINT_RTOL,
    FixedPointDetector,
    SwingProbe,
    impacts_lose,
    pressed_steady,
    train_loses,
    train_steady,
)
from core.theory import accumulation_time
from core.transitions import IMPACT_KINDS, TransitionLog

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


def new_log(cap: int, transitions: Sequence[Transition] = ()) -> TransitionLog:
    """A :class:`~core.transitions.TransitionLog` that keeps the last :data:`STEADY_WINDOW`
    transitions for :func:`steady_from_transitions`, holding ``transitions``.

    >>> new_log(cap=1).recent.maxlen == STEADY_WINDOW
    True
    """
    log = TransitionLog(cap, STEADY_WINDOW)
    log.extend(transitions)
    return log


def log_rest_at_stop(
    log: TransitionLog, t: float, w: float, r: float, a: float, c: float, t_end: float
) -> float:
    """A numerical method stops following the bounces at ``t`` (last approach speed ``w``):
    record the accumulation (for ``0 < r < 1`` with the stop behind the slip centre, after
    the closed-form remaining time, paper §4) and the rest at the stop; return the rest time.
    """
    t_rest = t
    if 0.0 < r < 1.0 and a > c:
        t_rest = t + accumulation_time(r * w, r, a - c)
        if t_rest <= t_end:
            log.add(TransitionKind.ACCUMULATION, t_rest, c, 0.0, 0.0)
    if t_rest <= t_end:
        log.add(TransitionKind.REST, t_rest, c, 0.0, 0.0)
    return t_rest


class StopWorkSamples(NamedTuple):
    """A deformable stop's work in closed form (:class:`core.deformable.stop_work.StopWork`): at the
    points, at the samples, and where the mass sticks in contact (mode ``CONTACT``, where
    the friction force is ``x + phi`` as on free stick)."""

    points: np.ndarray
    samples: np.ndarray
    stuck: np.ndarray


def _energy_at_samples(
    t: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    mode: np.ndarray,
    acc: np.ndarray | None,
    phi: np.ndarray,
    belt_speed: float,
    idx: np.ndarray,
    ts: np.ndarray,
    xs: np.ndarray,
    phis: np.ndarray,
    stop_work: StopWorkSamples | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Friction work, belt work and work done on the stop at the samples (per unit ``k``).

    Friction force over ``k`` on the interval after point ``i``: ``f = x'' + x + phi`` (the
    equation of motion solved for it, ``docs/physics.md``). On slip it is the constant ``s*a``
    (``+-b`` in the switch model's transition band), so its work ``f * dx`` is exact; on
    stick it is the spring-plus-contact force, summed by the trapezoid rule in ``x`` (exact
    off the stop, where it is linear in ``x``). A jump (rigid impact) hands its loss of
    kinetic energy to the stop; the deformable stop's work is the trapezoid rule in ``x``,
    or ``stop_work``, its values at the points and at the samples in closed form along the
    law's branches (then the contact force's work on stick is exact too).
    Inside an interval the same rules run from its start point to the sample, so the sums
    at the samples are as accurate as at the points.
    """
    n = len(t)
    if n < 2:
        z = np.zeros(len(ts))
        return z, z.copy(), z.copy()
    mech = 0.5 * (x * x + v * v)
    dx, dt = np.diff(x), np.diff(t)
    jump = dt == 0.0
    stick = mode[:-1] == Mode.STICK
    if stop_work is not None:
        stick = stick | stop_work.stuck[:-1]
    k = np.clip(idx, 0, n - 2)
    d_x = xs - x[k]
    phi_mid = 0.5 * (phi[:-1] + phi[1:])
    if stop_work is None:
        cum_stop = np.concatenate([[0.0], np.cumsum(np.where(jump, -np.diff(mech),
                                                             phi_mid * dx))])
        stop_s = cum_stop[k] + np.where(jump[k], 0.0, 0.5 * (phi[k] + phis) * d_x)
    else:
        w_points, stop_s = stop_work.points, stop_work.samples
    if acc is None:
        # no acceleration given: the caller closes the balance with the friction work
        return np.full(len(ts), math.nan), np.full(len(ts), math.nan), stop_s
    f_left = acc[:-1] + x[:-1] + phi[:-1]
    # On stick the friction force is the spring's and the stop's, x + phi: its mean over
    # an interval by the trapezoid rule, or from the stop's work in closed form.
    if stop_work is None:
        f_stick = 0.5 * (x[:-1] + x[1:]) + phi_mid
        f_stick_s = 0.5 * (x[k] + phi[k] + xs + phis)
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            f_stick = np.where(dx != 0.0, 0.5 * (x[:-1] + x[1:]) + np.diff(w_points) / dx,
                               f_left)
            f_stick_s = np.where(d_x != 0.0, 0.5 * (x[k] + xs) + (stop_s - w_points[k]) / d_x,
                                 f_left[k])
    f_int = np.where(stick, f_stick, f_left)
    fric = np.where(jump, 0.0, f_int * dx)
    belt = np.where(jump, 0.0, f_int * belt_speed * dt)
    cum_f = np.concatenate([[0.0], np.cumsum(fric)])
    cum_b = np.concatenate([[0.0], np.cumsum(belt)])
    f_s = np.where(stick[k], f_stick_s, f_left[k])
    f_s = np.where(jump[k], 0.0, f_s)
    fric_s = cum_f[k] + f_s * d_x
    belt_s = cum_b[k] + f_s * belt_speed * (ts - t[k])
    return fric_s, belt_s, stop_s


def steady_from_transitions(
    tail: Sequence[Transition],
    *,
    scale: float,
    rtol: float,
    t_end: float,
    final_mode: int,
    final_v: float,
    x_max_between=None,
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
        ``P^j`` (:class:`core.steady.FixedPointDetector`).
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

    for tr in reversed(tail):
        if tr.kind is TransitionKind.REST:
            return Steady(SteadyKind.REST, x_max=tr.x, impact_speed=0.0, t_reached=tr.t)
        if tr.kind is TransitionKind.FAILURE:
            return Steady(SteadyKind.NONE)
    t_last = tail[-1].t if tail else 0.0
    if not tail or t_end - t_last > 2.0 * math.pi:
        # no transition for more than a full slip circle: nothing will happen any more
        quiet = _quiet_steady(tail, t_last, t_end, final_mode, final_v, xmax, pressed)
        if quiet is not None:
            return quiet

    if limit is not None:
        train = train_steady(tail, limit)
        if train is not None:
            return train
    periodic = _periodic_tail(tail, scale, rtol, xmax, pressed, limit)
    if periodic is not None:
        return periodic
    if pressed:
        return pressed_steady(tail, lossless=lossless, probe=probe)
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


def _quiet_steady(
    tail: list[Transition],
    t_last: float,
    t_end: float,
    final_mode: int,
    final_v: float,
    xmax,
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


#: A period ``d`` that divides the ``j`` found is the period when its states repeat within
#: this factor of how well those ``j`` apart do (or of the tolerance).
SUB_PERIOD_FACTOR = 10.0


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


def _periodic_tail(
    tail: list[Transition], scale: float, rtol: float, xmax, pressed: bool,
    limit: ElasticLimit | None = None,
) -> Steady | None:
    """The periodic steady state (or its grazing limit) the transitions end on, or ``None``.

    Every transition goes through :class:`core.steady.FixedPointDetector`; the tail is
    periodic when each transition of its last ``STEADY_PERIODS`` periods of ``j``
    transitions repeats the state ``j`` transitions earlier (the smallest such ``j``).
    Not a period: reversals alone (loops on the stop, which :func:`core.steady.
    pressed_steady` labels from their swings: one reversal is half a loop, and loops
    that die out come within a tolerance of each other), nor a train of contacts the law
    makes lose energy (:func:`core.steady.train_loses`), nor inelastic rigid impacts with
    nothing but slip on one circle between them (:func:`core.steady.impacts_lose`).
    """
    n = len(tail)
    found = None
    # Repeats to the tolerance over STEADY_PERIODS periods, or to rounding over one: a
    # cycle through a state the motion is reset to (a stick that carries the mass onto the
    # stop at the belt's speed) repeats it to the bit, as the exact method's detector sees
    # after one period (a 41-time-unit cycle twice in t_end = 100: "periodic" by exact,
    # "none" by event).
    for tol, periods in ((rtol, STEADY_PERIODS), (FIXED_POINT_RTOL, 1)):
        det = FixedPointDetector(scale, rtol=tol, min_cycle_size=scale)
        for i, tr in enumerate(tail):
            det.add(tr.kind, tr.t, tr.x, tr.v, i)
        found = _repeat_period(tail, det, periods)
        if found is not None:
            break
    if found is None:
        return None
    j = found
    k = n - 1 - periods * j
    while k - j >= 0 and j in det.repeats[k]:
        k -= 1
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


def _repeat_period(tail: list[Transition], det: FixedPointDetector, periods: int) -> int | None:
    """The fewest transitions ``j`` per period such that each transition of the last
    ``periods`` periods repeats (``det``) the state ``j`` earlier, or ``None``."""
    n = len(tail)
    for j in range(1, min(STEADY_MAX_J, n // (periods + 1)) + 1):
        if all(j in det.repeats[n - 1 - i] for i in range(periods * j)) and (
                tail[-1].t - tail[-1 - j].t > 0.0):
            return j
    return None


def _falling_contacts(tail: list[Transition]) -> str | None:
    """``"grazing"`` when the last transitions are impacts (or contacts) with falling speed,
    ``"rest"`` when they are only overlap reversals of falling amplitude (a mass pressed on a
    deformable stop), else ``None``."""
    impacts = [tr for tr in tail if tr.kind in IMPACT_KINDS or tr.kind is TransitionKind.CONTACT]
    recent = tail[-ASYMPTOTIC_MIN:]
    if len(recent) < ASYMPTOTIC_MIN:
        return None
    if all(tr.kind is TransitionKind.REVERSAL for tr in recent):
        xs = [tr.x for tr in recent]
        upper, lower = xs[0::2], xs[1::2]
        if _monotone(upper) and _monotone(lower) and _shrinking(upper, lower):
            return "rest"
        return None
    kinds = {tr.kind for tr in recent}
    allowed = {
        TransitionKind.IMPACT,
        TransitionKind.CONTACT,
        TransitionKind.SEPARATION,
        TransitionKind.REVERSAL,
    }
    if kinds <= allowed and len(impacts) >= ASYMPTOTIC_MIN // 2:
        speeds = [tr.v for tr in impacts[-ASYMPTOTIC_MIN // 2 :]]
        if all(s1 < s0 for s0, s1 in zip(speeds, speeds[1:], strict=False)):
            return "grazing"
    return None


def _monotone(seq: list[float]) -> bool:
    d = np.diff(seq)
    return bool(np.all(d >= 0.0) or np.all(d <= 0.0))


def _shrinking(upper: list[float], lower: list[float]) -> bool:
    m = min(len(upper), len(lower))
    gaps = [abs(u - w) for u, w in zip(upper[:m], lower[:m], strict=False)]
    return all(g1 <= g0 for g0, g1 in zip(gaps, gaps[1:], strict=False))


def result_from_dense(
    t,
    x,
    v,
    mode,
    transitions: Sequence[Transition] | TransitionLog,
    *,
    t_end: float,
    n_samples: int,
    transition_cap: int,
    acc=None,
    contact_force=None,
    overlap=None,
    stop_stored=None,
    stop_law=None,
    impulses=None,
    energy: Energy | None = None,
    steady: Steady | None = None,
    steady_tol: float | None = None,
    rtol: float = 1e-6,
    model_rtol: float = 0.0,
    pressed: bool = False,
    limit: ElasticLimit | None = None,
    lossless: bool = False,
    rest_swing: tuple[float, float] | None = None,
    belt_speed: float = math.nan,
    x_max: float | None = None,
    x_upper: float | None = None,
    status: Status = Status.SUCCESS,
    method: str,
    stats: dict[str, int] | None = None,
    info: dict[str, object] | None = None,
    t_eval: np.ndarray | None = None,
    dense: DenseSolution | None = None,
) -> Result:
    """Assemble a :class:`~core.result.Result` from an integrator's dense points.

    Parameters
    ----------
    t, x, v : array_like
        Times (non-decreasing; a repeated time is a velocity jump), positions and
        velocities at the step points. The solve may end before ``t_end`` (stop failure):
        samples then cover ``[0, t[-1]]``.
    mode : array_like of int
        :class:`~core.result.Mode` on the interval starting at each point.
    transitions : sequence of Transition or TransitionLog
        All transitions in time order (capped here), or a log that already capped them.
    t_end : float
        The horizon asked for.
    n_samples : int
        Number of uniform samples over ``[0, t_end]``; the stored transitions' points are
        merged in (an impact contributes the state before and after it).
    transition_cap : int
        Transitions stored in the result (all are counted).
    acc : array_like, optional
        Acceleration ``x''`` on the interval starting at each point: makes the velocity
        samples cubic and the friction work exact on slip. Without it the velocity is
        interpolated linearly and the friction work closes the energy balance.
    contact_force, overlap : array_like, optional
        ``phi/k`` and ``x - clearance`` at the points (deformable stop); zeros otherwise.
    stop_stored : array_like or callable, optional
        Energy stored in the deformable stop: values at the points, or a function
        ``f(overlap, force)`` evaluated at the samples in contact only (cheaper: the stored
        energy needs a closed-form integral per call). ``stop_loss`` is the work done on the
        stop less this.
    stop_law : optional
        The deformable stop's law along the solution's branches (as
        :class:`core.deformable.stop_work.StopWork`): ``points``, the work done on the stop at the
        points, and ``at(idx, xs)``, the contact force, overlap, work and stored energy at
        samples ``xs`` in the intervals ``idx``, in closed form. Replaces
        ``contact_force``, ``overlap`` and ``stop_stored`` at the samples (no interpolation
        between the points) and the trapezoid rule of the stop's work.
    impulses : array_like, shape (n, 2), optional
        Impact times and impulses; by default from the stored impacts (``v - v_after``).
    energy : Energy, optional
        Energy terms already at the samples (overrides the computed ones).
    steady : Steady, optional
        The steady state if the caller knows it; else searched on the transitions with
        :func:`steady_from_transitions`.
    steady_tol : float, optional
        Absolute tolerance of that search; by default
        ``max(STEADY_TOL_PER_RTOL * rtol, STEADY_TOL_FLOOR)`` times the state scale.
    rtol : float
        The integrator's relative tolerance (for the default ``steady_tol``).
    model_rtol : float
        Relative error of the model itself, located anew at every transition (the switch
        model's stick band): a floor of the default ``steady_tol``. Unlike the integration
        error it does not grow with the horizon.
    pressed : bool
        The belt presses the mass on the stop (see :func:`steady_from_transitions`).
    limit, lossless : optional
        A deformable stop's law (see :func:`steady_from_transitions`).
    rest_swing : (float, float), optional
        The swing of the position and of the velocity within which loops on a pressed
        deformable stop are at rest (:func:`core.deformable.rest.rest_swing`): loops
        still swinging more at the horizon are an oscillation, not rest (needs ``dense``).
    belt_speed : float
        ``v`` (for the belt's work).
    x_max : float, optional
        The maximum displacement if known; else the maximum of the Hermite interpolant.
    x_upper : float, optional
        A bound the samples must respect (the rigid stop's face): interpolants that round
        beyond it are clipped.
    status : Status
    method : str
    stats : dict, optional
        Integer counts (:func:`core.result.make_stats`).
    info : dict, optional
        Diagnostics that are not counts (the solver's name, the stick band).
    t_eval : ndarray, optional
        Sample exactly at these times (checked by the caller) instead of the uniform grid
        and the transitions; those beyond the end of an early-stopped solve are dropped.
    dense : DenseSolution, optional
        The method's own interpolant: the samples of ``x`` and ``x'`` are taken from it,
        and it is attached to the result for :meth:`~core.result.Result.evaluate`.

    Returns
    -------
    Result
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    mode = np.asarray(mode, dtype=np.int8)
    acc_arr = None if acc is None else np.asarray(acc, dtype=float)
    n = len(t)
    phi = np.zeros(n) if contact_force is None else np.asarray(contact_force, dtype=float)
    ovl = np.zeros(n) if overlap is None else np.asarray(overlap, dtype=float)
    stored_fn = stop_stored if callable(stop_stored) else None
    stored = (
        np.zeros(n)
        if stop_stored is None or stored_fn is not None
        else np.asarray(stop_stored, dtype=float)
    )
    log = (
        transitions
        if isinstance(transitions, TransitionLog)
        else new_log(transition_cap, transitions)
    )

    t_stop = min(float(t_end), float(t[-1]))
    ts, is_left = _sample_times(t_stop, n_samples, log, t_eval)

    def sample(y: np.ndarray, dy: np.ndarray | None) -> np.ndarray:
        out = np.empty(len(ts))
        for side, sel in (("right", ~is_left), ("left", is_left)):
            if not np.any(sel):
                continue
            if dy is None:
                out[sel] = linear_eval(t, y, ts[sel], side)
            else:
                out[sel] = hermite_eval(t, y, dy, ts[sel], side)
        return out

    if dense is not None:
        xs, vs = np.empty(len(ts)), np.empty(len(ts))
        for side, sel in ((1, ~is_left), (-1, is_left)):
            if np.any(sel):
                xs[sel], vs[sel] = dense.evaluate(ts[sel], side)
    else:
        xs, vs = sample(x, v), sample(v, acc_arr)
    if x_upper is not None:
        # a rigid stop's face: the interpolant may round a few ulps beyond it
        xs = np.minimum(xs, x_upper)
    idx = np.where(
        is_left,
        np.clip(np.searchsorted(t, ts, side="left") - 1, 0, max(n - 1, 0)),
        np.clip(np.searchsorted(t, ts, side="right") - 1, 0, max(n - 1, 0)),
    )
    modes = mode[idx].astype(np.int8)
    if stop_law is not None:
        phis, ovls, work_s, stored_s = stop_law.at(idx, xs)
        exact_work = StopWorkSamples(np.asarray(stop_law.points, dtype=float), work_s,
                                     np.asarray(stop_law.stuck, dtype=bool))
    else:
        phis, ovls, exact_work = sample(phi, None), sample(ovl, None), None
        stored_s = (np.array([stored_fn(d, p) if d > 0.0 else 0.0
                              for d, p in zip(ovls, phis, strict=True)])
                    if stored_fn is not None else sample(stored, None))

    if energy is None:
        fric_s, belt_s, stop_s = _energy_at_samples(
            t, x, v, mode, acc_arr, phi, belt_speed, idx, ts, xs, phis, exact_work
        )
        mech_s = 0.5 * (xs * xs + vs * vs)
        if acc_arr is None:
            fric_s = mech_s - mech_s[0] + stop_s
        energy = Energy(
            mechanical=mech_s,
            friction_work=fric_s,
            belt_input=belt_s,
            stop_loss=stop_s - stored_s,
            stop_stored=stored_s,
        )

    if impulses is None:
        impulses = np.array(log.impulses, dtype=float).reshape(-1, 2)
    else:
        impulses = np.asarray(impulses, dtype=float).reshape(-1, 2)

    if x_max is None:
        x_max = hermite_max(t, x, v) if n else math.nan

    if steady is None:
        scale = _state_scale(x, v, belt_speed)
        steady_rtol = (max(STEADY_TOL_PER_RTOL * rtol, model_rtol, STEADY_TOL_FLOOR)
                       if steady_tol is None else steady_tol / scale)
        probe = _swing_probe(dense, t_stop, rest_swing) if pressed else None
        steady = _steady_of(log, t, x, v, mode, scale, steady_rtol, t_stop, pressed, limit,
                            lossless, probe)

    return Result(
        t=ts,
        x=xs,
        v=vs,
        mode=modes,
        transitions=tuple(log.stored),
        transition_counts=dict(log.counts),
        n_transitions=log.total,
        x_max=float(x_max),
        steady=steady,
        status=status,
        energy=energy,
        contact_force=phis,
        overlap=ovls,
        impulses=impulses,
        method=method,
        stats=dict(stats or {}),
        info=dict(info or {}),
        dense=dense,
    )


def result_from_track(
    track: PointTrack,
    log: TransitionLog,
    inputs: SolveInputs,
    *,
    rtol: float,
    model_rtol: float = 0.0,
    **result: object,
) -> Result:
    """:func:`result_from_dense` for an integrator's :class:`PointTrack` on a scene: the
    contact force, overlap and stored energy of a deformable stop, the face of a rigid one,
    sampled as ``inputs`` asks. ``result`` holds ``status``, ``method``, ``stats``, ``info``
    and ``dense`` for the :class:`~core.result.Result`."""
    osc, stop = inputs.osc, inputs.stop
    facts = StopFacts.of(osc, stop)
    soft, c = facts.soft, facts.c
    return result_from_dense(
        track.t,
        track.x,
        track.v,
        track.mode,
        log,
        t_end=inputs.t_end,
        n_samples=inputs.n_samples,
        t_eval=inputs.t_eval,
        transition_cap=log.cap,
        acc=track.acc,
        # a rigid stop's reaction is recorded only at rest on it (zero elsewhere)
        contact_force=track.phi,
        overlap=[xx - c for xx in track.x] if soft else None,
        stop_stored=(lambda d, p: stored_energy(d, p, stop)) if soft else None,
        rtol=rtol,
        model_rtol=model_rtol,
        pressed=facts.pressed,
        limit=elastic_limit(osc.a, c, stop) if soft and osc.v > 0.0 else None,
        lossless=soft and stop.law == "passive",
        # the hysteretic solver's rule for rest at the same rtol; not the switch model's
        # stick band (model_rtol, ~1e-3 at the standard preset): its loops on the stop never
        # stick, and it follows Fig. 11's to 1e-2 of their 6e-8 amplitude at t = 80, as the
        # event method does
        rest_swing=rest_swing_of(osc, stop, rtol, 0.0) if soft else None,
        belt_speed=osc.v,
        x_upper=c if facts.rigid else None,
        **result,
    )


def _swing_probe(dense: DenseSolution | None, t_stop: float,
                 rest_swing: tuple[float, float] | None) -> SwingProbe | None:
    """The method's interpolant at the horizon against the rule for rest, where there are
    both."""
    if dense is None or rest_swing is None:
        return None
    return SwingProbe(lambda t: dense.evaluate(t, -1), t_stop, *rest_swing)


def _state_scale(x: np.ndarray, v: np.ndarray, belt_speed: float) -> float:
    """Largest of ``|x|``, ``|x'|`` and the belt speed: the scale of the transition states."""
    scale = max(
        float(np.max(np.abs(x))) if len(x) else 0.0,
        float(np.max(np.abs(v))) if len(v) else 0.0,
        abs(belt_speed) if math.isfinite(belt_speed) else 0.0,
    )
    return max(scale, 1e-300)


def _steady_of(
    log: TransitionLog,
    t: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    mode: np.ndarray,
    scale: float,
    rtol: float,
    t_stop: float,
    pressed: bool,
    limit: ElasticLimit | None,
    lossless: bool,
    probe: SwingProbe | None = None,
) -> Steady:
    """The steady state of dense points ``(t, x, v, mode)`` and their transitions."""
    n = len(t)

    def x_max_between(t0: float, t1: float) -> float:
        i0 = int(np.searchsorted(t, t0, side="left"))
        i1 = int(np.searchsorted(t, t1, side="right"))
        i0 = max(min(i0, n - 1) - 1, 0)
        i1 = max(i1, i0 + 1)
        return hermite_max(t[i0 : i1 + 1], x[i0 : i1 + 1], v[i0 : i1 + 1])

    return steady_from_transitions(
        log.recent,
        scale=scale,
        rtol=rtol,
        t_end=t_stop,
        final_mode=int(mode[-1]) if n else int(Mode.SLIP),
        final_v=float(v[-1]) if n else math.nan,
        x_max_between=x_max_between,
        pressed=pressed,
        limit=limit,
        lossless=lossless,
        probe=probe,
    )


def _sample_times(
    t_stop: float, n_samples: int, log: TransitionLog, t_eval: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """Sample times and, for each, whether it is the left limit at a jump.

    ``t_eval`` (up to ``t_stop``) as given; else ``n_samples`` uniform times over
    ``[0, t_stop]`` merged with the stored transitions, an impact twice (the state before it
    sorts first).
    """
    if t_eval is not None:
        ts = np.asarray(t_eval, dtype=float)
        ts = ts[ts <= t_stop]
        return ts, np.zeros(len(ts), dtype=bool)
    uniform = np.linspace(0.0, t_stop, max(int(n_samples), 2))
    tr_pts = [tr for tr in log.stored if tr.t <= t_stop]
    jump_t = np.array([tr.t for tr in tr_pts if tr.kind in IMPACT_KINDS], dtype=float)
    other_t = np.array([tr.t for tr in tr_pts if tr.kind not in IMPACT_KINDS], dtype=float)
    right_t = np.concatenate([uniform, other_t, jump_t])
    order_key = np.concatenate([np.ones(len(right_t)), np.zeros(len(jump_t))])
    all_t = np.concatenate([right_t, jump_t])
    is_left = np.concatenate([np.zeros(len(right_t), bool), np.ones(len(jump_t), bool)])
    perm = np.lexsort((order_key, all_t))
    return all_t[perm], is_left[perm]
