"""Build a :class:`~core.result.Result` from the dense output of a numerical integrator.

The transitions go to the project's one log (:class:`core.transitions.TransitionLog`); the
steady state is read off them by :func:`core.steady.steady_from_transitions` at the
tolerance of the numerical method, and the energy terms at the samples come from
:mod:`core.dense_energy`.

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

import numpy as np

from core.deformable.law import ElasticLimit, elastic_limit, stored_energy
from core.deformable.rest import rest_swing_of
from core.dense_energy import StopWorkSamples, energy_at_samples
from core.numerics.dense_output import PointTrack
from core.numerics.hermite import hermite_eval, hermite_max, linear_eval
from core.result import (
    DenseSolution,
    Energy,
    Mode,
    Result,
    Status,
    Steady,
    Transition,
    TransitionKind,
)
from core.solve_inputs import SolveInputs, StopFacts
from core.steady import STEADY_WINDOW, SwingProbe, method_rtol, steady_from_transitions
from core.theory import accumulation_time
from core.transitions import IMPACT_KINDS, TransitionLog


def new_log(cap: int, transitions: Sequence[Transition] = ()) -> TransitionLog:
    """A :class:`~core.transitions.TransitionLog` that keeps the last :data:`STEADY_WINDOW`
    transitions for :func:`core.steady.steady_from_transitions`, holding ``transitions``.

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
        :func:`core.steady.steady_from_transitions`.
    steady_tol : float, optional
        Absolute tolerance of that search; by default
        :func:`core.steady.method_rtol` times the state scale.
    rtol : float
        The integrator's relative tolerance (for the default ``steady_tol``).
    model_rtol : float
        Relative error of the model itself, located anew at every transition (the switch
        model's stick band): a floor of the default ``steady_tol``. Unlike the integration
        error it does not grow with the horizon.
    pressed : bool
        The belt presses the mass on the stop (see :func:`core.steady.steady_from_transitions`).
    limit, lossless : optional
        A deformable stop's law (see :func:`core.steady.steady_from_transitions`).
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
    phi, ovl, stored, stored_fn = _stop_points(len(t), contact_force, overlap, stop_stored)
    log = (
        transitions
        if isinstance(transitions, TransitionLog)
        else new_log(transition_cap, transitions)
    )

    t_stop = min(float(t_end), float(t[-1]))
    ts, is_left = _sample_times(t_stop, n_samples, log, t_eval)
    sample = _sampler(t, ts, is_left)
    xs, vs = _sample_state(sample, dense, x, v, acc_arr, ts, is_left, x_upper)
    idx = _intervals(t, ts, is_left)
    modes = mode[idx].astype(np.int8)
    phis, ovls, stored_s, exact_work = _stop_samples(sample, stop_law, idx, xs, phi, ovl,
                                                     stored, stored_fn)
    if energy is None:
        fric_s, belt_s, stop_s = energy_at_samples(
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

    source = log.impulses if impulses is None else impulses
    impulses = np.asarray(source, dtype=float).reshape(-1, 2)
    if x_max is None:
        x_max = hermite_max(t, x, v) if len(t) else math.nan
    if steady is None:
        scale = _state_scale(x, v, belt_speed)
        steady_rtol = (method_rtol(rtol, model_rtol) if steady_tol is None
                       else steady_tol / scale)
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


def _stop_points(n: int, contact_force, overlap, stop_stored):
    """The contact force, overlap and stored energy at the ``n`` points (zeros where not
    given), and the stored energy's function when it is given as one."""
    phi = np.zeros(n) if contact_force is None else np.asarray(contact_force, dtype=float)
    ovl = np.zeros(n) if overlap is None else np.asarray(overlap, dtype=float)
    stored_fn = stop_stored if callable(stop_stored) else None
    given = stop_stored is not None and stored_fn is None
    stored = np.asarray(stop_stored, dtype=float) if given else np.zeros(n)
    return phi, ovl, stored, stored_fn


def _sampler(t: np.ndarray, ts: np.ndarray, is_left: np.ndarray):
    """``sample(y, dy)``: values at the sample times ``ts`` (left limits where
    ``is_left``) of ``y`` at the points ``t``, cubic Hermite with the derivative ``dy``,
    linear without it."""

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

    return sample


def _sample_state(sample, dense: DenseSolution | None, x: np.ndarray, v: np.ndarray,
                  acc: np.ndarray | None, ts: np.ndarray, is_left: np.ndarray,
                  x_upper: float | None) -> tuple[np.ndarray, np.ndarray]:
    """``x`` and ``x'`` at the samples: from the method's own interpolant where there is
    one, else interpolated between the points; clipped at a rigid stop's face."""
    if dense is not None:
        xs, vs = np.empty(len(ts)), np.empty(len(ts))
        for side, sel in ((1, ~is_left), (-1, is_left)):
            if np.any(sel):
                xs[sel], vs[sel] = dense.evaluate(ts[sel], side)
    else:
        xs, vs = sample(x, v), sample(v, acc)
    if x_upper is not None:
        # a rigid stop's face: the interpolant may round a few ulps beyond it
        xs = np.minimum(xs, x_upper)
    return xs, vs


def _intervals(t: np.ndarray, ts: np.ndarray, is_left: np.ndarray) -> np.ndarray:
    """The interval between points each sample lies in (the one that ends at it for a
    left limit)."""
    last = max(len(t) - 1, 0)
    return np.where(
        is_left,
        np.clip(np.searchsorted(t, ts, side="left") - 1, 0, last),
        np.clip(np.searchsorted(t, ts, side="right") - 1, 0, last),
    )


def _stop_samples(sample, stop_law, idx: np.ndarray, xs: np.ndarray, phi: np.ndarray,
                  ovl: np.ndarray, stored: np.ndarray, stored_fn):
    """The contact force, overlap and stored energy at the samples, and the stop's work in
    closed form where its law is given (:class:`StopWorkSamples`, else ``None``)."""
    if stop_law is not None:
        phis, ovls, work_s, stored_s = stop_law.at(idx, xs)
        exact_work = StopWorkSamples(np.asarray(stop_law.points, dtype=float), work_s,
                                     np.asarray(stop_law.stuck, dtype=bool))
        return phis, ovls, stored_s, exact_work
    phis, ovls = sample(phi, None), sample(ovl, None)
    if stored_fn is None:
        return phis, ovls, sample(stored, None), None
    stored_s = np.array([stored_fn(d, p) if d > 0.0 else 0.0
                         for d, p in zip(ovls, phis, strict=True)])
    return phis, ovls, stored_s, None


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
