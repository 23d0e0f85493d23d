"""Semi-analytic slip arcs inside a sustained contact (paper law): from one reversal of the
overlap rate to the next, the motion conserves an energy, so the next reversal is a root and
the duration a smooth quadrature (Gauss-Kronrod 7-15), instead of step by step."""

from __future__ import annotations

import math

import numpy as np

from core.deformable.law import (
    Branch,
)
from core.deformable.state import ARC, Solve, State

#: Semi-analytic arcs: the G7 and K15 estimates of an arc's duration must agree to this
#: fraction of it (K15 is then good to ~1e-10 relative: its error falls like the square of
#: G7's for analytic integrands), else the arc is integrated step by step.
ARC_QUAD_RTOL = 1e-6


#: Newton iterations of an arc's end point (3-5 are typical; bisection safeguards).
ARC_NEWTON_MAX = 60


#: Newton iterations when a sample's time is mapped to the arc's angle.
ARC_SAMPLE_NEWTON = 8
#: Step of the angle (rad) below which a sample's Newton stops. The steps stall at ~3e-11,
#: the rounding of the K15 time of the angle (k_c0 = 100, beta = 1000, D = 0.01: 450 of
#: 4,000 samples went on to the last iteration at 1e-14); 1e-10 rad moves a sample by
#: ~1e-10 of the arc's overlap, and a fifth of the samples' time is saved.
ARC_SAMPLE_STEP = 1e-10


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


def log_mean_m1(w: float) -> float:
    """``L(w) - 1`` with ``L(w) = -log(1 - w) / w`` (mean of ``1/(1 - w s)`` over ``[0, 1]``),
    by its series where the closed form cancels."""
    if abs(w) < 1e-3:
        return w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
    return -math.log1p(-w) / w - 1.0


def exp_mean(z: float) -> float:
    """``(exp(z) - 1) / z``, the mean of ``exp(z s)`` over ``[0, 1]``."""
    return math.expm1(z) / z if z != 0.0 else 1.0


def log_mean_m1_arr(w: np.ndarray) -> np.ndarray:
    small = np.abs(w) < 1e-3
    ws = np.where(small, 0.5, w)
    with np.errstate(divide="ignore", invalid="ignore"):
        direct = -np.log1p(-ws) / ws - 1.0
    series = w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
    return np.where(small, series, direct)


def exp_mean_arr(z: np.ndarray) -> np.ndarray:
    zero = z == 0.0
    zs = np.where(zero, 1.0, z)
    return np.where(zero, 1.0, np.expm1(zs) / zs)


def branch_constants(sv: Solve, branch: Branch) -> tuple[float, float, float]:
    """``(K, C, lam)`` of the unclipped curve ``phi = K d/(D - d) + C exp(lam (d - d_r))``."""
    stop, d_lim = sv.stop, sv.d_lim
    r = branch.delta_r
    if branch.loading:
        kc = stop.k_c0 * d_lim
        return kc, branch.phi_r - kc * r / (d_lim - r), -stop.beta_c / d_lim
    ke = stop.k_e0 * d_lim
    return ke, branch.phi_r - ke * r / (d_lim - r), stop.beta_e / d_lim


def arc(sv: Solve, st: State, s: int, branch: Branch):
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
    d_lim, xb = sv.d_lim, sv.xb
    x_r, dr = st.x, st.x - xb
    if dr <= 0.0 or dr >= sv.d_max:
        return None
    up = branch.loading
    kk, cc, lam = branch_constants(sv, branch)
    stop = sv.stop
    gap = d_lim - dr
    hyper_r = dr / gap
    if not _on_transition_curve(up, cc, (stop.k_c0 - stop.k_e0) * d_lim * hyper_r):
        return None
    sa = s * sv.a
    lim_mean = kk * hyper_r
    kg = kk * d_lim / gap
    log_m1, e_mean, exp = log_mean_m1, exp_mean, math.exp
    log1p, expm1 = math.log1p, math.expm1

    def q(d: float) -> float:
        # log_mean_m1 and exp_mean written out (as in _duration): Newton's iterations at
        # every reversal of loops followed on the stop
        w = d / gap
        if abs(w) < 1e-3:
            lm = w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
        else:
            lm = -log1p(-w) / w - 1.0
        z = lam * d
        em = expm1(z) / z if z != 0.0 else 1.0
        return (x_r - sa + lim_mean) + 0.5 * d + kg * lm + cc * em

    q0 = x_r - sa + lim_mean + cc
    slope0 = 1.0 + kg / gap + cc * lam
    if ((q0 >= 0.0) if up else (q0 <= 0.0)) or slope0 <= 0.0:
        return None

    def net_force(d: float) -> float:  # V'(x_r + d): the net force at the end point
        de = dr + d
        return x_r + d - sa + kk * de / (d_lim - de) + cc * exp(lam * d)

    bracket = (0.0, sv.d_max - dr) if up else (-dr, 0.0)
    root = _mean_force_root(q, net_force, bracket, -2.0 * q0 / slope0)
    if root is None:
        return None
    d, n_evals = root
    d_n = dr + d
    if not (0.0 < d_n < sv.d_max) or abs(q(d)) > 1e-9 * abs(q0):
        return None  # separation, the limit overlap, or no clean root: integrate
    phi_n = kk * d_n / (d_lim - d_n) + cc * exp(lam * d)
    if not _stays_exact(stop, up, s, sv.vb, phi_n, d_n, dr, cc, lam, 2.0 * abs(q0) * abs(d)):
        return None
    t_k = _duration(d, x_r - sa + lim_mean, kg, gap, cc, lam)
    sv.tally(arc_evals=n_evals + 15)
    if t_k is None or st.t + t_k >= sv.t_end:
        return None
    # (the arc's row and the state at its end: the inner loop of loops on the stop)
    t1 = st.t + t_k
    mean_phi = lim_mean + kg * log_m1(d / gap) + cc * e_mean(lam * d)
    sv.add_row(ARC, st.t, t1, (x_r, d, t_k, kk, cc, lam, dr), sa, st.work)
    wf, wb, ws = st.work
    st.work = (wf + sa * d, wb + sa * sv.vb * t_k, ws + d * mean_phi)
    st.t, st.x, st.v = t1, x_r + d, 0.0
    sv.reach(st.x)
    sv.tally(arcs=1)
    return phi_n


def _stays_exact(stop, up: bool, s: int, vb: float, phi_n: float, d_n: float, dr: float,
                 cc: float, lam: float, u2_max: float) -> bool:
    """Whether the arc ending at overlap ``d_n`` with force ``phi_n`` is exactly the motion:
    within the stop's strength, an unloading not clipped to an envelope, and speeds (their
    square at most ``u2_max``) on one side of the belt's."""
    if phi_n > stop.strength:
        return False
    if not up and _clipped(stop, d_n, dr, cc, lam):
        return False
    return _below_belt_speed(up, s, vb, u2_max)


def _on_transition_curve(up: bool, cc: float, band: float) -> bool:
    """Whether the branch starts on its transition curve: going up ``c = phi_C(d_r) - phi_r``
    lies in ``[0, phi_C - phi_E]`` (``band``) and is never clipped; going down ``C >= 0``."""
    return -band <= cc <= 0.0 if up else cc >= 0.0


def _mean_force_root(q, net_force, bracket, guess):
    """Root ``d != 0`` of the increasing mean net force ``Q`` in ``bracket``: Newton with the
    slope ``(V'(x_r + d) - Q(d)) / d``, safeguarded by bisection. Returns ``(d, evals)`` or
    ``None`` if it does not converge, or if ``Q`` keeps its sign to the bracket's far end
    (the separation going down, the limit overlap going up: there is no root, and Newton's
    steps, all beyond that end, left ~30 bisections to find so on ~370 arcs of a soft
    stop's loops, k_c0 = 100, beta = 1000, D = 0.01). That end is looked at only once a
    step leaves the bracket: a step inside it that converges is the root (an increasing
    ``Q`` has no other), and most arcs' Newton never leaves it (one ``Q`` of the four an
    arc cost)."""
    neg, pos = bracket
    far = neg if neg != 0.0 else pos  # None once looked at
    evals = 0
    d = guess
    if not min(neg, pos) < d < max(neg, pos):
        evals += 1
        if (q(far) < 0.0) == (far > 0.0):
            return None
        far, d = None, 0.5 * (neg + pos)
    for _ in range(ARC_NEWTON_MAX):
        qd = q(d)
        evals += 2
        if qd == 0.0:
            # The root to rounding. (It was taken as a bracket end: Newton's step of zero
            # then lay on the bracket's edge and fell back to bisection from the far end,
            # ~35 more iterations on ~370 arcs of a soft stop's loops.)
            return d, evals
        if qd < 0.0:
            neg = d
        else:
            pos = d
        dq = (net_force(d) - qd) / d
        d_new = d - qd / dq if dq > 0.0 else 0.5 * (neg + pos)
        if not min(neg, pos) < d_new < max(neg, pos):
            if far is not None:
                evals += 1
                if (q(far) < 0.0) == (far > 0.0):
                    return None
                far = None
            d_new = 0.5 * (neg + pos)
        if abs(d_new - d) <= 1e-9 * abs(d):  # quadratic convergence: d_new to ~1e-18
            return d_new, evals
        d = d_new
    return None


def _clipped(stop, d_n: float, dr: float, cc: float, lam: float) -> bool:
    """Whether an unloading arc from ``dr`` to ``d_n`` meets the clip to ``phi_C``: where
    ``(k_c0 - k_e0) D d/(D-d) < C exp(lam (d - d_r))``. The log of the left side over the
    right has its minima at the ends or at ``d_+``."""
    if not (stop.k_c0 > stop.k_e0 and cc > 0.0):
        return False
    d_lim = stop.limit_overlap
    kr = (stop.k_c0 - stop.k_e0) * d_lim
    if kr * d_n / (d_lim - d_n) < cc * math.exp(lam * (d_n - dr)):
        return True
    beta = stop.beta_e
    if beta <= 4.0:
        return False
    d_plus = 0.5 * d_lim * (1.0 + math.sqrt(1.0 - 4.0 / beta))
    return d_n < d_plus < dr and kr * d_plus / (d_lim - d_plus) < cc * math.exp(
        lam * (d_plus - dr))


def _below_belt_speed(up: bool, s: int, vb: float, u2_max: float) -> bool:
    """No stick/slip change on the arc: the speed bound ``u^2 <= u2_max`` stays on one side
    of the belt speed for the friction sign ``s``."""
    if up:
        return (s > 0 and vb * abs(vb) > u2_max) or (s < 0 and vb <= 0.0)
    return (s > 0 and vb >= 0.0) or (s < 0 and vb < 0.0 and vb * vb > u2_max)


#: The K15 nodes of :func:`_duration`: ``sin(theta/2)^2``, and the K15 and G7 weights times
#: ``cos(theta/2)``.
_ARC_NODES = tuple((s2, wk * c2, wg * c2)
                   for c2, s2, wk, wg in zip(_ARC_COS, _ARC_SIN2, _GK_WK, _GK_WG, strict=True))


def _duration(d: float, q0: float, kg: float, gap: float, cc: float,
              lam: float) -> float | None:
    """Duration of the arc: K15 over ``theta`` in ``[0, pi]``, or ``None`` where G7 disagrees
    by more than :data:`ARC_QUAD_RTOL` (or the integrand is not real).

    The mean net force ``Q(e) = q0 + e/2 + kg (L(e/gap) - 1) + cc (exp(lam e) - 1)/(lam e)``
    of :func:`arc` is written out here, as :func:`log_mean_m1` and :func:`exp_mean` do,
    and what does not change from node to node is taken out of the loop: it runs at every
    reversal of loops followed on the stop, and the calls were half its time."""
    t_k = t_g = 0.0
    w_end, z_end, m2d, half = d / gap, lam * d, -2.0 * d, 0.5 * d
    series = abs(w_end) < 1e-3  # then at every node: |w| <= |w_end|
    log1p, expm1, sqrt = math.log1p, math.expm1, math.sqrt
    for s2, wkc, wgc in _ARC_NODES:
        w = w_end * s2
        if series or abs(w) < 1e-3:
            lm = w * (0.5 + w * (1.0 / 3.0 + w * (0.25 + w * (0.2 + w / 6.0))))
        else:
            lm = -log1p(-w) / w - 1.0
        z = z_end * s2
        em = expm1(z) / z if z != 0.0 else 1.0
        den = m2d * (q0 + half * s2 + kg * lm + cc * em)
        if not den > 0.0:
            return None
        g = 1.0 / sqrt(den)
        t_k += wkc * g
        t_g += wgc * g
    scale = 0.5 * math.pi * abs(d)
    t_k *= scale
    t_g *= scale
    if not abs(t_k - t_g) <= ARC_QUAD_RTOL * t_k:
        return None
    return t_k


def evaluate_arcs(sv: Solve, t, idx, rows, x, xd, work) -> None:
    """Samples inside semi-analytic arcs (:meth:`Solve.arc`), vectorised.

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
        return kk * dr / gap + kg * log_mean_m1_arr(e / gap) + cc * exp_mean_arr(lam * e)

    def rate(th, k):  # dt/dtheta of the samples k
        dk = d[k]
        e = dk * np.sin(0.5 * th) ** 2
        q = (base[k] + 0.5 * e + kg[k] * log_mean_m1_arr(e / gap[k])
             + cc[k] * exp_mean_arr(lam[k] * e))
        return np.abs(dk) * np.cos(0.5 * th) / np.sqrt(np.maximum(-2.0 * dk * q, 1e-300))

    xi = np.array(_GK_X)
    wk = np.array(_GK_WK)
    th = np.clip(math.pi * tau / period, 0.0, math.pi)
    # Newton on the samples not yet converged only (most converge in a few iterations; a
    # sample's angle then no longer depends on which others are evaluated with it). A
    # sample at an arc's start (a reversal: every one is among a result's points) is its
    # angle 0 already.
    act = np.nonzero(tau != 0.0)[0]
    for _ in range(ARC_SAMPLE_NEWTON):
        if not len(act):
            break
        ta = th[act]
        nodes = 0.5 * ta[:, None] * (1.0 + xi[None, :])
        t_th = 0.5 * ta * (rate(nodes.T, act).T @ wk)
        g = rate(ta, act)
        step = (t_th - tau[act]) / np.where(g > 0.0, g, 1.0)
        th[act] = np.clip(ta - step, 0.0, math.pi)
        act = act[np.abs(step) > ARC_SAMPLE_STEP]
    e = d * np.sin(0.5 * th) ** 2
    q = base + 0.5 * e + kg * log_mean_m1_arr(e / gap) + cc * exp_mean_arr(lam * e)
    x[idx] = x_r + e
    xd[idx] = np.sign(d) * np.sqrt(np.maximum(-2.0 * e * q, 0.0))
    work[idx, 0] = w0[:, 0] + sa * e
    work[idx, 1] = w0[:, 1] + sa * sv.vb * tau
    work[idx, 2] = w0[:, 2] + e * mean_phi(e)
