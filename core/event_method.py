"""Event-driven integration of the non-smooth model with SciPy's Runge-Kutta and BDF solvers.

The method whole: its options, the solver class whose handlers share one state, and the
entry point; the modes' right-hand sides and events are :mod:`core.event_modes`, the
stepping loop with event location :mod:`core.numerics.events`.

A second numerical method beside the switch model (:mod:`core.switch`): the non-smooth
Coulomb model (paper Eqs. 3-6) is integrated mode by mode, each mode a smooth ODE, and every
mode change is an event located on the solver's own dense output. No stick band, no
regularisation: the error is the integration error alone.

The stepping loop is the one of :func:`scipy.integrate.solve_ivp` (the public
:class:`scipy.integrate.OdeSolver` classes advanced step by step, sign changes of the event
functions at the step ends, roots by :func:`scipy.optimize.brentq` on the step's
interpolant), written out so that the solve can count its work and stop at its limits.

The modes and the events that end them are :mod:`core.event_modes`.

Impact accumulation (Zeno, paper §4) is handled as in the switch model: a rebound slower
than ``rest_speed`` while the mass is pressed on the stop (:func:`core.steady.pressed_on_stop`)
ends the bouncing; the remaining arc durations are summed in closed form to give the
accumulation time. The default
``rest_speed = sqrt(2 atol (a - clearance))`` keeps the neglected rebounds' height
``w^2 / (2 (a - clearance))`` below ``atol``.

Work limits
-----------
A solve stops, and returns its result up to that time, with ``Status.STEP_LIMIT`` after
``max_steps`` solver steps, ``Status.TIME_BUDGET`` when ``time_budget`` seconds have passed,
and ``Status.EVENT_LIMIT`` after ``max_events`` events or when events keep firing at one
instant (:data:`MAX_SAME_TIME`). The default step limit, :data:`DEFAULT_MAX_STEPS`,
returns within a few seconds whatever the horizon.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import DOP853, LSODA, RK45, Radau

from core.deformable.law import (
    FIRST_LOADING,
    Branch,
    branch_kinks,
    force_and_slope,
    reverse,
    start_branch,
)
from core.deformable.stop_work import StopWork
from core.dense import log_rest_at_stop, new_log, result_from_track
from core.event_modes import (
    LIMIT_OVERLAP_FRACTION,
    slip_events,
    slip_rhs,
    stick_contact_end,
)
from core.method_entry import takes_options
from core.numerics.dense_output import PiecewiseDense, PointTrack, line_piece
from core.numerics.events import Event, SegmentIntegrator
from core.numerics.limits import COUNT_MAX, MAX_EVENTS, WorkLimit
from core.result import Mode, Result, Status, TransitionKind, make_stats
from core.solve_inputs import SolveInputs, StopFacts, solve_entry
from core.steady import rest_force
from core.validation import check_integer, check_range

#: Integrators offered: explicit Runge-Kutta pairs, an implicit Radau IIA method for stiff
#: contact, and LSODA's automatic stiffness switching.
SOLVERS = ("RK45", "DOP853", "Radau", "LSODA")
_SOLVER_CLASSES = {"RK45": RK45, "DOP853": DOP853, "Radau": Radau, "LSODA": LSODA}
#: Points that describe a stick segment inside a deformable contact (the force is a
#: nonlinear function of the overlap there; on free stick two points are exact).
STICK_CONTACT_POINTS = 16
#: Kinks of the force within this fraction of ``D`` of a branch's start (its reversal) or
#: of the face (the separation) are not stepped to.
KINK_MARGIN = 1e-9
#: Largest step of a rebound arc from a rigid stop, as a fraction of its estimated duration
#: ``2|x'|/|x''|`` (only the segment that starts at the stop).
REBOUND_STEP_FRACTION = 0.25
#: Restarts at (numerically) the same time that count as an event stuck in place.
MAX_SAME_TIME = 64
#: Default limit on the solver steps of one solve, sized so that a default call returns
#: within seconds whatever its horizon, having reached t ~ 4e3 (rigid scene 5a) and 2.5e3
#: (deformable scene 10) at the default tolerances
#: (benchmarks/results/2026-11-29-default-limits.md). Pass ``max_steps`` or
#: ``time_budget`` to go further.
DEFAULT_MAX_STEPS = 30_000


@dataclass(frozen=True)
class EventOptions:
    """Options of :func:`simulate_event`, declared and checked once (see its parameters;
    :func:`core.method_entry.takes_options` makes them its keyword options)."""

    rtol: float = 1e-8
    atol: float = 1e-10
    solver: str = "RK45"
    rest_speed: float | None = None
    max_steps: int = DEFAULT_MAX_STEPS
    time_budget: float | None = None
    max_events: int = MAX_EVENTS

    def __post_init__(self) -> None:
        check_range("rtol", self.rtol, 0.0, low_open=True)
        check_range("atol", self.atol, 0.0, low_open=True)
        if self.solver not in SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {self.solver!r}")
        if self.rest_speed is not None:
            check_range("rest_speed", self.rest_speed, 0.0)
        check_integer("max_events", self.max_events, 1, COUNT_MAX)


class EventSolver:
    """One solve of the non-smooth model by event location: the state of the motion (time,
    position, velocity, friction state, contact and branch of the contact law), the dense
    track and the work counts. :meth:`run` advances it to the horizon or a limit."""

    def __init__(self, inputs: SolveInputs, opts: EventOptions, limit: WorkLimit) -> None:
        osc, stop, x0, v0 = inputs.osc, inputs.stop, inputs.x0, inputs.v0
        self.inputs, self.osc, self.stop, self.t_end = inputs, osc, stop, inputs.t_end
        self.opts, self.limit = opts, limit
        facts = StopFacts.of(osc, stop)
        self.rigid, self.soft, self.c, self.r = facts.rigid, facts.soft, facts.c, facts.r
        self.pressed = facts.pressed
        a = osc.a
        if opts.rest_speed is not None:
            self.rest_speed = opts.rest_speed
        else:
            self.rest_speed = (
                math.sqrt(2.0 * opts.atol * max(a - self.c, 0.0)) if self.rigid else 0.0
            )
        self.log = new_log(inputs.transition_cap)
        self.track = PointTrack()
        self.dense = PiecewiseDense(self.c if self.rigid else None)
        self.t, self.x, self.v = 0.0, x0, v0
        self.contact = self.soft and x0 > self.c
        self.branch: Branch = FIRST_LOADING
        # Kinks of the force ahead on the branch (positions, next first) and the time of
        # the next one once a step has crossed it (stepped to in a segment of its own).
        self.kinks: list[float] = []
        self.land_at: float | None = None
        self.work = StopWork(stop, self.c) if self.soft else None
        self.fr = 0
        if self.contact:  # a start inside the stop: its branch there (start_branch)
            pull = self.start_mode(x0, v0) * a - x0
            self.set_branch(start_branch(x0 - self.c, v0, pull, stop))
        self.at_rest = False
        self.status = Status.SUCCESS
        self.n_seg = self.n_steps = self.n_eval = 0
        self.same_time = 0

    # --- the law at the current state ----------------------------------------------------
    def phi(self, x: float) -> float:
        """Contact force over ``k`` at ``x`` on the current branch (0 out of contact)."""
        if not (self.soft and self.contact):
            return 0.0
        d = x - self.c
        return force_and_slope(d, self.branch, self.stop)[0] if d > 0.0 else 0.0

    def set_branch(self, branch: Branch) -> None:
        """Follow ``branch`` of the law from here, with the kinks of its force ahead (where
        its curve is clipped to an envelope: :func:`core.deformable.law.branch_kinks`)."""
        self.branch, self.land_at, self.kinks = branch, None, []
        if self.work is not None:
            self.work.follow(branch if self.contact else None, self.x)
        if not (self.soft and self.contact):
            return
        d, d_lim = self.x - self.c, self.stop.limit_overlap
        # A kink at the branch's start is the reversal itself; one at the face is left to
        # the separation, whose event a step landed on the face would not fire.
        if branch.loading:
            kinks = branch_kinks(branch, self.stop, d + KINK_MARGIN * d_lim,
                                 d_lim * LIMIT_OVERLAP_FRACTION)
        else:
            kinks = branch_kinks(branch, self.stop, KINK_MARGIN * d_lim,
                                 d - KINK_MARGIN * d_lim)[::-1]
        self.kinks = [self.c + k for k in kinks]

    def start_mode(self, x: float, v: float) -> int:
        """+1/-1 slip with that sign, 0 stick (the relative velocity decides, Eqs. 3-6)."""
        vb, b = self.osc.v, self.osc.b
        if v < vb:
            return 1
        if v > vb:
            return -1
        f = x + self.phi(x)
        if abs(f) <= b:
            return 0
        return 1 if f > 0.0 else -1

    def slip_acc(self, x: float, s: int) -> float:
        return -x + s * self.osc.a - self.phi(x)

    def acc_of(self, x: float, fr: int) -> float:
        return 0.0 if fr == 0 else self.slip_acc(x, fr)

    def point(self, t: float, x: float, v: float, acc: float, fr: int) -> None:
        mode = Mode.CONTACT if self.contact else (Mode.STICK if fr == 0 else Mode.SLIP)
        self.track.add(t, x, v, acc, mode, self.phi(x) if self.soft else 0.0)
        if self.work is not None:
            self.work.add_point(x, fr == 0)

    # --- the loop --------------------------------------------------------------------------
    def run(self) -> None:
        self.fr = self.start_mode(self.x, self.v)
        self.point(self.t, self.x, self.v, self.acc_of(self.x, self.fr), self.fr)
        if self.rigid and self.x >= self.c and self.v > 0.0:
            self.impact(self.v, self.fr == 0)
        elif self.rigid and self.x >= self.c and self.v == 0.0 and self.pressed:
            self.rest_from(0.0)
        while self.t < self.t_end and not self.at_rest and self.status is Status.SUCCESS:
            if self.n_seg >= self.opts.max_events:
                self.status = Status.EVENT_LIMIT
                break
            self.n_seg += 1
            t_before = self.t
            if self.fr == 0:
                self.stick()
            else:
                self.slip()
            self.same_time = self.same_time + 1 if self.t <= t_before else 0
            if self.same_time > MAX_SAME_TIME:
                self.status = Status.EVENT_LIMIT

    # --- rigid impacts and rest ------------------------------------------------------------
    def rest_from(self, w: float) -> None:
        """The bouncing ends: rest on the stop (after the accumulation time for 0<r<1)."""
        t_rest = log_rest_at_stop(self.log, self.t, w, self.r, self.osc.a, self.c, self.t_end)
        self.contact = True
        t_hold = min(max(t_rest, self.t), self.t_end)
        # the stop's reaction joins the spring in x'' + x + phi = friction, so that the belt's
        # work at rest is that of kinetic friction, a (docs/physics.md, Rest at the stop)
        force = rest_force(self.osc, self.c)
        for tt in (self.t, t_hold, self.t_end):
            self.track.add(tt, self.c, 0.0, 0.0, Mode.CONTACT, force)
        self.dense.add(self.t, self.t_end, line_piece(self.t, self.c, 0.0))
        self.at_rest = True

    def impact(self, w: float, from_stick: bool) -> None:
        """Rigid impact at ``x = c`` with approach speed ``w`` (paper Eq. 8)."""
        v_after = -self.r * w
        kind = TransitionKind.STICK_IMPACT if from_stick else TransitionKind.IMPACT
        self.log.add(kind, self.t, self.c, w, v_after)
        if abs(v_after) <= self.rest_speed and self.pressed:
            self.rest_from(w)
            return
        self.x, self.v = self.c, v_after
        self.fr = self.start_mode(self.c, self.v)
        self.point(self.t, self.c, self.v, self.acc_of(self.c, self.fr), self.fr)

    # --- stick in closed form (paper Eqs. 5-6) ----------------------------------------------
    def stick(self) -> None:
        vb = self.osc.v
        if vb <= 0.0:
            self.point(self.t_end, self.x, 0.0, 0.0, 0)
            self.dense.add(self.t, self.t_end, line_piece(self.t, self.x, 0.0))
            self.t = self.t_end
        elif self.soft and self.contact:
            self.stick_in_contact()
        else:
            self.stick_free()

    def _stick_to(self, t_e: float, x_e: float) -> bool:
        """Move along the belt to ``(t_e, x_e)`` or the horizon; True if the horizon came
        first (the points on the way are the caller's)."""
        vb = self.osc.v
        t1 = min(t_e, self.t_end)
        self.dense.add(self.t, t1, line_piece(self.t, self.x, vb))
        if t_e >= self.t_end:
            self.x += vb * (self.t_end - self.t)
            self.t = self.t_end
            return True
        self.t, self.x, self.v = t_e, x_e, vb
        return False

    def stick_in_contact(self) -> None:
        vb, x0, t0 = self.osc.v, self.x, self.t
        kind, x_e = stick_contact_end(self.stop, self.branch, self.x, self.osc.b)
        t_e = t0 + (x_e - x0) / vb
        t_stop = min(t_e, self.t_end)
        for xx in np.linspace(x0, x0 + vb * (t_stop - t0), STICK_CONTACT_POINTS)[1:]:
            self.point(t0 + (xx - x0) / vb, float(xx), vb, 0.0, 0)
        if self._stick_to(t_e, x_e):
            return
        if kind is TransitionKind.FAILURE:
            self.log.add(kind, self.t, self.x, self.v)
            self.status = Status.STOP_FAILED
        elif kind is None:
            self.status = Status.LIMIT_OVERLAP
        else:
            self.log.add(TransitionKind.STICK_SLIP, self.t, self.x, self.v)
            self.fr = 1
            # right limit: the acceleration jumps
            self.point(self.t, self.x, self.v, self.slip_acc(self.x, 1), 1)

    def stick_free(self) -> None:
        vb, b, c = self.osc.v, self.osc.b, self.c
        target = min(b, c)
        t_e = self.t + max(target - self.x, 0.0) / vb
        if self._stick_to(t_e, target):
            self.point(self.t, self.x, vb, 0.0, 0)
            return
        if self.rigid and c <= b:
            self.point(self.t, self.x, self.v, 0.0, 0)
            self.impact(vb, True)
        elif self.soft and c < b:
            self.contact = True
            self.set_branch(FIRST_LOADING)
            self.log.add(TransitionKind.CONTACT, self.t, self.x, self.v)
            self.point(self.t, self.x, self.v, 0.0, 0)
        else:
            self.log.add(TransitionKind.STICK_SLIP, self.t, self.x, self.v)
            self.point(self.t, self.x, self.v, 0.0, 0)  # left limit of the acceleration
            self.fr = 1
            self.point(self.t, self.x, self.v, self.slip_acc(self.x, 1), 1)

    # --- slip: an ODE with events -----------------------------------------------------------
    def slip(self) -> None:
        """One slip segment with the sign ``fr``: integrated up to its first event, or to
        the next kink of the contact force (the horizon, a work limit)."""
        s = self.fr
        if self.land_at is not None and not self.land_at > self.t:  # on the kink already
            self.kinks.pop(0)
            self.land_at = None
        landing = self.land_at is not None
        watch = self.stop is not None and not self.contact
        solver = self.slip_solver(s, watch)

        def point(t: float, y) -> None:
            x, v = float(y[0]), float(y[1])
            self.point(t, x, v, self.slip_acc(x, s), s)

        segment = SegmentIntegrator(
            solver, self.slip_events(s), self.limit, point, level=self.c if watch else None,
            speed=(self.osc.v, float(s)),
        )
        end = segment.integrate(self.n_steps)
        self.n_steps += end.steps
        self.n_eval += solver.nfev
        if end.piece is not None:
            self.dense.add(end.t0, end.t, end.piece)
        if end.status is not None:
            self.status = end.status
        self.t, self.x, self.v = end.t, float(end.y[0]), float(end.y[1])
        self.slip_ended(end, s, landing, point)

    def in_contact_branch(self) -> Branch | None:
        """The branch of the law the mass follows in a deformable contact, else ``None``."""
        return self.branch if self.soft and self.contact else None

    def slip_events(self, s: int) -> list[Event]:
        """The events of a slip segment from here (:func:`core.event_modes.slip_events`);
        the next kink only while not stepping to it already."""
        kink = self.kinks[0] if self.kinks and self.land_at is None else None
        return slip_events(s, self.osc.v, self.c, self.stop, self.in_contact_branch(), kink,
                           lambda x: self.slip_acc(x, s))

    def slip_solver(self, s: int, watch: bool):
        """The SciPy solver of a slip segment with sign ``s`` from here, to the kink it
        steps to or the horizon."""
        opts = {}
        if watch and self.x == self.c and self.v < 0.0 and self.slip_acc(self.x, s) > 0.0:
            # pushed back to the stop, a rebound arc lasts about 2|x'|/x'': steps must not
            # jump over it (the event function would see no sign change, or a root at t)
            opts["max_step"] = REBOUND_STEP_FRACTION * 2.0 * abs(self.v) / self.slip_acc(self.x, s)
        return _SOLVER_CLASSES[self.opts.solver](
            slip_rhs(s, self.osc.a, self.c, self.stop, self.in_contact_branch()),
            self.t,
            np.array([self.x, self.v]),
            self.land_at if self.land_at is not None else self.t_end,
            rtol=self.opts.rtol,
            atol=self.opts.atol,
            **opts,
        )

    def slip_ended(self, end, s: int, landing: bool, point) -> None:
        """The state after a slip segment that ended at ``end``: on a kink (or stepping to
        the next one), at the horizon or a limit, or at an event (:meth:`handle`)."""
        if end.event == "kink" and end.target is not None:
            self.land_at = end.target  # the next segment steps to it
            return
        if end.event == "kink" or (landing and end.event is None and end.status is None):
            # on the kink: the next one is ahead, the steps go on from here
            self.kinks.pop(0)
        self.land_at = None
        if end.event is None or end.event == "kink":
            if self.t > self.track.t[-1]:
                point(self.t, end.y)
        else:
            self.handle(end.event, s)

    def handle(self, name: str, s: int) -> None:
        """The state after the event ``name`` that ended a slip segment with sign ``s``."""
        t, c = self.t, self.c
        if name == "ur":
            self.v = self.osc.v
            f = self.x + self.phi(self.x)
            self.point(t, self.x, self.v, self.slip_acc(self.x, s), s)  # left limit
            if abs(f) <= self.osc.b:
                self.log.add(TransitionKind.SLIP_STICK, t, self.x, self.v)
                self.fr = 0
            else:
                self.log.add(TransitionKind.SIGN_CHANGE, t, self.x, self.v)
                self.fr = 1 if f > 0.0 else -1
            self.point(t, self.x, self.v, self.acc_of(self.x, self.fr), self.fr)  # right limit
        elif name == "stop" and self.rigid:
            self.x = c
            self.point(t, c, self.v, self.slip_acc(c, s), s)
            self.impact(max(self.v, 0.0), False)
        elif name == "stop":
            self.x = c
            self.contact = True
            self.set_branch(FIRST_LOADING)
            self.log.add(TransitionKind.CONTACT, t, c, self.v)
            self.point(t, c, self.v, self.slip_acc(c, s), s)
        elif name in ("separation", "reversal"):
            self.leave_branch(name)
        else:  # failure or limit overlap: the solve ends here
            self.point(t, self.x, self.v, self.slip_acc(self.x, s), s)
            if name == "failure":
                self.log.add(TransitionKind.FAILURE, t, self.x, self.v)
                self.status = Status.STOP_FAILED
            else:
                self.status = Status.LIMIT_OVERLAP

    def leave_branch(self, name: str) -> None:
        """Separation from, or a reversal inside, a deformable contact."""
        if name == "separation":
            self.x = self.c
            self.contact = False
            self.set_branch(FIRST_LOADING)
            self.log.add(TransitionKind.SEPARATION, self.t, self.x, self.v)
        else:
            self.v = 0.0
            d = self.x - self.c
            phi = force_and_slope(d, self.branch, self.stop)[0] if d > 0.0 else 0.0
            self.set_branch(reverse(d, phi, self.branch, self.stop))
            self.log.add(TransitionKind.REVERSAL, self.t, self.x, self.v)
        self.fr = self.start_mode(self.x, self.v)
        self.point(self.t, self.x, self.v, self.acc_of(self.x, self.fr), self.fr)

    # --- the result ---------------------------------------------------------------------------
    def result(self) -> Result:
        stats = make_stats(
            segments=self.n_seg, steps=self.n_steps, rhs_evals=self.n_eval, events=self.log.total
        )
        return result_from_track(
            self.track,
            self.log,
            self.inputs,
            rtol=self.opts.rtol,
            status=self.status,
            method="event",
            stats=stats,
            info={"solver": self.opts.solver},
            dense=self.dense if self.dense.pieces else None,
            stop_law=self.work,
        )


@takes_options(EventOptions)
def solve_event(inputs: SolveInputs, opts: EventOptions) -> Result:
    """Response by event location on the non-smooth model (SciPy's solvers, see the module
    docstring).

    :func:`simulate_event` takes the scene, horizon, start and sampling as
    :func:`core.simulate` does (:class:`~core.solve_inputs.SolveInputs`); ``t_eval`` is
    sampled on the solvers' dense output (after an early stop, only the times it reached).

    Parameters
    ----------
    inputs : SolveInputs
        The checked scene, horizon, start and sampling.
    rtol, atol : float
        Tolerances of the solver (as in ``solve_ivp``).
    solver : {"RK45", "DOP853", "Radau", "LSODA"}
        The SciPy integrator.
    rest_speed : float, optional
        Rebound speed below which a mass pressed on a rigid stop rests there (Zeno guard);
        default ``sqrt(2 atol (a - clearance))``.
    max_steps : int
        Largest number of solver steps; default :data:`DEFAULT_MAX_STEPS`. When it is
        reached the solve stops with ``Status.STEP_LIMIT``; the result covers the time up
        to that point (``t[-1]``).
    time_budget : float, optional
        Wall-clock seconds the solve may take; then it stops with ``Status.TIME_BUDGET``
        (result up to that point). ``None``: no budget.
    max_events : int
        Largest number of segments between events. Too many events, or events that keep
        firing at one instant (more than :data:`MAX_SAME_TIME` restarts without progress),
        stop the solve with ``Status.EVENT_LIMIT``; the result covers the time up to that
        point.

    Returns
    -------
    Result
        ``method="event"``; ``stats`` (:func:`core.result.make_stats`) counts ``segments``
        (integrated and closed-form), ``steps`` (accepted solver steps), ``rhs_evals`` and
        ``events``; SciPy's solvers do not report rejected steps, so ``rejected`` is 0.
        ``info["solver"]`` names the integrator; ``dense`` is the solvers' own interpolant
        (closed forms on stick and rest) for :meth:`~core.result.Result.evaluate`.

    Examples
    --------
    >>> from core import Oscillator
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> res = simulate_event(osc, t_end=2.0)
    >>> tr = res.transitions[0]     # Eq. (30): first stick at x = a - sqrt(a^2 - v^2)
    >>> tr.kind.value, round(tr.x, 8)
    ('slip->stick', 0.02679492)
    """
    run = EventSolver(inputs, opts, WorkLimit(opts.max_steps, opts.time_budget))
    run.run()
    return run.result()


#: :func:`solve_event` with the inputs of :func:`core.simulate`.
simulate_event = solve_entry(solve_event)
