"""Vectorised closed-form stepper: many parameter points advance through their events together.

Each lane (parameter point) follows the exact event-driven solution of :mod:`core.rigid`
(no stop or a rigid stop; paper §3-4, Eq. 8, docs/physics.md): slip arcs about ``(s a, 0)``,
stick segments along ``x' = v``, impacts by Newton's law. One iteration takes every lane to
its next event with the formulas of :func:`core.flight.free_flight`, written here over
numpy arrays (:func:`free_flight` below; a test checks it against the scalar one); masks
tell which lane is in which mode. A lane ends as soon as its steady state is known, by the
same rules as :func:`core.rigid.simulate_rigid` and :mod:`core.steady`:

* a transition state repeats (the fixed point of ``P^j``, Eq. 20), tested as
  :class:`core.steady.FixedPointDetector` tests it against the lane's earlier transitions;
* a rebound whose arc comes back to the stop: the endless impact sequence of
  :mod:`core.impact_sequence` (rest after accumulation if ``x_bar < a``, else grazing);
* rest at the stop, equilibrium, pure slip, or the horizon.

An event decided within rounding of a threshold (:data:`TIE`) is taken by the scalar
:func:`core.flight.free_flight` for that lane. A lane whose transient outgrows the history
kept per lane (:data:`HISTORY`) is flagged and left to :func:`core.simulate` by the caller.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from core import flight
from core.flight import TWO_PI, Motion, Segment
from core.params import Oscillator
from core.result import Mode, SteadyKind, TransitionKind
from core.steady import FIXED_POINT_LOOKBACK, FIXED_POINT_RTOL, PERIOD_ULPS, REST_SPEED
from core.sweep.lanes import Lanes
from core.sweep.result import KIND_CODE, LABEL_CODE, LaneRecords

#: Decisions closer than this to their threshold (radians for event angles, relative to the
#: lane's length scale for lengths) are near-ties. numpy's ``atan2`` and ``hypot`` round
#: differently from :mod:`math`'s in the last bit or two, so at a near-tie (two events at
#: nearly the same phase; a slip circle tangent to the stop or to the stick line) the two
#: could take different branches. A near-tie event is therefore taken
#: by the scalar :func:`core.flight.free_flight` itself, from the lane's state, which is
#: the one ``simulate`` has bit for bit: every state is formed as :mod:`core.flight` forms
#: it, from sums, products and square roots (only the times pass through ``atan2``).
#: Rounding differences are ~1e-16; 1e-12 keeps a wide margin.
TIE = 1e-12

#: Ended lanes stay in the arrays (masked) until the live ones are at most this fraction.
COMPACT = 0.5

#: Transition states kept per lane for the fixed-point test. Every regime of the paper
#: closes its cycle within a few dozen transitions; a lane that needs more is solved by
#: ``simulate``, which keeps them all. At most the scalar look-back, so the two tests
#: compare the same earlier states.
HISTORY = min(40, FIXED_POINT_LOOKBACK)

# Motion codes of a lane.
SLIP, STICK = 0, 1
# Event codes of a flight (the transition kinds' codes; ENDLESS: no event ever).
SLIP_STICK = KIND_CODE[TransitionKind.SLIP_STICK]
STICK_SLIP = KIND_CODE[TransitionKind.STICK_SLIP]
SIGN_CHANGE = KIND_CODE[TransitionKind.SIGN_CHANGE]
IMPACT = KIND_CODE[TransitionKind.IMPACT]
STICK_IMPACT = KIND_CODE[TransitionKind.STICK_IMPACT]
ENDLESS = -1


def start_motion(x, xdot, v, b):
    """Vectorised :func:`core.flight.start_motion`: ``(mode, s)`` from the state."""
    stick = (xdot == v) & (np.abs(x) <= b)
    s = np.where(xdot < v, 1, np.where(xdot > v, -1, np.where(x > 0.0, 1, -1)))
    return np.where(stick, STICK, SLIP).astype(np.int8), s.astype(np.int8)


def free_flight(t0, x0, v0, mode, s, a, b, v, barrier, scale=None):
    """Vectorised :func:`core.flight.free_flight`: every lane to its next event.

    Returns ``(t1, kind, x1, v1, x_max, tie)``: the event time (``inf`` if ``kind`` is
    :data:`ENDLESS`), its kind code (an impact is :data:`IMPACT` from slip or stick), the
    state there, the segment's exact maximum of ``x`` (as ``Segment.x_max`` of the cut
    segment; ``c + R`` or ``x0`` for an endless one, as ``core.rigid`` reports it), and
    the lanes whose event was decided within :data:`TIE` of a threshold (``scale``: the
    lanes' length scales; ``None``: 1).
    """
    with np.errstate(all="ignore"):
        c = s * a
        dx = x0 - c
        radius = np.hypot(dx, v0)
        theta0 = np.arctan2(-v0, dx)
        slip = mode == SLIP

        # Relative velocity vanishes, x' = v (core.flight.stick_line_event).
        h2 = dx * dx + (v0 - v) * (v0 + v)
        cross = slip & (h2 >= 0.0) & ((dx != 0.0) | (v0 != 0.0))
        h = np.sqrt(np.maximum(h2, 0.0))
        approaching = s * dx < 0.0
        sine = np.where(
            approaching & (v + v0 > 0.0),
            s * (v - v0) * (v * (v + v0) / (h + np.abs(dx)) + h),
            -s * v0 * h - dx * v,
        )
        d = np.remainder(np.arctan2(sine, -s * dx * h + v0 * v), TWO_PI)
        d = np.where((d == 0.0) & ~approaching, TWO_PI, d)
        x_cross = c - s * h
        kind = np.where(cross, np.where(np.abs(x_cross) <= b, SLIP_STICK, SIGN_CHANGE), ENDLESS)
        dtheta = np.where(cross, d, np.inf)
        x1 = x_cross
        v1 = np.broadcast_to(v, x0.shape).astype(float)

        # The stop, reached with x' > 0 (core.flight.stop_event).
        finite = np.isfinite(barrier)
        gap, x_hit = barrier - x0, barrier - c
        speed2 = v0 * v0 - gap * (dx + x_hit)
        speed = np.sqrt(np.maximum(speed2, 0.0))
        sine_hit = np.where(
            v0 > 0.0,
            gap * (x_hit * (dx + x_hit) / (v0 + speed) + speed),
            v0 * x_hit - dx * speed,
        )
        d_hit = np.remainder(np.arctan2(sine_hit, dx * x_hit + v0 * speed), TWO_PI)
        hit = slip & finite & (speed2 > 0.0) & ((kind == ENDLESS) | (d_hit <= dtheta))
        pressed = slip & finite & ~(speed2 > 0.0) & (x0 >= barrier) & (c > barrier)
        dtheta = np.where(hit, d_hit, np.where(pressed, 0.0, dtheta))
        kind = np.where(hit | pressed, IMPACT, kind)
        x1 = np.where(hit | pressed, barrier, x1)
        v1 = np.where(hit, speed, np.where(pressed, 0.0, v1))
        t1_slip = t0 + dtheta

        # Stick along x' = v until x = b, or the stop when it lies at or before b.
        moving = v > 0.0
        to_stop = barrier <= b
        end = np.where(to_stop, barrier, b)
        t1_stick = np.where(moving, t0 + np.maximum(end - x0, 0.0) / v, np.inf)
        kind_stick = np.where(moving, np.where(to_stop, IMPACT, STICK_SLIP), ENDLESS)

        stick = ~slip
        t1 = np.where(stick, t1_stick, t1_slip)
        kind = np.where(stick, kind_stick, kind).astype(np.int8)
        x1 = np.where(stick, end, x1)
        v1 = np.where(stick, v, v1)

        # Segment maximum (Segment.x_max on the segment cut at t1).
        tau = t1 - t0
        x_end_slip = c + dx * np.cos(tau) + v0 * np.sin(tau)
        next_top = np.ceil(theta0 / TWO_PI) * TWO_PI
        top = (tau >= TWO_PI) | (theta0 + tau >= next_top)
        xmax_slip = np.where(top, c + radius, np.maximum(x0, x_end_slip))
        xmax_slip = np.where(kind == ENDLESS, c + radius, xmax_slip)
        xmax_stick = np.where(kind == ENDLESS, x0, np.maximum(x0, x0 + v * tau))
        x_max = np.where(stick, xmax_stick, xmax_slip)

        # Near-ties of the slip decisions (see TIE).
        tol = TIE * (1.0 if scale is None else scale)
        cross_maybe = slip & (radius > 0.0) & (s > 0) & (np.abs(radius - v) <= tol)
        stick_or_sign = cross & (np.abs(np.abs(x_cross) - b) <= tol)
        both = cross & slip & finite & (speed2 > 0.0) & (np.abs(d_hit - d) <= TIE)
        tangent = slip & finite & (x0 != barrier) & (np.abs(c + radius - barrier) <= tol)
        tie = cross_maybe | stick_or_sign | both | tangent
    return t1, kind, x1, v1, x_max, tie


class _Block:
    """State of a block of lanes; arrays shrink to the lanes still running."""

    def __init__(self, lanes: Lanes, x0: float, v0: float) -> None:
        n = len(lanes)
        self.id = np.arange(n)
        self.a, self.b, self.v = lanes.a, lanes.b, lanes.belt_speed.copy()
        self.mu_s, self.mu_k, self.u_s = lanes.mu_s.copy(), lanes.mu_k.copy(), lanes.u_s.copy()
        self.xb, self.r = lanes.clearance.copy(), lanes.restitution.copy()
        has_stop = np.isfinite(self.xb)
        scale = np.maximum.reduce(
            [self.a, self.b, self.v, np.where(has_stop, np.abs(self.xb), 0.0),
             np.full(n, abs(x0)), np.full(n, abs(v0)), np.full(n, 1e-300)]
        )
        self.scale = scale
        self.t = np.zeros(n)
        self.x = np.full(n, float(x0))
        self.xd = np.full(n, float(v0))
        self.mode, self.s = start_motion(self.x, self.xd, self.v, self.b)
        self.pending = has_stop & (self.x >= self.xb) & (self.xd > 0.0)
        self.pending_kind = np.zeros(n, np.int8)
        self.push_impact = np.zeros(n, bool)  # an impact state waits for its history entry
        self.check_sequence = np.zeros(n, bool)
        self.rebound = np.zeros(n, bool)  # the latest event was an impact the mass left
        self.seg_xmax = np.full(n, -np.inf)
        self.impact_w = np.zeros(n)
        self.h_kind = np.full((n, HISTORY), -1, np.int8)
        self.h_t = np.zeros((n, HISTORY))
        self.h_x = np.zeros((n, HISTORY))
        self.h_v = np.zeros((n, HISTORY))
        self.h_xmax = np.zeros((n, HISTORY))
        self.count = np.zeros(n, np.int64)
        self.alive = np.ones(n, bool)  # False once a lane has ended (until compaction)
        self.oscillators: dict[int, Oscillator] = {}  # by lane id, for near-tie events

    def keep(self, mask: np.ndarray) -> None:
        for name, value in list(vars(self).items()):
            if isinstance(value, np.ndarray):
                setattr(self, name, value[mask])


class _Out:
    """Per-lane outputs, filled as lanes end."""

    def __init__(self, n: int) -> None:
        self.rec = LaneRecords.empty(n)
        # Steady periods found so far: (lane ids, kind, x, v, v_after), one row a transition.
        self.cycles: list[tuple[np.ndarray, ...]] = []

    def finish(self, ids, kind: SteadyKind, period=np.nan, x_max=np.nan, impact=np.nan):
        rec = self.rec
        rec.label[ids] = LABEL_CODE[kind]
        rec.period[ids] = period
        rec.x_max[ids] = x_max
        rec.impact_speed[ids] = impact


def solve_lanes(lanes: Lanes, t_end: float, x0: float, v0: float) -> LaneRecords:
    """Steady state of every lane (no stop or a rigid stop) by the vectorised closed form.

    Lanes flagged ``fallback`` in the result were not resolved here (their history
    outgrew :data:`HISTORY`) and hold nothing else; the caller solves them one by one.
    """
    n = len(lanes)
    out = _Out(n)
    blk = _Block(lanes, x0, v0)
    # Starts pressed on the stop (as core.rigid does at t = 0).
    pressed = (
        np.isfinite(blk.xb) & (blk.x >= blk.xb) & (blk.xd == 0.0) & (blk.v > 0.0)
        & (blk.a >= blk.xb)
    )
    _rest(out, blk, pressed)
    blk.alive &= ~pressed
    while len(blk.id):
        _step(blk, out, t_end)
        # Compacting copies the histories: do it when half the lanes have ended, so its
        # cost stays proportional to the work instead of to the number of events.
        if np.count_nonzero(blk.alive) <= COMPACT * len(blk.id):
            blk.keep(blk.alive)
    return _collect(out, n)


def _rest(out: _Out, blk: _Block, mask: np.ndarray) -> None:
    out.finish(blk.id[mask], SteadyKind.REST, x_max=blk.xb[mask], impact=0.0)


def _step(blk: _Block, out: _Out, t_end: float) -> None:
    """One event for every live lane; lanes that end are marked in ``blk.alive``."""
    ended = ~blk.alive

    # 1. Impacts waiting to be applied (Newton's law, Eq. 8).
    p = np.flatnonzero(blk.pending & blk.alive)
    if len(p):
        w = blk.xd[p]
        r, xb, v, a = blk.r[p], blk.xb[p], blk.v[p], blk.a[p]
        # core.steady.comes_to_rest and pressed_on_stop over arrays.
        held = a >= xb
        d = np.abs(a - xb)
        bounce = REST_SPEED * np.sqrt(d * np.maximum(np.abs(xb), d))
        rest = held & ((w == 0.0) | (w <= bounce))
        after = -r * w
        pressed = ~rest & (after == 0.0) & (v > 0.0) & held
        _rest(out, blk, _mask(len(ended), p[rest | pressed]))
        ended[p[rest | pressed]] = True
        go = p[~(rest | pressed)]
        blk.pending_kind[go] = np.where(blk.mode[go] == STICK, STICK_IMPACT, IMPACT)
        blk.push_impact[go] = True
        blk.xd[go] = -blk.r[go] * blk.xd[go]
        blk.rebound[go] = True
        blk.mode[go], blk.s[go] = start_motion(blk.x[go], blk.xd[go], blk.v[go], blk.b[go])
        blk.check_sequence[go] = (blk.r[go] > 0.0) & (blk.r[go] < 1.0) & (blk.v[go] > 0.0)
        blk.pending[p] = False
        # The impact's history entry holds the approach speed, as core.rigid records it.
        blk.impact_w[go] = w[~(rest | pressed)]

    live = ~ended
    t1, kind, x1, v1, seg_xmax, tie = free_flight(
        blk.t, blk.x, blk.xd, blk.mode, blk.s, blk.a, blk.b, blk.v, blk.xb, blk.scale
    )
    redo = np.flatnonzero(tie & live)
    if len(redo):
        t1[redo], kind[redo], x1[redo], v1[redo], seg_xmax[redo] = _scalar_flights(blk, redo)

    # 2. A rebound whose arc returns to the stop: the endless impact sequence.
    seq = live & blk.check_sequence & (kind == IMPACT) & (t1 < t_end)
    if np.any(seq):
        zeno = seq & (blk.xb < blk.a)
        graze = seq & ~zeno
        _rest(out, blk, zeno)
        out.finish(blk.id[graze], SteadyKind.GRAZING, period=TWO_PI, x_max=blk.xb[graze],
                   impact=0.0)
        ended |= seq
        live &= ~seq
    blk.check_sequence[:] = False

    # 3. The impact's state joins the history; a repeat closes the cycle.
    push = live & blk.push_impact
    if np.any(push):
        idx = np.flatnonzero(push)
        _push(blk, out, idx, blk.pending_kind[idx], blk.t[idx], blk.xb[idx],
              blk.impact_w[idx], blk.seg_xmax[idx], ended)
        live &= ~ended
    blk.push_impact[:] = False

    # 4. The flight's event.
    endless = live & (kind == ENDLESS)
    if np.any(endless):
        c = blk.s * blk.a
        moving = (blk.mode == SLIP) & ((blk.x != c) | (blk.xd != 0.0))
        # A circle that leaves the stop at an impact (at zero speed) grazes it; one that
        # starts on it without an impact is the impactless circle (core.rigid._endless).
        grazes = endless & moving & blk.rebound
        slip_on = endless & moving & ~grazes
        out.finish(blk.id[slip_on], SteadyKind.PURE_SLIP, period=TWO_PI,
                   x_max=seg_xmax[slip_on])
        out.finish(blk.id[grazes], SteadyKind.GRAZING, period=TWO_PI, x_max=blk.xb[grazes],
                   impact=0.0)
        still = endless & ~moving
        out.finish(blk.id[still], SteadyKind.EQUILIBRIUM, x_max=blk.x[still])
        ended |= endless
        live &= ~endless
    late = live & (t1 >= t_end)
    if np.any(late):
        ended |= late  # no steady state within the horizon: the records keep 'none'
        live &= ~late
    blk.seg_xmax = seg_xmax
    hit = live & (kind == IMPACT)
    blk.t = np.where(live, t1, blk.t)
    blk.x = np.where(live, x1, blk.x)
    blk.xd = np.where(live, v1, blk.xd)
    blk.pending |= hit
    friction = live & ~hit
    if np.any(friction):
        idx = np.flatnonzero(friction)
        k = kind[idx]
        blk.mode[idx] = np.where(k == SLIP_STICK, STICK, SLIP)
        blk.rebound[idx] = False
        blk.s[idx] = np.where(
            k == STICK_SLIP, 1, np.where(k == SIGN_CHANGE, -blk.s[idx], blk.s[idx])
        )
        _push(blk, out, idx, k, t1[idx], x1[idx], v1[idx], seg_xmax[idx], ended)
    blk.alive &= ~ended


def _scalar_flights(blk: _Block, idx: np.ndarray) -> tuple[np.ndarray, ...]:
    """The next event of lanes ``idx`` from :func:`core.flight.free_flight` (near-ties)."""
    rows = []
    columns = (blk.id, blk.mu_s, blk.mu_k, blk.v, blk.u_s, blk.mode, blk.s, blk.t, blk.x,
               blk.xd, blk.xb)
    for lane, mu_s, mu_k, v, u_s, mode, s, t0, x0, v0, xb in zip(
        *(c[idx].tolist() for c in columns), strict=True
    ):
        osc = blk.oscillators.get(lane)
        if osc is None:  # a lane in case c meets the tie once per period: build it once
            osc = blk.oscillators[lane] = Oscillator(
                mu_s=mu_s, mu_k=mu_k, belt_speed=v, u_s=u_s
            )
        motion = Motion(Mode.STICK) if mode == STICK else Motion(Mode.SLIP, s)
        seg, ev = flight.free_flight(osc, t0, x0, v0, motion, xb)
        if ev is None:  # as core.rigid reports an endless segment's maximum
            radius = math.hypot(seg.x0 - seg.centre, seg.v0)
            top = seg.centre + radius if seg.mode is Mode.SLIP else seg.x0
            rows.append((math.inf, ENDLESS, math.nan, math.nan, top))
            continue
        cut = Segment(seg.mode, seg.t0, ev.t, seg.x0, seg.v0, seg.centre)
        rows.append((ev.t, KIND_CODE[ev.kind], ev.x, ev.v, cut.x_max()))
    t1, kind, x1, v1, x_max = (np.array(col) for col in zip(*rows, strict=True))
    return t1, kind.astype(np.int8), x1, v1, x_max


def _mask(n: int, idx: np.ndarray) -> np.ndarray:
    m = np.zeros(n, bool)
    m[idx] = True
    return m


def _push(blk, out, idx, kind, t, x, v, seg_xmax, ended) -> None:
    """Add transition states to the lanes' histories and close the cycles that repeat
    (:class:`core.steady.FixedPointDetector` and ``core.rigid._periodic``, over arrays)."""
    full = blk.count[idx] >= HISTORY
    if np.any(full):
        out.rec.fallback[blk.id[idx[full]]] = True
        ended[idx[full]] = True
        keep = ~full
        idx, kind, t, x, v = idx[keep], kind[keep], t[keep], x[keep], v[keep]
        seg_xmax = seg_xmax[keep]
    if not len(idx):
        return
    col = blk.count[idx]
    width = int(col.max())
    if width:
        hk = blk.h_kind[idx, :width]
        hx, hv = blk.h_x[idx, :width], blk.h_v[idx, :width]
        earlier = np.arange(width) < col[:, None]
        tol = (FIXED_POINT_RTOL * blk.scale[idx])[:, None]
        dx, dv = np.abs(hx - x[:, None]), np.abs(hv - v[:, None])
        same = earlier & (hk == kind[:, None])
        # A period the times can resolve (core.steady.PERIOD_ULPS).
        shortest = PERIOD_ULPS * np.spacing(np.maximum(np.abs(t), 1.0))
        resolved = (t[:, None] - blk.h_t[idx, :width]) > shortest[:, None]
        near = same & (dx <= tol) & (dv <= tol) & resolved
        rows = np.flatnonzero(near.any(axis=1))
        if len(rows):
            gap = dx[rows] + dv[rows]
            dist = np.where(earlier[rows], gap, -np.inf)
            # size_i = max over states i..now-1 of the distance to the new state.
            size = np.maximum.accumulate(dist[:, ::-1], axis=1)[:, ::-1]
            ok = near[rows] & (gap <= FIXED_POINT_RTOL * size)
            has = ok.any(axis=1)
            found = rows[has]
            if len(found):
                # The matching state with the smallest gap, the earliest of equals, as
                # core.steady.FixedPointDetector picks it.
                j = np.argmin(np.where(ok[has], gap[has], np.inf), axis=1)
                _periodic(blk, out, idx[found], j, kind[found], t[found], x[found],
                          v[found], seg_xmax[found])
                ended[idx[found]] = True
    blk.h_kind[idx, col] = kind
    blk.h_t[idx, col] = t
    blk.h_x[idx, col] = x
    blk.h_v[idx, col] = v
    blk.h_xmax[idx, col] = seg_xmax
    blk.count[idx] = col + 1


def _periodic(blk, out, idx, j, kind, t, x, v, seg_xmax) -> None:
    """The steady cycle from history entry ``j`` (exclusive) to the new state (inclusive)."""
    col = blk.count[idx]
    # Write the new state so the cycle is columns j+1 .. col of the history.
    blk.h_kind[idx, col] = kind
    blk.h_t[idx, col] = t
    blk.h_x[idx, col] = x
    blk.h_v[idx, col] = v
    blk.h_xmax[idx, col] = seg_xmax
    width = int(col.max()) + 1
    cols = np.arange(width)
    inside = (cols > j[:, None]) & (cols <= col[:, None])
    hk = blk.h_kind[idx, :width]
    hv = blk.h_v[idx, :width]
    impact = inside & ((hk == IMPACT) | (hk == STICK_IMPACT))
    ids = blk.id[idx]
    period = t - blk.h_t[idx, j]
    x_max = np.where(inside, blk.h_xmax[idx, :width], -np.inf).max(axis=1)
    impact_speed = np.where(impact, hv, -np.inf).max(axis=1)
    impact_speed = np.where(impact.any(axis=1), impact_speed, np.nan)
    out.finish(ids, SteadyKind.PERIODIC, period=period, x_max=x_max, impact=impact_speed)
    out.rec.transitions_per_period[ids] = col - j
    rows, cs = np.nonzero(inside)
    k = hk[rows, cs]
    vv = hv[rows, cs]
    r = blk.r[idx][rows]
    after = np.where((k == IMPACT) | (k == STICK_IMPACT), -r * vv, vv)
    out.cycles.append((ids[rows], k, blk.h_x[idx, :width][rows, cs], vv, after))


def _collect(out: _Out, n: int) -> LaneRecords:
    rec = out.rec
    grazing = np.flatnonzero(rec.label == LABEL_CODE[SteadyKind.GRAZING])
    parts = list(out.cycles)
    if len(grazing):  # the grazing limit: one impact of speed 0 at the stop per turn
        zeros = np.zeros(len(grazing))
        parts.append((grazing, np.full(len(grazing), IMPACT, np.int8), rec.x_max[grazing],
                      zeros, zeros))
    if parts:
        lane = np.concatenate([p[0] for p in parts])
        order = np.argsort(lane, kind="stable")
        lane = lane[order]
        rec = dataclasses.replace(
            rec,
            cycle_kind=np.concatenate([p[1] for p in parts]).astype(np.int8)[order],
            cycle_x=np.concatenate([p[2] for p in parts])[order],
            cycle_v=np.concatenate([p[3] for p in parts])[order],
            cycle_v_after=np.concatenate([p[4] for p in parts])[order],
            cycle_force=np.full(len(lane), np.nan),
        )
        counts = np.bincount(lane, minlength=n)
    else:
        lane = np.zeros(0, np.int64)
        counts = np.zeros(n, np.int64)
    offsets = np.concatenate(([0], np.cumsum(counts))).astype(np.int64)
    sequence: list[tuple[int, ...]] = [()] * n
    kinds = rec.cycle_kind.tolist()
    bounds = offsets.tolist()
    for i in np.flatnonzero(rec.label == LABEL_CODE[SteadyKind.PERIODIC]).tolist():
        sequence[i] = tuple(kinds[bounds[i] : bounds[i + 1]])
    return dataclasses.replace(rec, offsets=offsets, sequence=sequence)
