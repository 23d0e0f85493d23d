"""Response with a deformable (hysteretic) stop: exact free flight, integrated contact.

This module is longer than the project's ~500 lines because it holds the contact phase's
solver whole (its events, the steady state and the result); the reduced models, the arcs and
the samples live in their own modules.

Away from the stop the motion is the closed form of :mod:`core.flight` (slip circles and stick
lines, paper Eqs. 3-6). Only the contact phase ``x > clearance`` is integrated numerically
(paper Eqs. 14-15 with the law of :mod:`core.deformable.law`, Eqs. 11-13)::

    slip:  x'' + x = s*a - phi(delta)          s = sign(v - x'), delta = x - clearance
    stick: x' = v   while |x + phi(delta)| <= b

Events inside contact: separation (``delta`` back to 0), reversal of the overlap rate
(``x' = 0``: a new :class:`~core.deformable.law.Branch`), stick/slip changes (``x' = v``),
failure of the stop (``phi > strength``) and the limit overlap (``delta -> D``). A stick
segment inside contact is again exact (a straight line; its end ``x + phi = b`` is a scalar
root).

Integrator: chosen by measurement. One contact (fast belt, natural start, clearance 0.3,
approach speed 0.17, k_e0 = 0.09 k_c0, beta = 40, D = 3 x the overlap scale), rtol = 1e-9,
atol = 1e-12, terminal events for the reversal and the separation; median of 7 runs on the
development machine (2 cores, shared, so +-2x); the solve_ivp rows time the contact alone,
the last row the whole solve including free flight and samples:

==============================  ======================  ==========================
method                          k_c0 = 400              k_c0 = 1e8
==============================  ======================  ==========================
solve_ivp DOP853                454 f-evals, 2.6 ms     4318 f-evals, 24 ms
solve_ivp RK45                  526 f-evals, 3.7 ms     2452 f-evals, 33 ms
solve_ivp Radau (exact jac)     2447 f-evals, 69 ms     fails (inf in the LU)
solve_ivp LSODA (exact jac)     439 f-evals, 4.3 ms     435 f-evals, 4.2 ms
scalar Dormand-Prince 5(4)      590 f-evals, 1.0 ms     626 f-evals, 0.9 ms
==============================  ======================  ==========================

All give the rebound ratio to ~1e-8. The contact is stiff only in the sense that its
frequency ``sqrt(k_c0)`` is high; it has no fast decaying mode (the law is rate-independent:
no damping term), so an implicit method buys nothing: it must still resolve each
oscillation, and its Newton iterations cost more per step (Radau: 5x the evaluations). The
number of explicit steps per contact is set by the accuracy of one oscillation, not by
``k_c0`` (the contact lasts ``~pi/sqrt(k_c0)``): ~60 steps at rtol = 1e-9 whatever the
stiffness. What remains is the overhead per step, hence a scalar embedded Dormand-Prince
5(4) pair written with :mod:`math` (the force as a closure with the branch constants bound;
~8 us per step against ~50 us for a ``solve_ivp`` step) with a quintic Hermite interpolant
(position, velocity and acceleration at both ends, error ``O(h^6)``) for event location and
dense samples.

Energy (per unit ``k``): the work done on the stop is the path integral of the force along
the branches (:func:`core.deformable.law.branch_work`, closed form), friction work is ``s*a``
times the displacement in slip and ``int (x + phi) dx`` in stick: all are functions of the
integrated states, so the balance ``mechanical - mechanical[0] = friction_work - stop_loss
- stop_stored`` checks the integration itself.

Layout: this module is the solver's event loop, one class whose methods share the state of
a solve (the current branch, the rows, the log), hence its length; what stands alone lives
beside it: :mod:`core.deformable.state` (the Dormand-Prince pair, the dense rows, the log),
:mod:`core.deformable.arcs` (semi-analytic arcs), :mod:`core.deformable.reduced` (reduced
models of a pressed mass) and :mod:`core.deformable.samples` (samples, energy, steady state).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from core.deformable.arcs import arc
from core.deformable.law import (
    EXP_CAP,
    FIRST_LOADING,
    Branch,
    ElasticLimit,
    _on_compression,
    branch_work,
    elastic_limit,
    force_and_slope,
    passive_as_paper,
    passive_branch_force,
    phi_compression,
    phi_expansion,
    reverse,
    start_branch,
)
from core.deformable.reduced import (
    REST_AMPLITUDE_PER_RTOL,  # noqa: F401 (the rule's constant, read from here too)
    advance_train,
    creep_end,
    fit_train,
    reduce_extent,
    reduce_oscillation,
    rest_rule,
    rest_swing,
    rest_swing_factor,
)
from core.deformable.samples import _assemble
from core.deformable.state import (
    _A21,
    _A31,
    _A32,
    _A41,
    _A42,
    _A43,
    _A51,
    _A52,
    _A53,
    _A54,
    _A61,
    _A62,
    _A63,
    _A64,
    _A65,
    _B1,
    _B3,
    _B4,
    _B5,
    _B6,
    _E1,
    _E3,
    _E4,
    _E5,
    _E6,
    _E7,
    _HERMITE,
    _LINE,
    _REST,
    EVENT_XTOL,
    FIRST_STEP_FRACTION,
    FIXED_POINT_RTOL,
    MAX_FACTOR,
    MIN_FACTOR,
    MIN_STEP_FRACTION,
    SAFETY,
    STEADY_TAIL,
    _Contact,
    _dpoly,
    _first_exit,
    _hermite_coeffs,
    _poly,
    _State,
    limit_band,
)
from core.deformable.train_contact import TIGHT_RTOL, TIGHT_RTOL_MIN, Kinks, TrainContact
from core.deformable.train_map import MAP_CONTACTS_PER_STEP, map_train
from core.flight import Segment, after_event, free_flight, start_motion
from core.numerics.limits import COUNT_MAX
from core.params import HystereticStop
from core.result import Mode, Result, Status, Steady, SteadyKind, TransitionKind
from core.solve_inputs import SolveInputs, solve_entry
from core.steady import FixedPointDetector, pressed_on_stop, train_loses
from core.trajectory import SegmentTable
from core.transitions import TransitionLog
from core.validation import check_integer

#: Default work limit of :func:`solve_hysteretic`: its steps, counted as the Dormand-Prince
#: steps of the contacts (accepted and rejected), the semi-analytic arcs and the transitions
#: solved one by one, each of which costs ~15 us on the development machine (58e3 a second
#: on a grazing train, 62e3 on scene 11's loops), and the contacts the contact-to-contact
#: map lays out, far cheaper, at one step per
#: :data:`core.deformable.train_map.MAP_CONTACTS_PER_STEP`. It is checked at each transition;
#: past it the result ends there with ``Status.STEP_LIMIT``.
#: Sized so that a call without ``max_steps`` returns within a few seconds whatever the
#: horizon (~4 s; benchmarks/hysteretic_limits.py) while scene 11's loops (2.1e5 steps to
#: rest) still end at rest.
DEFAULT_MAX_STEPS = 250_000


#: Tolerance of the equilibrium on the stop (relative to the length scale): the rest force
#: then equals ``a - x`` to ~1e-15 relative, far inside the 1e-9 promised.
EQUILIBRIUM_XTOL = 1e-16


#: Relative tolerance of brentq's roots (its smallest allowed value).
ROOT_RTOL = 4.0 * np.finfo(float).eps


#: Reversals between two tries of the reduced oscillation: a try fits the decay of the last
#: cycles (35 % of a soft stop's solve when made at every reversal, k_c0 = 100, t_end = 1e4),
#: and a switch two cycles later changes nothing the model's bounds do not state.
REDUCE_EVERY = 4


#: Points of the grid on which a step's velocity is searched for the belt's speed where it
#: turns inside the step (:func:`_belt_speed_inside`).
BELT_GRID = 64


def _may_pass_belt(u0: float, u1: float, a0: float, a1: float, h: float, s: int,
                   vb: float) -> bool:
    """Whether a step's velocity turns inside it (towards the belt's speed for the friction
    sign ``s``) and could reach it: an acceleration varying linearly from ``a0`` to ``a1``
    takes it at most ``h |a| / 2`` past its ends; twice that leaves a margin."""
    if s > 0:
        return a0 > 0.0 > a1 and max(u0, u1) + h * max(a0, -a1) >= vb
    return a0 < 0.0 < a1 and min(u0, u1) - h * max(-a0, a1) <= vb


def _belt_speed_inside(coeffs, h: float, s: int, vb: float) -> float | None:
    """The first ``theta`` in ``(0, 1)`` where the step's velocity reaches the belt's speed
    (from below for ``s = 1``, from above for ``s = -1``) though it ends on the near side,
    or ``None``: searched on a grid of :data:`BELT_GRID` points, then refined."""
    def g(th: float) -> float:
        return s * (vb - _dpoly(coeffs, th) / h)

    prev = None  # the last grid point inside the mode (a step may start on the boundary)
    for k in range(BELT_GRID):
        th = k / BELT_GRID
        if g(th) > 0.0:
            prev = th
        elif prev is not None:
            return brentq(g, prev, th, xtol=EVENT_XTOL)
    return None


class _Solver:
    """One solve: the event loop over free flight and contact phases."""

    def __init__(self, osc, stop, t_end, rtol, atol, cap):
        self.osc, self.stop, self.t_end = osc, stop, t_end
        self.rtol, self.atol = rtol, atol
        self.tight_rtol = min(rtol, max(TIGHT_RTOL * rtol, TIGHT_RTOL_MIN))
        self.a, self.b, self.vb = osc.a, osc.b, osc.v
        self.xb, self.d_lim = stop.clearance, stop.limit_overlap
        self.d_max = limit_band(stop.clearance, stop.limit_overlap)
        self.table = SegmentTable()
        self.contact = _Contact()
        self.timeline: list[tuple[float, int, int]] = []  # (t0, 0 free / 1 contact, row)
        self.log = TransitionLog(cap, window=STEADY_TAIL)
        self.status = Status.SUCCESS
        self.rhs_evals = 0
        self.steps = 0
        self.rejected = 0
        self.arc_evals = 0
        self.arcs = 0
        self.use_arcs = True
        self.use_reduced = True
        self.max_steps = DEFAULT_MAX_STEPS
        self.n_solved = 0  # transitions recorded by the solve (not laid out by a model)
        self.laid_out = 0  # contacts laid out by the contact-to-contact map
        self.restitution: list[float] = []
        self.x_max = -math.inf
        self.t_stop = t_end  # end of the computed motion (earlier on failure)
        self.n_contacts = 0
        self.steady: Steady | None = None
        self.tail: tuple[float, float, float, tuple[float, float, float]] | None = None
        self.detector: FixedPointDetector | None = None
        self._limit: ElasticLimit | None = None
        self.reduced_error = 0.0  # bound of the reduced models' error in the end state
        self.reduced_band = 0.0  # bound of their error in the position while they run
        self.rest_time_error = 0.0  # bound of a reduced oscillation's error in its rest time
        self.train: list[tuple[float, float, float, int]] = []  # contacts: t, w, peak, n
        self.map_tried = False  # the contact-to-contact map is tried once per solve
        self.reduce_after = -math.inf  # no reduced oscillation is tried before this time
        self._rest_tol: tuple[float, float] | None = None  # rest amplitude and tolerance
        self.rest_force = math.nan

    # --- free flight ---------------------------------------------------------------------

    def add_free(self, seg: Segment, t1: float, st: _State) -> None:
        self.timeline.append((seg.t0, 0, len(self.table)))
        self.table.work = st.work
        self.table.add(seg, t1, self.vb)
        self.x_max = max(self.x_max, self.table.x_max)
        st.work = self.table.work

    # --- contact -------------------------------------------------------------------------

    def accel(self, s: int, branch: Branch):
        """``x'' = -x + s a - phi(x - clearance)`` on one branch, as a fast closure (the
        law of :func:`core.deformable.law.force_and_slope` with the branch constants bound)."""
        stop = self.stop
        if stop.law == "passive":
            as_paper = passive_as_paper(branch, stop)
            if as_paper is None:
                return self.accel_passive(s, branch)
            branch = as_paper  # the same curve: the paper's closure below is faster
        xb, d_lim, sa = self.xb, self.d_lim, s * self.a
        kc, ke = stop.k_c0 * d_lim, stop.k_e0 * d_lim
        r = branch.delta_r
        exp, cap = math.exp, EXP_CAP
        # Eq. 13 on either branch: phi = k_own h + g exp(rate (d - r)), h = d / (D - d),
        # held between the envelopes (Eq. 11): at least phi_E while loading, at most phi_C
        # while unloading. ``side`` turns "at least" into "at most" without a branch.
        if branch.loading:
            k_own, k_env, side = kc, ke, -1.0
            gap, rate = branch.phi_r - kc * r / (d_lim - r), -stop.beta_c / d_lim
        else:
            k_own, k_env, side = ke, kc, 1.0
            gap, rate = branch.phi_r - ke * r / (d_lim - r), stop.beta_e / d_lim

        if gap == 0.0:
            # On its own envelope (a first loading, every contact of a train): the
            # exponential term is 0 and the clip keeps the envelope, the same bits.
            def acc_envelope(x: float) -> float:
                d = x - xb
                if d <= 0.0:
                    return sa - x - kc * d / (d_lim - d)
                return sa - x - k_own * (d / (d_lim - d))

            return acc_envelope

        def acc(x: float) -> float:
            d = x - xb
            if d <= 0.0:
                # The smooth continuation of the compression envelope, which every contact
                # follows into separation (docs/contact-law.md): a step that crosses the
                # face then stays smooth up to the separation found on it. With the force
                # cut to 0 there, that step's kink cost ~1e-11 of the rebound speed at any
                # rtol, an error of the phase of a long train that no tolerance removed.
                return sa - x - kc * d / (d_lim - d)
            hyper = d / (d_lim - d)
            envelope = k_env * hyper
            z = rate * (d - r)
            phi = k_own * hyper + gap * exp(z if z < cap else cap)
            return sa - x - (phi if side * (phi - envelope) < 0.0 else envelope)

        return acc

    def accel_passive(self, s: int, branch: Branch):
        """:meth:`accel` on a branch of the passive law that is none of the paper's."""
        xb, sa, d_lim, kc = self.xb, s * self.a, self.d_lim, self.stop.k_c0 * self.d_lim
        force = passive_branch_force(branch, self.stop)

        def acc_passive(x: float) -> float:
            d = x - xb
            if d <= 0.0:  # phi_C continued past the face, as in accel's closures
                return sa - x - kc * d / (d_lim - d)
            return sa - x - force(d)

        return acc_passive

    def new_branch(self, branch: Branch, delta: float, w_stop: float) -> None:
        self.contact.branches.append(branch)
        self.contact.branch_start.append((delta, w_stop))

    def close_branch(self, branch: Branch, d0: float, d1: float, st: _State) -> None:
        wf, wb, ws = st.work
        st.work = (wf, wb, ws + branch_work(d0, d1, branch, self.stop))

    def run_contact(self, st: _State, stick: bool, inside: Branch | None = None) -> str:
        """Integrate one contact from ``st`` (at the face, moving in) until it ends; with
        ``inside``, from a start inside the stop on that branch
        (:func:`~core.deformable.law.start_branch`).

        Returns ``"separated"``, ``"rest"``, ``"failed"``, ``"limit"``, ``"periodic"`` or
        ``"horizon"``.
        """
        stop, xb = self.stop, self.xb
        opened = self.open_contact(st, inside)
        if isinstance(opened, str):
            return opened
        branch, s = opened
        d_branch0 = st.x - xb
        w_in = st.v if inside is None else math.nan
        reversal_x: list[tuple[float, float, int]] = []  # (t, x, transitions) of reversals
        # a contact of a train is kept on its first integral (core/deformable/train_contact.py)
        train = TrainContact(self, st.x, w_in, s, stick)
        while True:
            if stick:
                outcome = self.stick_in_contact(st, branch)
                if outcome != "slip":
                    self.close_branch(branch, d_branch0, st.x - xb, st)
                    return outcome
                stick, s = False, 1
                continue
            if self.use_arcs and st.v == 0.0 and branch.delta_r == st.x - xb:
                phi = arc(self, st, s, branch)
                if phi is not None:
                    train.regular = False  # a second reversal
                    branch, ended = self.reversal(st, branch, phi, reversal_x, s)
                    d_branch0 = st.x - xb
                    if ended:
                        return ended
                    if self.status is not Status.SUCCESS:
                        return "failed"
                    continue
            outcome, s_new = self.slip_in_contact(st, s, branch, train.kinks(),
                                                  train.tight(len(reversal_x)))
            delta = st.x - xb
            if outcome == "separated":
                st.v = train.separation(st.v, branch, len(reversal_x))
                self.close_branch(branch, d_branch0, 0.0, st)
                st.x = xb
                self.restitution.append(-st.v / w_in if w_in > 0 else math.nan)
                self.record(TransitionKind.SEPARATION, st, st.v)
                return "separated"
            if outcome == "reversal":
                st.x = xb + self.retraced_top(train.peak(delta, len(reversal_x)), branch)
                delta = st.x - xb
                phi, _ = force_and_slope(delta, branch, stop)
                self.close_branch(branch, d_branch0, delta, st)
                branch, ended = self.reversal(st, branch, phi, reversal_x, s)
                d_branch0 = delta
                train.unloading(branch)
                if ended:
                    return ended
                if self.status is not Status.SUCCESS:
                    return "failed"
                continue
            if outcome == "friction":
                train.regular = False
                stick, s, branch, d_branch0 = self.belt_speed_reached(
                    st, s, s_new, branch, d_branch0)
                continue
            if outcome in ("failed", "limit", "horizon"):
                self.close_branch(branch, d_branch0, delta, st)
                return outcome

    def open_contact(self, st: _State, inside: Branch | None) -> str | tuple[Branch, int]:
        """The branch and friction sign a contact starts with, or how it ended at once (see
        :meth:`start_contact`). From the face (``inside`` None) on the first loading; from
        a start inside the stop on ``inside``: not a contact of a train (no entry speed)."""
        if inside is None:
            started = self.start_contact(st)
            if started:
                return started
            # a train's map may have moved st to the start of a later contact
            branch = FIRST_LOADING
        else:
            self.n_contacts += 1
            self.record(TransitionKind.CONTACT, st, st.v)
            branch = inside
        delta = st.x - self.xb
        self.new_branch(branch, delta, st.work[2])
        if st.v != self.vb:
            return branch, 1 if st.v < self.vb else -1
        # at the belt's speed and not held: friction gives way to the net force
        return branch, 1 if st.x + force_and_slope(delta, branch, self.stop)[0] > 0.0 else -1

    def start_contact(self, st: _State) -> str | None:
        """Record a contact's start; ``"periodic"`` if the motion is periodic from here (a
        fixed point of the friction-impact map), ``"horizon"`` or ``"rest"`` if a shrinking
        train is advanced by its reduced model from here (its contact-to-contact map,
        :func:`core.deformable.train_map.map_train`, or its fitted loss law,
        :func:`core.deformable.reduced.fit_train`). A train whose contacts turn elastic
        tends to the elastic speed without reaching it: it is never tiled as periodic."""
        self.n_contacts += 1
        self.record(TransitionKind.CONTACT, st, st.v)
        if self.steady is not None:
            return "periodic"
        self.train.append((st.t, st.v, math.nan, self.log.total))
        if map_train(self, st, self.train):
            # st is now the start of a later contact, handed back to the integration
            self.n_contacts += 1
            self.record(TransitionKind.CONTACT, st, st.v)
            self.train.append((st.t, st.v, math.nan, self.log.total))
            return None
        model = fit_train(self, self.train)
        if model is None:
            return None
        return advance_train(self, st, model)

    def belt_speed_reached(self, st: _State, s: int, s_new: int, branch: Branch,
                           d_branch0: float):
        """The mass reaches the belt speed inside contact: it sticks if static friction
        holds the stop's force, ``|x + phi| <= b``, else friction changes sign. Returns
        ``(stick, s, branch, start overlap of the branch)``."""
        delta = st.x - self.xb
        phi, _ = force_and_slope(delta, branch, self.stop)
        if not (abs(st.x + phi) <= self.b and self.vb > 0.0):
            self.record(TransitionKind.SIGN_CHANGE, st, st.v)
            return False, s_new, branch, d_branch0
        st.v = self.vb
        self.record(TransitionKind.SLIP_STICK, st, st.v)
        if not branch.loading:  # x' = v > 0: the overlap grows again
            self.close_branch(branch, d_branch0, delta, st)
            branch = reverse(delta, phi, branch, self.stop)
            d_branch0 = delta
            self.new_branch(branch, delta, st.work[2])
        return True, s, branch, d_branch0

    def slip_in_contact(self, st: _State, s: int, branch: Branch, kinks: list[float] = (),
                        tight: bool = False) -> tuple[str, int]:
        """Dormand-Prince 5(4) steps until an event; ``st`` is left at the event.

        A step that would cross one of ``kinks`` (positions, descending) moving out is redone
        to end on it (:class:`core.deformable.train_contact.Kinks`); ``tight``: steps at
        :data:`core.deformable.train_contact.TIGHT_RTOL` times ``rtol``.

        The step is the solve's inner loop (~200 steps a contact at the map's node
        tolerance): the rows are appended and the work advanced here, and the events are
        located (:meth:`step_events`) only when a step's end leaves the mode."""
        stop, xb, vb = self.stop, self.xb, self.vb
        rtol, atol = self.tolerances(tight)
        t_end, d_lim, d_max = self.t_end, stop.limit_overlap, self.d_max
        loading = branch.loading
        strength_finite = math.isfinite(stop.strength)
        sa = s * self.a
        sav = sa * vb
        c = self.contact
        kind_add, t0_add, t1_add, data_add = c.kind.append, c.t0.append, c.t1.append, c.data.append
        branch_add, friction_add, work_add = c.branch.append, c.friction.append, c.work0.append
        bi = len(c.branches) - 1
        isfinite, sqrt = math.isfinite, math.sqrt
        x, u, t = st.x, st.v, st.t
        acc = self.accel(s, branch)
        a0 = acc(x)
        n_evals = 1
        _, slope = force_and_slope(max(x - xb, 0.0), branch, stop)
        omega = math.sqrt(1.0 + max(slope, 0.0))
        h = FIRST_STEP_FRACTION * 2.0 * math.pi / omega
        h_min = MIN_STEP_FRACTION * 2.0 * math.pi / omega
        x_max = self.x_max
        ahead = Kinks(kinks)
        kink_x = ahead.x
        landing = False  # the step is redone to end on the kink
        while True:
            left = t_end - t
            if left < h:
                h = left
            if h <= 0.0:
                self.rhs_evals += n_evals
                self.x_max = x_max
                return "horizon", s
            n_evals += 6
            # Dormand-Prince stages; the acceleration depends on x only.
            k1x, k1u = u, a0
            y2x, y2u = x + h * _A21 * k1x, u + h * _A21 * k1u
            k2x, k2u = y2u, acc(y2x)
            y3x = x + h * (_A31 * k1x + _A32 * k2x)
            y3u = u + h * (_A31 * k1u + _A32 * k2u)
            k3x, k3u = y3u, acc(y3x)
            y4x = x + h * (_A41 * k1x + _A42 * k2x + _A43 * k3x)
            y4u = u + h * (_A41 * k1u + _A42 * k2u + _A43 * k3u)
            k4x, k4u = y4u, acc(y4x)
            y5x = x + h * (_A51 * k1x + _A52 * k2x + _A53 * k3x + _A54 * k4x)
            y5u = u + h * (_A51 * k1u + _A52 * k2u + _A53 * k3u + _A54 * k4u)
            k5x, k5u = y5u, acc(y5x)
            y6x = x + h * (_A61 * k1x + _A62 * k2x + _A63 * k3x + _A64 * k4x + _A65 * k5x)
            y6u = u + h * (_A61 * k1u + _A62 * k2u + _A63 * k3u + _A64 * k4u + _A65 * k5u)
            k6x, k6u = y6u, acc(y6x)
            x1 = x + h * (_B1 * k1x + _B3 * k3x + _B4 * k4x + _B5 * k5x + _B6 * k6x)
            u1 = u + h * (_B1 * k1u + _B3 * k3u + _B4 * k4u + _B5 * k5u + _B6 * k6u)
            if not (isfinite(x1) and isfinite(u1)) or x1 - xb >= d_lim:
                err = math.inf
                a1 = math.nan
            else:
                a1 = acc(x1)
                k7x, k7u = u1, a1
                ex = h * (_E1 * k1x + _E3 * k3x + _E4 * k4x + _E5 * k5x + _E6 * k6x + _E7 * k7x)
                eu = h * (_E1 * k1u + _E3 * k3u + _E4 * k4u + _E5 * k5u + _E6 * k6u + _E7 * k7u)
                ax, ax1, au, au1 = abs(x), abs(x1), abs(u), abs(u1)
                sx = atol + rtol * (ax if ax >= ax1 else ax1)
                su = atol + rtol * (au if au >= au1 else au1)
                err = sqrt(0.5 * ((ex / sx) ** 2 + (eu / su) ** 2))
            if x1 < kink_x and not landing:
                h_cut = ahead.cut(x, u, a0, x1, u1, a1, h)
                if h_cut > 0.0:
                    h, landing = h_cut, True
                    continue
            if err > 1.0:
                self.rejected += 1
                h *= max(MIN_FACTOR, SAFETY * err**-0.2) if isfinite(err) else MIN_FACTOR
                if h < h_min:
                    self.rhs_evals += n_evals
                    self.x_max = x_max
                    self.status = Status.INTEGRATION_FAILED
                    st.t, st.x, st.v = t, x, u
                    return "failed", s
                continue
            coeffs = _hermite_coeffs(x, u, a0, x1, u1, a1, h)
            turn = _may_pass_belt(u, u1, a0, a1, h, s, vb)
            if (x1 < xb or (u1 < 0.0 if loading else u1 > 0.0)
                    or (u1 > vb if s > 0 else u1 < vb) or x1 - xb > d_max or strength_finite
                    or turn):
                found = self.step_events(coeffs, h, x1, u1, s, branch, turn)
            else:
                found = None
            if found:
                self.rhs_evals += n_evals
                self.x_max = x_max
                return self.end_at_event(st, t, coeffs, h, s, min(found)), -s
            # The step's row (add_step, inlined) and the work it adds.
            t1 = t + h
            if t1 > t:
                if not c.kind or self.timeline[-1][1] != 1:
                    self.timeline.append((t, 1, len(c.kind)))
                work = st.work
                kind_add(_HERMITE)
                t0_add(t)
                t1_add(t1)
                data_add((*coeffs, h))
                branch_add(bi)
                friction_add(sa)
                work_add(work)
                x_end = _poly(coeffs, (t1 - t) / h)
                wf, wb, ws = work
                st.work = (wf + sa * (x_end - x), wb + sav * (t1 - t), ws)
            self.steps += 1
            t, x, u, a0 = t1, x1, u1, a1
            st.t, st.x, st.v = t, x, u
            if x > x_max:
                x_max = x
            h *= min(MAX_FACTOR, SAFETY * err**-0.2) if err > 0.0 else MAX_FACTOR
            if landing:
                landing = False
                ahead.landed(coeffs[0], x1)  # coeffs[0]: the step's start
                kink_x = ahead.x

    def tolerances(self, tight: bool) -> tuple[float, float]:
        """``(rtol, atol)`` of the contact's steps: the solve's, or the tighter ones of a
        contact's first branches that are not kept on their first integral
        (:mod:`core.deformable.train_contact`)."""
        if tight:
            return self.tight_rtol, self.atol * self.tight_rtol / self.rtol
        return self.rtol, self.atol

    def end_at_event(self, st: _State, t: float, coeffs, h: float, s: int, event) -> str:
        """Cut the step ``(t, coeffs, h)`` at ``event = (theta, name)``, store it, move ``st``
        there and return the name (recording a failure of the stop)."""
        th, name = event
        t_ev = t + th * h
        x_ev = _poly(coeffs, th)
        u_ev = _dpoly(coeffs, th) / h
        if name == "reversal":
            u_ev = 0.0
        elif name == "friction":
            u_ev = self.vb
        elif name == "separated":
            x_ev = self.xb
        self.add_step(t, t_ev, coeffs, h, s, st)
        self.steps += 1
        st.t, st.x, st.v = t_ev, x_ev, u_ev
        self.x_max = max(self.x_max, x_ev)
        if name == "failed":
            self.status = Status.STOP_FAILED
            self.record(TransitionKind.FAILURE, st, st.v)
        elif name == "limit":
            self.status = Status.LIMIT_OVERLAP
        return name

    def step_events(self, coeffs, h: float, x1: float, u1: float, s: int, branch: Branch,
                    turn: bool = False):
        """Events of one step: which condition is violated at the step's end, then its
        first root on the step's interpolant, as ``(theta, name)``. Each ``g`` is positive
        inside the current mode. ``turn``: the velocity turns inside the step and may pass
        the belt's speed there (:func:`_may_pass_belt`)."""
        stop, xb, vb, strength = self.stop, self.xb, self.vb, self.stop.strength
        found: list[tuple[float, str]] = []
        if x1 < xb:
            found.append((_first_exit(lambda th: _poly(coeffs, th) - xb), "separated"))
        if (u1 < 0.0) if branch.loading else (u1 > 0.0):
            sign = 1.0 if branch.loading else -1.0
            found.append((_first_exit(lambda th: sign * _dpoly(coeffs, th)), "reversal"))
        if (u1 > vb) if s > 0 else (u1 < vb):
            found.append((_first_exit(lambda th: s * (vb - _dpoly(coeffs, th) / h)), "friction"))
        elif turn:
            # The velocity may pass the belt's speed inside the step and come back (it
            # turns there): a contact entered just below the belt's speed reaches it within
            # microseconds and sticks for milliseconds. Missed, that stick was lost: the
            # period of such a train off by 4e-7 at rtol 1e-8 to 1e-10.
            th = _belt_speed_inside(coeffs, h, s, vb)
            if th is not None:
                found.append((th, "friction"))
        if x1 - xb > self.d_max:
            found.append(
                (_first_exit(lambda th: xb + self.d_max - _poly(coeffs, th)), "limit")
            )
        if math.isfinite(strength) and force_and_slope(x1 - xb, branch, stop)[0] > strength:
            found.append((_first_exit(
                lambda th: strength - force_and_slope(_poly(coeffs, th) - xb, branch, stop)[0]
            ), "failed"))
        return found

    def add_step(self, t0, t1, coeffs, h, s, st: _State) -> None:
        """Store one step (cut at ``t1``) and advance the friction and belt work."""
        if t1 <= t0:
            return
        if not self.contact.kind or self.timeline[-1][1] != 1:
            self.timeline.append((t0, 1, len(self.contact.kind)))
        x0 = coeffs[0]
        self.contact.add(_HERMITE, t0, t1, (*coeffs, h), s * self.a, st.work)
        x1 = _poly(coeffs, (t1 - t0) / h)
        wf, wb, ws = st.work
        st.work = (wf + s * self.a * (x1 - x0), wb + s * self.a * self.vb * (t1 - t0), ws)

    def stick_in_contact(self, st: _State, branch: Branch) -> str:
        """Exact stick inside contact, ``x = x0 + v (t - t0)``, until ``x + phi = b``."""
        stop, xb, vb = self.stop, self.xb, self.vb
        x0 = st.x

        def excess(x: float) -> float:
            return x + force_and_slope(x - xb, branch, stop)[0] - self.b

        x_lim = xb + self.d_max
        ends = []
        if excess(x_lim) > 0.0:
            ends.append((brentq(excess, x0, x_lim, xtol=EVENT_XTOL * self.scale()), "slip"))
        if math.isfinite(stop.strength):

            def over(x: float) -> float:
                return force_and_slope(x - xb, branch, stop)[0] - stop.strength

            if over(x_lim) > 0.0:
                ends.append((brentq(over, x0, x_lim, xtol=EVENT_XTOL * self.scale()), "failed"))
        ends.append((x_lim, "limit"))
        x1, name = min(ends)
        t1 = st.t + (x1 - x0) / vb
        if not self.contact.kind or self.timeline[-1][1] != 1:
            self.timeline.append((st.t, 1, len(self.contact.kind)))
        t_cut = min(t1, self.t_end)
        self.contact.add(_LINE, st.t, t_cut, (x0, vb), math.nan, st.work)
        x_cut = x0 + vb * (t_cut - st.t)
        wstick = 0.5 * (x_cut * x_cut - x0 * x0) + branch_work(x0 - xb, x_cut - xb, branch, stop)
        wf, wb, ws = st.work
        st.work = (wf + wstick, wb + wstick, ws)
        self.x_max = max(self.x_max, x_cut)
        st.t, st.x, st.v = t_cut, x_cut, vb
        if t1 >= self.t_end:
            return "horizon"
        if name == "slip":  # the branch goes on: the overlap still grows as the slip starts
            self.record(TransitionKind.STICK_SLIP, st, vb)
            return "slip"
        if name == "failed":
            self.status = Status.STOP_FAILED
            self.record(TransitionKind.FAILURE, st, vb)
            return "failed"
        self.status = Status.LIMIT_OVERLAP
        return "limit"

    def reversal(
        self, st: _State, branch: Branch, phi: float, reversal_x: list[tuple[float, float]],
        s: int,
    ) -> tuple[Branch, str | None]:
        """The overlap rate changes sign at ``st``: the new branch starts from the stored
        reversal point (Eq. 13). Returns it, and ``"periodic"`` or ``"rest"`` when the
        contact ends here (a fixed point, or the reversals have died out)."""
        delta = st.x - self.xb
        branch = reverse(delta, phi, branch, self.stop)
        self.new_branch(branch, delta, st.work[2])
        self.record(TransitionKind.REVERSAL, st, 0.0, phi=phi)
        if self.steady is not None:
            return branch, "periodic"
        reversal_x.append((st.t, st.x, self.log.total))
        if len(reversal_x) == 1 and self.train and math.isnan(self.train[-1][2]):
            self.train[-1] = (*self.train[-1][:2], st.x, self.train[-1][3])
        rule, error = self.settled(reversal_x)
        if rule == "model" and not self.use_reduced:
            rule = "follow"  # a solve without reduced models follows the creeping loops
        if rule == "follow":
            # Rest would be a model stating more than the tolerance, and the loops to the
            # horizon are few: they are followed, and no reduced model is tried on them.
            self.reduce_after = self.t_end
        elif rule is not None:
            if rule == "model":
                # Rest is then a model of loops still creeping: its error is stated, the
                # velocity's too (the loops left move at omega times their amplitude).
                self.record(TransitionKind.REDUCED, st, 0.0)
                self.reduced_error = max(self.reduced_error, error)
            return branch, self.rest_at_stop(st, branch, s, creep_end(self, reversal_x, s))
        if len(reversal_x) % REDUCE_EVERY or st.t < self.reduce_after:
            return branch, None
        return branch, reduce_oscillation(self, st, branch, reversal_x, s)

    def settled(self, reversal_x: list[tuple[float, float, int]]) -> tuple[str | None, float]:
        """The rule for rest on the reversals of this contact (:func:`rest_rule`)."""
        if len(reversal_x) < 4:
            return None, 0.0
        if self._rest_tol is None:  # fixed for the solve; this runs at every reversal
            self._rest_tol = (self.rest_amplitude(), reduce_extent(self))
        rest, tol = self._rest_tol
        # the rule's first test without building lists (loops followed on the stop: a tenth
        # of their time went here)
        x0, x1, x2, x3 = reversal_x[-1][1], reversal_x[-2][1], reversal_x[-3][1], reversal_x[-4][1]
        factor = rest_swing_factor(reversal_x[-1][0] - reversal_x[-3][0])
        if (max(x0, x1, x2, x3) - min(x0, x1, x2, x3)) * factor > rest:
            return None, 0.0
        tail = reversal_x[-5:]
        return rest_rule([t for t, _, _ in tail], [x for _, x, _ in tail], self.t_end, rest,
                         tol)

    def retraced_top(self, delta: float, branch: Branch) -> float:
        """The overlap of a reversal ending a loading of the passive law along the curve
        through its anchor: the anchor itself when the integration overshot it onto
        ``phi_C`` by less than its tolerance.

        Such a loading is the exactly conservative motion back up the curve the mass came
        down from the anchor, so its reversal is the anchor. An overshoot reverses from a
        new point of ``phi_C``, a new curve a little higher at every loop: at rtol 1e-5
        (k_c0 = 1e4, beta = 1000, D = 0.01) the loops then never retraced one curve and
        were followed one by one to the horizon (3,000 reversals, 0.6 s)."""
        anchor = branch.anchor
        if self.stop.law != "passive" or not branch.loading or anchor is None:
            return delta
        d_a, p_a = anchor
        if (_on_compression(d_a, p_a, self.stop)
                and 0.0 < delta - d_a <= max(self.rtol * self.scale(), self.atol)):
            return d_a
        return delta

    def rest_amplitude(self) -> float:
        """Amplitude of the overlap oscillation below which the mass rests on the stop."""
        return rest_swing(self.rtol, self.atol, self.scale())[0]

    def equilibrium(self, branch: Branch, s: int) -> float | None:
        """Position on ``branch`` where the stop holds the mass against friction,
        ``x + phi(x - clearance) = s a`` (paper Eq. 14 with ``x' = x'' = 0``); ``None`` if
        friction pushes the mass away from the stop. The left side grows with ``x`` on every
        branch, so the root is unique."""
        xb, stop, sa = self.xb, self.stop, s * self.a

        def excess(x: float) -> float:
            return x + force_and_slope(x - xb, branch, stop)[0] - sa

        x_hi = xb + self.d_max
        if not (excess(xb) < 0.0 < excess(x_hi)):
            return None
        return brentq(excess, xb, x_hi, xtol=EQUILIBRIUM_XTOL * self.scale(), rtol=ROOT_RTOL)

    def held(self, x: float, s: int) -> float:
        """``x``, or the equilibrium on the envelope (paper Eq. 11) that the law's state at
        rest there, ``(x - clearance, s a - x)``, lies beyond: the stop holds the mass only
        with a force between its envelopes. (Loops that end next to the compression
        envelope, k_c0 = 4000, k_e0 = 100, rtol 1e-5, left their centre 2e-7 short of it:
        the force at rest was clipped onto it, 0.4 % off ``a - x``.)"""
        d_lim, sa = self.d_lim, s * self.a
        d, c = x - self.xb, sa - self.xb
        for k, beyond in ((self.stop.k_c0, sa - x > float(phi_compression(d, self.stop))),
                          (self.stop.k_e0, sa - x < float(phi_expansion(d, self.stop)))):
            if beyond:
                # d + k D d / (D - d) = c: the smaller root of d^2 - (D (1 + k) + c) d + c D,
                # in the form without cancellation
                b = d_lim * (1.0 + k) + c
                return self.xb + 2.0 * c * d_lim / (b + math.sqrt(b * b - 4.0 * c * d_lim))
        return x

    def rest_at_stop(
        self, st: _State, branch: Branch, s: int, x_rest: float | None = None
    ) -> str:
        """The reversals have shrunk to nothing: the mass rests pressed on the stop, at the
        equilibrium on the current branch (the centre of the vanished oscillation).

        ``st`` is a reversal (``x' = 0``). Moving the state to the equilibrium, friction
        does ``s a (x_eq - x)`` and the mechanical energy changes by
        ``(x_eq^2 - x^2) / 2``; the difference is the work the vanished oscillation did on
        the stop (its energy, dissipated by the ever smaller loops), so the balance closes.
        The law's state at rest is the reversal point ``(delta_eq, phi_eq)``.
        """
        x_eq = self.equilibrium(branch, s) if x_rest is None else self.held(x_rest, s)
        if x_eq is not None:
            sa = s * self.a
            wf, wb, ws = st.work
            dx = x_eq - st.x
            dm = 0.5 * (x_eq * x_eq - st.x * st.x - st.v * st.v)
            st.work = (wf + sa * dx, wb, ws + sa * dx - dm)
            st.x, st.v = x_eq, 0.0
            d_eq = x_eq - self.xb
            phi_eq = force_and_slope(d_eq, branch, self.stop)[0]
            if x_rest is not None:  # the law's state where the shrinking loops end
                phi_eq = sa - x_eq
            branch = Branch(False, d_eq, phi_eq)
            self.new_branch(branch, d_eq, st.work[2])
        self.record(TransitionKind.REST, st, 0.0)
        if not self.contact.kind or self.timeline[-1][1] != 1:
            self.timeline.append((st.t, 1, len(self.contact.kind)))
        self.contact.add(_REST, st.t, self.t_end, (st.x,), s * self.a, st.work)
        wf, wb, ws = st.work
        st.work = (wf, wb + s * self.a * self.vb * (self.t_end - st.t), ws)
        phi = force_and_slope(st.x - self.xb, branch, self.stop)[0]
        self.steady = Steady(
            SteadyKind.REST, x_max=st.x, impact_speed=0.0, t_reached=st.t, period=math.nan
        )
        self.rest_force = phi
        st.t = self.t_end
        return "rest"

    def rest_in_place(self, st: _State, branch: Branch) -> None:
        """A start inside the stop that static friction holds on a still belt
        (``|x + phi| <= b``, ``v = 0``): the mass never moves, the stop holds ``phi``."""
        self.n_contacts += 1
        self.record(TransitionKind.CONTACT, st, 0.0)
        self.new_branch(branch, st.x - self.xb, st.work[2])
        self.record(TransitionKind.REST, st, 0.0)
        self.timeline.append((st.t, 1, len(self.contact.kind)))
        self.contact.add(_REST, st.t, self.t_end, (st.x,), 0.0, st.work)
        self.rest_force = force_and_slope(st.x - self.xb, branch, self.stop)[0]
        self.steady = Steady(
            SteadyKind.REST, x_max=st.x, impact_speed=0.0, t_reached=st.t, period=math.nan
        )
        st.t = self.t_end

    def pressed(self) -> bool:
        """The belt presses the mass on the stop (the one rule of
        :func:`core.steady.pressed_on_stop`, ``x_bar <= a``, with the belt moving towards
        the stop so that kinetic friction ``+a`` acts on a mass at rest there)."""
        return self.vb > 0.0 and pressed_on_stop(self.osc, self.xb)

    def scale(self) -> float:
        return max(self.a, self.b, self.vb, abs(self.xb), self.d_lim, 1e-300)

    # --- transitions and the fixed point of the friction-impact map ------------------------

    def record(self, kind: TransitionKind, st: _State, v_after: float, phi: float = 0.0):
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
        if self.detector is None:
            # states repeat to the contact integration's accuracy (FIXED_POINT_RTOL) and a
            # cycle's own size tells nothing at that tolerance; the force is ~k_c0 times a
            # length
            scale = self.scale()
            self.detector = FixedPointDetector(
                scale, rtol=FIXED_POINT_RTOL, min_cycle_size=scale,
                phi_scale=max(1.0, self.stop.k_c0),
            )
        cycle = self.detector.add(kind, st.t, st.x, st.v, self.log.total, phi)
        if cycle is not None:
            self.periodic(cycle.t_then, cycle.tag_then, st)

    def work_steps(self) -> int:
        """The steps counted against ``max_steps`` (:data:`DEFAULT_MAX_STEPS`); the map's
        contacts, far cheaper, count as one per
        :data:`core.deformable.train_map.MAP_CONTACTS_PER_STEP`."""
        return (self.steps + self.rejected + self.arcs + self.n_solved
                + self.laid_out // MAP_CONTACTS_PER_STEP)

    def elastic_limit(self) -> ElasticLimit | None:
        """What the law makes of a regular train's contacts
        (:func:`core.deformable.law.elastic_limit`); ``None`` on a still belt."""
        if self.vb <= 0.0:
            return None
        if self._limit is None:
            self._limit = elastic_limit(self.a, self.xb, self.stop)
        return self._limit

    def periodic(self, t_then: float, n_then: int, st: _State) -> None:
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


def solve_hysteretic(
    inputs: SolveInputs,
    *,
    rtol: float = 1e-9,
    atol: float = 1e-12,
    arcs: bool = True,
    reduce: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> Result:
    """Response with a hysteretic stop: exact free flight and integrated contact phases.

    :func:`simulate_hysteretic` takes the scene, horizon, start and sampling as
    :func:`core.simulate` does (:class:`~core.solve_inputs.SolveInputs`); the stop must be
    a :class:`~core.params.HystereticStop` (paper Eqs. 9-13, docs/contact-law.md).

    Parameters
    ----------
    inputs : SolveInputs
        The checked scene, horizon, start and sampling.
    rtol, atol : float
        Tolerances of the contact integration (position and velocity).
    arcs : bool
        Take the slip between two reversals of a contact semi-analytically where that is
        exact (:meth:`_Solver.arc`); ``False`` integrates every contact step by step (the
        reference of the tests and ``benchmarks/hysteretic_speed.py``).
    max_steps : int
        Work limit (``>= 1``; default :data:`DEFAULT_MAX_STEPS`, which returns within a few
        seconds whatever the horizon): contact steps, arcs, transitions solved and the
        contacts a map lays out (one per eight), counted in ``info["work_steps"]``. At the
        first transition past it the result ends there (``t[-1]``) with
        ``Status.STEP_LIMIT``.
    reduce : bool
        Advance the small motion of a mass pressed on the stop by a reduced model
        (:mod:`core.deformable.reduced`) once it is below the tolerance; ``False`` follows
        every loop and contact (the reference of the error columns of the benchmark).

    Returns
    -------
    Result
        ``contact_force`` (``phi/k``) and ``overlap`` at the samples; the transitions include
        ``contact``, ``separation``, ``reversal`` and ``reduced`` (the switch into a
        reduced model). ``stats`` holds the counts of :func:`core.result.make_stats`;
        ``info`` holds ``n_contacts``, the effective restitution (rebound over approach
        speed) of the first and the last contact (``effective_restitution_first``,
        ``effective_restitution``; :func:`effective_restitutions` lists all), ``law``, and
        when they apply ``rest_force`` (``phi/k`` at rest), ``reduced_error`` (bound of
        a reduced model's error in the state where it ends, the horizon or rest: for a
        train fitted to a loss law that runs to the horizon, twice its approach speed at
        least, the velocity's bound) and ``reduced_band`` (bound of the
        position's error while the model runs), both absolute, with ``length_scale``
        (``max(a, b, v, |x_bar|, D)``, the scale the tolerances are relative to), and
        ``rest_time_error`` (bound of the error of a rest time a reduced oscillation
        gives).

    Examples
    --------
    >>> from core import HystereticStop, Oscillator
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    >>> stop = HystereticStop(clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.02,
    ...                       beta_c=40.0, beta_e=40.0)
    >>> res = simulate_hysteretic(osc, stop, 80.0, 0.0, 0.0)
    >>> res.status.value, res.info["n_contacts"] > 0
    ('success', True)
    """
    osc, stop, t_end, x0, v0 = inputs.osc, inputs.stop, inputs.t_end, inputs.x0, inputs.v0
    if not isinstance(stop, HystereticStop):
        raise TypeError(f"stop must be a HystereticStop; got {type(stop).__name__}")
    transition_cap, n_samples, t_eval = inputs.transition_cap, inputs.n_samples, inputs.t_eval
    sv = _Solver(osc, stop, t_end, rtol, atol, transition_cap)
    sv.max_steps = check_integer("max_steps", max_steps, 1, COUNT_MAX)
    sv.use_arcs = arcs and stop.law == "paper"  # the arcs' closed forms are the paper's
    sv.use_reduced = reduce
    xb = stop.clearance
    st = _State(0.0, x0, v0, (0.0, 0.0, 0.0))
    motion = start_motion(osc, x0, v0)
    # Each pass records a transition, or moves to a contact that records one: twice the
    # limit bounds the passes should a pass record none.
    for _ in range(2 * sv.max_steps + 2):
        if st.t >= t_end or sv.steady is not None or sv.status is not Status.SUCCESS:
            break
        if st.t == 0.0 and x0 > xb:  # a start inside the stop
            inside = start_branch(x0 - xb, v0, motion.s * osc.a - x0, stop)
            phi0 = force_and_slope(x0 - xb, inside, stop)[0]
            held = v0 == osc.v and abs(x0 + phi0) <= osc.b
            if held and osc.v == 0.0:  # held for ever where it starts
                sv.rest_in_place(st, inside)
                break
            outcome = sv.run_contact(st, stick=held, inside=inside)
            if outcome != "separated":
                break
            motion = start_motion(osc, st.x, st.v)
            continue
        into_stop = st.x >= xb and (
            st.v > 0.0 or (st.v == 0.0 and motion.mode is Mode.SLIP and motion.s * osc.a > xb)
        )
        if into_stop:
            outcome = sv.run_contact(st, stick=motion.mode is Mode.STICK and st.v == osc.v)
            if outcome != "separated":
                break
            motion = start_motion(osc, st.x, st.v)
            continue
        seg, ev = free_flight(osc, st.t, st.x, st.v, motion, xb)
        if ev is None or ev.t >= t_end:
            sv.add_free(seg, t_end, st)
            st.x, st.v = seg.state_at(min(t_end, seg.t1) if ev is not None else t_end)
            st.t = t_end
            if ev is None:
                sv.endless = seg
            break
        sv.add_free(seg, ev.t, st)
        st.t, st.x, st.v = ev.t, ev.x, ev.v
        if ev.kind is TransitionKind.IMPACT:
            if motion.mode is Mode.STICK:
                st.v = osc.v
            continue
        sv.record(ev.kind, st, ev.v)
        motion = after_event(osc, ev, motion)
    else:
        sv.status = Status.STEP_LIMIT
    return _assemble(sv, osc, stop, t_end, x0, v0, n_samples, t_eval)


#: :func:`solve_hysteretic` with the inputs of :func:`core.simulate`.
simulate_hysteretic = solve_entry(solve_hysteretic)


def effective_restitutions(res: Result) -> np.ndarray:
    """Rebound speed over approach speed of each stored contact that separated.

    The measured restitution of the deformable stop (docs/contact-law.md), to compare with the
    equivalent rigid stop's ``sqrt(k_e0/k_c0)`` (paper Eq. 16).
    """
    out = []
    w_in = None
    for tr in res.transitions:
        if tr.kind is TransitionKind.CONTACT:
            w_in = tr.v
        elif tr.kind is TransitionKind.SEPARATION and w_in:
            out.append(-tr.v / w_in)
            w_in = None
    return np.array(out, dtype=float)
