"""Exact event-driven response with no stop or a rigid stop (paper §3-4; docs/physics.md,
"Exact solution" and "Rigid impacts").

The motion is advanced from event to event with :func:`core.flight.free_flight`; impacts
apply Newton's law ``x'(+) = -r x'(-)`` (Eq. 8). Three closed-form continuations end the
loop early and keep long horizons cheap:

* a **periodic** steady state, found as a fixed point of the friction-impact map ``P^j``
  (Eq. 20, :class:`core.steady.FixedPointDetector`): the rest of the horizon is the cycle
  repeated;
* an endless **impact sequence** (accumulation or grazing, :mod:`core.impact_sequence`);
* a motion that never ends: **rest** at the stop, **equilibrium**, or **pure slip**.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from core.flight import FreeEvent, Motion, Segment, after_event, free_flight, start_motion
from core.impact_sequence import ImpactSequence, impact_sequence, tail_impacts
from core.params import HystereticStop, Oscillator, RigidStop
from core.result import Energy, Mode, Result, Status, Steady, SteadyKind, TransitionKind, make_stats
from core.solve_inputs import SolveInputs, solve_entry
from core.steady import Cycle, FixedPointDetector, comes_to_rest, pressed_on_stop, rest_force
from core.trajectory import ExactSolution, PeriodicTail, SegmentTable
from core.transitions import IMPACT_KINDS, TransitionLog

#: Guard against an endless event loop (never reached by the paper's regimes: their
#: transients end in a few dozen events). A solve that reaches it returns the response up
#: to the last event with ``Status.EVENT_LIMIT`` and no steady state.
MAX_EVENTS = 2_000_000


def length_scale(osc: Oscillator, stop: RigidStop | None, x0: float, v0: float) -> float:
    """A length that sets the scale of absolute tolerances (never zero)."""
    xb = abs(stop.clearance) if stop is not None else 0.0
    return max(osc.a, osc.b, osc.v, xb, abs(x0), abs(v0), 1e-300)


def solve_rigid(inputs: SolveInputs, *, max_events: int = MAX_EVENTS) -> Result:
    """Exact response over ``[0, t_end]`` with no stop or a rigid stop.

    After ``max_events`` events without reaching ``t_end`` or a steady state, the result
    covers ``[0, t]`` up to the last event and has ``status = Status.EVENT_LIMIT``.
    """
    osc, stop, t_end, t_eval = inputs.osc, inputs.stop, inputs.t_end, inputs.t_eval
    if isinstance(stop, HystereticStop):
        raise TypeError("the exact rigid solver takes no stop or a RigidStop; got a "
                        "HystereticStop (use core.simulate)")
    run = _Run(osc, stop, t_end, inputs.x0, inputs.v0, inputs.transition_cap)
    status = Status.SUCCESS
    if not run.step_until_done(max_events):
        status, t_end = Status.EVENT_LIMIT, run.t  # the response is known up to here
        if t_eval is not None:
            t_eval = t_eval[t_eval <= t_end]
    res = _assemble(run, t_end, inputs.n_samples, t_eval)
    return res if status is Status.SUCCESS else dataclasses.replace(res, status=status)


#: :func:`solve_rigid` with the inputs of :func:`core.simulate`.
simulate_rigid = solve_entry(solve_rigid)


class _Run:
    """The state of one exact solve: where the mass is, what it does next, what is known.

    :meth:`step` advances by one event (or one impact) and returns True once the motion
    is known up to ``t_end``: the horizon was reached, or a closed-form continuation (a
    cycle, an impact sequence, a motion without end) covers the rest.
    """

    def __init__(
        self,
        osc: Oscillator,
        stop: RigidStop | None,
        t_end: float,
        x0: float,
        v0: float,
        cap: int,
    ) -> None:
        self.osc, self.stop, self.t_end, self.x0, self.v0 = osc, stop, t_end, x0, v0
        self.xb = stop.clearance if stop is not None else math.inf
        self.r = stop.restitution if stop is not None else 1.0
        self.scale = length_scale(osc, stop, x0, v0)
        self.table = SegmentTable()
        self.log = TransitionLog(cap)
        self.detector = FixedPointDetector(self.scale)
        self.tail: PeriodicTail | None = None
        self.sequence: ImpactSequence | None = None
        self.steady = Steady(SteadyKind.NONE)
        self.t, self.x, self.xd = 0.0, x0, v0
        #: Time of the latest impact the mass left the stop at (nan: none yet).
        self.t_rebound = math.nan
        self.motion = start_motion(osc, x0, v0)
        at_stop = stop is not None and x0 >= self.xb
        self.pending_impact = at_stop and v0 > 0.0
        if self.pending_impact:  # keep the state before an impact at t = 0 for the samples
            seg = Segment(Mode.SLIP, 0.0, 0.0, x0, v0, self.motion.s * osc.a)
            self.table.add(seg, 0.0, osc.v)
        if at_stop and v0 == 0.0 and osc.v > 0.0 and pressed_on_stop(osc, self.xb):
            self.motion = Motion(Mode.CONTACT)  # starts pressed on the stop
            self.log.add(TransitionKind.REST, 0.0, self.xb, 0.0, 0.0)

    def step_until_done(self, max_events: int) -> bool:
        """Advance until the motion is known up to ``t_end``; False at the event limit."""
        for _ in range(max_events):
            if self.step():
                return True
        return False

    def step(self) -> bool:
        if self.pending_impact:
            self.pending_impact = False
            return self._impact()
        if self.motion.mode is Mode.CONTACT:  # pressed on the stop for good
            self.table.add(
                Segment(Mode.CONTACT, self.t, math.inf, self.xb, 0.0, self.osc.a),
                self.t_end,
                self.osc.v,
            )
            self.steady = Steady(SteadyKind.REST, x_max=self.xb, impact_speed=0.0, t_reached=self.t)
            return True
        seg, ev = free_flight(self.osc, self.t, self.x, self.xd, self.motion, self.xb)
        if ev is None or ev.t >= self.t_end:
            self.table.add(seg, self.t_end, self.osc.v)
            if ev is None:
                self.steady = _endless(seg, self.t, self.xb, rebound=self.t == self.t_rebound)
            return True
        self.table.add(seg, ev.t, self.osc.v, ev.x)
        self.t, self.x, self.xd = ev.t, ev.x, ev.v
        if ev.kind is TransitionKind.IMPACT:
            self.pending_impact = True
            return False
        return self._friction_event(ev)

    def _friction_event(self, ev: FreeEvent) -> bool:
        self.log.add(ev.kind, ev.t, ev.x, ev.v, ev.v)
        self.motion = after_event(self.osc, ev, self.motion)
        return self._closes_cycle(ev.kind, ev.v)

    def _impact(self) -> bool:
        """Newton's law at the stop (Eq. 8), or rest when the mass stays pressed on it."""
        osc, xb, r, t, w = self.osc, self.xb, self.r, self.t, self.xd
        if comes_to_rest(osc, xb, w):
            # Pressed on the stop, and the bounces left (an accumulation, or elastic
            # bounces of a height below rounding) take less than ~w/|a - x_bar| of time.
            self.table.add_loss(0.5 * w * w)
            if w > 0.0:
                self.log.add(TransitionKind.ACCUMULATION, t, xb, w, 0.0)
            self.log.add(TransitionKind.REST, t, xb, 0.0, 0.0)
            self.xd, self.motion = 0.0, Motion(Mode.CONTACT)
            return False
        stuck = self.motion.mode is Mode.STICK
        kind = TransitionKind.STICK_IMPACT if stuck else TransitionKind.IMPACT
        after = -r * w
        self.log.add(kind, t, xb, w, after)
        self.table.add_loss(0.5 * (1.0 - r * r) * w * w)
        self.xd = after
        if after == 0.0 and osc.v > 0.0 and pressed_on_stop(osc, xb):
            self.log.add(TransitionKind.REST, t, xb, 0.0, 0.0)
            self.motion = Motion(Mode.CONTACT)
        else:
            self.t_rebound = t
            self.motion = start_motion(osc, self.x, after)
            if 0.0 < r < 1.0 and osc.v > 0.0 and self._returns_to_stop():
                self.sequence = impact_sequence(t, w, r, xb, osc.a, self.t_end, self.scale)
                self.steady = _sequence_steady(self.sequence, self.log, self.t_end)
                return True
        return self._closes_cycle(kind, w)

    def _returns_to_stop(self) -> bool:
        """True when the rebound arc comes back to the stop before the horizon, with no
        friction event between: the start of an endless impact sequence."""
        _, ev = free_flight(self.osc, self.t, self.x, self.xd, self.motion, self.xb)
        return ev is not None and ev.kind is TransitionKind.IMPACT and ev.t < self.t_end

    def _closes_cycle(self, kind: TransitionKind, speed: float) -> bool:
        cycle = self.detector.add(kind, self.t, self.x, speed, len(self.table))
        if cycle is None:
            return False
        self.tail, self.steady = _periodic(cycle, self.table, self.log, self.t_end)
        return True


def _periodic(
    cycle: Cycle, table: SegmentTable, log: TransitionLog, t_end: float
) -> tuple[PeriodicTail, Steady]:
    """Close a cycle found by the detector: the steady state, the periodic continuation,
    and the transitions after it (the cycle's, shifted by whole periods)."""
    t_then, t_now, row_then, row_now = cycle.t_then, cycle.t_now, cycle.tag_then, cycle.tag_now
    period = cycle.period
    # The cycle's transitions are the last n_transitions up to now: a stick of zero
    # length (mu_s = mu_k) puts a stick->slip at the very time t_then, which a window
    # (t_then, t_now] left out of the tiled log.
    in_cycle = [tr for tr in log.stored if t_then <= tr.t <= t_now][-cycle.n_transitions:]
    x_max_cycle = max(
        Segment(
            Mode(table.mode[i]), table.t0[i], table.t1[i], table.x0[i], table.v0[i],
            table.centre[i],
        ).x_max()
        for i in range(row_then, row_now)
    )
    work_then = table.work0[row_then]
    work_per_period = tuple(w1 - w0 for w0, w1 in zip(work_then, table.work, strict=True))
    impact_speed = max((tr.v for tr in in_cycle if tr.kind in IMPACT_KINDS), default=math.nan)
    steady = Steady(
        SteadyKind.PERIODIC,
        period=period,
        transitions_per_period=cycle.n_transitions,
        sequence=tuple(tr.kind.value for tr in in_cycle),
        x_max=x_max_cycle,
        impact_speed=impact_speed,
        t_reached=t_then,
    )
    log.tile(in_cycle, period, t_end)
    table.x_max = max(table.x_max, x_max_cycle)
    tail = PeriodicTail(t_now, t_then, period, work_per_period)  # type: ignore[arg-type]
    return tail, steady


def _sequence_steady(seq: ImpactSequence, log: TransitionLog, t_end: float) -> Steady:
    """Record the impacts of an endless sequence and say where it leads."""
    log.add_impacts(seq.t_impacts[1:], seq.clearance, seq.speeds[1:], seq.r)
    t_counted = float(seq.t_impacts[-1])
    if seq.truncated:
        # the impacts past the explicit ones, up to the horizon or the speed floor: counted
        h_end, t_h = tail_impacts(seq, np.array([t_end]))
        log.count(TransitionKind.IMPACT, int(h_end[0]) - (len(seq.t_impacts) - 1))
        t_counted = float(t_h[0])
    if seq.zeno:
        if seq.limit_follows and seq.t_accumulation <= t_end:
            for kind in (TransitionKind.ACCUMULATION, TransitionKind.REST):
                log.add(kind, seq.t_accumulation, seq.clearance, 0.0, 0.0)
        return Steady(
            SteadyKind.REST, x_max=seq.clearance, impact_speed=0.0, t_reached=seq.t_accumulation
        )
    if seq.limit_follows:
        # Impacts of vanishing speed go on, one per turn of the limit circle (half a turn
        # when it shrinks to the point at the stop): counted, not stored.
        d = seq.clearance - seq.a
        turn = 2.0 * math.pi if d > 0.0 else math.pi
        log.count(TransitionKind.IMPACT, int((t_end - t_counted) // turn))
    return Steady(SteadyKind.GRAZING, period=2.0 * math.pi, x_max=seq.clearance, impact_speed=0.0)


def _endless(
    seg: Segment, t: float, x_bar: float = math.inf, rebound: bool = False
) -> Steady:
    """Steady state of a motion that no event ends: a slip circle, or the equilibrium.
    A circle that leaves the stop at an impact (``rebound``: at zero speed, after a plastic
    impact with ``x_bar > a``, paper Secs. 4.3-4.4) grazes it; one that only touches it
    from an impactless start, even a start at rest on the stop, is the impactless circle
    (continuous in ``x_bar`` and ``x0`` at ``x_bar = x_max``, docs/physics.md)."""
    if seg.mode is Mode.SLIP and (seg.x0 != seg.centre or seg.v0 != 0.0):
        radius = math.hypot(seg.x0 - seg.centre, seg.v0)
        x_max = seg.centre + radius
        return Steady(
            SteadyKind.GRAZING if rebound else SteadyKind.PURE_SLIP,
            period=2.0 * math.pi,
            x_max=min(x_max, x_bar),
            impact_speed=0.0 if rebound else math.nan,
            t_reached=seg.t0,
        )
    return Steady(SteadyKind.EQUILIBRIUM, x_max=seg.x0, t_reached=t)


def _sample_times(
    t_end: float, n_samples: int, log: TransitionLog, t_eval: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """Uniform samples plus each stored transition (the state after it) and the state
    before every stored impact; or exactly ``t_eval`` when given. The second array is the
    side of a transition each sample stands for (-1 before, +1 after, 0 none)."""
    if t_eval is not None:
        return t_eval, np.zeros(len(t_eval), np.int8)
    uniform = np.linspace(0.0, t_end, n_samples)
    marks = [tr.t for tr in log.stored if tr.t <= t_end]
    impacts = [tr.t for tr in log.stored if tr.kind in IMPACT_KINDS and tr.t <= t_end]
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


def _assemble(run: _Run, t_end: float, n_samples: int, t_eval: np.ndarray | None) -> Result:
    """Evaluate the samples and build the :class:`Result`."""
    osc, stop, table, log, seq = run.osc, run.stop, run.table, run.log, run.sequence
    times, side = _sample_times(t_end, n_samples, log, t_eval)
    v = osc.v
    if len(table) == 0:  # the motion starts with an endless impact sequence
        table.add(Segment(Mode.SLIP, 0.0, 0.0, run.x0, run.v0, osc.a), 0.0, v)
    x_max = table.x_max
    info: dict[str, object] = {}
    dense = ExactSolution(
        table.arrays(v),
        v,
        t_end,
        run.xb,
        run.tail,
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
    if stop is not None:  # an arc's top at the stop, rounded past it: the stop holds x there
        x_max = min(x_max, stop.clearance)
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
    impulses = np.array(log.impulses, dtype=float).reshape(-1, 2)
    return Result(
        t=times,
        x=x,
        v=xd,
        mode=out["mode"].astype(np.int8),
        **log.result_fields(),
        x_max=x_max,
        steady=run.steady,
        status=Status.SUCCESS,
        energy=energy,
        contact_force=contact_force,
        overlap=np.zeros_like(x),
        impulses=impulses,
        method="exact",
        stats=make_stats(segments=len(table), events=log.total),
        info=info,
        dense=dense,
    )
