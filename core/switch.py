"""The paper's numerical method: the switch model integrated by Runge-Kutta-Fehlberg 4(5).

Andreaus & Casini integrate the non-smooth oscillator with the switch model of Leine et al.
(1998) (paper §2.2, Eq. 7, Fig. 1c) and an adaptive Runge-Kutta-Fehlberg 4(5) scheme (paper
§2.5). The project keeps it as one selectable method, the baseline that the exact and
event-driven solvers are measured against (SPEC §5).

The switch model (state ``(x, x')``, relative velocity ``u_r = v - x'``, applied force over
``k`` ``F = -x - phi``):

* ``|u_r| > eta`` (slip): ``x'' = F + s*a`` with ``s = sign(u_r)`` (paper Eq. 3);
* ``|u_r| <= eta`` and ``|F| <= b`` (stick): ``x'' = 0``, the belt's acceleration;
* ``|u_r| <= eta`` and ``|F| > b`` (stick->slip transition): ``x'' = F - b sign(F)``, static
  friction at its limit against the applied force, which takes the mass out of the band.

The right-hand side is discontinuous across the band edges; nothing locates those switches:
the error control of the embedded pair shrinks the step across them, which is what the
method costs. Its error is ``O(eta)`` for stick (the mass sticks at ``x' = v -+ eta``
instead of ``v``) on top of the integration error; :mod:`benchmarks.work_precision` measures
both.

The stop
--------
* Rigid (paper Eq. 8): the crossing of ``x = clearance`` is located inside the accepted step
  (cubic Hermite root, then the RKF step recomputed to that time with one Newton
  correction), the state is put on the stop and the velocity reflected, ``x' -> -r x'``.
  The samples therefore never pass the stop.
* Deformable (paper Eqs. 9-15): the contact force of :mod:`core.hysteresis` enters ``F``;
  its branch (the memory of the law) is held fixed over a step, and the step is cut where
  the overlap rate changes sign so that :func:`core.hysteresis.reverse` stores the reversal
  point; contact start is cut too (a new contact starts on the first-loading branch).

Impact accumulation (Zeno)
--------------------------
For ``0 < r < 1`` and ``clearance < a`` the rebound speeds fall as ``r^h`` and infinitely
many impacts happen in finite time (SPEC §3). A rebound slower than ``rest_speed`` (default
``eta``, the model's own velocity resolution) while the belt presses the mass on the stop
(``a >= clearance`` on a moving belt; ``|clearance| <= b`` on a still one) ends the
bouncing: the rest of the geometric series of arc durations ``2 atan(r^h w / (a -
clearance))`` is summed in closed form to give the accumulation time, and from there the
mass rests on the stop. The number of impacts is thus bounded by ``log(rest_speed/w_0) /
log(1/r)``.
"""

from __future__ import annotations

import math
from functools import partial

from core.dense import TransitionLog, log_rest_at_stop, result_from_dense
from core.hysteresis import FIRST_LOADING, Branch, force_and_slope, reverse, stored_energy
from core.numerics.limits import MAX_STEPS, WorkLimit
from core.params import HystereticStop, Oscillator, RigidStop
from core.result import Mode, Result, Status, TransitionKind
from core.validation import check_range, check_start

# --- Runge-Kutta-Fehlberg 4(5) coefficients (Fehlberg 1969, "Formula 2" of Table III) ------
A21 = 1.0 / 4.0
A31, A32 = 3.0 / 32.0, 9.0 / 32.0
A41, A42, A43 = 1932.0 / 2197.0, -7200.0 / 2197.0, 7296.0 / 2197.0
A51, A52, A53, A54 = 439.0 / 216.0, -8.0, 3680.0 / 513.0, -845.0 / 4104.0
A61, A62, A63, A64, A65 = -8.0 / 27.0, 2.0, -3544.0 / 2565.0, 1859.0 / 4104.0, -11.0 / 40.0
#: Fourth-order weights: the solution that is advanced (classic Fehlberg, no extrapolation).
B1, B3, B4, B5 = 25.0 / 216.0, 1408.0 / 2565.0, 2197.0 / 4104.0, -1.0 / 5.0
#: Fifth-order minus fourth-order weights: the local error estimate.
E1, E3, E4, E5, E6 = (
    16.0 / 135.0 - B1,
    6656.0 / 12825.0 - B3,
    28561.0 / 56430.0 - B4,
    -9.0 / 50.0 - B5,
    2.0 / 55.0,
)

# --- step-size control -------------------------------------------------------------------
#: Safety factor of the step-size update ``h * SAFETY * err**(-1/5)``.
SAFETY = 0.9
#: Largest growth of the step between two steps.
FACTOR_MAX = 5.0
#: Largest shrink of the step after a rejection.
FACTOR_MIN = 0.2
#: Exponent of the update: the error estimate is ``O(h^5)`` for the fourth-order solution.
ERROR_EXPONENT = -1.0 / 5.0
#: First trial step (dimensionless time); the controller grows it within a few steps.
FIRST_STEP = 1e-3
#: A step below this many ulps of the current time means the integration cannot proceed.
MIN_STEP_ULPS = 64.0

# --- the switch model --------------------------------------------------------------------
#: Default stick-band half-width relative to the belt speed, ``eta = ETA_REL * v``
#: (``eta << v``, SPEC §5); on a still belt relative to ``max(a, b)``.
ETA_REL = 1e-4

# --- event location ----------------------------------------------------------------------
#: Iterations of the safeguarded root search on a step's Hermite interpolant (bisection
#: halves the bracket each time: 2**-60 of a step is below double precision).
ROOT_ITER = 60
#: Newton corrections of a located event with the recomputed Runge-Kutta step.
EVENT_NEWTON = 2
#: An overlap within this fraction of the limit overlap ``D`` counts as reaching it.
LIMIT_OVERLAP_FRACTION = 1.0 - 1e-9


def rkf45_step(f, x: float, v: float, a1: float, h: float) -> tuple[float, float, float, float]:
    """One Runge-Kutta-Fehlberg 4(5) step of ``x' = v, v' = f(x, v)``.

    Parameters
    ----------
    f : callable
        Acceleration ``f(x, v)``.
    x, v : float
        State at the start.
    a1 : float
        ``f(x, v)`` (the first stage, reused from the end of the previous step).
    h : float
        Step size.

    Returns
    -------
    x4, v4 : float
        Fourth-order solution at ``t + h``.
    ex, ev : float
        Error estimate (fifth- minus fourth-order solution).

    Examples
    --------
    >>> x4, v4, ex, ev = rkf45_step(lambda x, v: -x, 1.0, 0.0, -1.0, 0.1)
    >>> abs(x4 - math.cos(0.1)) < 1e-7, abs(ex) < 1e-7
    (True, True)
    """
    v2 = v + h * A21 * a1
    a2 = f(x + h * A21 * v, v2)
    v3 = v + h * (A31 * a1 + A32 * a2)
    a3 = f(x + h * (A31 * v + A32 * v2), v3)
    v4s = v + h * (A41 * a1 + A42 * a2 + A43 * a3)
    a4 = f(x + h * (A41 * v + A42 * v2 + A43 * v3), v4s)
    v5 = v + h * (A51 * a1 + A52 * a2 + A53 * a3 + A54 * a4)
    a5 = f(x + h * (A51 * v + A52 * v2 + A53 * v3 + A54 * v4s), v5)
    v6 = v + h * (A61 * a1 + A62 * a2 + A63 * a3 + A64 * a4 + A65 * a5)
    a6 = f(x + h * (A61 * v + A62 * v2 + A63 * v3 + A64 * v4s + A65 * v5), v6)
    x4 = x + h * (B1 * v + B3 * v3 + B4 * v4s + B5 * v5)
    v4 = v + h * (B1 * a1 + B3 * a3 + B4 * a4 + B5 * a5)
    ex = h * (E1 * v + E3 * v3 + E4 * v4s + E5 * v5 + E6 * v6)
    ev = h * (E1 * a1 + E3 * a3 + E4 * a4 + E5 * a5 + E6 * a6)
    return x4, v4, ex, ev


def switch_rhs(osc: Oscillator, eta: float, stop: HystereticStop | None, branch: Branch | None):
    """The switch model's acceleration ``f(x, x')`` (paper Eq. 7 with Eq. 14 in contact).

    Parameters
    ----------
    osc : Oscillator
    eta : float
        Half-width of the stick band ``|v - x'| <= eta``.
    stop : HystereticStop or None
        Deformable stop whose contact force enters the applied force, or ``None``.
    branch : Branch or None
        Branch of the contact law held over the step.

    Returns
    -------
    callable
        ``f(x, v) -> x''``.

    Examples
    --------
    >>> f = switch_rhs(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1), 1e-5, None, None)
    >>> f(0.0, 0.0), f(0.1, 0.1), f(0.4, 0.1)   # slip, stick, stick->slip
    (0.2, 0.0, -0.10000000000000003)
    """
    a, b, vb = osc.a, osc.b, osc.v
    if stop is None or branch is None:

        def rhs(x: float, v: float) -> float:
            ur = vb - v
            if ur > eta:
                return a - x
            if ur < -eta:
                return -a - x
            if x < -b:
                return -x - b
            if x > b:
                return b - x
            return 0.0

        return rhs

    c = stop.clearance
    d_lim = stop.limit_overlap * LIMIT_OVERLAP_FRACTION

    def rhs_contact(x: float, v: float) -> float:
        d = x - c
        if d > 0.0:
            if d >= d_lim:
                return -math.inf
            force = -x - force_and_slope(d, branch, stop)[0]
        else:
            force = -x
        ur = vb - v
        if ur > eta:
            return force + a
        if ur < -eta:
            return force - a
        if force > b:
            return force - b
        if force < -b:
            return force + b
        return 0.0

    return rhs_contact


def _hermite(
    s: float, h: float, y0: float, d0: float, y1: float, d1: float, shift: float = 0.0
) -> float:
    """Cubic Hermite interpolant on a step at fraction ``s`` in ``[0, 1]``, minus ``shift``
    (the end value ``y1`` is then given already shifted)."""
    s2 = s * s
    s3 = s2 * s
    y0 = y0 - shift
    return y0 + (3 * s2 - 2 * s3) * (y1 - y0) + h * ((s3 - 2 * s2 + s) * d0 + (s3 - s2) * d1)


def _root(g, lo: float, hi: float, g_lo: float, g_hi: float) -> float:
    """Root of ``g`` in ``[lo, hi]`` with ``g_lo, g_hi`` of opposite signs (Illinois method)."""
    side = 0
    for _ in range(ROOT_ITER):
        if g_hi == g_lo:
            break
        m = hi - g_hi * (hi - lo) / (g_hi - g_lo)
        if not lo < m < hi:
            m = 0.5 * (lo + hi)
        gm = g(m)
        if gm == 0.0:
            return m
        if (gm > 0.0) == (g_hi > 0.0):
            hi, g_hi = m, gm
            if side == 1:
                g_lo *= 0.5
            side = 1
        else:
            lo, g_lo = m, gm
            if side == -1:
                g_hi *= 0.5
            side = -1
        if hi - lo <= 4e-16 * max(abs(hi), 1.0):
            break
    return lo if abs(g_lo) < abs(g_hi) else hi


def _x_crossing(h, x0, v0, x1, v1, level) -> float | None:
    """Fraction of the step where the Hermite ``x`` first rises through ``level``, or None.

    Also finds a crossing inside the step that the end points miss: ``x`` rises above
    ``level`` and falls back (a maximum inside the step).
    """
    g0 = x0 - level
    if g0 > 0.0:
        return None

    def g(s: float) -> float:
        return _hermite(s, h, x0, v0, x1, v1) - level

    if g0 == 0.0:
        # leaving the stop (after an impact): a short rebound arc can come back inside the
        # same step; look for the crossing after the interpolant's minimum
        if v0 >= 0.0 or x1 <= level or v1 <= 0.0:
            return None
        s_low = _root(lambda s: _hermite_dx(s, h, x0, v0, x1, v1), 0.0, 1.0, v0, v1)
        g_low = g(s_low)
        return _root(g, s_low, 1.0, g_low, x1 - level) if g_low < 0.0 else None
    if x1 > level:
        return _root(g, 0.0, 1.0, g0, x1 - level)
    if v0 > 0.0 and v1 < 0.0:
        s_top = _root(lambda s: _hermite_dx(s, h, x0, v0, x1, v1), 0.0, 1.0, v0, v1)
        g_top = g(s_top)
        if g_top > 0.0:
            return _root(g, 0.0, s_top, g0, g_top)
    return None


def _hermite_dx(s: float, h: float, x0: float, v0: float, x1: float, v1: float) -> float:
    """``dx/dt`` of the cubic Hermite interpolant of ``x`` (same sign as ``d/ds``)."""
    s2 = s * s
    return (
        (6 * s2 - 6 * s) * x0
        + (3 * s2 - 4 * s + 1) * h * v0
        + (-6 * s2 + 6 * s) * x1
        + (3 * s2 - 2 * s) * h * v1
    ) / h


def band_edge(vb: float, eta: float, s: int) -> float:
    """The velocity where slip with sign ``s`` enters the stick band ``|vb - x'| <= eta``,
    rounded so that the band test holds for it (``vb - (vb - eta)`` may round above ``eta``).

    >>> v = band_edge(1e-5, 1e-9, 1); abs(1e-5 - v) <= 1e-9
    True
    """
    v = vb - s * eta
    while abs(vb - v) > eta:
        v = math.nextafter(v, vb)
    return v


def _default_eta(osc: Oscillator) -> float:
    scale = osc.v if osc.v > 0.0 else max(osc.a, osc.b, osc.u_s)
    return ETA_REL * scale


def simulate_switch(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None = None,
    t_end: float = 100.0,
    x0: float = 0.0,
    v0: float = 0.0,
    *,
    n_samples: int = 2000,
    transition_cap: int = 10_000,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    eta: float | None = None,
    max_step: float = math.inf,
    rest_speed: float | None = None,
    max_steps: int = MAX_STEPS,
    time_budget: float | None = None,
) -> Result:
    """Response by the switch model and adaptive RKF 4(5), the paper's method (SPEC §5).

    Parameters
    ----------
    osc : Oscillator
    stop : RigidStop, HystereticStop or None
    t_end : float
        Horizon (dimensionless time), ``> 0``.
    x0, v0 : float
        Initial state; ``x0 <= clearance`` for a rigid stop, ``x0 - clearance < D`` for a
        deformable one.
    n_samples : int
        Uniform samples of the result (transition points are added).
    transition_cap : int
        Transitions stored (all are counted).
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
        Largest number of Runge-Kutta steps tried (accepted and rejected). When it is
        reached the solve stops with ``Status.STEP_LIMIT`` and the result covers the time
        up to that point.
    time_budget : float, optional
        Wall-clock seconds the solve may take; when they run out it stops with
        ``Status.TIME_BUDGET`` (result up to that point). ``None``: no budget.

    Returns
    -------
    Result
        ``method="switch"``; ``stats`` holds ``steps`` (accepted), ``rejected`` and
        ``rhs_evals``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> res = simulate_switch(osc, t_end=10.0)
    >>> round(res.x_max, 5)           # fast belt: x_max = 2a (paper §3)
    0.4
    """
    t_end = check_range("t_end", t_end, 0.0, low_open=True)
    x0 = check_range("x0", x0)
    v0 = check_range("v0", v0)
    rtol = check_range("rtol", rtol, 0.0, low_open=True)
    atol = check_range("atol", atol, 0.0, low_open=True)
    n_samples = int(check_range("n_samples", n_samples, 2))
    transition_cap = int(check_range("transition_cap", transition_cap, 0))
    max_step = check_range("max_step", max_step, 0.0, low_open=True, allow_inf=True)
    limit = WorkLimit(max_steps, time_budget)
    eta = _default_eta(osc) if eta is None else check_range("eta", eta, 0.0, low_open=True)
    rest_speed = eta if rest_speed is None else check_range("rest_speed", rest_speed, 0.0)
    rigid = isinstance(stop, RigidStop)
    soft = isinstance(stop, HystereticStop)
    c = stop.clearance if stop is not None else math.inf
    if stop is not None:
        check_start(x0, c, stop.limit_overlap if soft else None)

    a, b, vb = osc.a, osc.b, osc.v
    r = stop.restitution if rigid else 1.0
    log = TransitionLog(transition_cap)
    contact = soft and x0 > c
    branch = FIRST_LOADING
    rhs = switch_rhs(osc, eta, stop if soft else None, branch)

    def phi_at(xx: float) -> float:
        if not soft or xx <= c:
            return 0.0
        return force_and_slope(xx - c, branch, stop)[0]

    def friction_state(xx: float, vv: float) -> int:
        """+1/-1: slip with that sign; 0: stick (switch model, paper Eq. 7)."""
        ur = vb - vv
        if ur > eta:
            return 1
        if ur < -eta:
            return -1
        force = -xx - phi_at(xx)
        if -b <= force <= b:
            return 0
        return 1 if force < 0.0 else -1

    t, x, v = 0.0, x0, v0
    acc = rhs(x, v)
    n_eval = 1
    fr = friction_state(x, v)
    ts: list[float] = []
    xs: list[float] = []
    vs: list[float] = []
    accs: list[float] = []
    modes: list[int] = []
    phis: list[float] | None = [] if soft else None
    steps = rejected = 0
    status = Status.SUCCESS
    h = min(FIRST_STEP, max_step, t_end)
    at_rest = False

    def record() -> None:
        """Store the current state as a dense point (mode of the interval that follows)."""
        ts.append(t)
        xs.append(x)
        vs.append(v)
        accs.append(acc)
        modes.append(Mode.CONTACT if contact else (Mode.STICK if fr == 0 else Mode.SLIP))
        if soft:
            phis.append(phi_at(x))

    def step_to(hh: float) -> tuple[float, float]:
        nonlocal n_eval
        xn_, vn_, _, _ = rkf45_step(rhs, x, v, acc, hh)
        n_eval += 5
        return xn_, vn_

    def locate(s0: float, h_full: float, g_of, dg_of) -> tuple[float, float, float]:
        """Recompute the step to the located fraction ``s0`` and refine it by Newton."""
        hh = s0 * h_full
        xe, ve = step_to(hh)
        for _ in range(EVENT_NEWTON):
            g = g_of(xe, ve)
            dg = dg_of(xe, ve)
            if g == 0.0 or dg == 0.0 or not math.isfinite(dg):
                break
            h_new = hh - g / dg
            if not 0.0 < h_new <= h_full:
                break
            x_try, v_try = step_to(h_new)
            if abs(g_of(x_try, v_try)) >= abs(g):
                break
            hh, xe, ve = h_new, x_try, v_try
        return hh, xe, ve

    def advance(hh: float, xn_: float, vn_: float) -> None:
        """Move to the end of an accepted (possibly cut) step of length ``hh``; report the
        friction transitions that happened on it (detected, not located by cutting: the
        switch model) and store the point."""
        nonlocal t, x, v, acc, fr, n_eval
        an_ = rhs(xn_, vn_)
        n_eval += 1
        fr_new = friction_state(xn_, vn_)
        if fr_new != fr:
            _friction_transition(
                log, fr, fr_new, hh, t, x, v, acc, xn_, vn_, an_, vb, eta, b, phi_at
            )
        t = t + hh
        x, v, acc, fr = xn_, vn_, an_, fr_new
        record()

    def rest_pressed() -> bool:
        if vb > eta:
            return a >= c
        return abs(c) <= b

    def impact(from_stick: bool) -> None:
        """Rigid impact at ``x = c`` with the approach speed ``v`` (paper Eq. 8)."""
        nonlocal v, acc, fr, n_eval
        w = v
        v_after = -r * w
        kind = TransitionKind.STICK_IMPACT if from_stick else TransitionKind.IMPACT
        log.add(kind, t, c, w, v_after)
        if abs(v_after) <= rest_speed and rest_pressed():
            come_to_rest(w)
            return
        v = v_after
        acc = rhs(c, v)
        n_eval += 1
        fr = friction_state(c, v)
        record()

    def come_to_rest(w: float) -> None:
        """The bouncing ends on the stop (Zeno guard, module docstring)."""
        nonlocal at_rest, t, v, acc, contact
        t_rest = log_rest_at_stop(log, t, w, r, a, c, t_end)
        at_rest, contact = True, True  # the mass sits on the stop: x = c, x' = 0
        v = acc = 0.0
        record()
        for t_next in (min(t_rest, t_end), t_end):
            if t_next > t:
                t = t_next
                record()

    record()
    if rigid and x0 >= c and v0 > 0.0:
        impact(fr == 0)
    elif rigid and x0 >= c and v0 == 0.0 and rest_pressed():
        come_to_rest(0.0)

    while t < t_end and not at_rest:
        stopped = limit.reached(steps + rejected)
        if stopped is not None:
            status = stopped
            break
        h = min(h, max_step)
        last = t + h >= t_end
        if last:
            h = t_end - t
        xn, vn, ex, ev = rkf45_step(rhs, x, v, acc, h)
        n_eval += 5
        sx = atol + rtol * max(abs(x), abs(xn))
        sv = atol + rtol * max(abs(v), abs(vn))
        err = math.sqrt(0.5 * ((ex / sx) ** 2 + (ev / sv) ** 2))
        if not err <= 1.0:  # also catches nan from a stage beyond the limit overlap
            rejected += 1
            shrink = SAFETY * err**ERROR_EXPONENT if math.isfinite(err) else FACTOR_MIN
            h *= max(FACTOR_MIN, shrink)
            if h <= MIN_STEP_ULPS * math.ulp(max(t, 1.0)):
                near_limit = soft and x - c >= 0.5 * stop.limit_overlap
                status = Status.LIMIT_OVERLAP if near_limit else Status.INTEGRATION_FAILED
                break
            continue
        steps += 1
        h_next = h * (FACTOR_MAX if err == 0.0 else min(FACTOR_MAX, SAFETY * err**ERROR_EXPONENT))
        if last:
            h_next = h

        # --- events that cut the step ---------------------------------------------------
        if stop is not None and not contact:
            s_ev = _x_crossing(h, x, v, xn, vn, c)
            if s_ev is not None:
                was_stick = fr == 0
                hh, xe, ve = locate(s_ev, h, lambda xx, vv: xx - c, lambda xx, vv: vv)
                advance(hh, c, max(ve, 0.0))
                if rigid:
                    impact(was_stick)
                else:
                    contact = True
                    branch = FIRST_LOADING
                    rhs = switch_rhs(osc, eta, stop, branch)
                    acc = rhs(x, v)
                    n_eval += 1
                    log.add(TransitionKind.CONTACT, t, x, v)
                    modes[-1] = Mode.CONTACT
                h = max(h_next, hh)
                continue
        if contact:
            if (vn < 0.0) if branch.loading else (vn > 0.0):
                an = rhs(xn, vn)
                n_eval += 1
                s_ev = _root(partial(_hermite, h=h, y0=v, d0=acc, y1=vn, d1=an), 0.0, 1.0, v, vn)
                hh, xe, ve = locate(s_ev, h, lambda xx, vv: vv, rhs)
                if xe > c:
                    advance(hh, xe, 0.0)
                    branch = reverse(x - c, phi_at(x), branch)
                    rhs = switch_rhs(osc, eta, stop, branch)
                    acc = rhs(x, v)
                    n_eval += 1
                    log.add(TransitionKind.REVERSAL, t, x, 0.0)
                    h = h_next
                    continue
            if math.isfinite(stop.strength) and phi_at(xn) > stop.strength:
                advance(h, xn, vn)
                log.add(TransitionKind.FAILURE, t, x, v)
                status = Status.STOP_FAILED
                break

        # --- the step jumped over the stick band: cut it where it enters the band -------
        if fr != 0 and friction_state(xn, vn) == -fr:
            level = vb - fr * eta
            an = rhs(xn, vn)
            n_eval += 1
            s_ev = _root(
                partial(_hermite, h=h, y0=v, d0=acc, y1=vn - level, d1=an, shift=level),
                0.0,
                1.0,
                v - level,
                vn - level,
            )
            hh, xe, _ = locate(s_ev, h, lambda xx, vv, lv=level: vv - lv, rhs)
            advance(hh, xe, band_edge(vb, eta, fr))
            h = h_next
            continue

        # --- a maximum of x inside the step: stored as a point, so x_max has the
        #     integration accuracy ------------------------------------------------------------
        if v > 0.0 and vn <= 0.0 and not contact:
            an = rhs(xn, vn)
            n_eval += 1
            s_top = _root(partial(_hermite, h=h, y0=v, d0=acc, y1=vn, d1=an), 0.0, 1.0, v, vn)
            if 0.0 < s_top < 1.0:
                xt, vt = step_to(s_top * h)
                advance(s_top * h, xt, vt)
                h = h_next
                continue

        x_prev, v_prev, a_prev = x, v, acc
        advance(h, xn, vn)
        if last:
            t = t_end
            ts[-1] = t_end
        if contact and x <= c:
            s_sep = _root(
                partial(_hermite, h=h, y0=x_prev, d0=v_prev, y1=x - c, d1=v, shift=c),
                0.0,
                1.0,
                x_prev - c,
                x - c,
            )
            v_sep = _hermite(s_sep, h, v_prev, a_prev, v, acc)
            log.add(TransitionKind.SEPARATION, t - h + s_sep * h, c, v_sep)
            contact = False
            branch = FIRST_LOADING
            rhs = switch_rhs(osc, eta, stop, branch)
            modes[-1] = Mode.STICK if fr == 0 else Mode.SLIP
        h = h_next

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
        contact_force=phis,
        overlap=[xx - c for xx in xs] if soft else None,
        stop_stored=(lambda d, p: stored_energy(d, p, stop)) if soft else None,
        rtol=max(rtol, eta / max(vb, eta)),
        belt_speed=vb,
        x_upper=c if rigid else None,
        status=status,
        method="switch",
        stats={"steps": steps, "rejected": rejected, "rhs_evals": n_eval, "eta": eta},
    )


def _friction_transition(
    log: TransitionLog,
    fr: int,
    fr_new: int,
    h: float,
    t0: float,
    x0: float,
    v0: float,
    a0: float,
    x1: float,
    v1: float,
    a1: float,
    vb: float,
    eta: float,
    b: float,
    phi_at,
) -> None:
    """Report a friction transition found at the end of a step, at its interpolated time.

    Slip->stick where ``x'`` enters the band, stick->slip where the applied force reaches
    ``b``, a sign change where ``x' = v`` (paper §2.5).
    """

    def xv(s: float) -> tuple[float, float]:
        return _hermite(s, h, x0, v0, x1, v1), _hermite(s, h, v0, a0, v1, a1)

    if fr_new == 0:
        kind = TransitionKind.SLIP_STICK
        level = vb - fr * eta

        def g(s: float) -> float:
            return xv(s)[1] - level

    elif fr == 0:
        kind = TransitionKind.STICK_SLIP

        def g(s: float) -> float:
            xx = xv(s)[0]
            return abs(xx + phi_at(xx)) - b

    else:
        kind = TransitionKind.SIGN_CHANGE

        def g(s: float) -> float:
            return xv(s)[1] - vb

    g0, g1 = g(0.0), g(1.0)
    s = _root(g, 0.0, 1.0, g0, g1) if g0 * g1 < 0.0 else 1.0
    xs, vs = xv(s)
    log.add(kind, t0 + s * h, xs, vs)
