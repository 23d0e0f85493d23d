"""The samples of a finished deformable-stop solve: states, energy terms, dense evaluation
and the steady state, read from the rows and transitions its :class:`Solve` recorded."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from core.deformable.arcs import evaluate_arcs
from core.deformable.hermite import dpoly, poly
from core.deformable.law import (
    BranchPrimitive,
    branch_work,
    force_on_branches,
    phi_compression,
    stored_energy_many,
)
from core.deformable.rest import REST_SPEED_PER_AMPLITUDE, rest_amplitude
from core.deformable.state import (
    ARC,
    FIXED_POINT_RTOL,
    HERMITE,
    LINE,
    OSC,
    TRAIN,
    Solve,
)
from core.numerics.hermite import hermite_max
from core.params import HystereticStop
from core.result import Energy, Mode, Result, Status, Steady, SteadyKind, TransitionKind, make_stats
from core.steady import SwingProbe, pressed_steady, steady_from_transitions, train_steady
from core.trajectory import evaluate

#: Samples added on each branch of a contact (from its start, a reversal of the overlap
#: rate or its end to the next) besides the uniform grid: a contact lasts ~pi/sqrt(k_c0),
#: a few uniform samples at most, and a force history or hysteresis loop drawn through so
#: few is a polygon of chords that cuts above the compression envelope.
CONTACT_SAMPLES = 16


#: Branches sampled so at the start and at the end of a response (a mass that rattles on
#: the stop has thousands; the first loops are the large ones, the last the steady ones).
CONTACT_SAMPLED_BRANCHES = 16


def _continued(sv: Solve, times: np.ndarray, with_work: bool = True
               ) -> tuple[np.ndarray, np.ndarray]:
    """Times mapped into the detected cycle (periodic continuation) and the work the
    repeated cycles add (zeros without ``with_work``); the identity and zeros without a
    cycle."""
    shift_work = np.zeros((len(times), 3))
    t_eval = np.array(times, dtype=float)
    if sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        t_then, t_now = sv.tail_start
        period = t_now - t_then
        late = t_eval > t_now
        k = np.floor((t_eval[late] - t_then) / period)
        t_eval[late] = t_eval[late] - k * period
        if not with_work:
            return t_eval, shift_work
        per = _work_at(sv, np.array([t_now, t_then]))
        shift_work[late] = k[:, None] * (per[0] - per[1])[None, :]
        # Each repeated cycle returns to the same state, so the stop takes exactly the
        # friction work of the cycle: a cycle that is a fixed point only to a tolerance
        # (a reduced model's) would otherwise add its energy drift once per cycle.
        shift_work[late, 2] = shift_work[late, 0]
    return t_eval, shift_work


class HystereticDense:
    """The solution as a function of time (:attr:`core.result.Result.dense`): exact free
    flight, the contact rows' quintic Hermite steps, arcs, lines and reduced models, and
    the periodic continuation. Position and velocity are continuous at a deformable stop,
    so ``side`` makes no difference."""

    def __init__(self, sv: Solve, t_stop: float) -> None:
        self._sv, self._t_stop = sv, t_stop

    def evaluate(self, t, side: int = -1) -> tuple[np.ndarray, np.ndarray]:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if np.any(t < 0.0) or np.any(t > self._t_stop):
            raise ValueError(f"t must lie in [0, {self._t_stop:g}] (the computed motion)")
        t_eval, _ = _continued(self._sv, t, with_work=False)
        x, xd, *_ = _evaluate(self._sv, t_eval, self._sv.stop, state_only=True)
        return x, xd


#: Points per cycle on which a periodic motion's largest displacement is looked for (the
#: cubic Hermite interpolant of the exact states between them: ~h^4, below rounding).
CYCLE_MAX_POINTS = 2000


def _cycle_x_max(sv: Solve, stop: HystereticStop, t_then: float, t_now: float) -> float:
    """Largest ``x`` of the periodic cycle ``[t_then, t_now]``: the Hermite interpolant of
    the solution's states on :data:`CYCLE_MAX_POINTS` points and its transitions."""
    marks = [tr.t for tr in sv.log.recent if t_then <= tr.t <= t_now]
    tt = np.unique(np.concatenate((np.linspace(t_then, t_now, CYCLE_MAX_POINTS), marks)))
    x, xd = _evaluate(sv, tt, stop, state_only=True)[:2]
    return float(hermite_max(tt, x, xd))


def assemble(sv: Solve, osc, stop, t_end, x0, v0, n_samples, t_eval=None) -> Result:
    """Samples on the free segments and the contact rows, energy terms, steady state."""
    t_stop = t_end if sv.status is Status.SUCCESS else min(t_end, _last_time(sv))
    times = _sample_times(sv, t_end, t_stop, n_samples, t_eval)
    if sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        sv.replicate_cycle(t_end)
    t_eval, shift_work = _continued(sv, times)
    x, xd, mode, phi, delta, work, stored = _evaluate(sv, t_eval, stop)
    work = work + shift_work
    mechanical = 0.5 * (x * x + xd * xd)
    energy = Energy(
        mechanical=mechanical,
        friction_work=work[:, 0],
        belt_input=work[:, 1],
        stop_loss=work[:, 2] - stored,
        stop_stored=stored,
    )
    steady = sv.steady
    if steady is None:
        steady = _asymptotic(sv, t_end, mode, xd)
    elif steady.kind is SteadyKind.PERIODIC and math.isnan(steady.x_max):
        steady = dataclasses.replace(steady, x_max=_cycle_x_max(sv, stop, *sv.tail_start))
    stats = make_stats(
        segments=len(sv.table) + len(sv.contact.kind),
        steps=sv.steps,
        rejected=sv.rejected,
        rhs_evals=sv.rhs_evals + sv.arc_evals,
        events=sv.log.total,
    )
    info = _info(sv, stop)
    x_max = sv.x_max
    if sv.table.t0:
        x_max = max(x_max, sv.table.x_max)
    return Result(
        t=times,
        x=x,
        v=xd,
        mode=mode.astype(np.int8),
        transitions=tuple(sv.log.stored),
        transition_counts=dict(sv.log.counts),
        n_transitions=sv.log.total,
        x_max=float(x_max),
        steady=steady,
        status=sv.status,
        energy=energy,
        contact_force=phi,
        overlap=delta,
        impulses=np.zeros((0, 2)),
        method="exact",
        stats=stats,
        info=info,
        dense=HystereticDense(sv, t_stop),
    )


def _sample_times(sv: Solve, t_end: float, t_stop: float, n_samples: int, t_eval
                  ) -> np.ndarray:
    """The sample times up to ``t_stop``: ``t_eval``, or ``n_samples`` uniform ones with the
    transitions, the motion's end and the extra samples of contacts and reduced trains."""
    if t_eval is None:
        # The motion's end is one of its points: a solve stopped early (the limit
        # overlap, a failed stop, a budget) ends between samples, and without it the
        # result's last state was a contact sample before the end (a limit reached at
        # t = 1.79626 read as x at t = 1.79588, 6 % of the overlap short).
        marks = [tr.t for tr in sv.log.stored if tr.t <= t_stop] + [t_stop]
        times = np.unique(np.concatenate((np.linspace(0.0, t_end, n_samples), marks,
                                          _contact_samples(sv, t_stop, t_end),
                                          _train_samples(sv, t_stop, n_samples))))
    else:
        times = np.asarray(t_eval, dtype=float)
    return times[times <= t_stop]


def _info(sv: Solve, stop: HystereticStop) -> dict:
    """The result's ``info`` (:func:`core.deformable.solver.solve_hysteretic`)."""
    restitution = sv.restitution
    info = {
        "n_contacts": sv.n_contacts,
        "work_steps": sv.work_steps(),
        "contact_rhs_evals": sv.rhs_evals,
        "arcs": sv.arcs,
        "arc_evals": sv.arc_evals,
        "effective_restitution": restitution[-1] if restitution else math.nan,
        "effective_restitution_first": restitution[0] if restitution else math.nan,
        "law": stop.law,
    }
    if not math.isnan(sv.rest_force):
        info["rest_force"] = sv.rest_force
    if sv.reduced_error > 0.0:
        info["length_scale"] = sv.scale()
        info["reduced_error"] = sv.reduced_error
        # The band where a model states one (a fitted train's error also holds the
        # velocity, up to twice its approach speed); else its error bounds the position too.
        info["reduced_band"] = sv.reduced_band if sv.reduced_band > 0.0 else sv.reduced_error
    if sv.rest_time_error > 0.0:
        info["rest_time_error"] = sv.rest_time_error
    return info


def _last_time(sv: Solve) -> float:
    ends = [sv.contact.t1[-1]] if sv.contact.t1 else []
    if sv.table.t1:
        ends.append(sv.table.t1[-1])
    return max(ends) if ends else 0.0


#: Where in each contact of a reduced train samples are taken (fractions of its duration):
#: its ends and middle (the peak overlap and force), and twice early on, where the belt's
#: push still speeds the mass up (x' peaks ~1.4 % above the approach speed at ~6 % of a
#: contact of scene 11's stop at k_c0 = 1e4; the two samples catch it to 0.1 %). Six
#: samples per contact with the flight's: 16 ms more at t_end = 1e4 (11,800 samples).
TRAIN_CONTACT_FRACTIONS = np.array([0.0, 0.04, 0.08, 0.5, 1.0])


def _train_samples(sv: Solve, t_stop: float, bins: int) -> np.ndarray:
    """Times at the extremes of the contacts a reduced train lays out (their start, middle
    and end, :data:`TRAIN_CONTACT_FRACTIONS`, and the bottom of the flight after each), which
    a uniform grid aliases: a
    train of contacts 0.15 apart sampled every 0.05 showed beats in x'(t) and in the
    contact force. Past ``bins`` contacts per row, the first contact of each of ``bins``
    equal spans of the row: the train shrinks, so it is the span's largest."""
    c = sv.contact
    out = []
    for r, kind in enumerate(c.kind):
        if kind != TRAIN:
            continue
        model, t0, t1 = c.data[r][0], c.t0[r], min(c.t1[r], t_stop)
        start = t0 + np.asarray(model.start, dtype=float)
        dur = np.asarray(model.dur, dtype=float)
        k = np.arange(len(start))
        if len(k) > bins:
            edges = np.linspace(t0, t1, bins + 1)[:-1]
            k = np.unique(np.clip(np.searchsorted(start, edges), 0, len(start) - 1))
        end = start[k] + dur[k]
        nxt = np.where(k + 1 < len(start), start[np.minimum(k + 1, len(start) - 1)], t1)
        inside = (start[k][:, None] + dur[k][:, None] * TRAIN_CONTACT_FRACTIONS).ravel()
        times = np.concatenate((inside, 0.5 * (end + nxt)))
        out.append(times[(times >= t0) & (times <= t1)])
    return np.concatenate(out) if out else np.zeros(0)


def _repeated_spans(tail: tuple[float, float], spans: list[tuple[float, float]],
                    t_end: float) -> list[tuple[float, float]]:
    """The contact branches of the periodic cycle ``tail = (t_then, t_now)`` among
    ``spans``, shifted by the cycle's repeats up to ``t_end`` (the last of them only)."""
    t_then, t_now = tail
    period = t_now - t_then
    cycle = [(a, b) for a, b in spans if a >= t_then and b <= t_now + 1e-12 * period]
    repeats = int(max(0.0, t_end - t_now) // period) + 1 if cycle and period > 0 else 0
    # Only the last repeats can be among the sampled branches: a cycle of a train of
    # micro-contacts may repeat a million times.
    first = max(1, repeats - CONTACT_SAMPLED_BRANCHES)
    return [(a + k * period, b + k * period)
            for k in range(first, repeats + 1) for a, b in cycle if a + k * period < t_end]


def _contact_samples(sv: Solve, t_stop: float, t_end: float) -> np.ndarray:
    """:data:`CONTACT_SAMPLES` times on each branch of the first and the last
    :data:`CONTACT_SAMPLED_BRANCHES` contact branches, a detected cycle's continuation
    included."""
    kinds = (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION)
    marks = [(tr.t, tr.kind) for tr in sv.log.stored if tr.kind in kinds and tr.t <= t_stop]
    marks.append((t_stop, TransitionKind.SEPARATION))
    spans = [(t0, t1) for (t0, k0), (t1, _) in zip(marks[:-1], marks[1:], strict=True)
             if k0 is not TransitionKind.SEPARATION and t1 > t0]
    if spans and sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        spans += _repeated_spans(sv.tail_start, spans, t_end)
    if len(spans) > 2 * CONTACT_SAMPLED_BRANCHES:
        spans = spans[:CONTACT_SAMPLED_BRANCHES] + spans[-CONTACT_SAMPLED_BRANCHES:]
    if not spans:
        return np.zeros(0)
    a, b = np.array(spans).T
    frac = np.arange(1, CONTACT_SAMPLES + 1) / (CONTACT_SAMPLES + 1)
    return (a[:, None] + (b - a)[:, None] * frac[None, :]).ravel()


def _locate(sv: Solve, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    starts = np.array([e[0] for e in sv.timeline])
    src = np.array([e[1] for e in sv.timeline], dtype=int)
    row = np.array([e[2] for e in sv.timeline], dtype=int)
    i = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(starts) - 1)
    return src[i], row[i]


def _work_at(sv: Solve, t: np.ndarray) -> np.ndarray:
    _, _, _, _, _, work, _ = _evaluate(sv, t, sv.stop)
    return work


def _anchors(brs, rows: np.ndarray, stop: HystereticStop) -> tuple[np.ndarray, np.ndarray]:
    """The anchors of the passive law's curves kept over reversals inside the band
    (:class:`~core.deformable.law.Branch`), ``nan`` where none, of the branches ``rows``."""
    a_d, a_p = np.full(len(rows), math.nan), np.full(len(rows), math.nan)
    if stop.law == "passive":
        for k, i in enumerate(rows):
            a_d[k], a_p[k] = brs[i].anchor or (math.nan, math.nan)
    return a_d, a_p


def _evaluate(sv: Solve, t: np.ndarray, stop: HystereticStop, state_only: bool = False):
    """State, mode, force, overlap, cumulative work and stored energy at times ``t``.

    With ``state_only`` only the state ``x, xd`` is complete (the other arrays are left
    partly filled and are not to be read): what a picture of the motion needs, without
    the law's force and stored energy at every contact sample, which cost most of an
    evaluation."""
    n = len(t)
    x = np.zeros(n)
    xd = np.zeros(n)
    mode = np.zeros(n, dtype=np.int8)
    phi = np.zeros(n)
    work = np.zeros((n, 3))
    stored = np.zeros(n)
    if not sv.timeline:
        return x, xd, mode, phi, x - stop.clearance, work, stored
    src, first_row = _locate(sv, t)
    free = src == 0
    if np.any(free):
        _evaluate_free(sv, t, free, x, xd, mode, work)
    idx = np.nonzero(~free)[0]
    if len(idx):
        c = sv.contact
        t0 = np.array(c.t0)
        rows = np.clip(np.searchsorted(t0, t[idx], side="right") - 1, 0, len(t0) - 1)
        xb = stop.clearance
        kinds = np.array(c.kind, dtype=np.int8)[rows]
        branch_rows = np.array(c.branch, dtype=int)[rows]
        is_arc = kinds == ARC
        is_osc = (kinds == OSC) | (kinds == TRAIN)
        if np.any(is_arc):
            evaluate_arcs(sv, t, idx[is_arc], rows[is_arc], x, xd, work)
        _evaluate_reduced(sv, t, idx[is_osc], rows[is_osc], x, xd, work, stored)
        plain = ~is_arc & ~is_osc
        _evaluate_rows(sv, t, idx[plain], rows[plain], x, xd, work)
        if state_only:
            return x, xd, mode, phi, x - stop.clearance, work, stored
        mode[idx] = Mode.CONTACT
        # A reduced train's flights are slip towards the stop.
        mode[idx[(kinds == TRAIN) & (x[idx] < xb)]] = Mode.SLIP
        brs = c.branches
        delta = x[idx] - xb
        loading = np.array([brs[i].loading for i in branch_rows])
        d_r = np.array([brs[i].delta_r for i in branch_rows])
        p_r = np.array([brs[i].phi_r for i in branch_rows])
        a_d, a_p = _anchors(brs, branch_rows, stop)
        # A reduced train's contact unloads from its own peak (paper Eq. 12): the row's
        # branch is the first loading of every contact, the envelope.
        for r in np.unique(rows[kinds == TRAIN]):
            sel = np.nonzero((kinds == TRAIN) & (rows == r))[0]
            model = c.data[r][0]
            unloading = (xd[idx[sel]] < 0.0) & (delta[sel] > 0.0)
            peak = np.asarray(model.peak(t[idx[sel]] - c.t0[r]), dtype=float)
            loading[sel] = ~unloading
            d_r[sel] = np.where(unloading, peak, d_r[sel])
            p_r[sel] = np.where(unloading, phi_compression(peak, stop), p_r[sel])
            a_d[sel] = np.where(unloading, math.nan, a_d[sel])
        phi[idx] = force_on_branches(delta, loading, d_r, p_r, stop, a_d, a_p)
        _reduced_oscillation_forces(c, idx[kinds == OSC], rows[kinds == OSC], t, x, phi)
        primitives: dict[int, BranchPrimitive] = {}

        def primitive(bi: int) -> BranchPrimitive:
            # Unloading branches from 0: their integral up to delta is the stored energy.
            if bi not in primitives:
                d0 = c.branch_start[bi][0]
                sel = delta[branch_rows == bi]
                lo = 0.0 if not brs[bi].loading else min(d0, float(sel.min()))
                hi = max(d0, float(sel.max()), brs[bi].delta_r)
                primitives[bi] = BranchPrimitive(brs[bi], stop, lo, hi)
            return primitives[bi]

        # Once per branch and overlap: the samples of a rest share both (1,600 of them
        # when the mass rests early in a long horizon).
        stop_work: dict[tuple[int, float], float] = {}
        for k in np.nonzero(plain)[0]:
            key = (int(branch_rows[k]), max(float(delta[k]), 0.0))
            if key not in stop_work:
                d0, w0 = c.branch_start[key[0]]
                prim = primitive(key[0])
                stop_work[key] = w0 + prim(key[1]) - prim(d0)
            work[idx[k], 2] = stop_work[key]
        # (a reduced model's samples hold their own, above)
        own = np.nonzero(~is_osc)[0]
        stored[idx[own]] = _stored(delta[own], phi[idx[own]], ~loading[own] & (delta[own] > 0.0),
                                   d_r[own], p_r[own], branch_rows[own], primitive, stop)
    return x, xd, mode, phi, x - stop.clearance, work, stored


def _evaluate_free(sv: Solve, t, free, x, xd, mode, work) -> None:
    """The samples ``free`` (a mask of ``t``) in free flight, from its closed form."""
    table = sv.table.arrays(sv.vb)
    out = evaluate(table, t[free], np.zeros(free.sum(), bool), sv.vb)
    x[free], xd[free], mode[free] = out["x"], out["v"], out["mode"]
    work[free, 0] = out["friction_work"]
    work[free, 1] = out["belt_input"]
    work[free, 2] = out["stop_loss"]


def _evaluate_reduced(sv: Solve, t, idx, rows, x, xd, work, stored) -> None:
    """The samples ``idx`` in the reduced models' ``rows``, one call per row (a train's lays
    out its contacts by a search over thousands: vectorised, not per sample)."""
    c = sv.contact
    for r in np.unique(rows):
        js = idx[rows == r]
        model, x_s, m_s, loss_s = c.data[r]
        tau = t[js] - c.t0[r]
        xj, uj, amp = (np.broadcast_to(np.asarray(q, dtype=float), tau.shape)
                       for q in model.state(tau))
        wf, wb, ws = c.work0[r]
        dwf = c.friction[r] * (xj - x_s)
        x[js], xd[js] = xj, uj
        work[js, 0] = wf + dwf
        work[js, 1] = wb + c.friction[r] * sv.vb * tau
        work[js, 2] = ws + dwf - (0.5 * (xj * xj + uj * uj) - m_s)
        dissipated = model.energy(model.amp0) - model.energy(amp)
        stored[js] = work[js, 2] - (loss_s + dissipated)


def _evaluate_rows(sv: Solve, t, idx, rows, x, xd, work) -> None:
    """The samples ``idx`` in Dormand-Prince steps, stick lines and rest (``rows``): the
    state and the friction and belt work."""
    c, stop, xb = sv.contact, sv.stop, sv.xb
    for j, r in zip(idx, rows, strict=True):
        kind = c.kind[r]
        tau = t[j] - c.t0[r]
        wf, wb, ws = c.work0[r]
        if kind == HERMITE:
            coeffs, h = c.data[r][:6], c.data[r][6]
            th = tau / h
            xj, uj = poly(coeffs, th), dpoly(coeffs, th) / h
            fr = c.friction[r]
            wf += fr * (xj - coeffs[0])
            wb += fr * sv.vb * tau
        elif kind == LINE:
            x_start, vb = c.data[r]
            xj, uj = x_start + vb * tau, vb
            bi = c.branch[r]
            wst = 0.5 * (xj * xj - x_start * x_start) + branch_work(
                x_start - xb, xj - xb, c.branches[bi], stop
            )
            wf += wst
            wb += wst
        else:
            xj, uj = c.data[r][0], 0.0
            wb += c.friction[r] * sv.vb * tau
        x[j], xd[j] = xj, uj
        work[j, 0], work[j, 1] = wf, wb


def _reduced_oscillation_forces(c, idx, rows, t, x, phi) -> None:
    """The force at the samples ``idx`` (in the contact rows ``rows``) of a reduced
    oscillation: the one its motion implies, ``x'' = s a - x - phi`` (paper Eq. 3 in
    contact). The law on the branch it started on drifts off it as the centre creeps (by
    2 % of the force over tens of time units on a stiff stop)."""
    for r in np.unique(rows):
        js = idx[rows == r]
        model = c.data[r][0]
        phi[js] = c.friction[r] - x[js] - model.acceleration(t[js] - c.t0[r])


def _stored(delta, phi, on_branch, d_r, p_r, branch_rows, primitive, stop) -> np.ndarray:
    """The energy the stop gives back on unloading from the law's current state: while
    loading, a new unloading branch would start here (Eq. 12); while unloading
    (``on_branch``), the current branch goes on (not a fresh one from ``(delta, phi)``:
    they differ where the branch has been clipped onto the compression envelope)."""
    if stop.law != "passive":
        return stored_energy_many(delta, phi, stop, np.where(on_branch, d_r, delta),
                                  np.where(on_branch, p_r, phi))
    # the passive law's branches keep an anchor: integrated one branch at a time
    stored = np.empty(np.shape(delta))
    fresh = ~on_branch
    stored[fresh] = stored_energy_many(delta[fresh], phi[fresh], stop)
    for k in np.nonzero(on_branch)[0]:
        prim = primitive(branch_rows[k])
        stored[k] = prim(delta[k]) - prim(0.0)
    return stored


def swing_probe(sv: Solve, t_end: float) -> SwingProbe:
    """The solution at the horizon against the solver's rule for rest
    (:func:`core.deformable.rest.rest_rule`): a swing of ``rest_amplitude`` in the
    position and :data:`~core.deformable.rest.REST_SPEED_PER_AMPLITUDE` times it in the
    velocity."""
    rest = rest_amplitude(sv)
    return SwingProbe(HystereticDense(sv, t_end).evaluate, t_end, rest,
                      REST_SPEED_PER_AMPLITUDE * rest)


def _asymptotic(sv: Solve, t_end: float, mode: np.ndarray, xd: np.ndarray) -> Steady:
    """Steady state read off the last transitions when no fixed point was found."""
    if sv.status is not Status.SUCCESS:
        return Steady(SteadyKind.NONE)
    limit = sv.elastic_limit()
    if sv.pressed():
        train = train_steady(list(sv.log.recent), limit) if limit is not None else None
        if train is not None:
            return train
        # The passive law's loops of reversals alone retrace their curve: no loss.
        return pressed_steady(list(sv.log.recent), lossless=sv.stop.law == "passive",
                              probe=swing_probe(sv, t_end))
    endless = sv.endless
    if endless is not None:
        if endless.mode is Mode.SLIP:
            radius = math.hypot(endless.x0 - endless.centre, endless.v0)
            if radius > 0.0:
                return Steady(
                    SteadyKind.PURE_SLIP,
                    period=2.0 * math.pi,
                    x_max=endless.centre + radius,
                    t_reached=endless.t0,
                )
        return Steady(SteadyKind.EQUILIBRIUM, x_max=endless.x0, t_reached=endless.t0)
    # A train of contacts is labelled by the law (core.steady.train_steady): slower than
    # w_inf its contacts are elastic (periodic, whatever the integration's drift), faster
    # they lose energy and the speeds fall towards w_inf (docs/contact-law.md).
    return steady_from_transitions(
        list(sv.log.recent),
        scale=sv.scale(),
        rtol=FIXED_POINT_RTOL,
        t_end=t_end,
        final_mode=int(mode[-1]) if len(mode) else 0,
        final_v=float(xd[-1]) if len(xd) else 0.0,
        limit=limit,
    )
