"""A contact of a train on the deformable stop, kept on its first integral.

A contact that starts at the stop's face with the law fresh (first loading, paper Eq. 13
from the origin) and slides towards the stop throughout (``s = +1``, paper Eq. 14) follows
one curve of the law on each branch, a function of the overlap alone, so it conserves
``u^2/2 + U(delta)`` with ``U = int phi + delta^2/2 - (a - x_bar) delta`` (as the node
contacts of :mod:`core.deformable.node` do). Integrated step by step at the preset's
tolerance, each such contact left its separation speed off by up to ~2e-7 relative at
rtol 1e-8, and a train of them added those errors up in its phase: the state at
``t = 100`` was off by up to 1.1e-4 of the length scale after 60 to 600 contacts
(``benchmarks/hysteretic_speed.py``). Two causes, both removed here:

* the unloading curve meets ``phi_C`` where it is clipped back onto it (Eq. 11): a kink of
  the force, which a step across it does not resolve (its error estimate does not see
  it). The step that would cross it is redone to end on it (:class:`Kinks`);
* the peak and the separation speed carry the integration's error. They are projected onto
  the first integral: the peak is the root of ``U_C(r) = w^2 / 2`` on ``phi_C``
  (:func:`project_peak`), the separation speed ``sqrt(w^2 - 2 L)`` with ``L`` the area
  between ``phi_C`` and the unloading curve, in closed form (:func:`project_separation`).

What is left is each contact's duration, integrated (~1e-10 at rtol 1e-8), which adds up
only linearly. The first two branches of a contact that is not of this kind (a stick or a
sign change in contact: the first contacts of a train from rest) are stepped at a tighter
tolerance (:data:`TIGHT_RTOL`): they are few, and their errors stay in the phase of every
contact after them.
"""

from __future__ import annotations

import math

from core.deformable.arcs import exp_mean, log_mean_m1
from core.deformable.hermite import first_exit, hermite_coeffs, poly
from core.deformable.law import Branch, clip_breaks, leaving_overlap
from core.deformable.node import S_PLUS_MARGIN, envelope_work
from core.deformable.state import Solve

#: The tolerance of a contact's first two branches where they are not projected, relative
#: to the solve's ``rtol``, and its floor: 1e-11 at the standard preset. From rest on
#: ``k_c0 = 1e4, beta = 10, D = 1e-3`` the first contact's error in the speed (1e-10 at
#: 1e-11, 7e-9 at 1e-8) was 5.4e-8 of the scale at ``t = 100`` with this, 4.2e-6 with
#: 1e-2 times ``rtol``; on ``k_c0 = 100, beta = 1, D = 0.01`` (a stick in every contact)
#: 2.8e-6 at the preset.
TIGHT_RTOL, TIGHT_RTOL_MIN = 1e-3, 1e-13
#: A step redone to end on a kink has landed on it when what is left to it is below this
#: fraction of the step.
KINK_LANDING = 1e-6
#: Clip points within this fraction of the peak overlap are the peak itself (the unloading
#: curve leaves ``phi_C`` there).
KINK_MARGIN = 1e-9
#: Kinks within this fraction of the peak overlap from the face are left to the separation.
KINK_FACE = 1e-6
#: Newton steps for where an unloading curve meets ``phi_C`` again (:func:`unloading_breaks`;
#: then brentq).
BREAK_NEWTON = 60
#: Below this the break (over ``D``) is at the face, to rounding.
BREAK_FLOOR = 1e-300
#: Largest correction of a projected peak (over ``D``) or separation speed (over the
#: approach speed) that is taken, and its floor: this times the solve's ``rtol``, at least
#: the floor. A larger one means the contact is not the one the projection assumes. The
#: integration's own error can be far above ``rtol`` on a sharp stop: on ``k_c0 = 1e4,
#: beta = 1000, D = 0.01`` a contact's integrated separation speed was off by 1.5e-6 of it
#: at rtol 1e-8, and a fixed 1e-6 refused its projection (its phase then kept that error:
#: 5e-6 of the scale at t = 100). On ``k_c0 = 1500, beta_e = 880, D = 0.035`` it was off
#: by 2.7e-6 at rtol 1e-9, and the floor of 1e-6 refused that projection too (the state
#: 3.1e-6 off by t = 40; a pressed stop's rest 4.8e-5 off, beyond its stated bound): the
#: floor is 1e-4. A contact the projection does not describe (a stick, a sign change, a
#: second reversal) is told by :class:`TrainContact`'s ``regular``; the floor guards the rest.
PROJECTION_PER_RTOL, PROJECTION_MAX = 1e3, 1e-4


class TrainContact:
    """The step-by-step solve's current contact, as far as it is one of a train.

    ``regular`` while it is: from the face with the law fresh, slip towards the stop (paper
    law), no stick or sign change, at most one reversal, and a peak the closed forms hold
    for. ``breaks`` are where its unloading curve meets ``phi_C`` (descending).
    """

    def __init__(self, sv: Solve, x: float, w: float, s: int, stick: bool):
        self.sv, self.w = sv, w
        self.regular = s == 1 and not stick and x == sv.xb
        self.breaks: list[float] = []
        self.r = 0.0  # the peak overlap

    def kinks(self) -> list[float]:
        """Positions of the kinks ahead on the unloading branch; one within
        :data:`KINK_FACE` of the peak from the face is left to the separation (a step landed
        on the face started the next on the separation's event, which is not taken at a
        step's start: on Fig. 10's stop at rtol 1e-10 the separation came 5e-8 late; one
        landed 2e-8 of the peak above it, at rtol 1e-13 on ``k_c0 = 1e6, beta = 1000,
        D = 1e-3``, left the speed 2e-5 off). The force differs there by less than
        ``k_c0 D`` times that from the curve it is clipped to."""
        if not self.regular or not self.breaks:
            return []
        face = KINK_FACE * self.r
        return [self.sv.xb + d for d in self.breaks if d > face]

    def tight(self, reversals: int) -> bool:
        """Whether the current branch is stepped at the tighter tolerance."""
        return reversals <= 1 and not self.regular

    def peak(self, delta: float, reversals: int) -> float:
        """The overlap of a reversal: projected at the first of a regular contact."""
        if self.regular and reversals == 0:
            return project_peak(self.sv, self.w, delta)
        self.regular = False
        return delta

    def unloading(self, branch: Branch) -> None:
        """The branch after the reversal: where it meets ``phi_C``."""
        if self.regular:
            self.r = branch.delta_r
            breaks = unloading_breaks(self.sv, branch)
            self.regular = breaks is not None
            self.breaks = breaks or []

    def separation(self, v: float, branch: Branch, reversals: int) -> float:
        """The separation velocity: projected for a regular contact."""
        if self.regular and reversals == 1:
            return project_separation(self.sv, self.w, branch, self.breaks, v)
        return v


class Kinks:
    """Kinks of the force ahead of a contact's steps, positions descending (the overlap
    falls): a step that would cross the next one is redone to end on it (:meth:`cut`); once
    it has (:meth:`landed`), the next one is ahead."""

    def __init__(self, xs: list[float]):
        self.xs = list(xs)
        self.x = self.xs.pop(0) if self.xs else -math.inf

    def cut(self, x, u, a0, x1, u1, a1, h: float) -> float:
        """The step from ``(x, u)`` of size ``h`` ending at ``x1 < self.x`` shortened to end
        on the kink (located on the step's interpolant), or 0 if it cannot be."""
        if not (math.isfinite(a1) and math.isfinite(u1)):
            return 0.0
        coeffs = hermite_coeffs(x, u, a0, x1, u1, a1, h)
        kink = self.x
        th = first_exit(lambda th: poly(coeffs, th) - kink)
        return th * h if 0.0 < th < 1.0 else 0.0

    def landed(self, x0: float, x1: float) -> None:
        """After the shortened step from ``x0`` to ``x1``: on to the next kink if it ended
        on this one (to the interpolant's accuracy)."""
        if x1 - self.x <= KINK_LANDING * (x0 - x1):
            self.x = self.xs.pop(0) if self.xs else -math.inf


def project_peak(sv: Solve, w: float, delta: float) -> float:
    """The peak overlap of a first loading from the face at approach speed ``w`` in slip
    towards the stop: the root of ``U_C(r) = w^2 / 2`` (``U_C = int phi_C + delta^2 / 2 -
    (a - x_bar) delta``, paper Eq. 14 with ``x' = 0``), by Newton from the integrated
    ``delta`` (``U_C`` rises there: the net force pushes back); ``delta`` itself if that
    does not converge close to it."""
    stop, d_lim = sv.stop, sv.d_lim
    kc, gap, level = stop.k_c0 * d_lim, sv.a - sv.xb, 0.5 * w * w
    r = delta
    for _ in range(4):
        if not 0.0 < r < sv.d_max:
            return delta
        excess = envelope_work(kc, d_lim, r) + r * (0.5 * r - gap) - level
        slope = kc * r / (d_lim - r) - gap + r
        if not slope > 0.0:
            return delta
        step = excess / slope
        r -= step
        if abs(step) <= 4e-16 * r:
            break
    return r if abs(r - delta) <= _projection_max(sv) * d_lim else delta


def project_separation(sv: Solve, w: float, branch: Branch, breaks: list[float],
                       v: float) -> float:
    """The separation velocity of a regular contact, ``-sqrt(w^2 - 2 L)``: ``L`` is the area
    between ``phi_C`` and the unloading ``branch`` where that is below ``phi_C`` (between
    its ``breaks``, :func:`unloading_breaks`), in closed form; the integrated ``v`` where
    the correction is not small (not the contact this assumes)."""
    stop, d_lim = sv.stop, sv.d_lim
    r = branch.delta_r
    gap = d_lim - r
    k_d = (stop.k_c0 - stop.k_e0) * d_lim
    c0 = branch.phi_r - stop.k_e0 * d_lim * r / gap
    lam = stop.beta_e / d_lim

    def area(span: float) -> float:
        # int (phi_C - phi) over [r - span, r] as means over it, without cancellation
        # (core.deformable.node._loss, in scalars)
        if not span > 0.0:
            return 0.0
        band = k_d * r / gap + k_d * d_lim / gap * log_mean_m1(-span / gap)
        return span * (band - c0 * exp_mean(-lam * span))

    # none: an elastic contact; two (from a peak above s+): less the part above the
    # first, where the curve is above phi_C (clipped to it)
    loss = 0.0
    if breaks:
        loss = area(r - breaks[-1]) - (area(r - breaks[0]) if len(breaks) == 2 else 0.0)
    out2 = w * w - 2.0 * loss
    if not out2 > 0.0:
        return v
    out = -math.sqrt(out2)
    return out if abs(out - v) <= _projection_max(sv) * w else v


def _projection_max(sv: Solve) -> float:
    """The largest relative correction a projection may make (:data:`PROJECTION_PER_RTOL`)."""
    return max(PROJECTION_MAX, PROJECTION_PER_RTOL * sv.rtol)


def unloading_breaks(sv: Solve, branch: Branch) -> list[float] | None:
    """Where the unloading ``branch`` from a peak on ``phi_C`` meets ``phi_C`` again,
    descending: none (an elastic contact, clipped onto ``phi_C`` all the way), one (where it
    is clipped back onto it) or, from a peak above ``s+``, where it first keeps to
    ``phi_C``, two (where it leaves it, and where it is clipped back); ``None`` where that
    is not what the law does (a peak near ``s+``).

    Below ``s+`` it meets ``phi_C`` once, at ``u = delta / D < s- / D``, if the peak is
    above ``s-``, where ``g(u) = log(u / (1 - u)) - beta_e u + C`` vanishes (the logarithm
    of :func:`core.deformable.law.clip_breaks`'s ``f``): ``g`` rises and is concave on
    ``(0, s- / D)``, so Newton from the root of its first two terms, left of the root,
    converges to it from the left (in ~5 steps; brentq took ten times as long). Above
    ``s+`` (rare: the first contacts of a train from rest), by brentq."""
    stop, r, d_lim = sv.stop, branch.delta_r, sv.d_lim
    if branch.loading:
        return None
    s_plus = leaving_overlap(stop)
    if r >= s_plus - S_PLUS_MARGIN * d_lim:
        if stop.law == "passive":
            return None  # it keeps to phi_C down to s+ (docs/contact-law.md): not this
        breaks = clip_breaks(0.0, r * (1.0 - KINK_MARGIN), branch, stop)
        return sorted(breaks, reverse=True) if len(breaks) == 2 else None
    c = branch.phi_r - stop.k_e0 * d_lim * r / (d_lim - r)
    k_d = (stop.k_c0 - stop.k_e0) * d_lim
    if r <= d_lim - s_plus or not (c > 0.0 and k_d > 0.0):
        return []
    beta = stop.beta_e
    big_c = math.log(k_d / c) + beta * r / d_lim
    u = 1.0 / (1.0 + math.exp(big_c)) if big_c < 700.0 else math.exp(-big_c)
    if u < BREAK_FLOOR:
        return [0.0]
    u = _clip_root(u, beta, big_c, (d_lim - s_plus) / d_lim)
    if u is not None:
        return [u * d_lim]
    breaks = [d for d in clip_breaks(0.0, r, branch, stop) if d < r * (1.0 - KINK_MARGIN)]
    return breaks if len(breaks) <= 1 else None


def _clip_root(u: float, beta: float, big_c: float, u_minus: float) -> float | None:
    """Newton on ``g(u) = log(u / (1 - u)) - beta u + C`` from ``u`` (left of its root in
    ``(0, u_minus)``, see :func:`unloading_breaks`); ``None`` if it leaves that interval or
    does not converge."""
    for _ in range(BREAK_NEWTON):
        step = (math.log(u / (1.0 - u)) - beta * u + big_c) / (1.0 / (u * (1.0 - u)) - beta)
        u -= step
        if not 0.0 < u < u_minus:
            return None
        if abs(step) <= 4e-16 * u:
            return u
    return None
