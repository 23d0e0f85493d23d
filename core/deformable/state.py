"""One solve's state: its setup and everything it records (the free-flight segments, the
contact rows, the transitions, the counts and the reduced models' error bounds); only the
methods of :class:`Solve` write it, and every sub-step takes it and calls them."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from core.deformable.law import LIMIT_MARGIN, Branch, ElasticLimit, elastic_limit
from core.result import Status, Steady, SteadyKind, TransitionKind
from core.steady import FixedPointDetector, pressed_on_stop, train_loses
from core.trajectory import SegmentTable
from core.transitions import TransitionLog

#: Default work limit of :func:`core.deformable.solver.solve_hysteretic`: its steps, counted
#: as the Dormand-Prince steps of the contacts (accepted and rejected), the semi-analytic
#: arcs and the transitions solved one by one, each of which costs ~15 us on the development
#: machine (58e3 a second on a grazing train, 62e3 on scene 11's loops), and the contacts
#: the contact-to-contact map lays out, far cheaper, at one step per
#: :data:`MAP_CONTACTS_PER_STEP`. It is checked at each transition; past it the result ends
#: there with ``Status.STEP_LIMIT``.
#: Sized so that a call without ``max_steps`` returns within a few seconds whatever the
#: horizon (~4 s; benchmarks/hysteretic_limits.py) while scene 11's loops (2.1e5 steps to
#: rest) still end at rest.
DEFAULT_MAX_STEPS = 250_000


#: Contacts the map lays out per step of the solve's work limit (``max_steps``,
#: :data:`DEFAULT_MAX_STEPS`): 0.2-1.7 us a contact (2e6 in 0.4-3.5 s on the pressed cells
#: of benchmarks/hysteretic_speed.py) against ~15 us a contact step, an arc or a transition
#: solved. Uncounted, a train laid out to t_end = 1e6 took 2 s (7.5e5 contacts) and one to
#: 1e9 would hold arrays of 7.5e8.
MAP_CONTACTS_PER_STEP = 8


#: Positions (doubles) the band ``(d_max, D)`` where a contact counts as reaching the limit
#: overlap holds at least: a step is rejected past ``D`` (the asymptote) and the event needs
#: an accepted step ending inside the band, which the controller's factors (0.2 to 5) find
#: only if the band is several position spacings wide. With ``LIMIT_MARGIN D`` alone, a stop
#: at clearance 0.24 with ``D = 1e-12`` had a band of 1e-18 between positions 2.8e-17 apart:
#: the steps shrank to nothing and grew back past ``D`` without end.
LIMIT_BAND_SPACINGS = 16


def limit_band(clearance: float, limit_overlap: float) -> float:
    """``d_max``: the overlap at which a contact counts as reaching the limit ``D``,
    ``(1 - LIMIT_MARGIN) D`` (:data:`core.deformable.law.LIMIT_MARGIN`) or lower where positions
    near the stop are too coarse for that band (:data:`LIMIT_BAND_SPACINGS`); ``<= 0`` when
    ``D`` itself is below their resolution (a contact then ends at the limit at once).

    Examples
    --------
    >>> limit_band(0.24, 0.01) == (1.0 - LIMIT_MARGIN) * 0.01
    True
    >>> limit_band(0.24, 1e-12) < (1.0 - LIMIT_MARGIN) * 1e-12
    True
    """
    spacing = math.ulp(abs(clearance) + limit_overlap)
    return min((1.0 - LIMIT_MARGIN) * limit_overlap,
               limit_overlap - LIMIT_BAND_SPACINGS * spacing)


#: Two transition states closer than this (relative to the length scale) are the same point
#: of the friction-impact map. Cycles with a stick phase restart from an exact state and
#: repeat to rounding; a looser value (1e-7 was tried) took the slowly shrinking oscillation
#: on the stop of Fig. 11 (amplitude ~1e-7, change per cycle ~1e-10) and the decaying
#: contacts of Fig. 10 for periodic motions, and the energy balance of the repeated cycle
#: then drifted (2.5e-5 at t = 1000). Contact cycles without a stick phase are integrated to
#: ~1e-8 per cycle and are not taken for fixed points: the horizon is then computed.
FIXED_POINT_RTOL = 1e-10


#: Transitions inspected for the asymptotic steady state when no fixed point is found.
STEADY_TAIL = 64


#: Kinds of contact rows: a Dormand-Prince step, a stick line, rest, a semi-analytic arc, a
#: reduced oscillation, a reduced train.
HERMITE, LINE, REST, ARC, OSC, TRAIN = 0, 1, 2, 3, 4, 5


@dataclass
class Rows:
    """Dense description of the contact phases: one row per integration step, line, arc or
    reduced model (their kinds: :data:`HERMITE` ... :data:`TRAIN`).

    Rows hold the quintic Hermite data of a step (or a stick line / rest), the branch
    index, and the energy terms at the row's start.
    """

    kind: list[int] = field(default_factory=list)
    t0: list[float] = field(default_factory=list)
    t1: list[float] = field(default_factory=list)
    data: list[tuple[float, ...]] = field(default_factory=list)
    branch: list[int] = field(default_factory=list)
    friction: list[float] = field(default_factory=list)  # s*a in slip, nan in stick
    work0: list[tuple[float, float, float]] = field(default_factory=list)  # wf, wb, W_stop
    branches: list[Branch] = field(default_factory=list)
    branch_start: list[tuple[float, float]] = field(default_factory=list)  # (delta0, W0)


@dataclass
class State:
    """The motion's state, which each sub-step of a solve takes and advances: time,
    position, velocity and the work terms so far."""

    t: float
    x: float
    v: float
    work: tuple[float, float, float]  # friction work, belt input, work done on the stop




class Solve:
    """One solve of a deformable stop: its setup (read only once built) and its record.

    The setup: the scene, the horizon, the tolerances and the work limit, with the options
    ``use_arcs`` and ``use_reduced``. The record: the free-flight segments (``table``), the
    contact rows (``contact``) and the ``timeline`` that interleaves them, the transitions
    (``log``), the counts, the status and steady state, the train of contacts so far and
    the reduced models' error bounds. Every write goes through a method here, so the
    record's invariants (a timeline entry where contact rows resume, the work limit checked
    at each transition, the bounds only ever growing) hold in one place.
    """

    def __init__(self, osc, stop, t_end: float, rtol: float, atol: float, cap: int, *,
                 max_steps: int = DEFAULT_MAX_STEPS, use_arcs: bool = True,
                 use_reduced: bool = True) -> None:
        self.osc, self.stop, self.t_end = osc, stop, t_end
        self.rtol, self.atol = rtol, atol
        self.a, self.b, self.vb = osc.a, osc.b, osc.v
        self.xb, self.d_lim = stop.clearance, stop.limit_overlap
        self.d_max = limit_band(stop.clearance, stop.limit_overlap)
        self.max_steps = max_steps
        self.use_arcs = use_arcs
        self.use_reduced = use_reduced
        self.table = SegmentTable()
        self.contact = Rows()
        self.timeline: list[tuple[float, int, int]] = []  # (t0, 0 free / 1 contact, row)
        self.log = TransitionLog(cap, window=STEADY_TAIL)
        self.status = Status.SUCCESS
        self.rhs_evals = 0
        self.steps = 0
        self.rejected = 0
        self.arc_evals = 0
        self.arcs = 0
        self.n_solved = 0  # transitions recorded by the solve (not laid out by a model)
        self.laid_out = 0  # contacts laid out by the contact-to-contact map
        self.restitution: list[float] = []
        self.x_max = -math.inf
        self.n_contacts = 0
        self.steady: Steady | None = None
        self.tail_start: tuple[float, float] | None = None  # the periodic cycle's span
        self.endless = None  # the last free segment when it never ends (no event)
        self.rest_force = math.nan
        self.reduced_error = 0.0  # bound of the reduced models' error in the end state
        self.reduced_band = 0.0  # bound of their error in the position while they run
        self.rest_time_error = 0.0  # bound of a reduced oscillation's error in its rest time
        self.train: list[tuple[float, float, float, int]] = []  # contacts: t, w, peak, n
        self.map_tried = False  # the contact-to-contact map is tried once per solve
        self.reduce_after = -math.inf  # no reduced oscillation is tried before this time
        self._detector: FixedPointDetector | None = None
        self._limit: ElasticLimit | None = None
        self._rest_tol: tuple[float, float] | None = None

    # --- the setup ---------------------------------------------------------------------

    def scale(self) -> float:
        """The length scale the tolerances are relative to, ``max(a, b, v, |x_bar|, D)``."""
        return max(self.a, self.b, self.vb, abs(self.xb), self.d_lim, 1e-300)

    def pressed(self) -> bool:
        """The belt presses the mass on the stop (the one rule of
        :func:`core.steady.pressed_on_stop`, ``x_bar <= a``, with the belt moving towards
        the stop so that kinetic friction ``+a`` acts on a mass at rest there)."""
        return self.vb > 0.0 and pressed_on_stop(self.osc, self.xb)

    def elastic_limit(self) -> ElasticLimit | None:
        """What the law makes of a regular train's contacts
        (:func:`core.deformable.law.elastic_limit`); ``None`` on a still belt."""
        if self.vb <= 0.0:
            return None
        if self._limit is None:
            self._limit = elastic_limit(self.a, self.xb, self.stop)
        return self._limit

    def rest_tolerances(self, compute) -> tuple[float, float]:
        """The rest amplitude and the reduced models' tolerance, ``compute(self)`` once per
        solve (the rule for rest reads them at every reversal)."""
        if self._rest_tol is None:
            self._rest_tol = compute(self)
        return self._rest_tol

    def work_steps(self) -> int:
        """The steps counted against ``max_steps`` (:data:`DEFAULT_MAX_STEPS`); the map's
        contacts, far cheaper, count as one per :data:`MAP_CONTACTS_PER_STEP`."""
        return (self.steps + self.rejected + self.arcs + self.n_solved
                + self.laid_out // MAP_CONTACTS_PER_STEP)

    # --- rows ----------------------------------------------------------------------------

    def add_free(self, seg, t1: float, st: State) -> None:
        """A free-flight segment up to ``t1``; ``st.work`` advances by its work."""
        self.timeline.append((seg.t0, 0, len(self.table)))
        self.table.work = st.work
        self.table.add(seg, t1, self.vb)
        self.x_max = max(self.x_max, self.table.x_max)
        st.work = self.table.work

    def add_row(self, kind: int, t0: float, t1: float, data, friction: float,
                work: tuple[float, float, float]) -> None:
        """A contact row over ``[t0, t1]`` (a timeline entry first where contact rows
        resume after free flight)."""
        c = self.contact
        if not c.kind or self.timeline[-1][1] != 1:
            self.timeline.append((t0, 1, len(c.kind)))
        # (called at every step of a contact: the appends written out)
        c.kind.append(kind)
        c.t0.append(t0)
        c.t1.append(t1)
        c.data.append(data)
        c.branch.append(len(c.branches) - 1)
        c.friction.append(friction)
        c.work0.append(work)

    def new_branch(self, branch: Branch, delta: float, w_stop: float) -> None:
        """The law's branch from overlap ``delta`` on, with the stop's work ``w_stop`` there."""
        self.contact.branches.append(branch)
        self.contact.branch_start.append((delta, w_stop))

    # --- counts, bounds, status ----------------------------------------------------------

    def tally(self, steps: int = 0, rejected: int = 0, rhs_evals: int = 0,
              arc_evals: int = 0, arcs: int = 0) -> None:
        """Add to the work counts."""
        self.steps += steps
        self.rejected += rejected
        self.rhs_evals += rhs_evals
        self.arc_evals += arc_evals
        self.arcs += arcs

    def reach(self, x: float) -> None:
        """The motion reached ``x`` (the largest displacement so far)."""
        if x > self.x_max:
            self.x_max = x

    def fail(self, status: Status) -> None:
        """The solve ends with ``status``."""
        self.status = status

    def bound(self, error: float = 0.0, band: float = 0.0, rest_time: float = 0.0) -> None:
        """A reduced model's error bounds: in the end state, in the position while it
        runs, in a time of rest (each the largest stated)."""
        self.reduced_error = max(self.reduced_error, error)
        self.reduced_band = max(self.reduced_band, band)
        self.rest_time_error = max(self.rest_time_error, rest_time)

    def add_restitution(self, ratio: float) -> None:
        """A contact's rebound over approach speed."""
        self.restitution.append(ratio)

    def defer_reduction(self, t: float) -> None:
        """No reduced oscillation is tried before ``t``."""
        self.reduce_after = t

    def mark_map_tried(self) -> None:
        """The contact-to-contact map has been tried (once per solve)."""
        self.map_tried = True

    def add_train_contact(self, st: State) -> None:
        """A contact of the train starts at ``st`` (its peak to come)."""
        self.train.append((st.t, st.v, math.nan, self.log.total))

    def set_train_peak(self, x: float) -> None:
        """The first reversal of the train's last contact, if it has none yet."""
        if self.train and math.isnan(self.train[-1][2]):
            self.train[-1] = (*self.train[-1][:2], x, self.train[-1][3])

    def count_laid_out(self, contacts: int, laid_out: int = 0) -> None:
        """Contacts a reduced model lays out (``laid_out`` of them by the map, which count
        against the work limit)."""
        self.n_contacts += contacts
        self.laid_out += laid_out

    def settle(self, steady: Steady, rest_force: float = math.nan) -> None:
        """The steady state found (with the stop's force at rest)."""
        self.steady = steady
        self.rest_force = rest_force

    def end_free(self, seg) -> None:
        """The last free segment never ends (no event): its motion is the steady state."""
        self.endless = seg

    # --- transitions and the fixed point of the friction-impact map ----------------------

    def add_transition(self, kind: TransitionKind, t: float, x: float, v: float,
                       v_after: float) -> None:
        """A transition laid out by a reduced model: stored, not solved (it costs no work
        and is not compared for a fixed point)."""
        self.log.add(kind, t, x, v, v_after)

    def count_transitions(self, kind: TransitionKind, n: int) -> None:
        """Transitions of ``kind`` a reduced model lays out, counted and not stored."""
        self.log.count(kind, n)

    def contact_starts(self, st: State, v_after: float) -> None:
        """A contact starts at ``st``."""
        self.n_contacts += 1
        self.record(TransitionKind.CONTACT, st, v_after)

    def record(self, kind: TransitionKind, st: State, v_after: float, phi: float = 0.0):
        """A transition solved at ``st``: logged, counted against the work limit and
        compared for a fixed point of the friction-impact map."""
        self.log.add(kind, st.t, st.x, st.v, v_after)
        # Only transitions solved here count against the work limit: those a reduced model
        # lays out cost no work and are not stored.
        self.n_solved += 1
        if self.work_steps() >= self.max_steps and self.status is Status.SUCCESS:
            self.status = Status.STEP_LIMIT
        # Reversals inside a sustained contact are not compared: a cycle made only of them
        # is integrated to ~1e-8 and never passes the fixed-point test, and comparing each
        # of the thousands of reversals of a long contact costs a third of the solve. A
        # cycle that does repeat still contains a contact, separation or stick transition.
        if kind in (TransitionKind.FAILURE, TransitionKind.REST, TransitionKind.REVERSAL,
                    TransitionKind.REDUCED):
            return
        if self._detector is None:
            # states repeat to the contact integration's accuracy (FIXED_POINT_RTOL) and a
            # cycle's own size tells nothing at that tolerance; the force is ~k_c0 times a
            # length
            scale = self.scale()
            self._detector = FixedPointDetector(
                scale, rtol=FIXED_POINT_RTOL, min_cycle_size=scale,
                phi_scale=max(1.0, self.stop.k_c0),
            )
        cycle = self._detector.add(kind, st.t, st.x, st.v, self.log.total, phi)
        if cycle is not None:
            self.periodic(cycle.t_then, cycle.tag_then, st)

    def periodic(self, t_then: float, n_then: int, st: State) -> None:
        """The motion repeats from ``t_then`` (``n_then`` transitions then) to ``st``: the
        periodic steady state, unless the law makes its contacts lose energy."""
        period = st.t - t_then
        if period <= 0.0:
            return
        cycle = [tr for tr in self.log.recent if t_then < tr.t <= st.t]
        limit = self.elastic_limit()
        if limit is not None and train_loses(cycle, limit):
            # contacts the law makes lose energy repeat only to the tolerance: their speeds
            # fall at every contact (towards w_inf), never a fixed point
            return
        impact = [tr.v for tr in cycle if tr.kind is TransitionKind.CONTACT]
        # Read from the contact that begins it (a train of contacts whose approach speeds
        # repeat to rounding closes at a contact, one whose separations do at a separation).
        first = next((k for k, tr in enumerate(cycle) if tr.kind is TransitionKind.CONTACT), 0)
        cycle = cycle[first:] + cycle[:first]
        self.steady = Steady(
            SteadyKind.PERIODIC,
            period=period,
            transitions_per_period=self.log.total - n_then,
            sequence=tuple(tr.kind.value for tr in cycle),
            impact_speed=max(impact) if impact else math.nan,
            t_reached=t_then,
        )
        self.tail_start = (t_then, st.t)

    def replicate_cycle(self, t_end: float) -> None:
        """Transitions after the detected cycle: shifted copies, stored up to the cap.

        Those the solve recorded after the cycle closed (the contact in progress went on
        to its end) give way to the copies, as the samples there do: kept, each was
        recorded twice."""
        t_then, t_now = self.tail_start
        period = t_now - t_then
        log = self.log
        late = [tr for tr in log.stored if tr.t > t_now]
        if late:
            log.stored = [tr for tr in log.stored if tr.t <= t_now]
            for tr in late:
                log.total -= 1
                log.counts[tr.kind.value] -= 1
        cycle = [tr for tr in log.stored
                 if t_then < tr.t <= t_now and tr.kind is not TransitionKind.REDUCED]
        if not cycle:
            return
        k = 1
        while cycle[0].t + k * period <= t_end:
            if len(log.stored) >= log.cap:
                self._count_copies(cycle, k, period, t_end)
                return
            for tr in cycle:
                ts = tr.t + k * period
                if ts > t_end:
                    return
                log.add(tr.kind, ts, tr.x, tr.v, tr.v_after)
            k += 1

    def _count_copies(self, cycle, k: int, period: float, t_end: float) -> None:
        """Count, not store, the copies of ``cycle`` from the ``k``-th on to ``t_end``."""
        log = self.log
        remaining = t_end - (cycle[0].t + k * period)
        full = int(remaining // period) + 1
        for tr in cycle:
            n = (
                full
                if tr.t - cycle[0].t + (full - 1) * period + cycle[0].t + k * period <= t_end
                else full - 1
            )
            log.total += n
            log.counts[tr.kind.value] += n
