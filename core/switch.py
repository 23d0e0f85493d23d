"""The paper's numerical method: the switch model integrated by Runge-Kutta-Fehlberg 4(5).

The method whole: its options, the solver class whose event handlers share one state, and
the entry point; the switch law itself (Eq. 7) is :mod:`core.switch_model`, and what other
methods share (tableau, step control, Hermite roots, dense output, work limits) lives in
:mod:`core.numerics`.

Andreaus & Casini integrate the non-smooth oscillator with the switch model of Leine et al.
(1998) (paper §2.2, Eq. 7, Fig. 1c) and an adaptive Runge-Kutta-Fehlberg 4(5) scheme (paper
§2.5). The project keeps it as one selectable method, the baseline that the exact and
event-driven solvers are measured against (``docs/physics.md``).

The right-hand side is discontinuous across the band edges. The error control of the
embedded pair shrinks the step across them, which is what the method costs; one crossing is
located: a step that jumps over the whole band (from one slip direction to the other) is cut
where the velocity enters it and the state is put on the band's edge, where the model's own
solution sticks. Without that cut, a band thinner than the velocity tolerance (a slow belt:
``eta = 1e-4 v`` below ``atol``) is never entered and the solution chatters across it with
tiny steps. The method's error is ``O(eta)`` for stick (the mass sticks at ``x' = v -+ eta``
instead of ``v``) on top of the integration error; :mod:`benchmarks.work_precision` measures
both.

The stop
--------
* Rigid (paper Eq. 8): the crossing of ``x = clearance`` is located inside the accepted step
  (cubic Hermite root, then the RKF step recomputed to that time with one Newton
  correction), the state is put on the stop and the velocity reflected, ``x' -> -r x'``.
  The samples therefore never pass the stop.
* Deformable (paper Eqs. 9-15): the contact force of :mod:`core.deformable.law` enters ``F``;
  its branch (the memory of the law) is held fixed over a step, and the step is cut where
  the overlap rate changes sign so that :func:`core.deformable.law.reverse` stores the reversal
  point; contact start is cut too (a new contact starts on the first-loading branch). The
  work done on the stop, and the energy it stores, are the law's along the branch each
  step follows (:mod:`core.deformable.stop_work`), not a quadrature over the steps.

Impact accumulation (Zeno)
--------------------------
For ``0 < r < 1`` and ``clearance < a`` the rebound speeds fall as ``r^h`` and infinitely
many impacts happen in finite time (paper §4, ``docs/physics.md``). A rebound slower than
``rest_speed`` (default ``eta``, the model's own velocity resolution) while the mass is
pressed on the stop (:func:`core.steady.pressed_on_stop`, ``a >= clearance``) ends the
bouncing: the rest of the geometric series of arc durations ``2 atan(r^h w / (a -
clearance))`` is summed in closed form to give the accumulation time, and from there the
mass rests on the stop. The number of impacts is thus bounded by ``log(rest_speed/w_0) /
log(1/r)``.

Work limits
-----------
A solve stops, and returns its result up to that time, with ``Status.STEP_LIMIT`` after
``max_steps`` Runge-Kutta steps (accepted and rejected) and with ``Status.TIME_BUDGET`` when
``time_budget`` seconds have passed. The method has no other event count to limit: every
event is a cut step, counted among the steps. The default step limit,
:data:`DEFAULT_MAX_STEPS`, returns within a few seconds whatever the horizon.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import partial

from core.deformable.law import (
    FIRST_LOADING,
    Branch,
    force_and_slope,
    reverse,
    start_branch,
)
from core.deformable.stop_work import StopWork
from core.dense import log_rest_at_stop, new_log, result_from_track
from core.method_entry import takes_options
from core.numerics.dense_output import HermiteDense, PointTrack
from core.numerics.hermite import hermite, root, x_crossing
from core.numerics.limits import WorkLimit
from core.numerics.rk import STAGES_PER_STEP, StepControl, rkf45_step
from core.params import Oscillator
from core.result import Mode, Result, Status, TransitionKind, make_stats
from core.solve_inputs import SolveInputs, StopFacts, solve_entry
from core.steady import rest_force
from core.switch_model import band_edge, check_eta, default_eta, eta_bounds, switch_rhs
from core.validation import check_range

#: First trial step (dimensionless time); the controller grows it within a few steps.
FIRST_STEP = 1e-3
#: Default limit on the Runge-Kutta steps (accepted and rejected) of one solve, sized so
#: that a default call returns within seconds whatever its horizon, having reached
#: t ~ 1.4e4 (rigid scene 5a) to 1.7e4 (deformable scene 10) at the default tolerances
#: (benchmarks/results/2026-11-29-default-limits.md). Pass ``max_steps`` or
#: ``time_budget`` to go further.
DEFAULT_MAX_STEPS = 200_000
#: Least scatter of the model's transition states over a cycle, relative to the state's
#: scale, whatever the band: a stick-slip cycle's states scatter by 8 to 20 eta at
#: ``eta = 1e-5 v`` (up to 7e-5 of the scale), and the cycle of Fig. 5a went unfound
#: ("no steady state") where the band's ``eta / v`` alone set the repeat's tolerance.
TRANSITION_SCATTER = 3e-4
#: Newton corrections of a located event with the recomputed Runge-Kutta step.
EVENT_NEWTON = 2


@dataclass(frozen=True)
class SwitchOptions:
    """Options of :func:`simulate_switch`, declared and checked once (see its parameters;
    :func:`core.method_entry.takes_options` makes them its keyword options). ``eta`` and
    ``rest_speed`` left ``None`` are set for the scene by :meth:`for_scene`."""

    rtol: float = 1e-6
    atol: float = 1e-9
    eta: float | None = None
    max_step: float = math.inf
    rest_speed: float | None = None
    max_steps: int = DEFAULT_MAX_STEPS
    time_budget: float | None = None

    def __post_init__(self) -> None:
        check_range("rtol", self.rtol, 0.0, low_open=True)
        check_range("atol", self.atol, 0.0, low_open=True)
        if self.eta is not None:
            check_range("eta", self.eta, 0.0, low_open=True)
        check_range("max_step", self.max_step, 0.0, low_open=True, allow_inf=True)
        if self.rest_speed is not None:
            check_range("rest_speed", self.rest_speed, 0.0)

    def for_scene(self, osc: Oscillator) -> SwitchOptions:
        """The options with the stick band checked against the scene (:func:`check_eta`),
        or by default ``ETA_REL`` times its speed scale within what ``rtol`` resolves
        (:func:`eta_bounds`), and the rest speed by default the band."""
        if self.eta is None:
            low, high = eta_bounds(osc, self.rtol)
            eta = min(max(default_eta(osc), low), high)
        else:
            eta = check_eta(self.eta, osc, self.rtol)
        rest_speed = eta if self.rest_speed is None else self.rest_speed
        return dataclasses.replace(self, eta=eta, rest_speed=rest_speed)


class SwitchSolver:
    """One solve of the switch model by RKF 4(5): the state of the motion (time, position,
    velocity, acceleration, friction state, contact and branch of the contact law), the
    step size, the dense points and the work counts. :meth:`run` advances it to the
    horizon or a limit; each accepted step goes through the events that may cut it."""

    # slots: fixed attributes, and faster access in the step loop
    __slots__ = (
        "inputs", "osc", "stop", "t_end", "opts", "limit", "control", "rigid", "soft", "c", "r",
        "pressed", "log", "track", "t", "x", "v", "contact", "branch", "rhs", "acc", "fr", "h",
        "at_rest", "status", "steps", "rejected", "n_eval", "work",
    )  # fmt: skip

    def __init__(self, inputs: SolveInputs, opts: SwitchOptions, limit: WorkLimit) -> None:
        osc, stop, x0, v0 = inputs.osc, inputs.stop, inputs.x0, inputs.v0
        self.inputs, self.osc, self.stop, self.t_end = inputs, osc, stop, inputs.t_end
        self.opts, self.limit = opts, limit
        self.control = StepControl(opts.rtol, opts.atol)
        facts = StopFacts.of(osc, stop)
        self.rigid, self.soft, self.c, self.r = facts.rigid, facts.soft, facts.c, facts.r
        self.pressed = facts.pressed
        self.log = new_log(inputs.transition_cap)
        self.track = PointTrack()
        self.t, self.x, self.v = 0.0, x0, v0
        self.contact = self.soft and x0 > self.c
        self.branch: Branch = FIRST_LOADING
        # the stop's work along the law's branches (core/deformable/stop_work.py)
        self.work = StopWork(stop, self.c) if self.soft else None
        if self.contact:  # a start inside the stop: its branch there (start_branch)
            s = 1 if v0 < osc.v else -1 if v0 > osc.v else (1 if x0 > 0.0 else -1)
            self.branch = start_branch(x0 - self.c, v0, s * osc.a - x0, stop)
            self.work.follow(self.branch, x0)
        self.rhs = switch_rhs(osc, opts.eta, stop if self.soft else None, self.branch)
        self.acc = self.rhs(x0, v0)
        self.fr = self.friction_state(x0, v0)
        self.h = min(FIRST_STEP, opts.max_step, self.t_end)
        self.at_rest = False
        self.status = Status.SUCCESS
        self.steps = self.rejected = 0
        self.n_eval = 1

    # --- the law at a state --------------------------------------------------------------
    def phi_at(self, x: float) -> float:
        """Contact force over ``k`` at ``x`` on the current branch (0 off the stop)."""
        if not self.soft or x <= self.c:
            return 0.0
        return force_and_slope(x - self.c, self.branch, self.stop)[0]

    def friction_state(self, x: float, v: float) -> int:
        """+1/-1: slip with that sign; 0: stick (switch model, paper Eq. 7)."""
        eta = self.opts.eta
        ur = self.osc.v - v
        if ur > eta:
            return 1
        if ur < -eta:
            return -1
        force = -x - self.phi_at(x)
        if -self.osc.b <= force <= self.osc.b:
            return 0
        return 1 if force < 0.0 else -1

    def set_branch(self, branch: Branch) -> None:
        """Follow ``branch`` of the contact law from here on (out of contact: the first
        loading of the next contact). The step's end point is stored before the contact
        starts, reverses or ends there, so the interval after it is retagged."""
        self.branch = branch
        self.rhs = switch_rhs(self.osc, self.opts.eta, self.stop, branch)
        if self.work is not None:
            self.work.follow(branch if self.contact else None, self.x)
            self.work.retag_last(self.fr == 0)

    def eval_rhs(self, x: float, v: float) -> float:
        self.n_eval += 1
        return self.rhs(x, v)

    # --- points, sub-steps, events ----------------------------------------------------------
    def record(self) -> None:
        """Store the current state as a dense point (mode of the interval that follows)."""
        mode = Mode.CONTACT if self.contact else (Mode.STICK if self.fr == 0 else Mode.SLIP)
        if self.soft:
            phi = self.phi_at(self.x)
        else:
            # at rest the rigid stop's reaction joins the spring in x'' + x + phi = friction,
            # so that the belt's work there is that of kinetic friction (docs/physics.md)
            phi = rest_force(self.osc, self.c) if self.at_rest else 0.0
        tr = self.track
        tr.t.append(self.t)
        tr.x.append(self.x)
        tr.v.append(self.v)
        tr.acc.append(self.acc)
        tr.mode.append(mode)
        tr.phi.append(phi)
        if self.work is not None:
            self.work.add_point(self.x, self.fr == 0)

    def step_to(self, hh: float) -> tuple[float, float]:
        """The RKF solution a step of ``hh`` from the current state."""
        xn, vn, _, _ = rkf45_step(self.rhs, self.x, self.v, self.acc, hh)
        self.n_eval += STAGES_PER_STEP
        return xn, vn

    def locate(self, s0: float, h_full: float, g_of, dg_of) -> tuple[float, float, float]:
        """Recompute the step to the located fraction ``s0`` and refine it by Newton."""
        hh = s0 * h_full
        xe, ve = self.step_to(hh)
        for _ in range(EVENT_NEWTON):
            g = g_of(xe, ve)
            dg = dg_of(xe, ve)
            if g == 0.0 or dg == 0.0 or not math.isfinite(dg):
                break
            h_new = hh - g / dg
            if not 0.0 < h_new <= h_full:
                break
            x_try, v_try = self.step_to(h_new)
            if abs(g_of(x_try, v_try)) >= abs(g):
                break
            hh, xe, ve = h_new, x_try, v_try
        return hh, xe, ve

    def advance(self, hh: float, xn: float, vn: float) -> None:
        """Move to the end of an accepted (possibly cut) step of length ``hh``; report the
        friction transitions that happened on it (detected, not located: the switch model)
        and store the point."""
        an = self.rhs(xn, vn)
        self.n_eval += 1
        fr_new = self.friction_state(xn, vn)
        if fr_new != self.fr:
            step = (hh, self.t, self.x, self.v, self.acc, xn, vn, an)
            _friction_transition(self, self.fr, fr_new, step)
        self.t = self.t + hh
        self.x, self.v, self.acc, self.fr = xn, vn, an, fr_new
        self.record()

    def impact(self, from_stick: bool) -> None:
        """Rigid impact at ``x = c`` with the approach speed ``v`` (paper Eq. 8)."""
        w = self.v
        v_after = -self.r * w
        kind = TransitionKind.STICK_IMPACT if from_stick else TransitionKind.IMPACT
        self.log.add(kind, self.t, self.c, w, v_after)
        if abs(v_after) <= self.opts.rest_speed and self.pressed:
            self.come_to_rest(w)
            return
        self.v = v_after
        self.acc = self.eval_rhs(self.c, self.v)
        self.fr = self.friction_state(self.c, self.v)
        self.record()

    def come_to_rest(self, w: float) -> None:
        """The bouncing ends on the stop (Zeno guard, module docstring)."""
        t_rest = log_rest_at_stop(self.log, self.t, w, self.r, self.osc.a, self.c, self.t_end)
        self.at_rest = self.contact = True  # the mass sits on the stop: x = c, x' = 0
        self.v = self.acc = 0.0
        self.record()
        for t_next in (min(t_rest, self.t_end), self.t_end):
            if t_next > self.t:
                self.t = t_next
                self.record()

    # --- the loop -----------------------------------------------------------------------------
    def run(self) -> None:
        self.record()
        if self.rigid and self.x >= self.c and self.v > 0.0:
            self.impact(self.fr == 0)
        elif self.rigid and self.x >= self.c and self.v == 0.0 and self.pressed:
            self.come_to_rest(0.0)
        while self.t < self.t_end and not self.at_rest and self.status is Status.SUCCESS:
            stopped = self.limit.reached(self.steps + self.rejected)
            if stopped is not None:
                self.status = stopped
                break
            self.try_step()

    def try_step(self) -> None:
        """One RKF 4(5) trial step: rejected (smaller step), or accepted and handed to the
        events that may cut it."""
        h = min(self.h, self.opts.max_step)
        last = self.t + h >= self.t_end
        if last:
            h = self.t_end - self.t
        xn, vn, ex, ev = rkf45_step(self.rhs, self.x, self.v, self.acc, h)
        self.n_eval += STAGES_PER_STEP
        err = self.control.error(self.x, xn, ex, self.v, vn, ev)
        if not err <= 1.0:  # also catches nan from a stage beyond the limit overlap
            self.reject(h, err)
            return
        self.steps += 1
        h_next = h if last else self.control.grown(h, err)
        if not self.cut(h, xn, vn, h_next):
            self.finish_step(h, xn, vn, h_next, last)

    def reject(self, h: float, err: float) -> None:
        """A rejected step of length ``h``: a smaller one next, or the end of the solve
        where it would be too small (at the limit overlap of a deformable stop)."""
        self.rejected += 1
        self.h = self.control.shrunk(h, err)
        if self.control.too_small(self.h, self.t):
            near_limit = self.soft and self.x - self.c >= 0.5 * self.stop.limit_overlap
            self.status = Status.LIMIT_OVERLAP if near_limit else Status.INTEGRATION_FAILED

    def cut(self, h: float, xn: float, vn: float, h_next: float) -> bool:
        """The first event that cuts an accepted step, each tried only where it can
        happen; True if one did."""
        contact, fr = self.contact, self.fr
        if self.stop is not None and not contact and self.cut_at_stop(h, xn, vn, h_next):
            return True
        if contact and self.cut_in_contact(h, xn, vn, h_next):
            return True
        if fr != 0 and self.cut_at_band(h, xn, vn, h_next):
            return True
        return self.v > 0.0 >= vn and not contact and self.cut_at_top(h, xn, vn, h_next)

    def cut_at_stop(self, h: float, xn: float, vn: float, h_next: float) -> bool:
        """The step reaches the stop: impact (rigid) or the start of a contact (tried off the
        stop only)."""
        c = self.c
        s_ev = x_crossing(h, self.x, self.v, xn, vn, c)
        if s_ev is None:
            return False
        was_stick = self.fr == 0
        hh, _, ve = self.locate(s_ev, h, lambda xx, vv: xx - c, lambda xx, vv: vv)
        self.advance(hh, c, max(ve, 0.0))
        if self.rigid:
            self.impact(was_stick)
        else:
            self.contact = True
            self.set_branch(FIRST_LOADING)
            self.acc = self.eval_rhs(self.x, self.v)
            self.log.add(TransitionKind.CONTACT, self.t, self.x, self.v)
            self.track.mode[-1] = Mode.CONTACT
        self.h = max(h_next, hh)
        return True

    def cut_in_contact(self, h: float, xn: float, vn: float, h_next: float) -> bool:
        """Inside a deformable contact (tried there only): a reversal of the overlap rate
        (the law's branch changes there) or the force passing the stop's strength."""
        if (vn < 0.0) if self.branch.loading else (vn > 0.0):
            an = self.eval_rhs(xn, vn)
            v, acc = self.v, self.acc
            s_ev = root(partial(hermite, h=h, y0=v, d0=acc, y1=vn, d1=an), 0.0, 1.0, v, vn)
            hh, xe, _ = self.locate(s_ev, h, lambda xx, vv: vv, self.rhs)
            if xe > self.c:
                self.advance(hh, xe, 0.0)
                self.set_branch(reverse(self.x - self.c, self.phi_at(self.x), self.branch,
                                        self.stop))
                self.acc = self.eval_rhs(self.x, self.v)
                self.log.add(TransitionKind.REVERSAL, self.t, self.x, 0.0)
                self.h = h_next
                return True
        if math.isfinite(self.stop.strength) and self.phi_at(xn) > self.stop.strength:
            self.advance(h, xn, vn)
            self.log.add(TransitionKind.FAILURE, self.t, self.x, self.v)
            self.status = Status.STOP_FAILED
            return True
        return False

    def cut_at_band(self, h: float, xn: float, vn: float, h_next: float) -> bool:
        """The step jumped over the stick band: cut it where it enters the band (tried in
        slip only)."""
        fr, vb, eta = self.fr, self.osc.v, self.opts.eta
        # fr * (vb - x') is the relative velocity seen from the slip direction at the step's
        # start: beyond -eta the step ended in the other slip, the band skipped
        if fr * (vb - vn) >= -eta:
            return False
        level = vb - fr * eta
        an = self.eval_rhs(xn, vn)
        v, acc = self.v, self.acc
        s_ev = root(
            partial(hermite, h=h, y0=v, d0=acc, y1=vn - level, d1=an, shift=level),
            0.0,
            1.0,
            v - level,
            vn - level,
        )
        hh, xe, _ = self.locate(s_ev, h, lambda xx, vv: vv - level, self.rhs)
        self.advance(hh, xe, band_edge(self.osc.v, self.opts.eta, fr))
        self.h = h_next
        return True

    def cut_at_top(self, h: float, xn: float, vn: float, h_next: float) -> bool:
        """A maximum of ``x`` inside the step (tried off contact where ``x'`` falls through
        0): stored as a point, so ``x_max`` has the integration accuracy."""
        v = self.v
        an = self.eval_rhs(xn, vn)
        s_top = root(partial(hermite, h=h, y0=v, d0=self.acc, y1=vn, d1=an), 0.0, 1.0, v, vn)
        if not 0.0 < s_top < 1.0:
            return False
        xt, vt = self.step_to(s_top * h)
        self.advance(s_top * h, xt, vt)
        self.h = h_next
        return True

    def finish_step(self, h: float, xn: float, vn: float, h_next: float, last: bool) -> None:
        """Take the whole step; a deformable contact may have ended inside it."""
        x_prev, v_prev, a_prev = self.x, self.v, self.acc
        self.advance(h, xn, vn)
        if last:
            self.t = self.t_end
            self.track.t[-1] = self.t_end
        c = self.c
        if self.contact and self.x <= c:
            s_sep = root(
                partial(hermite, h=h, y0=x_prev, d0=v_prev, y1=self.x - c, d1=self.v, shift=c),
                0.0,
                1.0,
                x_prev - c,
                self.x - c,
            )
            v_sep = hermite(s_sep, h, v_prev, a_prev, self.v, self.acc)
            self.log.add(TransitionKind.SEPARATION, self.t - h + s_sep * h, c, v_sep)
            self.contact = False
            self.set_branch(FIRST_LOADING)
            self.track.mode[-1] = Mode.STICK if self.fr == 0 else Mode.SLIP
        self.h = h_next

    # --- the result ---------------------------------------------------------------------------
    def result(self) -> Result:
        tr, eta = self.track, self.opts.eta
        stats = make_stats(
            segments=1,
            steps=self.steps,
            rejected=self.rejected,
            rhs_evals=self.n_eval,
            events=self.log.total,
        )
        return result_from_track(
            tr,
            self.log,
            self.inputs,
            rtol=self.opts.rtol,
            # the stick band's model error (~eta / v) moves each transition state by about
            # that much; it does not grow with the horizon as the integration error does
            model_rtol=max(eta / max(self.osc.v, eta), TRANSITION_SCATTER),
            status=self.status,
            method="switch",
            stats=stats,
            info={"eta": eta},
            dense=HermiteDense(tr.t, tr.x, tr.v, tr.acc, self.c if self.rigid else None),
            stop_law=self.work,
        )


def _friction_transition(run: SwitchSolver, fr: int, fr_new: int, step: tuple) -> None:
    """Report a friction transition found at the end of a step, at its interpolated time.

    Slip->stick where ``x'`` enters the band, stick->slip where the applied force reaches
    ``b``, a sign change where ``x' = v`` (paper §2.5). ``step`` is ``(h, t0, x0, v0, a0,
    x1, v1, a1)``: its length and the states at its ends.
    """
    h, t0, x0, v0, a0, x1, v1, a1 = step
    vb, eta, b = run.osc.v, run.opts.eta, run.osc.b

    def xv(s: float) -> tuple[float, float]:
        return hermite(s, h, x0, v0, x1, v1), hermite(s, h, v0, a0, v1, a1)

    if fr_new == 0:
        kind = TransitionKind.SLIP_STICK
        level = vb - fr * eta

        def g(s: float) -> float:
            return xv(s)[1] - level

    elif fr == 0:
        kind = TransitionKind.STICK_SLIP

        def g(s: float) -> float:
            xx = xv(s)[0]
            return abs(xx + run.phi_at(xx)) - b

    else:
        kind = TransitionKind.SIGN_CHANGE

        def g(s: float) -> float:
            return xv(s)[1] - vb

    g0, g1 = g(0.0), g(1.0)
    s = root(g, 0.0, 1.0, g0, g1) if g0 * g1 < 0.0 else 1.0
    xs, vs = xv(s)
    run.log.add(kind, t0 + s * h, xs, vs)


@takes_options(SwitchOptions)
def solve_switch(inputs: SolveInputs, opts: SwitchOptions) -> Result:
    """Response by the switch model and adaptive RKF 4(5), the paper's method.

    :func:`simulate_switch` takes the scene, horizon, start and sampling as
    :func:`core.simulate` does (:class:`~core.solve_inputs.SolveInputs`); ``t_eval`` is
    sampled on the cubic Hermite interpolant of the steps (after an early stop, only the
    times it reached).

    Parameters
    ----------
    inputs : SolveInputs
        The checked scene, horizon, start and sampling.
    rtol, atol : float
        Relative and absolute tolerance of the RKF 4(5) error control, on ``x`` and ``x'``.
    eta : float, optional
        Half-width of the stick band ``|v - x'| <= eta`` (paper Eq. 7); default
        ``ETA_REL * v`` (``ETA_REL * max(a, b)`` on a still belt).
    max_step : float
        Largest step.
    rest_speed : float, optional
        Rebound speed below which a mass pressed on a rigid stop is taken to rest there
        (the Zeno guard, see the module docstring); default ``eta``.
    max_steps : int
        Largest number of Runge-Kutta steps tried (accepted and rejected); default
        :data:`DEFAULT_MAX_STEPS`. When it is reached the solve stops with
        ``Status.STEP_LIMIT`` and the result covers the time up to that point (``t[-1]``).
    time_budget : float, optional
        Wall-clock seconds the solve may take; when they run out it stops with
        ``Status.TIME_BUDGET`` (result up to that point). ``None``: no budget.

    Returns
    -------
    Result
        ``method="switch"``; ``stats`` (:func:`core.result.make_stats`) counts ``steps``
        (accepted), ``rejected``, ``rhs_evals`` and ``events`` (one ``segment``);
        ``info["eta"]`` is the stick band; ``dense`` the Hermite interpolant of the steps
        for :meth:`~core.result.Result.evaluate`. The switch model has no limit on events
        of its own: each is a cut step, counted by ``max_steps``.

    Examples
    --------
    >>> from core import Oscillator
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> res = simulate_switch(osc, t_end=10.0)
    >>> round(res.x_max, 5)           # fast belt: x_max = 2a (paper §3)
    0.4
    """
    opts = opts.for_scene(inputs.osc)
    run = SwitchSolver(inputs, opts, WorkLimit(opts.max_steps, opts.time_budget))
    run.run()
    return run.result()


#: :func:`solve_switch` with the inputs of :func:`core.simulate`.
simulate_switch = solve_entry(solve_switch)
