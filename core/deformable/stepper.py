"""The contact's integration on one branch of the law: scalar Dormand-Prince 5(4) steps in
slip with their events located on each step's quintic Hermite interpolant, and the exact
stick line inside contact.

In slip, ``x'' + x = s a - phi(delta)`` (paper Eqs. 14-15 with the law of
:mod:`core.deformable.law`, Eqs. 11-13); in stick, ``x' = v`` while ``|x + phi| <= b``, a
straight line whose end ``x + phi = b`` is a scalar root. The events of a step: separation
(``delta`` back to 0), reversal of the overlap rate (``x' = 0``), stick/slip changes
(``x' = v``), failure of the stop (``phi > strength``) and the limit overlap
(``delta -> D``).

Why a scalar explicit pair (measured against SciPy's solvers on one contact,
benchmarks/results/2026-11-29-deformable-restructure.md, "Integrator"): the contact is
stiff only in that its frequency ``sqrt(k_c0)`` is high; it has no fast decaying mode (the
law is rate-independent: no damping term), so an implicit method buys nothing: it must
still resolve each oscillation, and its Newton iterations cost more per step. The number of
explicit steps per contact is set by the accuracy of one oscillation, not by ``k_c0`` (the
contact lasts ``~pi/sqrt(k_c0)``): ~60 steps at rtol = 1e-9 whatever the stiffness. What
remains is the overhead per step, hence the pair written with :mod:`math` (the force as a
closure with the branch constants bound) and a quintic Hermite interpolant (position,
velocity and acceleration at both ends, error ``O(h^6)``) for event location and dense
samples.
"""

from __future__ import annotations

import math

from scipy.optimize import brentq

from core.deformable.hermite import EVENT_XTOL, dpoly, first_exit, hermite_coeffs, poly
from core.deformable.law import (
    EXP_CAP,
    Branch,
    branch_work,
    force_and_slope,
    passive_as_paper,
    passive_branch_force,
)
from core.deformable.state import HERMITE, LINE, Solve, State
from core.deformable.train_contact import TIGHT_RTOL, TIGHT_RTOL_MIN, Kinks
from core.result import Status, TransitionKind

# Dormand-Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Norsett & Wanner, Table II.5.2).
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9


A21 = 1 / 5


A31, A32 = 3 / 40, 9 / 40


A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9


A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729


A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656


B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84


E1, E3, E4, E5, E6, E7 = (
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


#: Points of the grid on which a step's velocity is searched for the belt's speed where it
#: turns inside the step (:func:`belt_speed_inside`).
BELT_GRID = 64


def may_pass_belt(u0: float, u1: float, a0: float, a1: float, h: float, s: int,
                   vb: float) -> bool:
    """Whether a step's velocity turns inside it (towards the belt's speed for the friction
    sign ``s``) and could reach it: an acceleration varying linearly from ``a0`` to ``a1``
    takes it at most ``h |a| / 2`` past its ends; twice that leaves a margin."""
    if s > 0:
        return a0 > 0.0 > a1 and max(u0, u1) + h * max(a0, -a1) >= vb
    return a0 < 0.0 < a1 and min(u0, u1) - h * max(-a0, a1) <= vb


def belt_speed_inside(coeffs, h: float, s: int, vb: float) -> float | None:
    """The first ``theta`` in ``(0, 1)`` where the step's velocity reaches the belt's speed
    (from below for ``s = 1``, from above for ``s = -1``) though it ends on the near side,
    or ``None``: searched on a grid of :data:`BELT_GRID` points, then refined."""
    def g(th: float) -> float:
        return s * (vb - dpoly(coeffs, th) / h)

    prev = None  # the last grid point inside the mode (a step may start on the boundary)
    for k in range(BELT_GRID):
        th = k / BELT_GRID
        if g(th) > 0.0:
            prev = th
        elif prev is not None:
            return brentq(g, prev, th, xtol=EVENT_XTOL)
    return None


def accel(sv: Solve, s: int, branch: Branch):
    """``x'' = -x + s a - phi(x - clearance)`` on one branch, as a fast closure (the
    law of :func:`core.deformable.law.force_and_slope` with the branch constants bound)."""
    stop = sv.stop
    if stop.law == "passive":
        as_paper = passive_as_paper(branch, stop)
        if as_paper is None:
            return accel_passive(sv, s, branch)
        branch = as_paper  # the same curve: the paper's closure below is faster
    xb, d_lim, sa = sv.xb, sv.d_lim, s * sv.a
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


def accel_passive(sv: Solve, s: int, branch: Branch):
    """:func:`accel` on a branch of the passive law that is none of the paper's."""
    xb, sa, d_lim, kc = sv.xb, s * sv.a, sv.d_lim, sv.stop.k_c0 * sv.d_lim
    force = passive_branch_force(branch, sv.stop)

    def acc_passive(x: float) -> float:
        d = x - xb
        if d <= 0.0:  # phi_C continued past the face, as in accel's closures
            return sa - x - kc * d / (d_lim - d)
        return sa - x - force(d)

    return acc_passive


def step_tolerances(sv: Solve, tight: bool) -> tuple[float, float]:
    """``(rtol, atol)`` of the contact's steps: the solve's, or the tighter ones of a
    contact's first branches that are not kept on their first integral
    (:mod:`core.deformable.train_contact`)."""
    if tight:
        tight_rtol = min(sv.rtol, max(TIGHT_RTOL * sv.rtol, TIGHT_RTOL_MIN))
        return tight_rtol, sv.atol * tight_rtol / sv.rtol
    return sv.rtol, sv.atol


def slip(sv: Solve, st: State, s: int, branch: Branch, kinks: list[float] = (),
          tight: bool = False) -> tuple[str, int]:
    """Dormand-Prince 5(4) steps until an event; ``st`` is left at the event.

    A step that would cross one of ``kinks`` (positions, descending) moving out is redone
    to end on it (:class:`core.deformable.train_contact.Kinks`); ``tight``: steps at
    :data:`core.deformable.train_contact.TIGHT_RTOL` times ``rtol``.

    The step is the solve's inner loop (~200 steps a contact at the map's node
    tolerance): the rows are appended and the work advanced here, and the events are
    located (:func:`step_events`) only when a step's end leaves the mode."""
    stop, xb, vb = sv.stop, sv.xb, sv.vb
    rtol, atol = step_tolerances(sv, tight)
    t_end, d_lim, d_max = sv.t_end, stop.limit_overlap, sv.d_max
    leaves = _mode_test(xb, branch.loading, s, vb, d_max, math.isfinite(stop.strength))
    sa = s * sv.a
    sav = sa * vb
    add_row = sv.add_row
    steps = rejected = 0
    x, u, t = st.x, st.v, st.t
    acc = accel(sv, s, branch)
    a0 = acc(x)
    n_evals = 1
    _, slope = force_and_slope(max(x - xb, 0.0), branch, stop)
    omega = math.sqrt(1.0 + max(slope, 0.0))
    h = FIRST_STEP_FRACTION * 2.0 * math.pi / omega
    h_min = MIN_STEP_FRACTION * 2.0 * math.pi / omega
    x_max = sv.x_max
    ahead = Kinks(kinks)
    kink_x = ahead.x
    landing = False  # the step is redone to end on the kink
    while True:
        left = t_end - t
        if left < h:
            h = left
        if h <= 0.0:
            sv.tally(steps, rejected, n_evals)
            sv.reach(x_max)
            return "horizon", s
        n_evals += 6
        x1, u1, a1, err = dp_step(acc, x, u, a0, h, rtol, atol, xb, d_lim)
        if x1 < kink_x:  # (-inf while landing)
            h_cut = ahead.cut(x, u, a0, x1, u1, a1, h)
            if h_cut > 0.0:
                h, landing, kink_x = h_cut, True, -math.inf
                continue
        if err > 1.0:
            rejected += 1
            h *= max(MIN_FACTOR, SAFETY * err**-0.2) if math.isfinite(err) else MIN_FACTOR
            if h < h_min:
                sv.tally(steps, rejected, n_evals)
                sv.reach(x_max)
                sv.fail(Status.INTEGRATION_FAILED)
                st.t, st.x, st.v = t, x, u
                return "failed", s
            continue
        coeffs = hermite_coeffs(x, u, a0, x1, u1, a1, h)
        turn = may_pass_belt(u, u1, a0, a1, h, s, vb)
        if leaves(x1, u1, turn):
            found = step_events(sv, coeffs, h, x1, u1, s, branch, turn)
        else:
            found = None
        if found:
            sv.tally(steps, rejected, n_evals)
            sv.reach(x_max)
            return end_at_event(sv, st, t, coeffs, h, s, min(found)), -s
        # The step's row (add_step, inlined) and the work it adds.
        t1 = t + h
        if t1 > t:
            work = st.work
            add_row(HERMITE, t, t1, (*coeffs, h), sa, work)
            x_end = poly(coeffs, (t1 - t) / h)
            wf, wb, ws = work
            st.work = (wf + sa * (x_end - x), wb + sav * (t1 - t), ws)
        steps += 1
        t, x, u, a0 = t1, x1, u1, a1
        st.t, st.x, st.v = t, x, u
        if x > x_max:
            x_max = x
        h *= min(MAX_FACTOR, SAFETY * err**-0.2) if err > 0.0 else MAX_FACTOR
        if landing:
            landing = False
            ahead.landed(coeffs[0], x1)  # coeffs[0]: the step's start
            kink_x = ahead.x


def _mode_test(xb: float, loading: bool, s: int, vb: float, d_max: float,
               strength_finite: bool):
    """Whether a step's end ``(x1, u1)`` may have left the mode (separation, reversal,
    the belt's speed, the limit, a finite strength to check, or a velocity that turns,
    ``turn``): its events are then located."""
    if loading:
        if s > 0:
            def leaves(x1: float, u1: float, turn: bool) -> bool:
                return (x1 < xb or u1 < 0.0 or u1 > vb or x1 - xb > d_max or strength_finite
                        or turn)
        else:
            def leaves(x1: float, u1: float, turn: bool) -> bool:
                return (x1 < xb or u1 < 0.0 or u1 < vb or x1 - xb > d_max or strength_finite
                        or turn)
    elif s > 0:
        def leaves(x1: float, u1: float, turn: bool) -> bool:
            return (x1 < xb or u1 > 0.0 or u1 > vb or x1 - xb > d_max or strength_finite
                    or turn)
    else:
        def leaves(x1: float, u1: float, turn: bool) -> bool:
            return (x1 < xb or u1 > 0.0 or u1 < vb or x1 - xb > d_max or strength_finite
                    or turn)
    return leaves


def dp_step(acc, x: float, u: float, a0: float, h: float, rtol: float, atol: float,
            xb: float, d_lim: float) -> tuple[float, float, float, float]:
    """One Dormand-Prince 5(4) step of ``x'' = acc(x)`` from ``(x, u)`` (``a0 = acc(x)``):
    ``(x1, u1, acc(x1), err)`` with ``err`` the error estimate's norm over the tolerances,
    infinite (and the acceleration ``nan``) where the step leaves the numbers or reaches
    the limit overlap ``d_lim`` past the face ``xb`` (the law's asymptote)."""
    isfinite, sqrt = math.isfinite, math.sqrt
    # Dormand-Prince stages; the acceleration depends on x only.
    k1x, k1u = u, a0
    y2x, y2u = x + h * A21 * k1x, u + h * A21 * k1u
    k2x, k2u = y2u, acc(y2x)
    y3x = x + h * (A31 * k1x + A32 * k2x)
    y3u = u + h * (A31 * k1u + A32 * k2u)
    k3x, k3u = y3u, acc(y3x)
    y4x = x + h * (A41 * k1x + A42 * k2x + A43 * k3x)
    y4u = u + h * (A41 * k1u + A42 * k2u + A43 * k3u)
    k4x, k4u = y4u, acc(y4x)
    y5x = x + h * (A51 * k1x + A52 * k2x + A53 * k3x + A54 * k4x)
    y5u = u + h * (A51 * k1u + A52 * k2u + A53 * k3u + A54 * k4u)
    k5x, k5u = y5u, acc(y5x)
    y6x = x + h * (A61 * k1x + A62 * k2x + A63 * k3x + A64 * k4x + A65 * k5x)
    y6u = u + h * (A61 * k1u + A62 * k2u + A63 * k3u + A64 * k4u + A65 * k5u)
    k6x, k6u = y6u, acc(y6x)
    x1 = x + h * (B1 * k1x + B3 * k3x + B4 * k4x + B5 * k5x + B6 * k6x)
    u1 = u + h * (B1 * k1u + B3 * k3u + B4 * k4u + B5 * k5u + B6 * k6u)
    if not (isfinite(x1) and isfinite(u1)) or x1 - xb >= d_lim:
        err = math.inf
        a1 = math.nan
    else:
        a1 = acc(x1)
        k7x, k7u = u1, a1
        ex = h * (E1 * k1x + E3 * k3x + E4 * k4x + E5 * k5x + E6 * k6x + E7 * k7x)
        eu = h * (E1 * k1u + E3 * k3u + E4 * k4u + E5 * k5u + E6 * k6u + E7 * k7u)
        ax, ax1, au, au1 = abs(x), abs(x1), abs(u), abs(u1)
        sx = atol + rtol * (ax if ax >= ax1 else ax1)
        su = atol + rtol * (au if au >= au1 else au1)
        err = sqrt(0.5 * ((ex / sx) ** 2 + (eu / su) ** 2))
    return x1, u1, a1, err


def end_at_event(sv: Solve, st: State, t: float, coeffs, h: float, s: int, event) -> str:
    """Cut the step ``(t, coeffs, h)`` at ``event = (theta, name)``, store it, move ``st``
    there and return the name (recording a failure of the stop)."""
    th, name = event
    t_ev = t + th * h
    x_ev = poly(coeffs, th)
    u_ev = dpoly(coeffs, th) / h
    if name == "reversal":
        u_ev = 0.0
    elif name == "friction":
        u_ev = sv.vb
    elif name == "separated":
        x_ev = sv.xb
    add_step(sv, t, t_ev, coeffs, h, s, st)
    sv.tally(steps=1)
    st.t, st.x, st.v = t_ev, x_ev, u_ev
    sv.reach(x_ev)
    if name == "failed":
        sv.fail(Status.STOP_FAILED)
        sv.record(TransitionKind.FAILURE, st, st.v)
    elif name == "limit":
        sv.fail(Status.LIMIT_OVERLAP)
    return name


def step_events(sv: Solve, coeffs, h: float, x1: float, u1: float, s: int, branch: Branch,
                turn: bool = False):
    """Events of one step: which condition is violated at the step's end, then its
    first root on the step's interpolant, as ``(theta, name)``. Each ``g`` is positive
    inside the current mode. ``turn``: the velocity turns inside the step and may pass
    the belt's speed there (:func:`may_pass_belt`)."""
    stop, xb, vb, strength = sv.stop, sv.xb, sv.vb, sv.stop.strength
    found: list[tuple[float, str]] = []
    if x1 < xb:
        found.append((first_exit(lambda th: poly(coeffs, th) - xb), "separated"))
    if (u1 < 0.0) if branch.loading else (u1 > 0.0):
        sign = 1.0 if branch.loading else -1.0
        found.append((first_exit(lambda th: sign * dpoly(coeffs, th)), "reversal"))
    if (u1 > vb) if s > 0 else (u1 < vb):
        found.append((first_exit(lambda th: s * (vb - dpoly(coeffs, th) / h)), "friction"))
    elif turn:
        # The velocity may pass the belt's speed inside the step and come back (it
        # turns there): a contact entered just below the belt's speed reaches it within
        # microseconds and sticks for milliseconds. Missed, that stick was lost: the
        # period of such a train off by 4e-7 at rtol 1e-8 to 1e-10.
        th = belt_speed_inside(coeffs, h, s, vb)
        if th is not None:
            found.append((th, "friction"))
    if x1 - xb > sv.d_max:
        found.append(
            (first_exit(lambda th: xb + sv.d_max - poly(coeffs, th)), "limit")
        )
    if math.isfinite(strength) and force_and_slope(x1 - xb, branch, stop)[0] > strength:
        found.append((first_exit(
            lambda th: strength - force_and_slope(poly(coeffs, th) - xb, branch, stop)[0]
        ), "failed"))
    return found


def add_step(sv: Solve, t0, t1, coeffs, h, s, st: State) -> None:
    """Store one step (cut at ``t1``) and advance the friction and belt work."""
    if t1 <= t0:
        return
    x0 = coeffs[0]
    sv.add_row(HERMITE, t0, t1, (*coeffs, h), s * sv.a, st.work)
    x1 = poly(coeffs, (t1 - t0) / h)
    wf, wb, ws = st.work
    st.work = (wf + s * sv.a * (x1 - x0), wb + s * sv.a * sv.vb * (t1 - t0), ws)


def stick_line(sv: Solve, st: State, branch: Branch) -> str:
    """Exact stick inside contact, ``x = x0 + v (t - t0)``, until ``x + phi = b``."""
    stop, xb, vb = sv.stop, sv.xb, sv.vb
    x0 = st.x

    def excess(x: float) -> float:
        return x + force_and_slope(x - xb, branch, stop)[0] - sv.b

    x_lim = xb + sv.d_max
    ends = []
    if excess(x_lim) > 0.0:
        ends.append((brentq(excess, x0, x_lim, xtol=EVENT_XTOL * sv.scale()), "slip"))
    if math.isfinite(stop.strength):

        def over(x: float) -> float:
            return force_and_slope(x - xb, branch, stop)[0] - stop.strength

        if over(x_lim) > 0.0:
            ends.append((brentq(over, x0, x_lim, xtol=EVENT_XTOL * sv.scale()), "failed"))
    ends.append((x_lim, "limit"))
    x1, name = min(ends)
    t1 = st.t + (x1 - x0) / vb
    t_cut = min(t1, sv.t_end)
    sv.add_row(LINE, st.t, t_cut, (x0, vb), math.nan, st.work)
    x_cut = x0 + vb * (t_cut - st.t)
    wstick = 0.5 * (x_cut * x_cut - x0 * x0) + branch_work(x0 - xb, x_cut - xb, branch, stop)
    wf, wb, ws = st.work
    st.work = (wf + wstick, wb + wstick, ws)
    sv.reach(x_cut)
    st.t, st.x, st.v = t_cut, x_cut, vb
    if t1 >= sv.t_end:
        return "horizon"
    if name == "slip":  # the branch goes on: the overlap still grows as the slip starts
        sv.record(TransitionKind.STICK_SLIP, st, vb)
        return "slip"
    if name == "failed":
        sv.fail(Status.STOP_FAILED)
        sv.record(TransitionKind.FAILURE, st, vb)
        return "failed"
    sv.fail(Status.LIMIT_OVERLAP)
    return "limit"
