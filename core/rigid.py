"""Exact event-driven response with no stop or a rigid stop (paper §3-4, SPEC §2-3).

The motion is advanced from event to event with :func:`core.flight.free_flight`; impacts
apply Newton's law ``x'(+) = -r x'(-)`` (Eq. 8). Three closed-form continuations end the
loop early and keep long horizons cheap:

* a **periodic** steady state, found as a fixed point of the friction-impact map ``P^j``
  (Eq. 20): a transition state that repeats; the rest of the horizon is the cycle repeated;
* an endless **impact sequence** (accumulation or grazing, :mod:`core.impact_sequence`);
* a motion that never ends: **rest** at the stop, **equilibrium**, or **pure slip**.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter

import numpy as np

from core.flight import Motion, Segment, after_event, free_flight, start_motion
from core.impact_sequence import ImpactSequence, impact_sequence
from core.params import Oscillator, RigidStop
from core.result import (
    Energy,
    Mode,
    Result,
    Status,
    Steady,
    SteadyKind,
    Transition,
    TransitionKind,
    make_stats,
)
from core.steady import comes_to_rest, pressed_on_stop, rest_force
from core.trajectory import ExactSolution, PeriodicTail, SegmentTable

#: Two transition states closer than this (relative to the problem's length scale) are the
#: same point of the friction-impact map. The exact solution repeats to a few ulps; 1e-11
#: leaves room for the rounding of long transients without merging distinct states.
FIXED_POINT_RTOL = 1e-11
#: A cycle must last more than this many ulps of the time it closes at (a shorter one is a
#: bounce below the resolution of time and cannot be tiled).
PERIOD_ULPS = 1024
#: How many earlier transitions of the same kind are compared with each new one.
FIXED_POINT_LOOKBACK = 64
#: Guard against an endless event loop (never reached by the paper's regimes: their
#: transients end in a few dozen events). A solve that reaches it returns the response up
#: to the last event with ``Status.EVENT_LIMIT`` and no steady state.
MAX_EVENTS = 2_000_000


def length_scale(osc: Oscillator, stop: RigidStop | None, x0: float, v0: float) -> float:
    """A length that sets the scale of absolute tolerances (never zero)."""
    xb = abs(stop.clearance) if stop is not None else 0.0
    return max(osc.a, osc.b, osc.v, xb, abs(x0), abs(v0), 1e-300)


class _Recorder:
    """Transitions: the first ``cap`` stored, all counted."""

    def __init__(self, cap: int) -> None:
        self.cap = cap
        self.stored: list[Transition] = []
        self.counts: Counter[str] = Counter()
        self.total = 0
        self.impulses: list[tuple[float, float]] = []

    def add(self, kind: TransitionKind, t: float, x: float, v: float, v_after: float) -> None:
        self.total += 1
        self.counts[kind.value] += 1
        if len(self.stored) < self.cap:
            self.stored.append(Transition(kind, t, x, v, v_after))
            if kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT):
                self.impulses.append((t, v - v_after))

    def add_many(self, kind: TransitionKind, count: int) -> None:
        self.total += count
        self.counts[kind.value] += count


def simulate_rigid(
    osc: Oscillator,
    stop: RigidStop | None,
    t_end: float,
    x0: float,
    v0: float,
    *,
    n_samples: int,
    transition_cap: int,
    t_eval: np.ndarray | None = None,
    max_events: int = MAX_EVENTS,
) -> Result:
    """Exact response over ``[0, t_end]`` (inputs already validated by ``simulate``).

    After ``max_events`` events without reaching ``t_end`` or a steady state, the result
    covers ``[0, t]`` up to the last event and has ``status = Status.EVENT_LIMIT``.
    """
    xb = stop.clearance if stop is not None else math.inf
    r = stop.restitution if stop is not None else 1.0
    a, v = osc.a, osc.v
    scale = length_scale(osc, stop, x0, v0)
    tol = FIXED_POINT_RTOL * scale

    table = SegmentTable()
    rec = _Recorder(transition_cap)
    history: dict[str, list[int]] = {}  # kind -> indices into `states`
    states: list[tuple[float, float, float, int]] = []  # (t, x, v, table row after it)
    tail: PeriodicTail | None = None
    sequence: ImpactSequence | None = None
    steady = Steady(SteadyKind.NONE)

    t, x, xd = 0.0, x0, v0
    motion = start_motion(osc, x, xd)
    pending_impact = stop is not None and x >= xb and xd > 0.0
    if pending_impact:  # keep the state before an impact at t = 0 for the samples
        table.add(Segment(Mode.SLIP, 0.0, 0.0, x0, v0, motion.s * a), 0.0, v)
    if stop is not None and x >= xb and xd == 0.0 and v > 0.0 and pressed_on_stop(osc, xb):
        motion = Motion(Mode.CONTACT)  # starts pressed on the stop
        rec.add(TransitionKind.REST, t, xb, 0.0, 0.0)

    status = Status.SUCCESS
    for _ in range(max_events):
        if pending_impact:
            pending_impact = False
            stuck = motion.mode is Mode.STICK
            kind = TransitionKind.STICK_IMPACT if stuck else TransitionKind.IMPACT
            w, after = xd, -r * xd
            if comes_to_rest(osc, xb, w):
                # Pressed on the stop, and the bounces left (an accumulation, or elastic
                # bounces of a height below rounding) take less than ~w/|a - x_bar| of time.
                table.add_loss(0.5 * w * w)
                if w > 0.0:
                    rec.add(TransitionKind.ACCUMULATION, t, xb, w, 0.0)
                rec.add(TransitionKind.REST, t, xb, 0.0, 0.0)
                xd, motion = 0.0, Motion(Mode.CONTACT)
                continue
            rec.add(kind, t, xb, w, after)
            table.add_loss(0.5 * (1.0 - r * r) * w * w)
            xd = after
            if after == 0.0 and v > 0.0 and pressed_on_stop(osc, xb):
                rec.add(TransitionKind.REST, t, xb, 0.0, 0.0)
                motion = Motion(Mode.CONTACT)
            else:
                motion = start_motion(osc, x, xd)
                if 0.0 < r < 1.0 and v > 0.0:
                    seg, ev = free_flight(osc, t, x, xd, motion, xb)
                    if ev is not None and ev.kind is TransitionKind.IMPACT and ev.t < t_end:
                        sequence = impact_sequence(t, w, r, xb, a, t_end, scale)
                        steady = _sequence_steady(sequence, rec, t_end)
                        break
            j = _repeats(states, history, kind, t, x, w, tol, len(table))
            if j is not None:
                tail, steady = _periodic(states, j, table, rec, t_end)
                break
            continue

        if motion.mode is Mode.CONTACT:  # pressed on the stop for good: force a - x_bar
            table.add(Segment(Mode.CONTACT, t, math.inf, xb, 0.0, a), t_end, v)
            steady = Steady(
                SteadyKind.REST, x_max=xb, impact_speed=0.0, t_reached=t, period=math.nan
            )
            break

        seg, ev = free_flight(osc, t, x, xd, motion, xb)
        if ev is None or ev.t >= t_end:
            table.add(seg, t_end, v)
            if ev is None:
                steady = _endless(seg, t)
            break
        table.add(seg, ev.t, v)
        t, x = ev.t, ev.x
        if ev.kind is TransitionKind.IMPACT:
            xd = ev.v
            pending_impact = True
            continue
        rec.add(ev.kind, t, x, ev.v, ev.v)
        xd = ev.v
        motion = after_event(osc, ev, motion)
        j = _repeats(states, history, ev.kind, t, x, xd, tol, len(table))
        if j is not None:
            tail, steady = _periodic(states, j, table, rec, t_end)
            break
    else:
        status, t_end = Status.EVENT_LIMIT, t  # the response is known up to here
        if t_eval is not None:
            t_eval = t_eval[t_eval <= t]

    res = _assemble(
        osc, stop, table, rec, tail, sequence, steady, t_end, x0, v0, n_samples, t_eval
    )
    return res if status is Status.SUCCESS else dataclasses.replace(res, status=status)


def _repeats(
    states: list[tuple[float, float, float, int]],
    history: dict[str, list[int]],
    kind: TransitionKind,
    t: float,
    x: float,
    v: float,
    tol: float,
    row: int,
) -> int | None:
    """Record a transition state; return the index of the earlier state it repeats
    (Eq. 20), or ``None``.

    A repeat must hold to ``tol`` and also to ``FIXED_POINT_RTOL`` of the cycle's own size:
    a sequence converging on a point (an accumulation) has consecutive states that come
    within any absolute tolerance without ever repeating. Its period must be resolvable
    in time (more than :data:`PERIOD_ULPS` ulps of ``t``): a cycle shorter than that
    cannot be tiled.
    """
    seen = history.setdefault(kind.value, [])
    shortest = PERIOD_ULPS * math.ulp(max(abs(t), 1.0))
    best: int | None = None
    best_gap = math.inf
    for i in seen[-FIXED_POINT_LOOKBACK:]:
        ti, xi, vi, _ = states[i]
        dx, dv = abs(xi - x), abs(vi - v)
        if dx <= tol and dv <= tol and t - ti > shortest and dx + dv < best_gap:
            size = max(abs(st[1] - x) + abs(st[2] - v) for st in states[i:])
            if dx + dv <= FIXED_POINT_RTOL * size:
                best, best_gap = i, dx + dv
    states.append((t, x, v, row))
    seen.append(len(states) - 1)
    return best


def _periodic(
    states: list[tuple[float, float, float, int]],
    j: int,
    table: SegmentTable,
    rec: _Recorder,
    t_end: float,
) -> tuple[PeriodicTail, Steady]:
    """Close the cycle from ``states[j]`` to the last state: the steady state and the
    periodic continuation."""
    t_now, _, _, row_now = states[-1]
    t_then, _, _, row_then = states[j]
    period = t_now - t_then
    cycle = [tr for tr in rec.stored if t_then < tr.t <= t_now]
    n_cycle = len([s for s in states if t_then < s[0] <= t_now])
    cycle_rows = range(row_then, row_now)
    x_max_cycle = max(
        Segment(
            Mode(table.mode[i]),
            table.t0[i],
            table.t1[i],
            table.x0[i],
            table.v0[i],
            table.centre[i],
        ).x_max()
        for i in cycle_rows
    )
    work_then = table.work0[row_then]
    work_per_period = tuple(w1 - w0 for w0, w1 in zip(work_then, table.work, strict=True))
    impact_speed = max(
        (tr.v for tr in cycle if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)),
        default=math.nan,
    )
    steady = Steady(
        SteadyKind.PERIODIC,
        period=period,
        transitions_per_period=n_cycle,
        sequence=tuple(tr.kind.value for tr in cycle),
        x_max=x_max_cycle,
        impact_speed=impact_speed,
        t_reached=t_then,
    )
    # Transitions after t_now repeat the cycle's, shifted by whole periods.
    if cycle and period > 0.0:
        k = 1
        while rec.total < 10**15:
            t_shift = k * period
            if cycle[0].t + t_shift > t_end:
                break
            if len(rec.stored) >= rec.cap:  # count the rest arithmetically
                remaining = t_end - (cycle[0].t + t_shift)
                full = int(remaining // period)
                rec.total += full * len(cycle)
                for tr in cycle:
                    rec.counts[tr.kind.value] += full
                last_start = cycle[0].t + t_shift + full * period
                for tr in cycle:
                    if tr.t - cycle[0].t + last_start <= t_end:
                        rec.add_many(tr.kind, 1)
                break
            for tr in cycle:
                ts = tr.t + t_shift
                if ts > t_end:
                    break
                rec.add(tr.kind, ts, tr.x, tr.v, tr.v_after)
            k += 1
    table.x_max = max(table.x_max, x_max_cycle)
    tail = PeriodicTail(t_now, t_then, period, work_per_period)  # type: ignore[arg-type]
    return tail, steady


def _sequence_steady(seq: ImpactSequence, rec: _Recorder, t_end: float) -> Steady:
    """Record the impacts of an endless sequence and say where it leads."""
    n_explicit = len(seq.t_impacts) - 1
    room = max(0, min(n_explicit, rec.cap - len(rec.stored)))
    times = seq.t_impacts[1 : room + 1].tolist()
    speeds = seq.speeds[1 : room + 1].tolist()
    impact, xb, r = TransitionKind.IMPACT, seq.clearance, seq.r
    pairs = list(zip(times, speeds, strict=True))
    rec.stored.extend(Transition(impact, t, xb, w, -r * w) for t, w in pairs)
    rec.impulses.extend((t, (1.0 + r) * w) for t, w in pairs)
    rec.add_many(impact, n_explicit)
    if seq.zeno:
        if seq.limit_follows and seq.t_accumulation <= t_end:
            for kind in (TransitionKind.ACCUMULATION, TransitionKind.REST):
                rec.add(kind, seq.t_accumulation, seq.clearance, 0.0, 0.0)
        return Steady(
            SteadyKind.REST, x_max=seq.clearance, impact_speed=0.0, t_reached=seq.t_accumulation
        )
    if seq.limit_follows:
        # Impacts of vanishing speed go on, one per turn of the limit circle (half a turn
        # when it shrinks to the point at the stop): counted, not stored.
        d = seq.clearance - seq.a
        turn = 2.0 * math.pi if d > 0.0 else math.pi
        rec.add_many(TransitionKind.IMPACT, int((t_end - float(seq.t_impacts[-1])) // turn))
    return Steady(SteadyKind.GRAZING, period=2.0 * math.pi, x_max=seq.clearance, impact_speed=0.0)


def _endless(seg: Segment, t: float) -> Steady:
    """Steady state of a motion that no event ends."""
    if seg.mode is Mode.SLIP and (seg.x0 != seg.centre or seg.v0 != 0.0):
        radius = math.hypot(seg.x0 - seg.centre, seg.v0)
        return Steady(
            SteadyKind.PURE_SLIP,
            period=2.0 * math.pi,
            x_max=seg.centre + radius,
            t_reached=seg.t0,
        )
    return Steady(SteadyKind.EQUILIBRIUM, x_max=seg.x0, t_reached=t)


def _sample_times(
    t_end: float, n_samples: int, rec: _Recorder, t_eval: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """Uniform samples plus each stored transition (the state after it) and the state
    before every stored impact; or exactly ``t_eval`` when given. The second array is the
    side of a transition each sample stands for (-1 before, +1 after, 0 none)."""
    if t_eval is not None:
        return t_eval, np.zeros(len(t_eval), np.int8)
    uniform = np.linspace(0.0, t_end, n_samples)
    marks = [tr.t for tr in rec.stored if tr.t <= t_end]
    impacts = [
        tr.t
        for tr in rec.stored
        if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT) and tr.t <= t_end
    ]
    times = np.concatenate((uniform, marks, impacts))
    side = np.concatenate(
        (
            np.zeros(len(uniform), np.int8),
            np.ones(len(marks), np.int8),
            -np.ones(len(impacts), np.int8),
        )
    )
    order = np.lexsort((side, times))  # at equal times the state before comes first
    return times[order], side[order]


def _assemble(
    osc: Oscillator,
    stop: RigidStop | None,
    table: SegmentTable,
    rec: _Recorder,
    tail: PeriodicTail | None,
    seq: ImpactSequence | None,
    steady: Steady,
    t_end: float,
    x0: float,
    v0: float,
    n_samples: int,
    t_eval: np.ndarray | None,
) -> Result:
    """Evaluate the samples and build the :class:`Result`."""
    times, side = _sample_times(t_end, n_samples, rec, t_eval)
    v = osc.v
    if len(table) == 0:  # the motion starts with an endless impact sequence
        table.add(Segment(Mode.SLIP, 0.0, 0.0, x0, v0, osc.a), 0.0, v)
    x_max = table.x_max
    info: dict[str, object] = {}
    dense = ExactSolution(
        table.arrays(v),
        v,
        t_end,
        stop.clearance if stop is not None else math.inf,
        tail,
        seq,
        table.work,
    )
    # The samples are the solution evaluated on their side of each transition: before an
    # impact the approach velocity, after it the rebound (docs/physics.md, "Rigid impacts").
    out = dense.sample(times, side)
    if seq is not None:
        x_max = max(x_max, seq.clearance)
        info["impacts_evaluated"] = len(seq.t_impacts)
        info["last_impact_speed"] = float(seq.speeds[-1])
    x, xd = out["x"], out["v"]
    mechanical = 0.5 * (x * x + xd * xd)
    pressing = rest_force(osc, stop.clearance) if stop is not None else 0.0
    contact_force = np.where(out["mode"] == Mode.CONTACT, pressing, 0.0)
    energy = Energy(
        mechanical=mechanical,
        friction_work=out["friction_work"],
        belt_input=out["belt_input"],
        stop_loss=out["stop_loss"],
        stop_stored=np.zeros_like(x),
    )
    impulses = np.array(rec.impulses, dtype=float).reshape(-1, 2)
    return Result(
        t=times,
        x=x,
        v=xd,
        mode=out["mode"].astype(np.int8),
        transitions=tuple(rec.stored),
        transition_counts=dict(rec.counts),
        n_transitions=rec.total,
        x_max=x_max,
        steady=steady,
        status=Status.SUCCESS,
        energy=energy,
        contact_force=contact_force,
        overlap=np.zeros_like(x),
        impulses=impulses,
        method="exact",
        stats=make_stats(segments=len(table), events=rec.total),
        info=info,
        dense=dense,
    )
