"""Event-driven integration of the non-smooth model with :func:`scipy.integrate.solve_ivp`.

A second numerical method beside the switch model (:mod:`core.switch`): the non-smooth
Coulomb model (paper Eqs. 3-6) is integrated mode by mode, each mode a smooth ODE, and every
mode change is an event located by ``solve_ivp``'s root finder on its dense output. No stick
band, no regularisation: the error is the integration error alone.

Modes and the events that end them
----------------------------------
* **slip** with a fixed ``s`` (``x'' = -x + s*a - phi``, paper Eq. 3 and Eq. 14 in contact):
  ``x' = v`` (relative velocity vanishes: stick if ``|x + phi| <= b``, else the sign of the
  relative velocity changes, SPEC §2); ``x = clearance`` with ``x' > 0`` (rigid impact,
  paper Eq. 8, or the start of a deformable contact); in a deformable contact, ``x' = 0``
  (reversal of the overlap rate: the branch of the hysteresis law is updated with
  :func:`core.hysteresis.reverse`), ``x = clearance`` with ``x' < 0`` (separation), the
  force reaching the stop's strength (failure), the overlap reaching the limit overlap.
  A non-terminal event at ``x' = 0`` records every maximum of ``x`` as a point, so
  ``x_max`` has the integration accuracy.
* **stick** (``x' = v``): in closed form, ``x = x_0 + v t``, up to ``x = b``, the stop, or in
  a deformable contact up to ``x + phi(x - clearance) = b`` (one monotone root by
  :func:`scipy.optimize.brentq`: along stick the overlap only grows, so the force follows
  one loading branch).

Impact accumulation (Zeno, SPEC §3) is handled as in the switch model: a rebound slower than
``rest_speed`` while the belt presses the mass on the stop ends the bouncing; the remaining
arc durations are summed in closed form to give the accumulation time. The default
``rest_speed = sqrt(2 atol (a - clearance))`` keeps the neglected rebounds' height
``w^2 / (2 (a - clearance))`` below ``atol``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from core.dense import TransitionLog, log_rest_at_stop, result_from_dense
from core.hysteresis import FIRST_LOADING, force_and_slope, reverse, stored_energy
from core.params import HystereticStop, Oscillator, RigidStop
from core.result import Mode, Result, Status, TransitionKind
from core.validation import check_range, check_start

#: Integrators of :func:`scipy.integrate.solve_ivp` offered (explicit RK pairs, an implicit
#: Radau IIA method for stiff contact, and LSODA's automatic stiffness switching).
SOLVERS = ("RK45", "DOP853", "Radau", "LSODA")
#: Points that describe a stick segment inside a deformable contact (the force is a
#: nonlinear function of the overlap there; on free stick two points are exact).
STICK_CONTACT_POINTS = 16
#: An overlap within this fraction of the limit overlap ``D`` counts as reaching it.
LIMIT_OVERLAP_FRACTION = 1.0 - 1e-9
#: Relative tolerance of the stick-in-contact end point (monotone bracketed root).
STICK_ROOT_RTOL = 4.0 * np.finfo(float).eps
#: Largest step of a rebound arc from a rigid stop, as a fraction of its estimated duration
#: ``2|x'|/|x''|`` (only the segment that starts at the stop).
REBOUND_STEP_FRACTION = 0.25
#: Absolute time tolerance of a crossing found on the dense output (dimensionless time).
ROOT_XTOL = 1e-15
#: Largest number of restarts (events) before giving up with INTEGRATION_FAILED: a guard
#: against an event that keeps firing at the same time.
MAX_SEGMENTS = 5_000_000
#: Restarts at (numerically) the same time that count as an event stuck in place.
MAX_SAME_TIME = 64


def _phi(stop: HystereticStop, branch, x: float) -> float:
    d = x - stop.clearance
    return force_and_slope(d, branch, stop)[0] if d > 0.0 else 0.0


def simulate_event(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None = None,
    t_end: float = 100.0,
    x0: float = 0.0,
    v0: float = 0.0,
    *,
    n_samples: int = 2000,
    transition_cap: int = 10_000,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    solver: str = "RK45",
    rest_speed: float | None = None,
) -> Result:
    """Response by ``solve_ivp`` with event location on the non-smooth model.

    Parameters
    ----------
    osc : Oscillator
    stop : RigidStop, HystereticStop or None
    t_end : float
        Horizon (dimensionless time), ``> 0``.
    x0, v0 : float
        Initial state (``x0 <= clearance`` for a rigid stop).
    n_samples : int
        Uniform samples of the result (transition points are added).
    transition_cap : int
        Transitions stored (all are counted).
    rtol, atol : float
        Tolerances handed to ``solve_ivp``.
    solver : {"RK45", "DOP853", "Radau", "LSODA"}
        The ``solve_ivp`` method.
    rest_speed : float, optional
        Rebound speed below which a mass pressed on a rigid stop rests there (Zeno guard);
        default ``sqrt(2 atol (a - clearance))``.

    Returns
    -------
    Result
        ``method="event"``; ``stats`` holds ``segments`` (solve_ivp calls), ``steps``
        (accepted step points) and ``rhs_evals``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> res = simulate_event(osc, t_end=2.0)
    >>> tr = res.transitions[0]     # Eq. (30): first stick at x = a - sqrt(a^2 - v^2)
    >>> tr.kind.value, round(tr.x, 8)
    ('slip->stick', 0.02679492)
    """
    t_end = check_range("t_end", t_end, 0.0, low_open=True)
    x0 = check_range("x0", x0)
    v0 = check_range("v0", v0)
    rtol = check_range("rtol", rtol, 0.0, low_open=True)
    atol = check_range("atol", atol, 0.0, low_open=True)
    n_samples = int(check_range("n_samples", n_samples, 2))
    transition_cap = int(check_range("transition_cap", transition_cap, 0))
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {solver!r}")
    rigid = isinstance(stop, RigidStop)
    soft = isinstance(stop, HystereticStop)
    c = stop.clearance if stop is not None else math.inf
    if stop is not None:
        check_start(x0, c, stop.limit_overlap if soft else None)
    a, b, vb = osc.a, osc.b, osc.v
    r = stop.restitution if rigid else 1.0
    if rest_speed is None:
        rest_speed = math.sqrt(2.0 * atol * max(a - c, 0.0)) if rigid else 0.0
    else:
        rest_speed = check_range("rest_speed", rest_speed, 0.0)

    log = TransitionLog(transition_cap)
    ts: list[float] = []
    xs: list[float] = []
    vs: list[float] = []
    accs: list[float] = []
    modes: list[int] = []
    phis: list[float] = []
    n_eval = n_steps = n_seg = 0
    status = Status.SUCCESS

    contact = soft and x0 > c
    branch = FIRST_LOADING
    t, x, v = 0.0, x0, v0

    def phi_now(xx: float) -> float:
        return _phi(stop, branch, xx) if soft and contact else 0.0

    def start_mode(xx: float, vv: float) -> int:
        """+1/-1 slip with that sign, 0 stick (SPEC §2; the relative velocity decides)."""
        if vv < vb:
            return 1
        if vv > vb:
            return -1
        f = xx + phi_now(xx)
        if abs(f) <= b:
            return 0
        return 1 if f > 0.0 else -1

    def point(tt: float, xx: float, vv: float, aa: float, fr_: int) -> None:
        ts.append(tt)
        xs.append(xx)
        vs.append(vv)
        accs.append(aa)
        modes.append(Mode.CONTACT if contact else (Mode.STICK if fr_ == 0 else Mode.SLIP))
        if soft:
            phis.append(phi_now(xx))

    def slip_acc(xx: float, s_: int) -> float:
        return -xx + s_ * a - phi_now(xx)

    def pressed() -> bool:
        return a >= c if vb > 0.0 else abs(c) <= b

    at_rest = False

    def rest_from(w: float) -> None:
        """The bouncing ends: rest on the stop (after the accumulation time for 0<r<1)."""
        nonlocal at_rest
        t_rest = log_rest_at_stop(log, t, w, r, a, c, t_end)
        for tt in (t, min(max(t_rest, t), t_end), t_end):
            point(tt, c, 0.0, 0.0, 0)
            modes[-1] = Mode.CONTACT
        at_rest = True

    def impact(w: float, from_stick: bool) -> int:
        nonlocal v
        v_after = -r * w
        kind = TransitionKind.STICK_IMPACT if from_stick else TransitionKind.IMPACT
        log.add(kind, t, c, w, v_after)
        if abs(v_after) <= rest_speed and pressed():
            rest_from(w)
            return 0
        v = v_after
        fr_ = start_mode(c, v)
        point(t, c, v, 0.0 if fr_ == 0 else slip_acc(c, fr_), fr_)
        return fr_

    fr = start_mode(x, v)
    point(t, x, v, 0.0 if fr == 0 else slip_acc(x, fr), fr)
    if rigid and x >= c and v > 0.0:
        fr = impact(v, fr == 0)
    elif rigid and x >= c and v == 0.0 and pressed():
        rest_from(0.0)

    same_time = 0
    while t < t_end and not at_rest and status is Status.SUCCESS:
        n_seg += 1
        t_before = t
        if n_seg > MAX_SEGMENTS:
            status = Status.INTEGRATION_FAILED
            break
        if fr == 0:
            # --- stick in closed form (paper Eqs. 5-6) ----------------------------------
            if vb <= 0.0:
                point(t_end, x, 0.0, 0.0, 0)
                t = t_end
                break
            if soft and contact:
                kind, x_e = _stick_contact_end(stop, branch, x, b)
                t_e = t + (x_e - x) / vb
                t_stop = min(t_e, t_end)
                for xx in np.linspace(x, x + vb * (t_stop - t), STICK_CONTACT_POINTS)[1:]:
                    point(t + (xx - x) / vb, float(xx), vb, 0.0, 0)
                if t_e >= t_end:
                    t = t_end
                    break
                t, x, v = t_e, x_e, vb
                if kind is TransitionKind.FAILURE:
                    log.add(kind, t, x, v)
                    status = Status.STOP_FAILED
                    break
                if kind is None:
                    status = Status.LIMIT_OVERLAP
                    break
                log.add(TransitionKind.STICK_SLIP, t, x, v)
                fr = 1
                point(t, x, v, slip_acc(x, fr), fr)  # right limit: the acceleration jumps
                continue
            target = min(b, c)
            t_e = t + max(target - x, 0.0) / vb
            if t_e >= t_end:
                x += vb * (t_end - t)
                t = t_end
                point(t, x, vb, 0.0, 0)
                break
            t, x, v = t_e, target, vb
            if rigid and c <= b:
                point(t, x, v, 0.0, 0)
                fr = impact(vb, True)
            elif soft and c < b:
                contact = True
                branch = FIRST_LOADING
                log.add(TransitionKind.CONTACT, t, x, v)
                point(t, x, v, 0.0, 0)
            else:
                log.add(TransitionKind.STICK_SLIP, t, x, v)
                point(t, x, v, 0.0, 0)  # left limit of the acceleration (stick)
                fr = 1
                point(t, x, v, slip_acc(x, fr), fr)
            continue

        # --- slip with fixed s: an ODE with events ----------------------------------------
        s = fr
        events, kinds = _slip_events(s, vb, c, rigid, soft, contact, branch, stop)
        if soft and contact:
            br = branch

            def fun(_t, y, s=s, br=br):
                d = y[0] - c
                p = force_and_slope(d, br, stop)[0] if d > 0.0 else 0.0
                return [y[1], -y[0] + s * a - p]

        else:

            def fun(_t, y, s=s):
                return [y[1], -y[0] + s * a]

        watch = stop is not None and not contact  # a crossing inside one step can be missed
        opts = {}
        if watch and x == c and v < 0.0 and slip_acc(x, s) > 0.0:
            # pushed back to the stop, a rebound arc lasts about 2|x'|/x'': steps must not
            # jump over it (the event function would see no sign change, or a root at t)
            opts["max_step"] = REBOUND_STEP_FRACTION * 2.0 * abs(v) / slip_acc(x, s)
        try:
            sol = solve_ivp(
                fun,
                (t, t_end),
                [x, v],
                method=solver,
                rtol=rtol,
                atol=atol,
                events=events,
                dense_output=watch,
                **opts,
            )
        except ValueError:
            # solve_ivp's event root search failed: the interpolant of an implicit method
            # (LSODA) did not reproduce the sign change its step end points showed
            status = Status.INTEGRATION_FAILED
            break
        n_eval += sol.nfev
        n_steps += len(sol.t) - 1
        if sol.status == -1:
            status = Status.INTEGRATION_FAILED
            break
        end_kind = None
        t_stop_at, y_stop_at = float(sol.t[-1]), sol.y[:, -1]
        if sol.status == 1:
            for kname, tev in zip(kinds, sol.t_events, strict=False):
                if kname != "top" and len(tev) and tev[-1] == t_stop_at:
                    end_kind = kname
                    break
        tops = [
            (te, ye)
            for te, ye in zip(sol.t_events[0], sol.y_events[0], strict=True)
            if te < t_stop_at
        ]
        if watch:
            missed = _missed_crossing(sol, tops, c)
            if missed is not None:
                t_stop_at, y_stop_at = missed
                end_kind = "stop"
        # the step points, merged with the maxima of x (non-terminal event 0)
        pts = [(float(sol.t[i]), sol.y[:, i]) for i in range(1, len(sol.t))]
        pts += [(float(te), ye) for te, ye in tops]
        pts = sorted((p for p in pts if p[0] < t_stop_at), key=lambda p: p[0])
        if end_kind is None:
            pts.append((t_stop_at, y_stop_at))
        for tt, yy in pts:
            point(tt, float(yy[0]), float(yy[1]), slip_acc(float(yy[0]), s), s)
        t = t_stop_at
        x, v = float(y_stop_at[0]), float(y_stop_at[1])
        if end_kind is None:
            break
        same_time = same_time + 1 if t <= t_before else 0
        if same_time > MAX_SAME_TIME:
            status = Status.INTEGRATION_FAILED
            break

        if end_kind == "ur":
            v = vb
            f = x + phi_now(x)
            point(t, x, v, slip_acc(x, s), s)  # left limit of the acceleration
            if abs(f) <= b:
                log.add(TransitionKind.SLIP_STICK, t, x, v)
                fr = 0
            else:
                log.add(TransitionKind.SIGN_CHANGE, t, x, v)
                fr = 1 if f > 0.0 else -1
            point(t, x, v, 0.0 if fr == 0 else slip_acc(x, fr), fr)  # right limit
        elif end_kind == "stop" and rigid:
            x = c
            point(t, x, v, slip_acc(x, s), s)
            fr = impact(max(v, 0.0), False)
        elif end_kind == "stop":
            x = c
            contact = True
            branch = FIRST_LOADING
            log.add(TransitionKind.CONTACT, t, x, v)
            point(t, x, v, slip_acc(x, s), s)
        elif end_kind == "separation":
            x = c
            contact = False
            branch = FIRST_LOADING
            log.add(TransitionKind.SEPARATION, t, x, v)
            fr = start_mode(x, v)
            point(t, x, v, 0.0 if fr == 0 else slip_acc(x, fr), fr)
        elif end_kind == "reversal":
            v = 0.0
            branch = reverse(x - c, _phi(stop, branch, x), branch)
            log.add(TransitionKind.REVERSAL, t, x, v)
            fr = start_mode(x, v)
            point(t, x, v, 0.0 if fr == 0 else slip_acc(x, fr), fr)
        elif end_kind == "failure":
            log.add(TransitionKind.FAILURE, t, x, v)
            point(t, x, v, slip_acc(x, s), s)
            status = Status.STOP_FAILED
        elif end_kind == "limit":
            point(t, x, v, slip_acc(x, s), s)
            status = Status.LIMIT_OVERLAP

    return result_from_dense(
        ts,
        xs,
        vs,
        modes,
        log,
        t_end=t_end,
        n_samples=n_samples,
        transition_cap=transition_cap,
        acc=accs,
        contact_force=phis if soft else None,
        overlap=[xx - c for xx in xs] if soft else None,
        stop_stored=(lambda d, p: stored_energy(d, p, stop)) if soft else None,
        rtol=rtol,
        belt_speed=vb,
        x_upper=c if rigid else None,
        status=status,
        method="event",
        stats={"segments": n_seg, "steps": n_steps, "rhs_evals": n_eval, "solver": solver},
    )


def _slip_events(s, vb, c, rigid, soft, contact, branch, stop):
    """Event functions of a slip segment and their names (see the module docstring)."""
    events, kinds = [], []

    def top(_t, y):
        return y[1]

    top.terminal, top.direction = False, -1.0
    events.append(top)
    kinds.append("top")

    def ur(_t, y):
        return y[1] - vb

    ur.terminal, ur.direction = True, 1.0 if s > 0 else -1.0
    events.append(ur)
    kinds.append("ur")
    if rigid or (soft and not contact):

        def hit(_t, y):
            return y[0] - c

        hit.terminal, hit.direction = True, 1.0
        events.append(hit)
        kinds.append("stop")
    elif soft:

        def sep(_t, y):
            return y[0] - c

        sep.terminal, sep.direction = True, -1.0

        def rev(_t, y):
            return y[1]

        rev.terminal, rev.direction = True, -1.0 if branch.loading else 1.0
        d_lim = stop.limit_overlap * LIMIT_OVERLAP_FRACTION

        def limit(_t, y):
            return y[0] - c - d_lim

        limit.terminal, limit.direction = True, 1.0
        events += [sep, rev, limit]
        kinds += ["separation", "reversal", "limit"]
        if math.isfinite(stop.strength):

            def fail(_t, y):
                return _phi(stop, branch, y[0]) - stop.strength

            fail.terminal, fail.direction = True, 1.0
            events.append(fail)
            kinds.append("failure")
    return events, kinds


def _missed_crossing(sol, tops, c: float):
    """First crossing of ``x = c`` that the event function missed, or ``None``.

    A grazing arc can rise above the stop and fall back inside one step: no sign change at
    the step ends, so ``solve_ivp`` sees no event. Every maximum of ``x`` is an event
    (``x' = 0``); a maximum beyond the stop betrays the missed crossing, which is then found
    on the dense output between the step point before it and the maximum.
    """
    for te, ye in tops:
        if ye[0] > c:
            i = max(int(np.searchsorted(sol.t, te, side="left")) - 1, 0)
            t_lo = float(sol.t[i])
            if sol.sol(t_lo)[0] > c:  # the previous crossing fired no event either
                t_lo = float(sol.t[0])
            t_c = brentq(
                lambda tt: sol.sol(tt)[0] - c, t_lo, float(te), xtol=ROOT_XTOL, rtol=STICK_ROOT_RTOL
            )
            y_c = sol.sol(t_c)
            return t_c, np.array([c, max(float(y_c[1]), 0.0)])
    return None


def _stick_contact_end(stop: HystereticStop, branch, x: float, b: float):
    """End of stick inside a deformable contact: ``x + phi = b`` (stick->slip), the force
    reaching the strength (``FAILURE``) or the limit overlap (``None``), whichever first.

    Along stick the overlap grows, so ``x + phi`` grows monotonically on the loading branch.
    """
    c, d_lim = stop.clearance, stop.limit_overlap
    x_hi = c + d_lim * LIMIT_OVERLAP_FRACTION

    def g(xx: float) -> float:
        return xx + _phi(stop, branch, xx) - b

    candidates = []
    if g(x) >= 0.0:
        return TransitionKind.STICK_SLIP, x
    if g(x_hi) > 0.0:
        candidates.append((brentq(g, x, x_hi, rtol=STICK_ROOT_RTOL), TransitionKind.STICK_SLIP))
    if math.isfinite(stop.strength):

        def gf(xx: float) -> float:
            return _phi(stop, branch, xx) - stop.strength

        if gf(x) < 0.0 < gf(x_hi):
            candidates.append((brentq(gf, x, x_hi, rtol=STICK_ROOT_RTOL), TransitionKind.FAILURE))
    if not candidates:
        return None, x_hi
    x_e, kind = min(candidates, key=lambda p: p[0])
    return kind, x_e
