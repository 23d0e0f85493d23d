"""Response with a deformable (hysteretic) stop: exact free flight, integrated contact.

Away from the stop the motion is the closed form of :mod:`core.flight` (slip circles and stick
lines, paper Eqs. 3-6). Only the contact phase ``x > clearance`` is integrated numerically
(paper Eqs. 14-15 with the law of :mod:`core.hysteresis`, Eqs. 11-13)::

    slip:  x'' + x = s*a - phi(delta)          s = sign(v - x'), delta = x - clearance
    stick: x' = v   while |x + phi(delta)| <= b

Events inside contact: separation (``delta`` back to 0), reversal of the overlap rate
(``x' = 0``: a new :class:`~core.hysteresis.Branch`), stick/slip changes (``x' = v``),
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
the branches (:func:`core.hysteresis.branch_work`, closed form), friction work is ``s*a``
times the displacement in slip and ``int (x + phi) dx`` in stick: all are functions of the
integrated states, so the balance ``mechanical - mechanical[0] = friction_work - stop_loss
- stop_stored`` checks the integration itself.
"""

from __future__ import annotations

import math
from collections import Counter, deque
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from core.dense import steady_from_transitions
from core.flight import Segment, after_event, free_flight, start_motion
from core.hysteresis import (
    EXP_CAP,
    FIRST_LOADING,
    Branch,
    BranchPrimitive,
    branch_work,
    force_and_slope,
    force_on_branches,
    reverse,
    stored_energy,
    stored_energy_many,
)
from core.hysteretic_reduced import DECAY_FIT, LIMIT, Oscillation, fit_decay
from core.params import HystereticStop, Oscillator
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
from core.trajectory import SegmentTable, evaluate

# Dormand-Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Norsett & Wanner, Table II.5.2).
_C2, _C3, _C4, _C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
_A21 = 1 / 5
_A31, _A32 = 3 / 40, 9 / 40
_A41, _A42, _A43 = 44 / 45, -56 / 15, 32 / 9
_A51, _A52, _A53, _A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
_A61, _A62, _A63, _A64, _A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
_B1, _B3, _B4, _B5, _B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
_E1, _E3, _E4, _E5, _E6, _E7 = (
    71 / 57600,
    -71 / 16695,
    71 / 1920,
    -17253 / 339200,
    22 / 525,
    -1 / 40,
)

#: Step-size controller: safety factor and bounds of the growth per step (standard values).
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 5.0
#: First step of a contact as a fraction of its period ``2 pi / sqrt(1 + k)``.
FIRST_STEP_FRACTION = 0.01
#: Steps below this fraction of the time scale mean the contact cannot be resolved.
MIN_STEP_FRACTION = 1e-14
#: The overlap is not allowed beyond ``(1 - LIMIT_MARGIN) D``: the envelopes' asymptote is
#: never crossed (the force there is ``k_c0 D / LIMIT_MARGIN``, the tangent stiffness
#: ``k_c0 / LIMIT_MARGIN^2``, far beyond any physical stop).
LIMIT_MARGIN = 1e-6
#: Two transition states closer than this (relative to the length scale) are the same point
#: of the friction-impact map. Cycles with a stick phase restart from an exact state and
#: repeat to rounding; a looser value (1e-7 was tried) took the slowly shrinking oscillation
#: on the stop of Fig. 11 (amplitude ~1e-7, change per cycle ~1e-10) and the decaying
#: contacts of Fig. 10 for periodic motions, and the energy balance of the repeated cycle
#: then drifted (2.5e-5 at t = 1000). Contact cycles without a stick phase are integrated to
#: ~1e-8 per cycle and are not taken for fixed points: the horizon is then computed.
FIXED_POINT_RTOL = 1e-10
#: Earlier transitions of the same kind compared with each new one.
FIXED_POINT_LOOKBACK = 64
#: Default limit on the number of transitions (a guard against an endless event loop);
#: past it the result ends there with ``Status.EVENT_LIMIT``.
MAX_EVENTS = 2_000_000
#: Tolerance of the equilibrium on the stop (relative to the length scale): the rest force
#: then equals ``a - x`` to ~1e-15 relative, far inside the 1e-9 promised.
EQUILIBRIUM_XTOL = 1e-16
#: Relative tolerance of brentq's roots (its smallest allowed value).
ROOT_RTOL = 4.0 * np.finfo(float).eps
#: Root tolerance of event times on the step's interpolant (relative to the step).
EVENT_XTOL = 1e-14
#: Points of the grid on which a step's interpolant is scanned for the first sign change
#: of an event function (catches two crossings in one step when they are 1/16 apart).
EVENT_GRID = 16
#: Halvings towards the step's start when it lies on the event's boundary.
EVENT_HALVINGS = 60
#: Overlap reversals of a sustained contact whose amplitude falls below this multiple of
#: ``rtol`` (times the length scale; ``atol`` at least) are the limit of rest at the stop:
#: the mass is pressed on the stop, and rest is declared at the equilibrium. The rest state
#: then differs from the motion by less than ``10 rtol``, inside the error the app states
#: for each accuracy preset (``~100 rtol``, app/solver.py).
REST_AMPLITUDE_PER_RTOL = 10.0
#: Extent of a pressed motion, as a multiple of ``rtol`` (times the length scale), below
#: which a reduced model takes over: its error in the state is at most that extent, half
#: the error the app states for each accuracy preset (``~100 rtol``, app/solver.py).
REDUCE_PER_RTOL = 50.0
#: ... and at least this fraction of the length scale, a thousandth of a pixel of a plot
#: 1000 pixels high: below it the motion is rest to the eye whatever the preset.
PAGE_RESOLUTION = 1e-6
#: Transitions inspected for the asymptotic steady state when no fixed point is found.
STEADY_TAIL = 64
#: Samples added on each branch of a contact (from its start, a reversal of the overlap
#: rate or its end to the next) besides the uniform grid: a contact lasts ~pi/sqrt(k_c0),
#: a few uniform samples at most, and a force history or hysteresis loop drawn through so
#: few is a polygon of chords that cuts above the compression envelope.
CONTACT_SAMPLES = 16
#: Branches sampled so at the start and at the end of a response (a mass that rattles on
#: the stop has thousands; the first loops are the large ones, the last the steady ones).
CONTACT_SAMPLED_BRANCHES = 16

#: Semi-analytic arcs: the G7 and K15 estimates of an arc's duration must agree to this
#: fraction of it (K15 is then good to ~1e-10 relative: its error falls like the square of
#: G7's for analytic integrands), else the arc is integrated step by step.
ARC_QUAD_RTOL = 1e-6
#: Newton iterations of an arc's end point (3-5 are typical; bisection safeguards).
ARC_NEWTON_MAX = 60
#: Newton iterations when a sample's time is mapped to the arc's angle.
ARC_SAMPLE_NEWTON = 8

_HERMITE, _LINE, _REST, _ARC, _OSC = 0, 1, 2, 3, 4

# Gauss-Kronrod 7-15 (QUADPACK): nodes on [-1, 1], Kronrod weights, Gauss weights (zero off
# the Gauss nodes, which are the odd entries).
_GK_X = (
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144838258730, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0,
    -0.207784955007898467600689403773245, -0.405845151377397166906606412076961,
    -0.586087235467691130294144838258730, -0.741531185599394439863864773280788,
    -0.864864423359769072789712788640926, -0.949107912342758524526189684047851,
    -0.991455371120812639206854697526329,
)  # fmt: skip
_GK_WK = (
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714,
    0.204432940075298892414161999234649, 0.190350578064785409913256402421014,
    0.169004726639267902826583426598550, 0.140653259715525918745189590510238,
    0.104790010322250183839876322541518, 0.063092092629978553290700663189204,
    0.022935322010529224963732008058970,
)  # fmt: skip
_GK_WG = (
    0.0, 0.129484966168869693270611432679082, 0.0, 0.279705391489276667901467771423780,
    0.0, 0.381830050505118944950369775488975, 0.0, 0.417959183673469387755102040816327,
    0.0, 0.381830050505118944950369775488975, 0.0, 0.279705391489276667901467771423780,
    0.0, 0.129484966168869693270611432679082, 0.0,
)  # fmt: skip
#: Angles of the K15 nodes on ``[0, pi]`` and ``cos(theta/2)``, ``sin(theta/2)^2`` there.
_ARC_TH = tuple(0.5 * math.pi * (1.0 + xi) for xi in _GK_X)
_ARC_COS = tuple(math.cos(0.5 * th) for th in _ARC_TH)
_ARC_SIN2 = tuple(math.sin(0.5 * th) ** 2 for th in _ARC_TH)


def _log_mean_m1(w: float) -> float:
    """``L(w) - 1`` with ``L(w) = -log(1 - w) / w`` (mean of ``1/(1 - w s)`` over ``[0, 1]``),
    by its series where the closed form cancels."""
    if abs(w) < 1e-3:
        return w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
    return -math.log1p(-w) / w - 1.0


def _exp_mean(z: float) -> float:
    """``(exp(z) - 1) / z``, the mean of ``exp(z s)`` over ``[0, 1]``."""
    return math.expm1(z) / z if z != 0.0 else 1.0


def _log_mean_m1_arr(w: np.ndarray) -> np.ndarray:
    small = np.abs(w) < 1e-3
    ws = np.where(small, 0.5, w)
    with np.errstate(divide="ignore", invalid="ignore"):
        direct = -np.log1p(-ws) / ws - 1.0
    series = w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
    return np.where(small, series, direct)


def _exp_mean_arr(z: np.ndarray) -> np.ndarray:
    zero = z == 0.0
    zs = np.where(zero, 1.0, z)
    return np.where(zero, 1.0, np.expm1(zs) / zs)


@dataclass
class _Log:
    """Transitions: the first ``cap`` stored, all counted, the latest ``STEADY_TAIL`` kept.

    The steady state is read off the latest transitions, which lie past the cap in a long
    response: reading it off the stored ones labelled the state at the cap's time.
    """

    cap: int
    stored: list[Transition] = field(default_factory=list)
    counts: Counter = field(default_factory=Counter)
    total: int = 0
    recent: deque = field(default_factory=lambda: deque(maxlen=STEADY_TAIL))

    def add(self, kind: TransitionKind, t: float, x: float, v: float, v_after: float) -> None:
        self.total += 1
        self.counts[kind.value] += 1
        tr = Transition(kind, t, x, v, v_after)
        self.recent.append(tr)
        if len(self.stored) < self.cap:
            self.stored.append(tr)


@dataclass
class _Contact:
    """Dense description of the contact phases: one row per integration step or line.

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

    def add(self, kind, t0, t1, data, friction, work0) -> None:
        self.kind.append(kind)
        self.t0.append(t0)
        self.t1.append(t1)
        self.data.append(data)
        self.branch.append(len(self.branches) - 1)
        self.friction.append(friction)
        self.work0.append(work0)


@dataclass
class _State:
    t: float
    x: float
    v: float
    work: tuple[float, float, float]  # friction work, belt input, work done on the stop


def _hermite_coeffs(x0, u0, a0, x1, u1, a1, h):
    """Coefficients of the quintic in ``theta = (t - t0)/h`` matching x, x', x'' at ends."""
    d = x1 - x0
    p0, p1, p2 = h * u0, h * u1, h * h * a0
    q2 = h * h * a1
    c3 = 10 * d - 6 * p0 - 4 * p1 - 1.5 * p2 + 0.5 * q2
    c4 = -15 * d + 8 * p0 + 7 * p1 + 1.5 * p2 - q2
    c5 = 6 * d - 3 * p0 - 3 * p1 - 0.5 * p2 + 0.5 * q2
    return (x0, p0, 0.5 * p2, c3, c4, c5)


def _first_exit(g) -> float:
    """First ``theta`` in ``(0, 1]`` where ``g`` (positive inside the mode, negative at 1)
    changes sign. The step may start on the boundary (``g(0) = 0``, e.g. at the face when a
    contact begins), so the start is never taken as the event: the bracket's left end is
    the last point found inside on a grid of ``EVENT_GRID`` points, refined towards 0."""
    prev = 0.0
    for k in range(1, EVENT_GRID + 1):
        th = k / EVENT_GRID
        if g(th) <= 0.0:
            break
        prev = th
    lo = prev
    if lo == 0.0 and not g(0.0) > 0.0:
        lo = th
        for _ in range(EVENT_HALVINGS):
            lo *= 0.5
            if g(lo) > 0.0:
                break
        else:
            return th  # the mode is left at once
    if lo >= th:
        return th
    return brentq(g, lo, th, xtol=EVENT_XTOL)


def _poly(c, th):
    return c[0] + th * (c[1] + th * (c[2] + th * (c[3] + th * (c[4] + th * c[5]))))


def _dpoly(c, th):
    return c[1] + th * (2 * c[2] + th * (3 * c[3] + th * (4 * c[4] + th * 5 * c[5])))


class _Solver:
    """One solve: the event loop over free flight and contact phases."""

    def __init__(self, osc, stop, t_end, rtol, atol, cap):
        self.osc, self.stop, self.t_end = osc, stop, t_end
        self.rtol, self.atol = rtol, atol
        self.a, self.b, self.vb = osc.a, osc.b, osc.v
        self.xb, self.d_lim = stop.clearance, stop.limit_overlap
        self.d_max = (1.0 - LIMIT_MARGIN) * stop.limit_overlap
        self.table = SegmentTable()
        self.contact = _Contact()
        self.timeline: list[tuple[float, int, int]] = []  # (t0, 0 free / 1 contact, row)
        self.log = _Log(cap)
        self.status = Status.SUCCESS
        self.rhs_evals = 0
        self.steps = 0
        self.rejected = 0
        self.arc_evals = 0
        self.arcs = 0
        self.use_arcs = True
        self.use_reduced = True
        self.max_events = MAX_EVENTS
        self.restitution: list[float] = []
        self.x_max = -math.inf
        self.t_stop = t_end  # end of the computed motion (earlier on failure)
        self.n_contacts = 0
        self.steady: Steady | None = None
        self.tail: tuple[float, float, float, tuple[float, float, float]] | None = None
        self.history: dict[str, list[tuple[float, float, float, float, int]]] = {}
        self.reduced_error = 0.0  # bound of the reduced models' error in the state
        self.train: list[tuple[float, float, float, int]] = []  # contacts: t, w, peak, n
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
        law of :func:`core.hysteresis.force_and_slope` with the branch constants bound)."""
        stop = self.stop
        if stop.law == "passive":
            xb_, sa_ = self.xb, s * self.a

            def acc_passive(x: float) -> float:
                return sa_ - x - force_and_slope(x - xb_, branch, stop)[0]

            return acc_passive
        xb, d_lim, sa = self.xb, self.d_lim, s * self.a
        kc, ke = stop.k_c0 * d_lim, stop.k_e0 * d_lim
        r = branch.delta_r
        exp, cap = math.exp, EXP_CAP
        if branch.loading:
            c = kc * r / (d_lim - r) - branch.phi_r
            rate = stop.beta_c / d_lim

            def acc(x: float) -> float:
                d = x - xb
                if d <= 0.0:
                    return sa - x
                hyper = d / (d_lim - d)
                lower = ke * hyper
                phi = kc * hyper - c * exp(min(rate * (r - d), cap))
                return sa - x - (phi if phi > lower else lower)

        else:
            c = branch.phi_r - ke * r / (d_lim - r)
            rate = stop.beta_e / d_lim

            def acc(x: float) -> float:
                d = x - xb
                if d <= 0.0:
                    return sa - x
                hyper = d / (d_lim - d)
                upper = kc * hyper
                phi = ke * hyper + c * exp(min(rate * (d - r), cap))
                return sa - x - (phi if phi < upper else upper)

        return acc

    def branch_constants(self, branch: Branch) -> tuple[float, float, float]:
        """``(K, C, lam)`` of the unclipped curve ``phi = K d/(D - d) + C exp(lam (d - d_r))``."""
        stop, d_lim = self.stop, self.d_lim
        r = branch.delta_r
        if branch.loading:
            kc = stop.k_c0 * d_lim
            return kc, branch.phi_r - kc * r / (d_lim - r), -stop.beta_c / d_lim
        ke = stop.k_e0 * d_lim
        return ke, branch.phi_r - ke * r / (d_lim - r), stop.beta_e / d_lim

    def arc(self, st: _State, s: int, branch: Branch):
        """Semi-analytic slip from a reversal to the next one, or ``None`` (integrate it).

        In slip with a fixed friction sign and on one branch the motion conserves
        ``u^2/2 + V(x)``, ``V(x) = x^2/2 - s a x + int phi``, and ``V`` is convex (``phi`` grows
        with the overlap on every branch). From a reversal ``x_r`` (``u = 0``) the next one is
        the other root of ``V(x) = V(x_r)``: with ``d = x - x_r`` the root of the mean net
        force ``Q(d) = (V(x_r + d) - V(x_r)) / d``, written without cancellation (``log1p``,
        ``expm1`` and series; the force is ``~1e-3`` of its terms in a sustained contact).
        The duration is ``int dx / |u|`` with ``x = x_r + d sin^2(theta/2)``, which removes
        both ``1/sqrt`` end points: ``dt/dtheta = |d| cos(theta/2) / sqrt(-2 d Q)`` is smooth,
        and Gauss-Kronrod 7-15 gives it with an error estimate.

        Taken only when it is exactly the motion: the branch stays on its transition curve
        (no clip to an envelope), no separation, no limit overlap or failure, no
        stick/slip change (the speed bound ``u^2 <= 2 |Q(0)| |d|`` from convexity stays on
        one side of the belt speed), the arc ends before ``t_end``, and the quadrature's
        estimate is within ``ARC_QUAD_RTOL``. Returns the force at the new reversal.
        """
        d_lim, xb = self.d_lim, self.xb
        x_r, dr = st.x, st.x - xb
        if dr <= 0.0 or dr >= self.d_max:
            return None
        up = branch.loading
        kk, cc, lam = self.branch_constants(branch)
        stop = self.stop
        gap = d_lim - dr
        hyper_r = dr / gap
        if up:  # c = phi_C(d_r) - phi_r in [0, phi_C - phi_E]: never clipped going up
            if not (-(stop.k_c0 - stop.k_e0) * d_lim * hyper_r <= cc <= 0.0):
                return None
        elif cc < 0.0:
            return None
        sa = s * self.a
        lim_mean = kk * hyper_r
        kg = kk * d_lim / gap
        log_m1, exp_mean, exp = _log_mean_m1, _exp_mean, math.exp

        def q(d: float) -> float:
            return (x_r - sa + lim_mean) + 0.5 * d + kg * log_m1(d / gap) + cc * exp_mean(lam * d)

        q0 = x_r - sa + lim_mean + cc
        if (q0 >= 0.0) if up else (q0 <= 0.0):
            return None
        slope0 = 1.0 + kg / gap + cc * lam
        if slope0 <= 0.0:
            return None
        # Newton on the increasing Q, safeguarded by the bracket [neg, pos].
        if up:
            neg, pos = 0.0, self.d_max - dr
        else:
            neg, pos = -dr, 0.0
        d = -2.0 * q0 / slope0
        if not min(neg, pos) < d < max(neg, pos):
            d = 0.5 * (neg + pos)
        n_evals = 0
        for _ in range(ARC_NEWTON_MAX):
            qd = q(d)
            de = dr + d
            vp = x_r + d - sa + kk * de / (d_lim - de) + cc * exp(lam * d)
            n_evals += 2
            if qd < 0.0:
                neg = d
            else:
                pos = d
            dq = (vp - qd) / d
            d_new = d - qd / dq if dq > 0.0 else 0.5 * (neg + pos)
            if not min(neg, pos) < d_new < max(neg, pos):
                d_new = 0.5 * (neg + pos)
            if abs(d_new - d) <= 1e-9 * abs(d):  # quadratic convergence: d_new to ~1e-18
                d = d_new
                break
            d = d_new
        else:
            return None
        d_n = dr + d
        if not (0.0 < d_n < self.d_max) or abs(q(d)) > 1e-9 * abs(q0):
            return None  # separation, the limit overlap, or no clean root: integrate
        phi_n = kk * d_n / (d_lim - d_n) + cc * exp(lam * d)
        if phi_n > stop.strength:
            return None
        if not up and stop.k_c0 > stop.k_e0 and cc > 0.0:
            # Unloading: clipped to phi_C where (k_c0 - k_e0) D d/(D-d) < C exp(lam (d - d_r)).
            # The log of the left side over the right has its minima at the ends or at d_+.
            kr = (stop.k_c0 - stop.k_e0) * d_lim
            checks = [d_n]
            beta = stop.beta_e
            if beta > 4.0:
                d_plus = 0.5 * d_lim * (1.0 + math.sqrt(1.0 - 4.0 / beta))
                if d_n < d_plus < dr:
                    checks.append(d_plus)
            for p in checks:
                if kr * p / (d_lim - p) < cc * exp(lam * (p - dr)):
                    return None
        u2_max = 2.0 * abs(q0) * abs(d)
        vb = self.vb
        if up:
            ok = (s > 0 and vb * abs(vb) > u2_max) or (s < 0 and vb <= 0.0)
        else:
            ok = (s > 0 and vb >= 0.0) or (s < 0 and vb < 0.0 and vb * vb > u2_max)
        if not ok:
            return None
        # Duration: K15 and G7 over theta in [0, pi].
        t_k = t_g = 0.0
        ad = abs(d)
        for c2, s2, wk, wg in zip(_ARC_COS, _ARC_SIN2, _GK_WK, _GK_WG, strict=True):
            den = -2.0 * d * q(d * s2)
            if not den > 0.0:
                return None
            g = ad * c2 / math.sqrt(den)
            t_k += wk * g
            t_g += wg * g
        n_evals += 15
        self.arc_evals += n_evals
        t_k *= 0.5 * math.pi
        t_g *= 0.5 * math.pi
        if not abs(t_k - t_g) <= ARC_QUAD_RTOL * t_k:
            return None
        t1 = st.t + t_k
        if t1 >= self.t_end:
            return None
        mean_phi = lim_mean + kg * log_m1(d / gap) + cc * exp_mean(lam * d)
        if not self.contact.kind or self.timeline[-1][1] != 1:
            self.timeline.append((st.t, 1, len(self.contact.kind)))
        self.contact.add(_ARC, st.t, t1, (x_r, d, t_k, kk, cc, lam, dr), sa, st.work)
        wf, wb, ws = st.work
        st.work = (wf + sa * d, wb + sa * vb * t_k, ws + d * mean_phi)
        st.t, st.x, st.v = t1, x_r + d, 0.0
        self.x_max = max(self.x_max, st.x)
        self.arcs += 1
        return phi_n

    def new_branch(self, branch: Branch, delta: float, w_stop: float) -> None:
        self.contact.branches.append(branch)
        self.contact.branch_start.append((delta, w_stop))

    def close_branch(self, branch: Branch, d0: float, d1: float, st: _State) -> None:
        wf, wb, ws = st.work
        st.work = (wf, wb, ws + branch_work(d0, d1, branch, self.stop))

    def run_contact(self, st: _State, stick: bool) -> str:
        """Integrate one contact from ``st`` (at the face, moving in) until it ends.

        Returns ``"separated"``, ``"rest"``, ``"failed"``, ``"limit"``, ``"periodic"`` or
        ``"horizon"``.
        """
        stop, xb = self.stop, self.xb
        self.n_contacts += 1
        w_in = st.v
        self.record(TransitionKind.CONTACT, st, st.v)
        if self.steady is not None:
            return "periodic"
        self.train.append((st.t, st.v, math.nan, self.log.total))
        if self.reduce_train(st, self.train) is not None:
            return "periodic"
        branch = FIRST_LOADING
        self.new_branch(branch, 0.0, st.work[2])
        d_branch0 = 0.0
        s = 1 if st.v < self.vb else -1
        reversal_x: list[tuple[float, float, int]] = []  # (t, x, transitions) of reversals
        while True:
            if stick:
                outcome = self.stick_in_contact(st, branch)
                if outcome != "slip":
                    self.close_branch(branch, d_branch0, st.x - xb, st)
                    return outcome
                stick, s = False, 1
                continue
            if self.use_arcs and st.v == 0.0 and branch.delta_r == st.x - xb:
                phi = self.arc(st, s, branch)
                if phi is not None:
                    branch, ended = self.reversal(st, branch, phi, reversal_x, s)
                    d_branch0 = st.x - xb
                    if ended:
                        return ended
                    if self.status is not Status.SUCCESS:
                        return "failed"
                    continue
            outcome, s_new = self.slip_in_contact(st, s, branch)
            delta = st.x - xb
            if outcome == "separated":
                self.close_branch(branch, d_branch0, 0.0, st)
                st.x = xb
                self.restitution.append(-st.v / w_in if w_in > 0 else math.nan)
                self.record(TransitionKind.SEPARATION, st, st.v)
                return "separated"
            if outcome == "reversal":
                phi, _ = force_and_slope(delta, branch, stop)
                self.close_branch(branch, d_branch0, delta, st)
                branch, ended = self.reversal(st, branch, phi, reversal_x, s)
                d_branch0 = delta
                if ended:
                    return ended
                if self.status is not Status.SUCCESS:
                    return "failed"
                continue
            if outcome == "friction":
                phi, _ = force_and_slope(delta, branch, stop)
                if abs(st.x + phi) <= self.b and self.vb > 0.0:
                    st.v = self.vb
                    self.record(TransitionKind.SLIP_STICK, st, st.v)
                    stick = True
                    if not branch.loading:  # x' = v > 0: the overlap grows again
                        self.close_branch(branch, d_branch0, delta, st)
                        branch = reverse(delta, phi, branch)
                        d_branch0 = delta
                        self.new_branch(branch, delta, st.work[2])
                else:
                    self.record(TransitionKind.SIGN_CHANGE, st, st.v)
                    s = s_new
                continue
            if outcome in ("failed", "limit", "horizon"):
                self.close_branch(branch, d_branch0, delta, st)
                return outcome

    def slip_in_contact(self, st: _State, s: int, branch: Branch) -> tuple[str, int]:
        """Dormand-Prince 5(4) steps until an event; ``st`` is left at the event."""
        stop, xb, vb = self.stop, self.xb, self.vb
        rtol, atol = self.rtol, self.atol
        x, u, t = st.x, st.v, st.t
        acc = self.accel(s, branch)
        a0 = acc(x)
        n_evals = 1
        _, slope = force_and_slope(max(x - xb, 0.0), branch, stop)
        omega = math.sqrt(1.0 + max(slope, 0.0))
        h = FIRST_STEP_FRACTION * 2.0 * math.pi / omega
        h_min = MIN_STEP_FRACTION * 2.0 * math.pi / omega
        strength = stop.strength
        while True:
            h = min(h, self.t_end - t)
            if h <= 0.0:
                self.rhs_evals += n_evals
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
            if not (math.isfinite(x1) and math.isfinite(u1)) or x1 - xb >= stop.limit_overlap:
                err = math.inf
                a1 = math.nan
            else:
                a1 = acc(x1)
                k7x, k7u = u1, a1
                ex = h * (_E1 * k1x + _E3 * k3x + _E4 * k4x + _E5 * k5x + _E6 * k6x + _E7 * k7x)
                eu = h * (_E1 * k1u + _E3 * k3u + _E4 * k4u + _E5 * k5u + _E6 * k6u + _E7 * k7u)
                sx = atol + rtol * max(abs(x), abs(x1))
                su = atol + rtol * max(abs(u), abs(u1))
                err = math.sqrt(0.5 * ((ex / sx) ** 2 + (eu / su) ** 2))
            if err > 1.0:
                self.rejected += 1
                h *= max(MIN_FACTOR, SAFETY * err**-0.2) if math.isfinite(err) else MIN_FACTOR
                if h < h_min:
                    self.rhs_evals += n_evals
                    self.status = Status.INTEGRATION_FAILED
                    st.t, st.x, st.v = t, x, u
                    return "failed", s
                continue
            coeffs = _hermite_coeffs(x, u, a0, x1, u1, a1, h)
            # Events: which condition is violated at the step's end, then its first root.
            # Each g is positive inside the current mode.
            found: list[tuple[float, str]] = []
            if x1 < xb:
                found.append(
                    (_first_exit(lambda th, c=coeffs, hh=h: _poly(c, th) - xb), "separated")
                )
            if (u1 < 0.0) if branch.loading else (u1 > 0.0):
                sign = 1.0 if branch.loading else -1.0
                found.append(
                    (
                        _first_exit(lambda th, c=coeffs, hh=h, sign=sign: sign * _dpoly(c, th)),
                        "reversal",
                    )
                )
            if (u1 > vb) if s > 0 else (u1 < vb):
                found.append(
                    (
                        _first_exit(lambda th, c=coeffs, hh=h: s * (vb - _dpoly(c, th) / hh)),
                        "friction",
                    )
                )
            if x1 - xb > self.d_max:
                found.append(
                    (
                        _first_exit(lambda th, c=coeffs, hh=h: xb + self.d_max - _poly(c, th)),
                        "limit",
                    )
                )
            if math.isfinite(strength) and force_and_slope(x1 - xb, branch, stop)[0] > strength:
                found.append(
                    (
                        _first_exit(
                            lambda th, c=coeffs, hh=h: (
                                strength - force_and_slope(_poly(c, th) - xb, branch, stop)[0]
                            )
                        ),
                        "failed",
                    )
                )
            if found:
                self.rhs_evals += n_evals
                th, name = min(found)
                t_ev = t + th * h
                x_ev = _poly(coeffs, th)
                u_ev = _dpoly(coeffs, th) / h
                if name == "reversal":
                    u_ev = 0.0
                elif name == "friction":
                    u_ev = vb
                elif name == "separated":
                    x_ev = xb
                self.add_step(t, t_ev, coeffs, h, s, st)
                self.steps += 1
                st.t, st.x, st.v = t_ev, x_ev, u_ev
                self.x_max = max(self.x_max, x_ev)
                if name == "failed":
                    self.status = Status.STOP_FAILED
                    self.record(TransitionKind.FAILURE, st, st.v)
                elif name == "limit":
                    self.status = Status.LIMIT_OVERLAP
                return name, -s
            self.add_step(t, t + h, coeffs, h, s, st)
            self.steps += 1
            t, x, u, a0 = t + h, x1, u1, a1
            st.t, st.x, st.v = t, x, u
            self.x_max = max(self.x_max, x)
            h *= min(MAX_FACTOR, SAFETY * err**-0.2) if err > 0.0 else MAX_FACTOR

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
        branch = reverse(delta, phi, branch)
        self.new_branch(branch, delta, st.work[2])
        self.record(TransitionKind.REVERSAL, st, 0.0, phi=phi)
        if self.steady is not None:
            return branch, "periodic"
        reversal_x.append((st.t, st.x, self.log.total))
        if len(reversal_x) == 1 and self.train and math.isnan(self.train[-1][2]):
            self.train[-1] = (*self.train[-1][:2], st.x, self.train[-1][3])
        if self.settled(reversal_x):
            return branch, self.rest_at_stop(st, branch, s, self.creep_end(reversal_x, s))
        return branch, self.reduce_oscillation(st, branch, reversal_x, s)

    def creep_end(self, reversal_x, s: int) -> float | None:
        """Where the centre of a settled pressed oscillation ends once its last amplitude
        is gone: the centre creeps ``kappa`` times the amplitude lost
        (:mod:`core.hysteretic_reduced`); ``None`` if it cannot be measured (then rest is
        at the equilibrium on the current branch)."""
        if not (self.pressed() and s > 0) or len(reversal_x) < 2 * DECAY_FIT + 1:
            return None
        xa = np.array([x for _, x, _ in reversal_x[-(2 * DECAY_FIT + 1):]])
        swings = np.abs(np.diff(xa))
        amps = 0.25 * (swings[0::2] + swings[1::2])
        if not np.all(np.diff(amps) < 0.0):
            return None
        centres = 0.25 * (xa[0:-2:2] + 2.0 * xa[1:-1:2] + xa[2::2])
        kappa = float((centres[-1] - centres[0]) / (amps[0] - amps[-1]))
        return 0.5 * (xa[-1] + xa[-2]) + kappa * 0.5 * float(swings[-1])

    def settled(self, reversal_x: list[tuple[float, float]]) -> bool:
        if len(reversal_x) < 4:
            return False
        last = [x for _, x, _ in reversal_x[-4:]]
        return max(last) - min(last) <= self.rest_amplitude()

    def reduce_oscillation(self, st: _State, branch: Branch, reversal_x, s: int):
        """Hand a small pressed oscillation to a reduced model (:mod:`core.hysteretic_reduced`),
        or return ``None`` while it is too large or its decay not yet regular.

        One cycle is two reversals; its amplitude is a quarter of its two swings. Loops that
        tend to a limit amplitude (they turn elastic) are a fixed point of the loop map once
        the amplitude is within the tolerance of its limit: the last cycle is then repeated.
        Loops that die out follow the fitted decay until the rest amplitude.
        """
        if not (self.use_reduced and self.pressed() and s > 0) or len(
            reversal_x
        ) < 2 * DECAY_FIT + 1:
            return None
        ts, xs, ns = zip(*reversal_x[-(2 * DECAY_FIT + 1):], strict=True)
        swings = np.abs(np.diff(xs))
        amps = 0.25 * (swings[0::2] + swings[1::2])
        decay = fit_decay(amps)
        if decay is None:
            return None
        period = ts[-1] - ts[-3]
        tol = self.reduce_extent()
        if decay.law == LIMIT and decay.limit > 0.5 * self.rest_amplitude():
            if amps[-1] - decay.limit > tol:
                return None
            self.periodic(ts[-3], ns[-3], st)
            self.record(TransitionKind.REDUCED, st, 0.0)
            self.reduced_error = max(self.reduced_error, 2.0 * (amps[-1] - decay.limit))
            return "periodic"
        if 2.0 * amps[-1] > tol or 2.0 * math.pi / period * amps[-1] >= self.vb:
            return None
        x_c = 0.5 * (xs[-1] + xs[-2])
        xa = np.asarray(xs)
        centres = 0.25 * (xa[0:-2:2] + 2.0 * xa[1:-1:2] + xa[2::2])
        kappa = float((centres[-1] - centres[0]) / (amps[0] - amps[-1]))
        model = Oscillation(x_c, 0.5 * swings[-1], period, 0.0 if st.x >= x_c else math.pi,
                            decay, kappa)
        if model.error_bound > tol:
            return None
        return self.oscillate(st, branch, s, model)

    def rest_amplitude(self) -> float:
        """Amplitude of the overlap oscillation below which the mass rests on the stop."""
        return REST_AMPLITUDE_PER_RTOL * max(self.rtol * self.scale(), self.atol)

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

    def reduce_extent(self) -> float:
        """Extent of a pressed motion (and drift from a limit cycle) below which a reduced
        model takes over: :data:`REDUCE_PER_RTOL` ``rtol``, at least :data:`PAGE_RESOLUTION`
        (times the length scale)."""
        return max(REDUCE_PER_RTOL * self.rtol, PAGE_RESOLUTION) * self.scale()

    def reduce_train(self, st: _State, train: list) -> str | None:
        """A train of contacts of a pressed mass whose amplitude tends to a limit (contacts
        that turn elastic): once the amplitude is within the tolerance of its limit, the
        contact-to-contact map is at its fixed point and the last cycle is repeated.

        ``train`` holds ``(t, approach speed, peak x, transitions so far)`` of this
        response's contacts; a cycle's amplitude is half the distance from the top of the
        flight before the contact, ``a - sqrt((a - x_bar)^2 + w^2)``, to the contact's peak.
        """
        if not (self.use_reduced and self.pressed()) or len(train) < DECAY_FIT + 2:
            return None
        done = train[-(DECAY_FIT + 1):-1]
        if any(math.isnan(peak) for _, _, peak, _ in done):
            return None
        gap = self.a - self.xb
        amps = [0.5 * (peak - (self.a - math.hypot(gap, w))) for _, w, peak, _ in done]
        decay = fit_decay(amps)
        if decay is None or decay.law != LIMIT or amps[-1] - decay.limit > self.reduce_extent():
            return None
        t_then, _, _, n_then = train[-2]
        self.periodic(t_then, n_then, st)
        if self.steady is None:
            return None
        self.record(TransitionKind.REDUCED, st, st.v)
        self.reduced_error = max(self.reduced_error, 2.0 * (amps[-1] - decay.limit))
        return "periodic"

    def oscillate(self, st: _State, branch: Branch, s: int, model: Oscillation) -> str:
        """Advance a small pressed oscillation by its reduced model until its amplitude is
        below the rest amplitude, then rest at the equilibrium.

        Energy: friction and belt work follow the model's motion; the stop takes the rest
        of the balance, and its loss grows by the oscillator's energy ``omega^2 A^2 / 2``
        as the amplitude decays, so ``stop_loss`` never falls.
        """
        self.record(TransitionKind.REDUCED, st, st.v)
        cycles = model.decay.cycles_to(model.amp0, 0.5 * self.rest_amplitude())
        tau_rest = math.ceil(2.0 * max(cycles, 0.5)) * 0.5 * model.period  # at a reversal
        t1 = min(st.t + tau_rest, self.t_end)
        x_s, m_s = st.x, 0.5 * (st.x * st.x + st.v * st.v)
        loss_s = st.work[2] - stored_energy(st.x - self.xb, branch.phi_r, self.stop)
        if not self.contact.kind or self.timeline[-1][1] != 1:
            self.timeline.append((st.t, 1, len(self.contact.kind)))
        sa = s * self.a
        self.contact.add(_OSC, st.t, t1, (model, x_s, m_s, loss_s), sa, st.work)
        x1, v1, _ = (float(q) for q in model.state(t1 - st.t))
        wf, wb, ws = st.work
        dwf = sa * (x1 - x_s)
        dm = 0.5 * (x1 * x1 + v1 * v1) - m_s
        st.work = (wf + dwf, wb + sa * self.vb * (t1 - st.t), ws + dwf - dm)
        st.t, st.x, st.v = t1, x1, v1
        self.reduced_error = max(self.reduced_error, model.error_bound)
        if t1 >= self.t_end:
            return "horizon"
        return self.rest_at_stop(st, branch, s, x_rest=model.centre(0.0))

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
        x_eq = self.equilibrium(branch, s) if x_rest is None else x_rest
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

    def pressed(self) -> bool:
        """The belt presses the mass on the stop: the slip equilibrium ``x = a`` lies
        beyond the stop's face (``x_bar < a``, belt moving towards the stop)."""
        return self.vb > 0.0 and self.xb < self.a

    def scale(self) -> float:
        return max(self.a, self.b, self.vb, abs(self.xb), self.d_lim, 1e-300)

    # --- transitions and the fixed point of the friction-impact map ------------------------

    def record(self, kind: TransitionKind, st: _State, v_after: float, phi: float = 0.0):
        self.log.add(kind, st.t, st.x, st.v, v_after)
        if self.log.total >= self.max_events and self.status is Status.SUCCESS:
            self.status = Status.EVENT_LIMIT
        # Reversals inside a sustained contact are not compared: a cycle made only of them
        # is integrated to ~1e-8 and never passes the fixed-point test, and comparing each
        # of the thousands of reversals of a long contact costs a third of the solve. A
        # cycle that does repeat still contains a contact, separation or stick transition.
        if kind in (TransitionKind.FAILURE, TransitionKind.REST, TransitionKind.REVERSAL,
                    TransitionKind.REDUCED):
            return
        tol = FIXED_POINT_RTOL * self.scale()
        seen = self.history.setdefault(kind.value, [])
        for t_then, x_then, v_then, phi_then, n_then in reversed(seen[-FIXED_POINT_LOOKBACK:]):
            if (
                abs(x_then - st.x) <= tol
                and abs(v_then - st.v) <= tol
                and abs(phi_then - phi) <= tol * max(1.0, self.stop.k_c0)
            ):
                self.periodic(t_then, n_then, st)
                break
        seen.append((st.t, st.x, st.v, phi, self.log.total))

    def periodic(self, t_then: float, n_then: int, st: _State) -> None:
        period = st.t - t_then
        if period <= 0.0:
            return
        cycle = [tr for tr in self.log.recent if t_then < tr.t <= st.t]
        impact = [tr.v for tr in cycle if tr.kind is TransitionKind.CONTACT]
        self.steady = Steady(
            SteadyKind.PERIODIC,
            period=period,
            transitions_per_period=self.log.total - n_then,
            sequence=tuple(tr.kind.value for tr in cycle),
            impact_speed=max(impact) if impact else math.nan,
            t_reached=t_then,
        )
        self.tail_start = (t_then, st.t)


def simulate_hysteretic(
    osc: Oscillator,
    stop: HystereticStop,
    t_end: float,
    x0: float,
    v0: float,
    *,
    n_samples: int = 2000,
    transition_cap: int = 10_000,
    rtol: float = 1e-9,
    atol: float = 1e-12,
    arcs: bool = True,
    reduce: bool = True,
    t_eval=None,
    max_events: int = MAX_EVENTS,
) -> Result:
    """Response with a hysteretic stop: exact free flight and integrated contact phases.

    Parameters
    ----------
    osc : Oscillator
    stop : HystereticStop
        The deformable stop (paper Eqs. 9-13, docs/contact-law.md).
    t_end : float
        Horizon (dimensionless time), ``> 0``.
    x0, v0 : float
        Initial state, ``x0 <= stop.clearance`` (inputs are checked by :func:`core.simulate`).
    n_samples : int
        Uniform samples in ``[0, t_end]``; the transition points are added.
    transition_cap : int
        Transitions stored at most; all are counted.
    rtol, atol : float
        Tolerances of the contact integration (position and velocity).
    arcs : bool
        Take the slip between two reversals of a contact semi-analytically where that is
        exact (:meth:`_Solver.arc`); ``False`` integrates every contact step by step (the
        reference of the tests and ``benchmarks/hysteretic_speed.py``).
    t_eval : array_like, optional
        Sample times (1-D, increasing, in ``[0, t_end]``) instead of ``n_samples`` uniform
        ones and the transition points.
    max_events : int
        Limit on the number of transitions; past it the result ends there with
        ``Status.EVENT_LIMIT``.
    reduce : bool
        Advance the small motion of a mass pressed on the stop by a reduced model
        (:mod:`core.hysteretic_reduced`) once it is below the tolerance; ``False`` follows
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
        when they apply ``rest_force`` (``phi/k`` at rest) and ``reduced_error`` (bound of
        a reduced model's error in the position).

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
    if t_eval is not None:
        t_eval = np.asarray(t_eval, dtype=float)
        if t_eval.ndim != 1 or np.any(t_eval < 0.0) or np.any(t_eval > t_end) or np.any(
            np.diff(t_eval) < 0.0
        ):
            raise ValueError("t_eval must be a 1-D increasing array of times in [0, t_end]")
    sv = _Solver(osc, stop, t_end, rtol, atol, transition_cap)
    sv.max_events = max_events
    sv.use_arcs = arcs and stop.law == "paper"  # the arcs' closed forms are the paper's
    sv.use_reduced = reduce
    xb = stop.clearance
    st = _State(0.0, x0, v0, (0.0, 0.0, 0.0))
    motion = start_motion(osc, x0, v0)
    for _ in range(max_events):
        if st.t >= t_end or sv.steady is not None or sv.status is not Status.SUCCESS:
            break
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
        sv.status = Status.EVENT_LIMIT
    return _assemble(sv, osc, stop, t_end, x0, v0, n_samples, t_eval)


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


def _continued(sv: _Solver, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times mapped into the detected cycle (periodic continuation) and the work the
    repeated cycles add; the identity and zeros without a cycle."""
    shift_work = np.zeros((len(times), 3))
    t_eval = np.array(times, dtype=float)
    if sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        t_then, t_now = sv.tail_start
        period = t_now - t_then
        late = t_eval > t_now
        k = np.floor((t_eval[late] - t_then) / period)
        t_eval[late] = t_eval[late] - k * period
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

    def __init__(self, sv: _Solver, t_stop: float) -> None:
        self._sv, self._t_stop = sv, t_stop

    def evaluate(self, t, side: int = -1) -> tuple[np.ndarray, np.ndarray]:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if np.any(t < 0.0) or np.any(t > self._t_stop):
            raise ValueError(f"t must lie in [0, {self._t_stop:g}] (the computed motion)")
        t_eval, _ = _continued(self._sv, t)
        x, xd, *_ = _evaluate(self._sv, t_eval, self._sv.stop)
        return x, xd


def _assemble(sv: _Solver, osc, stop, t_end, x0, v0, n_samples, t_eval=None) -> Result:
    """Samples on the free segments and the contact rows, energy terms, steady state."""
    t_stop = t_end if sv.status is Status.SUCCESS else min(t_end, _last_time(sv))
    if t_eval is None:
        marks = [tr.t for tr in sv.log.stored if tr.t <= t_stop]
        times = np.unique(np.concatenate((np.linspace(0.0, t_end, n_samples), marks,
                                          _contact_samples(sv, t_stop, t_end))))
    else:
        times = np.asarray(t_eval, dtype=float)
    times = times[times <= t_stop]
    if sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        t_then, t_now = sv.tail_start
        _replicate(sv, t_then, t_now, t_now - t_then, t_end)
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
    restitution = sv.restitution
    stats = make_stats(
        segments=len(sv.table) + len(sv.contact.kind),
        steps=sv.steps,
        rejected=sv.rejected,
        rhs_evals=sv.rhs_evals + sv.arc_evals,
        events=sv.log.total,
    )
    info = {
        "n_contacts": sv.n_contacts,
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
        info["reduced_error"] = sv.reduced_error
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


def _last_time(sv: _Solver) -> float:
    ends = [sv.contact.t1[-1]] if sv.contact.t1 else []
    if sv.table.t1:
        ends.append(sv.table.t1[-1])
    return max(ends) if ends else 0.0


def _contact_samples(sv: _Solver, t_stop: float, t_end: float) -> np.ndarray:
    """:data:`CONTACT_SAMPLES` times on each branch of the first and the last
    :data:`CONTACT_SAMPLED_BRANCHES` contact branches, a detected cycle's continuation
    included."""
    kinds = (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION)
    marks = [(tr.t, tr.kind) for tr in sv.log.stored if tr.kind in kinds and tr.t <= t_stop]
    marks.append((t_stop, TransitionKind.SEPARATION))
    spans = [(t0, t1) for (t0, k0), (t1, _) in zip(marks[:-1], marks[1:], strict=True)
             if k0 is not TransitionKind.SEPARATION and t1 > t0]
    if spans and sv.steady is not None and sv.steady.kind is SteadyKind.PERIODIC:
        t_then, t_now = sv.tail_start
        period = t_now - t_then
        cycle = [(a, b) for a, b in spans if a >= t_then and b <= t_now + 1e-12 * period]
        repeats = int(max(0.0, t_end - t_now) // period) + 1 if cycle and period > 0 else 0
        # Only the last repeats can be among the sampled branches: a cycle of a train of
        # micro-contacts may repeat a million times.
        first = max(1, repeats - CONTACT_SAMPLED_BRANCHES)
        spans += [(a + k * period, b + k * period)
                  for k in range(first, repeats + 1) for a, b in cycle if a + k * period < t_end]
    if len(spans) > 2 * CONTACT_SAMPLED_BRANCHES:
        spans = spans[:CONTACT_SAMPLED_BRANCHES] + spans[-CONTACT_SAMPLED_BRANCHES:]
    if not spans:
        return np.zeros(0)
    a, b = np.array(spans).T
    frac = np.arange(1, CONTACT_SAMPLES + 1) / (CONTACT_SAMPLES + 1)
    return (a[:, None] + (b - a)[:, None] * frac[None, :]).ravel()


def _replicate(sv: _Solver, t_then: float, t_now: float, period: float, t_end: float) -> None:
    """Transitions after the detected cycle: shifted copies, stored up to the cap."""
    cycle = [tr for tr in sv.log.stored
             if t_then < tr.t <= t_now and tr.kind is not TransitionKind.REDUCED]
    if not cycle:
        return
    k = 1
    while True:
        if cycle[0].t + k * period > t_end:
            return
        if len(sv.log.stored) >= sv.log.cap:
            remaining = t_end - (cycle[0].t + k * period)
            full = int(remaining // period) + 1
            for tr in cycle:
                n = (
                    full
                    if tr.t - cycle[0].t + (full - 1) * period + cycle[0].t + k * period <= t_end
                    else full - 1
                )
                sv.log.total += n
                sv.log.counts[tr.kind.value] += n
            return
        for tr in cycle:
            ts = tr.t + k * period
            if ts > t_end:
                return
            sv.log.add(tr.kind, ts, tr.x, tr.v, tr.v_after)
        k += 1


def _locate(sv: _Solver, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    starts = np.array([e[0] for e in sv.timeline])
    src = np.array([e[1] for e in sv.timeline], dtype=int)
    row = np.array([e[2] for e in sv.timeline], dtype=int)
    i = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(starts) - 1)
    return src[i], row[i]


def _work_at(sv: _Solver, t: np.ndarray) -> np.ndarray:
    _, _, _, _, _, work, _ = _evaluate(sv, t, sv.stop)
    return work


def _evaluate(sv: _Solver, t: np.ndarray, stop: HystereticStop):
    """State, mode, force, overlap, cumulative work and stored energy at times ``t``."""
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
        table = sv.table.arrays(sv.vb)
        out = evaluate(table, t[free], np.zeros(free.sum(), bool), sv.vb)
        x[free], xd[free], mode[free] = out["x"], out["v"], out["mode"]
        work[free, 0] = out["friction_work"]
        work[free, 1] = out["belt_input"]
        work[free, 2] = out["stop_loss"]
    idx = np.nonzero(~free)[0]
    if len(idx):
        c = sv.contact
        t0 = np.array(c.t0)
        rows = np.clip(np.searchsorted(t0, t[idx], side="right") - 1, 0, len(t0) - 1)
        xb = stop.clearance
        kinds = np.array(c.kind, dtype=np.int8)[rows]
        branch_rows = np.array(c.branch, dtype=int)[rows]
        is_arc = kinds == _ARC
        is_osc = kinds == _OSC
        if np.any(is_arc):
            _evaluate_arcs(sv, t, idx[is_arc], rows[is_arc], x, xd, work)
        osc_stored: dict[int, float] = {}
        for j, r in zip(idx[is_osc], rows[is_osc], strict=True):
            model, x_s, m_s, loss_s = c.data[r]
            tau = t[j] - c.t0[r]
            xj, uj, amp = (float(q) for q in model.state(tau))
            wf, wb, ws = c.work0[r]
            dwf = c.friction[r] * (xj - x_s)
            x[j], xd[j] = xj, uj
            work[j] = (wf + dwf, wb + c.friction[r] * sv.vb * tau,
                       ws + dwf - (0.5 * (xj * xj + uj * uj) - m_s))
            dissipated = model.energy(model.amp0) - model.energy(amp)
            osc_stored[j] = work[j, 2] - (loss_s + dissipated)
        plain = ~is_arc & ~is_osc
        for j, r in zip(idx[plain], rows[plain], strict=True):
            kind = c.kind[r]
            tau = t[j] - c.t0[r]
            wf, wb, ws = c.work0[r]
            if kind == _HERMITE:
                coeffs, h = c.data[r][:6], c.data[r][6]
                th = tau / h
                xj, uj = _poly(coeffs, th), _dpoly(coeffs, th) / h
                fr = c.friction[r]
                wf += fr * (xj - coeffs[0])
                wb += fr * sv.vb * tau
            elif kind == _LINE:
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
        mode[idx] = Mode.CONTACT
        brs = c.branches
        delta = x[idx] - xb
        loading = np.array([brs[i].loading for i in branch_rows])
        d_r = np.array([brs[i].delta_r for i in branch_rows])
        p_r = np.array([brs[i].phi_r for i in branch_rows])
        phi[idx] = force_on_branches(delta, loading, d_r, p_r, stop)
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

        for k in np.nonzero(plain)[0]:
            bi = branch_rows[k]
            d0, w0 = c.branch_start[bi]
            prim = primitive(bi)
            work[idx[k], 2] = w0 + prim(max(delta[k], 0.0)) - prim(d0)
        # The energy the stop gives back on unloading from the law's current state: while
        # loading, a new unloading branch would start here (Eq. 12); while unloading, the
        # current branch goes on (not a fresh one from (delta, phi): they differ where the
        # branch has been clipped onto the compression envelope).
        stored[idx] = stored_energy_many(delta, phi[idx], stop)
        for k in np.nonzero(~loading & (delta > 0.0) & ~is_osc)[0]:
            prim = primitive(branch_rows[k])
            stored[idx[k]] = prim(delta[k]) - prim(0.0)
        for j, value in osc_stored.items():
            stored[j] = value
    return x, xd, mode, phi, x - stop.clearance, work, stored


def _evaluate_arcs(sv: _Solver, t, idx, rows, x, xd, work) -> None:
    """Samples inside semi-analytic arcs (:meth:`_Solver.arc`), vectorised.

    The angle ``theta`` of each sample solves ``t(theta) = tau`` (Newton; ``t(theta)`` by
    15-point Gauss-Kronrod on ``[0, theta]``); position from ``x = x_r + d sin^2(theta/2)``,
    speed from the energy, ``u^2 = -2 e Q(e)``, so the energy balance holds at the samples
    to rounding whatever the error of the time.
    """
    c = sv.contact
    data = np.array([c.data[r] for r in rows], dtype=float)
    x_r, d, period, kk, cc, lam, dr = data.T
    sa = np.array([c.friction[r] for r in rows])
    w0 = np.array([c.work0[r] for r in rows])
    tau = t[idx] - np.array([c.t0[r] for r in rows])
    d_lim = sv.d_lim
    gap = d_lim - dr
    base = x_r - sa + kk * dr / gap
    kg = kk * d_lim / gap

    def mean_phi(e):
        return kk * dr / gap + kg * _log_mean_m1_arr(e / gap) + cc * _exp_mean_arr(lam * e)

    def rate(th):  # dt/dtheta
        e = d * np.sin(0.5 * th) ** 2
        q = base + 0.5 * e + kg * _log_mean_m1_arr(e / gap) + cc * _exp_mean_arr(lam * e)
        return np.abs(d) * np.cos(0.5 * th) / np.sqrt(np.maximum(-2.0 * d * q, 1e-300))

    xi = np.array(_GK_X)
    wk = np.array(_GK_WK)
    th = np.clip(math.pi * tau / period, 0.0, math.pi)
    for _ in range(ARC_SAMPLE_NEWTON):
        nodes = 0.5 * th[:, None] * (1.0 + xi[None, :])
        t_th = 0.5 * th * (rate(nodes.T).T @ wk) if len(th) else th
        g = rate(th)
        step = (t_th - tau) / np.where(g > 0.0, g, 1.0)
        th = np.clip(th - step, 0.0, math.pi)
        if np.all(np.abs(step) <= 1e-14):
            break
    e = d * np.sin(0.5 * th) ** 2
    q = base + 0.5 * e + kg * _log_mean_m1_arr(e / gap) + cc * _exp_mean_arr(lam * e)
    x[idx] = x_r + e
    xd[idx] = np.sign(d) * np.sqrt(np.maximum(-2.0 * e * q, 0.0))
    work[idx, 0] = w0[:, 0] + sa * e
    work[idx, 1] = w0[:, 1] + sa * sv.vb * tau
    work[idx, 2] = w0[:, 2] + e * mean_phi(e)


def _asymptotic(sv: _Solver, t_end: float, mode: np.ndarray, xd: np.ndarray) -> Steady:
    """Steady state read off the last transitions when no fixed point was found."""
    if sv.status is not Status.SUCCESS:
        return Steady(SteadyKind.NONE)
    if sv.pressed():
        return _pressed_steady(list(sv.log.recent))
    endless = getattr(sv, "endless", None)
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
    tail = list(sv.log.recent)
    return steady_from_transitions(
        tail,
        tol=FIXED_POINT_RTOL * sv.scale(),
        t_end=t_end,
        final_mode=int(mode[-1]) if len(mode) else 0,
        final_v=float(xd[-1]) if len(xd) else 0.0,
    )


def _pressed_steady(tail: list[Transition]) -> Steady:
    """Steady state of a mass the belt presses on the stop (``x_bar < a``), read off the
    latest transitions when no fixed point was found.

    No slip circle misses or grazes the stop then (the circles about ``(a, 0)`` all cross
    it), so neither pure slip nor grazing can be the limit: the motion ends at rest on the
    stop, or goes on as a train of contacts, or as an oscillation on the stop. A train is
    labelled with the measured ratio of successive approach speeds; a sustained oscillation
    whose swings shrink is rest approached, with the measured ratio of successive swings.
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
    xs = [tr.x for tr in tail if tr.kind is TransitionKind.REVERSAL]
    swings = np.abs(np.diff(xs))
    if len(swings) >= 4 and np.all(swings[-4:] > 0.0):
        ratio = float(np.median(swings[-4:][1:] / swings[-4:][:-1]))
        if ratio < 1.0:
            return Steady(SteadyKind.REST, x_max=max(xs), impact_speed=0.0, decay_rate=ratio)
    if tail and tail[-1].kind is TransitionKind.REDUCED:
        return Steady(SteadyKind.REST, x_max=tail[-1].x, impact_speed=0.0)
    return Steady(SteadyKind.NONE)
