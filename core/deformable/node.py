"""One regular contact of a pressed train in closed form and by quadrature: the node
contacts of the contact-to-contact map (:mod:`core.deformable.train_map`).

A contact of the train starts at the face with the law fresh and slip towards the stop
(``s = +1`` throughout: its speeds stay below the slip circle's largest, which is below the
belt's). On each branch the force is a function of the overlap alone, so the motion
conserves ``u^2/2 + U(delta)`` with ``U = int phi + (x_bar - a) delta + delta^2/2`` (paper
Eq. 14 with the law of Eqs. 11-13):

* loading follows ``phi_C`` from the origin to the peak ``r``, the root of
  ``U_C(r) = w^2/2``;
* unloading from ``(r, phi_C(r))`` follows the exponential of Eq. 13 towards ``phi_E``
  down to ``delta_c``, where it meets ``phi_C`` again, and ``phi_C`` below (above ``s-``;
  below ``s-`` it keeps to ``phi_C`` all the way: an elastic contact). For ``r < s+`` the
  paper's reading and the passive one give this same contact.

The speed lost is the area between the two curves, in closed form,
``L = int_{delta_c}^r (phi_C - phi_U)``, and the separation speed is
``sqrt(w^2 - 2 L)``. Only the durations need a quadrature: over each piece the time is
``int d delta / |u|`` with ``delta = top + span sin^2(theta / 2)`` between two turning
points of the piece's energy (on ``phi_C`` one of them lies past the face, on the
envelope continued), which removes both ``1/sqrt`` (:class:`_Piece`); each integrand is
interpolated by a Chebyshev series (:data:`CHEB_POINTS` points) and integrated term by
term, and the series' tail bounds its error. The same series give the
contact's profile (overlap and velocity at evenly spaced times, by Newton on the time).

Refused (``None``: the contact is integrated step by step) where it is not this contact:
a peak at or above ``s+`` (more than one clip on the unloading curve), the limit overlap,
the stop's strength, no separation, a speed that could reach the belt's, or a series
whose tail is above :data:`CHEB_RTOL`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import chebyshev as cheb

from core.deformable.arcs import exp_mean_arr, log_mean_m1_arr
from core.deformable.law import FIRST_LOADING, clip_breaks, leaving_overlap, reverse
from core.deformable.state import Solve

#: Chebyshev points of each piece's integrand: the integrands are analytic on ``s`` in
#: ``[0, 1]`` (the envelope's pole at ``D`` and the exponential's growth set how fast the
#: series converges; a piece that needs more is refused).
CHEB_POINTS = 33
#: Largest tail (the last :data:`TAIL` coefficients, doubled) of an integrand's series,
#: relative to its first coefficient (the mean): the duration is then good to ~1e-12, the
#: nodes' tolerance (the coefficients' rounding floor is ~1e-14).
CHEB_RTOL = 1e-12
TAIL = 3
#: Newton iterations of the profile's points on the time series, from a start
#: interpolated on :data:`PROFILE_GRID` points of it (good to ~1e-6: two reach rounding).
PROFILE_NEWTON = 2
PROFILE_GRID = 257
#: Margin below ``s+`` (relative to ``D``) for the peak of a contact taken in closed form.
S_PLUS_MARGIN = 1e-6

# Chebyshev-Lobatto points on [-1, 1] (descending) and on s in [0, 1], and the matrix
# taking values there to the series' coefficients (discrete cosine transform).
_N = CHEB_POINTS - 1
_Y = np.cos(np.pi * np.arange(CHEB_POINTS) / _N)
_S = 0.5 * (1.0 + _Y)
_DCT = np.cos(np.pi * np.outer(np.arange(CHEB_POINTS), np.arange(CHEB_POINTS)) / _N)
_DCT[:, 0] *= 0.5
_DCT[:, -1] *= 0.5
_DCT *= 2.0 / _N
_DCT[0] *= 0.5
_DCT[-1] *= 0.5
# Term-by-term integration of a series of CHEB_POINTS terms (from y = -1), and the basis
# on the grid the profile's times start from.
_INT = np.column_stack([cheb.chebint(np.eye(CHEB_POINTS)[j], lbnd=-1.0)
                        for j in range(CHEB_POINTS)])
_GRID_Y = np.linspace(-1.0, 1.0, PROFILE_GRID)
_GRID_BASIS = np.cos(np.outer(np.arccos(_GRID_Y), np.arange(CHEB_POINTS + 1)))


class _Piece:
    """One piece of the contact on one curve of the law: ``delta = top + span
    sin^2(theta / 2)`` (``span`` signed, from the turning point ``top`` towards the other
    turning point of the same energy), ``theta`` from ``th0`` to ``th1`` as ``s`` goes
    from 0 to 1, and ``u^2 = -2 e mean(e)`` with ``e = delta - top`` and ``mean`` the mean
    net force over ``[top, delta]`` (which has no cancellation). ``dt/dtheta = |span|
    cos(theta/2) / sqrt(-2 span mean)`` is analytic on ``[0, pi]``: both turning points'
    ``1/sqrt`` are removed, also where one of them lies beyond the face (the envelope
    continued), so the series converges fast. The time is a Chebyshev series in ``s``
    integrated term by term; ``tail`` is the integrand's relative tail."""

    def __init__(self, top: float, span: float, mean, th0: float, th1: float):
        self.top, self.span, self.mean, self.th0, self.th1 = top, span, mean, th0, th1
        _, _, rate = self.at(_S)
        self.finite = bool(np.all(np.isfinite(rate)))
        self.rate = _DCT @ rate
        self.time = 0.5 * (_INT @ self.rate)  # from s = 0 (y = -1)
        self.total = float(self.time.sum())  # T_k(1) = 1
        lead = abs(self.rate[0])
        self.tail = 2.0 * float(np.abs(self.rate[-TAIL:]).sum()) / lead if lead > 0 else math.inf

    def at(self, s):
        """Overlap, speed ``|u|`` and ``dt/ds`` at ``s``."""
        th = self.th0 + (self.th1 - self.th0) * s
        e = self.span * np.sin(0.5 * th) ** 2
        q = -2.0 * self.span * self.mean(e)
        rate = (self.th1 - self.th0) * abs(self.span) * np.cos(0.5 * th) / np.sqrt(
            np.maximum(q, 1e-300))
        return self.top + e, np.sqrt(np.maximum(q, 0.0)) * np.abs(np.sin(0.5 * th)), rate

    def ok(self) -> bool:
        return self.finite and self.tail <= CHEB_RTOL

    def invert(self, tau: np.ndarray) -> np.ndarray:
        """The ``s`` at which the piece's time is ``tau`` (an array within the piece):
        interpolated on a fine grid of the series, then Newton on it."""
        y = np.interp(tau, _GRID_BASIS @ self.time, _GRID_Y)
        k = np.arange(CHEB_POINTS + 1)
        for _ in range(PROFILE_NEWTON):
            basis = np.cos(np.outer(np.arccos(y), k))
            g = 0.5 * (basis[:, :-1] @ self.rate)
            y = np.clip(y - (basis @ self.time - tau) / np.where(g > 0.0, g, 1.0), -1.0, 1.0)
        return 0.5 * (1.0 + y)


def _mean_hyper(k_d: float, d_lim: float, top: float, e):
    """Mean of ``k_d delta / (D - delta)`` over ``[top - e, top]`` (``e >= 0``), without
    cancellation: ``k_d h(top) + k_d D / (D - top) (L(-e / (D - top)) - 1)`` with
    ``L(w) = -log(1 - w) / w`` (the form of :func:`core.deformable.arcs.arc`)."""
    gap = d_lim - top
    return k_d * top / gap + k_d * d_lim / gap * log_mean_m1_arr(-np.asarray(e) / gap)


def _root(f, slope, x: float) -> float | None:
    """Newton on a convex ``f`` from a point ``x`` where ``f(x) >= 0`` on the side of the
    root it converges to monotonically; ``None`` if it does not converge."""
    for _ in range(80):
        step = f(x) / slope(x)
        x_new = x - step
        if abs(step) <= 4e-16 * abs(x_new) or x_new == x:
            return x_new
        x = x_new
    return None


def _peak(sv: Solve, w: float):
    """Peak overlap ``r`` of the first loading at approach speed ``w``, the turning point
    ``low < 0`` of the same energy on ``phi_C`` continued past the face, the potential
    ``U_C`` and its slope; ``None`` at the limit overlap or within :data:`S_PLUS_MARGIN` of
    ``s+`` (or above)."""
    stop, d_lim = sv.stop, sv.d_lim
    gap = sv.a - sv.xb
    kc = stop.k_c0 * d_lim

    def u_c(d: float) -> float:  # U_C: the potential on phi_C (continued past the face)
        return envelope_work(kc, d_lim, d) - gap * d + 0.5 * d * d

    def f_c(d: float) -> float:
        return kc * d / (d_lim - d) - gap + d

    level = 0.5 * w * w
    hi = min(sv.d_max, w / math.sqrt(stop.k_c0) + 2.0 * gap / stop.k_c0 + w * w / gap)
    if u_c(hi) < level:
        hi = sv.d_max
        if u_c(hi) < level:
            return None  # the limit overlap
    r = _root(lambda d: u_c(d) - level, f_c, hi)
    low = _root(lambda d: u_c(d) - level, f_c, -w * w / gap)
    if r is None or low is None or not (low < 0.0 < r):
        return None
    if r >= leaving_overlap(stop) - S_PLUS_MARGIN * d_lim or r >= sv.d_max:
        return None
    return r, low, u_c, f_c


def _loss(stop, r: float, span: float, c0: float, lam: float) -> float:
    """The area between ``phi_C`` and the unloading curve over ``[r - span, r]``: the
    contact's loss of ``u^2 / 2``, without cancellation (means over the piece)."""
    if not span > 0.0:
        return 0.0
    d_lim = stop.limit_overlap
    band = _mean_hyper((stop.k_c0 - stop.k_e0) * d_lim, d_lim, r, span)
    return span * float(band - c0 * exp_mean_arr(np.array(-lam * span)))


def _unloading(sv: Solve, w: float):
    """The peak of the contact at approach speed ``w`` and its unloading:
    ``(r, low, U_C, phi_C, phi_r, d_c, w_out^2)`` with the peak overlap ``r``, the far
    turning point ``low`` and the potential and force on ``phi_C`` (:func:`_peak`), the
    force at the peak, the overlap ``d_c`` below which the unloading keeps to ``phi_C``, and
    the separation speed squared; ``None`` where the contact is not one regular contact."""
    stop, d_lim = sv.stop, sv.d_lim
    gap = sv.a - sv.xb
    if not (0.0 < w and gap > 0.0 and math.hypot(gap, w) < sv.vb):
        return None
    peak = _peak(sv, w)
    if peak is None:
        return None
    r, low, u_c, f_c = peak
    phi_r = stop.k_c0 * d_lim * r / (d_lim - r)
    if phi_r > stop.strength:
        return None
    breaks = clip_breaks(0.0, r, reverse(r, phi_r, FIRST_LOADING, stop), stop)
    if len(breaks) > 1:
        return None
    d_c = breaks[0] if breaks else r  # below d_c the unloading keeps to phi_C
    c0 = (stop.k_c0 - stop.k_e0) * d_lim * r / (d_lim - r)  # the exponential's amplitude
    loss = _loss(stop, r, r - d_c, c0, stop.beta_e / d_lim)
    w_out2 = w * w - 2.0 * loss
    if not w_out2 > 0.0:
        return None  # it does not separate: a second reversal in contact
    return r, low, u_c, f_c, phi_r, d_c, w_out2


def node_contact(sv: Solve, w: float, profile_points: int | None):
    """The contact from the face at approach speed ``w`` with the law fresh, in closed form:
    ``(separation speed, duration, peak x, largest |x''|, profile)`` (the profile
    ``None`` if ``profile_points`` is), or ``None`` where it is refused (see the module's
    docstring)."""
    stop, d_lim, xb = sv.stop, sv.d_lim, sv.xb
    gap = sv.a - xb
    kc, ke = stop.k_c0 * d_lim, stop.k_e0 * d_lim
    unloading = _unloading(sv, w)
    if unloading is None:
        return None
    r, low, u_c, f_c, phi_r, d_c, w_out2 = unloading
    c0 = (stop.k_c0 - stop.k_e0) * d_lim * r / (d_lim - r)  # the exponential's amplitude
    lam = stop.beta_e / d_lim
    span = r - d_c

    def on_c(top):  # mean net force over [top, top + e] on phi_C
        return lambda e: (_mean_hyper(kc, d_lim, top, -e) + top + 0.5 * e - gap)

    def on_raw(e):  # the same on the unloading exponential from the peak
        return (_mean_hyper(ke, d_lim, r, -e) + c0 * exp_mean_arr(lam * e) + r + 0.5 * e
                - gap)

    def angle(top: float, other: float, d: float) -> float:  # theta of d in [top, other]
        return 2.0 * math.asin(math.sqrt(min(1.0, (d - top) / (other - top))))

    load = _Piece(r, low - r, on_c(r), 0.0, angle(r, low, 0.0))
    parts = [load]
    if span > 0.0:
        parts.append(_Piece(r, -span, on_raw, 0.0, math.pi))
        # Below d_c on phi_C at the energy left: its turning points top_c > d_c, low_c < 0.
        level_c = 0.5 * w_out2
        top_c = _root(lambda d: u_c(d) - level_c, f_c, r)
        low_c = _root(lambda d: u_c(d) - level_c, f_c, -w_out2 / gap)
        if top_c is None or low_c is None or not (low_c < 0.0 <= d_c <= top_c):
            return None
        parts.append(_Piece(top_c, low_c - top_c, on_c(top_c), angle(top_c, low_c, d_c),
                            angle(top_c, low_c, 0.0)))
    if not all(p.ok() for p in parts):
        return None
    dur = load.total + (sum(p.total for p in parts[1:]) if span > 0.0 else load.total)
    accel = abs(sv.a - (xb + r) - phi_r)
    profile = None
    if profile_points is not None:
        profile = _node_profile(parts, dur, profile_points)
    return math.sqrt(w_out2), dur, xb + r, accel, profile


def envelope_work(kc: float, d_lim: float, d: float) -> float:
    """``int_0^d phi_C`` (``kc = k_c0 D``; continued past the face for ``d < 0``), by the
    series for small ``|d| / D``."""
    x = d / d_lim
    if abs(x) < 0.05:
        total, term = 0.0, x
        for n in range(2, 26):
            term *= x
            total += term / n
        return kc * d_lim * total
    return kc * d_lim * (-x - math.log1p(-x))


def _node_profile(parts, dur: float, n: int) -> np.ndarray:
    """Overlap and velocity of the contact at ``n`` times spread evenly over ``dur``:
    loading (time from the face: the piece's from the peak, reversed), then the unloading
    pieces (or the loading mirrored where the contact is elastic)."""
    times = np.linspace(0.0, dur, n)
    out = np.zeros((2, n))
    load = parts[0]
    t_load = load.total
    m = times <= t_load
    delta, speed, _ = load.at(load.invert(t_load - times[m]))
    out[0, m], out[1, m] = delta, speed
    t0 = t_load
    for k, piece in enumerate(parts[1:] if len(parts) > 1 else [load]):
        last = k == max(len(parts) - 2, 0)
        m = (times > t0) if last else ((times > t0) & (times <= t0 + piece.total))
        delta, speed, _ = piece.at(piece.invert(np.minimum(times[m] - t0, piece.total)))
        out[0, m], out[1, m] = delta, -speed
        t0 += piece.total
    out[0, -1] = 0.0
    return out
