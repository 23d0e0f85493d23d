"""The hysteretic contact law of the deformable stop (paper Eqs. 9-13): both readings, their
reversal rules, the work along their branches and the energy they store.

Two readings of the transition curves, chosen by ``HystereticStop.law`` and compared in
docs/contact-law.md: ``"paper"`` (below; reproduces the paper's Fig. 2b, returns energy on
some overlap programs) and ``"passive"`` (:func:`passive_force_and_slope`).

Overlap ``delta = x - clearance`` (a length, ``> 0`` in contact), limit overlap
``D = stop.limit_overlap``. Forces are contact forces over the spring stiffness ``k``
(lengths), stiffnesses are relative to ``k``.

Envelopes (paper Eq. 11), hyperbolas through the origin with the asymptote ``delta = D``::

    phi_C(delta) = k_c0 * D * delta / (D - delta)     compression
    phi_E(delta) = k_e0 * D * delta / (D - delta)     expansion, k_e0 <= k_c0

Transition curves (paper Eqs. 12-13, the ``"paper"`` reading). At each reversal of the
overlap rate the point ``(delta_r, phi_r)`` is stored, and the force approaches the
envelope of the new direction exponentially in the overlap travelled since the reversal::

    unloading: phi = phi_E(delta) + (phi_r - phi_E(delta_r)) * exp(-beta_e (delta_r - delta) / D)
    reloading: phi = phi_C(delta) - (phi_C(delta_r) - phi_r) * exp(-beta_c (delta - delta_r) / D)

The force is always kept between the envelopes, ``phi_E <= phi <= phi_C`` (they are limit
curves), and ``phi = 0`` for ``delta <= 0`` (separation). First loading from the origin is the
reloading curve from ``(0, 0)``: the compression envelope itself.

Two consequences worth knowing (both tested):

* An unloading curve meets the compression envelope again near the origin, so the last part of
  every unloading follows ``phi_C`` down to ``phi = 0`` at separation: the force is continuous
  in ``delta`` and vanishes at separation.
* Starting from the compression envelope, the unloading curve leaves it only where
  ``beta_e * delta * (D - delta) > D**2``; a contact whose overlap stays below about
  ``D / beta_e`` is elastic whatever ``k_e0 / k_c0`` says. The restitution of the equivalent
  rigid stop, ``sqrt(k_e0 / k_c0)`` (paper Eq. 16), needs a sharp transition,
  ``beta * delta_max / D >> 1``.

Along one branch the force is a function of ``delta`` alone, so the work done on the stop is a
path integral in ``delta``; :func:`branch_work` evaluates it in closed form (antiderivatives of
the hyperbola and the exponential, split where the clip to an envelope switches on or off).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from core.params import HystereticStop

#: Below this ``delta / D`` the envelope energy ``-x - log1p(-x)`` is summed as its series
#: ``x^2/2 + x^3/3 + ...``: the closed form loses all digits to cancellation as ``x -> 0``.
SERIES_CUTOFF = 0.05
#: Terms of that series: ``0.05**24 / 24 ~ 2e-33``, far below double precision of ``x^2/2``.
SERIES_TERMS = 24
#: Relative tolerance of the roots where a transition curve meets an envelope (the root is
#: only a breakpoint of a continuous integrand: its error enters the work at second order).
ROOT_RTOL = 4.0 * np.finfo(float).eps
#: Absolute tolerance of those roots, relative to ``D``.
ROOT_XTOL_REL = 1e-15
#: Cap of an exponent when a branch is evaluated behind its reversal point (an event
#: locator may probe there): ``exp(700)`` is finite, and the clip to the envelopes takes over.
EXP_CAP = 700.0


@dataclass(frozen=True)
class Branch:
    """The curve the contact force follows between two reversals of the overlap rate.

    Attributes
    ----------
    loading : bool
        ``True`` while the overlap grows (reloading curve towards ``phi_C``), ``False`` while
        it shrinks (unloading curve towards ``phi_E``).
    delta_r, phi_r : float
        The stored reversal point: overlap (a length) and force over ``k`` (a length).
    anchor : tuple of float, optional
        The passive law only: the point ``(overlap, force)`` its curve was created through
        (a reversal on ``phi_C``, or ``s+``), kept by reversals on that curve (:func:`reverse`).
        ``None``: the curve through ``(delta_r, phi_r)``. Recomputed from a reversal near
        ``phi_E``, where the curve is within a few ulps of it, the curve's constant would keep
        only those ulps, and ``exp(beta_e swing / D)`` would carry them to the top of the loop.
    """

    loading: bool
    delta_r: float
    phi_r: float
    anchor: tuple[float, float] | None = None


#: The overlap counts as reaching the limit overlap ``D`` at ``(1 - LIMIT_MARGIN) D``, in
#: every method: the envelopes' asymptote is never crossed (the force there is
#: ``k_c0 D / LIMIT_MARGIN``, the tangent stiffness ``k_c0 / LIMIT_MARGIN^2``, far beyond
#: any physical stop). With 1e-6 here and 1e-9 in the event and switch methods, a contact
#: peaking at ``1 - 2.3e-7`` of ``D`` ended one solve at the limit and not the others.
LIMIT_MARGIN = 1e-6

#: The branch of every new contact: the compression envelope from the origin (paper §2.4).
FIRST_LOADING = Branch(True, 0.0, 0.0)


def _hyperbola(delta, stiffness: float, d_lim: float):
    delta = np.asarray(delta, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(
            delta <= 0.0,
            0.0,
            np.where(delta < d_lim, stiffness * d_lim * delta / (d_lim - delta), np.inf),
        )
    return out[()] if out.ndim == 0 else out


def phi_compression(delta, stop: HystereticStop):
    """Compression envelope ``phi_C = k_c0 D delta / (D - delta)`` (paper Eq. 11, upper).

    Parameters
    ----------
    delta : float or array_like
        Overlap (a length); ``0`` for ``delta <= 0`` and ``inf`` for ``delta >= D``.
    stop : HystereticStop

    Returns
    -------
    float or ndarray
        Force over ``k`` (a length).

    Examples
    --------
    >>> stop = HystereticStop(clearance=0.1, k_c0=1000.0, k_e0=500.0, limit_overlap=0.05)
    >>> float(phi_compression(0.025, stop))     # k_c0 * D at delta = D/2
    50.0
    """
    return _hyperbola(delta, stop.k_c0, stop.limit_overlap)


def phi_expansion(delta, stop: HystereticStop):
    """Expansion envelope ``phi_E = k_e0 D delta / (D - delta)`` (paper Eq. 11, lower).

    Same conventions as :func:`phi_compression`.
    """
    return _hyperbola(delta, stop.k_e0, stop.limit_overlap)


def _envelope_slope(delta, stiffness: float, d_lim: float):
    """``d/d delta`` of ``stiffness * D * delta / (D - delta)``: ``stiffness * D^2/(D-delta)^2``."""
    delta = np.asarray(delta, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        gap = d_lim - delta
        out = np.where(gap > 0.0, stiffness * (d_lim / gap) ** 2, np.inf)
    return out


def _raw(delta, branch: Branch, stop: HystereticStop):
    """Unclipped transition curve of ``branch`` (paper Eq. 13, the "paper" reading)."""
    d_lim = stop.limit_overlap
    if branch.loading:
        gap0 = float(phi_compression(branch.delta_r, stop)) - branch.phi_r
        decay = np.exp(np.minimum(-stop.beta_c * (delta - branch.delta_r) / d_lim, EXP_CAP))
        return phi_compression(delta, stop) - gap0 * decay, gap0 * decay * stop.beta_c / d_lim
    gap0 = branch.phi_r - float(phi_expansion(branch.delta_r, stop))
    decay = np.exp(np.minimum(-stop.beta_e * (branch.delta_r - delta) / d_lim, EXP_CAP))
    return phi_expansion(delta, stop) + gap0 * decay, gap0 * decay * stop.beta_e / d_lim


#: A state within this relative distance of ``phi_C`` lies on the compression envelope
#: (the passive law's rules depend on it; states on it are reached by clipping, exactly).
ON_ENVELOPE_RTOL = 1e-9


def leaving_overlap(stop: HystereticStop) -> float:
    """Overlap ``s+`` above which unloading from ``phi_C`` keeps to ``phi_C``.

    From a point of the compression envelope the unloading curve (Eq. 13) leaves it going
    down only where ``beta_e s (D - s) > D^2``, i.e. between ``s-`` and
    ``s+ = D (1 + sqrt(1 - 4/beta_e)) / 2``; ``D`` (never reached) when ``beta_e <= 4``.
    """
    d_lim, beta = stop.limit_overlap, stop.beta_e
    if beta <= 4.0:
        return d_lim
    return 0.5 * d_lim * (1.0 + math.sqrt(1.0 - 4.0 / beta))


def _held_from_s_plus(d_a: float, c: float, s_plus: float, stop: HystereticStop) -> bool:
    """Whether the passive curve through the anchor at ``d_a`` (exponential's constant
    ``c``) reaches ``phi_C`` at ``s+`` and so keeps to it above (:func:`_passive_curve`)."""
    d_lim, rate = stop.limit_overlap, stop.beta_e / stop.limit_overlap
    if not s_plus < d_lim:
        return False
    raw_sp = stop.k_e0 * d_lim * s_plus / (d_lim - s_plus) + c * math.exp(
        min(rate * (s_plus - d_a), EXP_CAP))
    return raw_sp >= stop.k_c0 * d_lim * s_plus / (d_lim - s_plus) * (1.0 - ON_ENVELOPE_RTOL)


def _passive_curve(delta: float, d_a: float, p_a: float, stop: HystereticStop):
    """The passive law's curve through ``(d_a, p_a)``: the unloading exponential of Eq. 13
    through that point, clipped to the envelopes, and on ``phi_C`` above ``s+`` if it
    reaches ``phi_C`` there (see :func:`passive_force_and_slope`)."""
    d_lim = stop.limit_overlap
    gap = d_lim - delta
    hyper = d_lim * delta / gap
    hyper_slope = (d_lim / gap) ** 2
    upper, lower = stop.k_c0 * hyper, stop.k_e0 * hyper
    s_plus = leaving_overlap(stop)
    rate = stop.beta_e / d_lim
    c = p_a - stop.k_e0 * d_lim * d_a / (d_lim - d_a)
    if delta >= s_plus and _held_from_s_plus(d_a, c, s_plus, stop):
        return upper, stop.k_c0 * hyper_slope
    decay = c * math.exp(min(rate * (delta - d_a), EXP_CAP))
    raw = lower + decay
    if raw > upper:
        return upper, stop.k_c0 * hyper_slope
    if raw < lower:
        return lower, stop.k_e0 * hyper_slope
    return raw, stop.k_e0 * hyper_slope + decay * rate


def passive_force_and_slope(
    delta: float, branch: Branch, stop: HystereticStop
) -> tuple[float, float]:
    """``(phi, d phi / d delta)`` of the passive reading of Eqs. 12-13 (docs/contact-law.md).

    * Loading from a point of ``phi_C`` (a new contact, or a reversal on the envelope)
      follows ``phi_C``; loading from a point inside the band retraces the unloading curve
      through it (unloading and reloading inside the band are elastic, as in plasticity).
    * Unloading follows the exponential of Eq. 13 through the reversal point towards
      ``phi_E``, clipped to the envelopes; from a point of ``phi_C`` above ``s+``
      (:func:`leaving_overlap`) it keeps to ``phi_C`` down to ``s+`` and leaves there, as
      the incremental form of Eq. 13 does (the paper's reading restarts the exponent at
      the reversal, which leaves the envelope lower the higher the reversal).

    The energy the stop would give back from any state then never grows faster than the
    work done on it, so its loss never falls and no closed overlap program returns energy.
    """
    d_lim = stop.limit_overlap
    if delta <= 0.0:
        return 0.0, 0.0
    if delta >= d_lim:
        return math.inf, math.inf
    anchor = _passive_anchor(branch, stop)
    if anchor is None:
        gap = d_lim - delta
        return stop.k_c0 * d_lim * delta / gap, stop.k_c0 * (d_lim / gap) ** 2
    return _passive_curve(delta, anchor[0], anchor[1], stop)


def passive_branch_force(branch: Branch, stop: HystereticStop):
    """``phi(delta)`` of the passive law on one ``branch``, for ``0 < delta < D``, as a fast
    closure: the same operations as :func:`passive_force_and_slope` in the same order (so
    the same bits) with the branch's anchor and constants bound once, not found again at
    every stage of every step (about a third of the time per call)."""
    d_lim, k_c0, k_e0 = stop.limit_overlap, stop.k_c0, stop.k_e0
    anchor = _passive_anchor(branch, stop)
    if anchor is None:
        def on_compression(delta: float) -> float:
            gap = d_lim - delta
            return k_c0 * d_lim * delta / gap if gap > 0.0 else math.inf

        return on_compression
    d_a, p_a = anchor
    s_plus = leaving_overlap(stop)
    rate = stop.beta_e / d_lim
    c = p_a - k_e0 * d_lim * d_a / (d_lim - d_a)
    capped = _held_from_s_plus(d_a, c, s_plus, stop)  # on phi_C from s+ up
    exp = math.exp

    def on_curve(delta: float) -> float:
        if delta >= d_lim:
            return math.inf
        hyper = d_lim * delta / (d_lim - delta)
        upper = k_c0 * hyper
        if capped and delta >= s_plus:
            return upper
        lower = k_e0 * hyper
        raw = lower + c * exp(min(rate * (delta - d_a), EXP_CAP))
        if raw > upper:
            return upper
        return lower if raw < lower else raw

    return on_curve


def passive_as_paper(branch: Branch, stop: HystereticStop) -> Branch | None:
    """The branch of the paper's reading whose curve the passive law's ``branch`` is where
    the overlap goes on it, or ``None``: ``phi_C`` (a loading from a point of it) is the
    paper's first loading; an unloading from at most its anchor, below ``s+``, follows the
    exponential through the anchor clipped to ``phi_C``, the paper's unloading from the
    anchor where that lies above ``phi_E`` (the clip to ``phi_E`` never acts; the passive
    law's hold on ``phi_C`` from ``s+`` up is above the anchor, out of reach). The contact
    solver then evaluates it with the paper's closure (the same force to rounding; every
    contact of a train is of this kind)."""
    anchor = _passive_anchor(branch, stop)
    if anchor is None:
        return FIRST_LOADING
    if branch.loading:
        return None  # retracing up the curve: it may pass s+
    d_a, p_a = anchor
    d_lim = stop.limit_overlap
    if not (branch.delta_r <= d_a < leaving_overlap(stop)
            and p_a - stop.k_e0 * d_lim * d_a / (d_lim - d_a) > 0.0):
        return None
    return Branch(False, d_a, p_a)


def on_compression(d_r: float, p_r: float, stop: HystereticStop) -> bool:
    d_lim = stop.limit_overlap
    return d_r <= 0.0 or p_r >= stop.k_c0 * d_lim * d_r / (d_lim - d_r) * (1.0 - ON_ENVELOPE_RTOL)


def _passive_anchor(branch: Branch, stop: HystereticStop) -> tuple[float, float] | None:
    """The point the passive law's curve of ``branch`` goes through (:func:`_passive_curve`),
    ``None`` when it is ``phi_C`` (loading from a point of ``phi_C``)."""
    if branch.anchor is not None:
        return branch.anchor
    d_r, p_r = branch.delta_r, branch.phi_r
    on_c = on_compression(d_r, p_r, stop)
    if branch.loading and on_c:
        return None
    s_plus = leaving_overlap(stop)
    if not branch.loading and on_c and d_r > s_plus:
        d_lim = stop.limit_overlap
        return s_plus, stop.k_c0 * d_lim * s_plus / (d_lim - s_plus)
    return d_r, p_r


def _keeps_curve(delta: float, phi: float, anchor: tuple[float, float],
                 stop: HystereticStop) -> bool:
    """Whether ``(delta, phi)`` lies on the exponential of the passive curve through
    ``anchor`` where it is not clipped to ``phi_C`` (it is above ``phi_E`` wherever its
    constant is positive), to the force's rounding (the ``phi`` the law gave there)."""
    d_a, p_a = anchor
    d_lim = stop.limit_overlap
    if not (0.0 < delta < d_lim) or p_a <= stop.k_e0 * d_lim * d_a / (d_lim - d_a):
        return False
    value = _passive_curve(delta, d_a, p_a, stop)[0]
    return (value < stop.k_c0 * d_lim * delta / (d_lim - delta)
            and abs(phi - value) <= ON_ENVELOPE_RTOL * value)


def force_and_slope(delta: float, branch: Branch, stop: HystereticStop) -> tuple[float, float]:
    """Scalar ``(phi, d phi / d delta)`` on ``branch``: the fast path of the contact solver.

    Same law as :func:`contact_force` and :func:`dphi_ddelta` (tested to agree), written
    with :mod:`math` because the integrator calls it at every stage: about 1 us per call
    against ~30 us for the array versions on a scalar.
    """
    if stop.law == "passive":
        return passive_force_and_slope(delta, branch, stop)
    d_lim = stop.limit_overlap
    if delta <= 0.0:
        return 0.0, 0.0
    gap = d_lim - delta
    if gap <= 0.0:
        return math.inf, math.inf
    hyper = d_lim * delta / gap
    hyper_slope = (d_lim / gap) ** 2
    upper, lower = stop.k_c0 * hyper, stop.k_e0 * hyper
    if branch.loading:
        r_gap = branch.delta_r
        c = stop.k_c0 * d_lim * r_gap / (d_lim - r_gap) - branch.phi_r
        decay = c * math.exp(min(-stop.beta_c * (delta - r_gap) / d_lim, EXP_CAP))
        raw = upper - decay
        slope = stop.k_c0 * hyper_slope + decay * stop.beta_c / d_lim
    else:
        r_gap = branch.delta_r
        c = branch.phi_r - stop.k_e0 * d_lim * r_gap / (d_lim - r_gap)
        decay = c * math.exp(min(-stop.beta_e * (r_gap - delta) / d_lim, EXP_CAP))
        raw = lower + decay
        slope = stop.k_e0 * hyper_slope + decay * stop.beta_e / d_lim
    if raw > upper:
        return upper, stop.k_c0 * hyper_slope
    if raw < lower:
        return lower, stop.k_e0 * hyper_slope
    return raw, slope


def contact_force(delta, branch: Branch, stop: HystereticStop):
    """Contact force over ``k`` on ``branch`` at overlap ``delta`` (paper Eqs. 11-13).

    The transition curve from the stored reversal point, kept between the envelopes,
    ``phi_E(delta) <= phi <= phi_C(delta)``, and ``0`` for ``delta <= 0``.

    Parameters
    ----------
    delta : float or array_like
        Overlap (a length).
    branch : Branch
    stop : HystereticStop

    Returns
    -------
    float or ndarray
        ``phi / k`` (a length), ``>= 0``; ``inf`` at and beyond the limit overlap ``D``.

    Examples
    --------
    >>> stop = HystereticStop(clearance=0.1, k_c0=1000.0, k_e0=500.0, limit_overlap=0.05)
    >>> float(contact_force(0.025, FIRST_LOADING, stop))   # first loading: on phi_C
    50.0
    """
    if stop.law == "passive":
        return _passive_many(delta, branch, stop, 0)
    delta_arr = np.asarray(delta, dtype=float)
    inside = (delta_arr > 0.0) & (delta_arr < stop.limit_overlap)
    d = np.where(inside, delta_arr, 0.5 * stop.limit_overlap)
    with np.errstate(over="ignore", invalid="ignore"):
        raw, _ = _raw(d, branch, stop)
        phi = np.clip(raw, phi_expansion(d, stop), phi_compression(d, stop))
    out = np.where(inside, phi, np.where(delta_arr <= 0.0, 0.0, np.inf))
    return out[()] if out.ndim == 0 else out


def dphi_ddelta(delta, branch: Branch, stop: HystereticStop):
    """Tangent stiffness ``d phi / d delta`` on ``branch`` (relative to ``k``).

    Where the force is clipped to an envelope it is the envelope's slope
    ``k0 D^2 / (D - delta)^2``; on the transition curve it is that curve's slope. ``0`` for
    ``delta <= 0``, ``inf`` for ``delta >= D``. Used by implicit integrators and by the
    event location of the contact solver.
    """
    if stop.law == "passive":
        return _passive_many(delta, branch, stop, 1)
    delta_arr = np.asarray(delta, dtype=float)
    inside = (delta_arr > 0.0) & (delta_arr < stop.limit_overlap)
    d = np.where(inside, delta_arr, 0.5 * stop.limit_overlap)
    d_lim = stop.limit_overlap
    with np.errstate(over="ignore", invalid="ignore"):
        raw, raw_exp_slope = _raw(d, branch, stop)
        upper, lower = phi_compression(d, stop), phi_expansion(d, stop)
        slope_c = _envelope_slope(d, stop.k_c0, d_lim)
        slope_e = _envelope_slope(d, stop.k_e0, d_lim)
        if branch.loading:
            slope_raw = slope_c + raw_exp_slope
        else:
            slope_raw = slope_e + raw_exp_slope
        slope = np.where(raw > upper, slope_c, np.where(raw < lower, slope_e, slope_raw))
    out = np.where(inside, slope, np.where(delta_arr <= 0.0, 0.0, np.inf))
    return out[()] if out.ndim == 0 else out


def _passive_many(delta, branch: Branch, stop: HystereticStop, which: int):
    """Force (``which = 0``) or slope (``1``) of the passive law for an array of overlaps."""
    arr = np.asarray(delta, dtype=float)
    out = np.array([passive_force_and_slope(float(d), branch, stop)[which] for d in arr.ravel()])
    out = out.reshape(arr.shape)
    return out[()] if out.ndim == 0 else out


def reverse(delta: float, phi: float, branch: Branch,
            stop: HystereticStop | None = None) -> Branch:
    """The branch that starts at a reversal of the overlap rate at ``(delta, phi)``.

    Loading turns into unloading and vice versa; the reversal point is stored (paper §2.4:
    "up to a particular closure ... which must be stored, where a velocity sign inversion
    occurs"). With ``stop`` on the passive law, a reversal inside the band on the curve of
    ``branch`` keeps that curve's anchor (:class:`Branch`): the curve retraced is the one
    the state is on, not one recomputed from the rounded reversal point.
    """
    new = Branch(not branch.loading, float(delta), float(phi))
    if stop is None or stop.law != "passive":
        return new
    if branch.anchor is not None and (new.delta_r, new.phi_r) == branch.anchor:
        return Branch(new.loading, new.delta_r, new.phi_r, branch.anchor)  # the same curve
    if on_compression(new.delta_r, new.phi_r, stop):
        return new
    anchor = _passive_anchor(branch, stop)
    if anchor is None or not _keeps_curve(new.delta_r, new.phi_r, anchor, stop):
        return new
    return Branch(new.loading, new.delta_r, new.phi_r, anchor)



def start_branch(delta: float, v0: float, pull: float, stop: HystereticStop) -> Branch:
    """The branch of a motion that starts inside the stop, at overlap ``delta > 0`` with
    speed ``v0`` and net force ``pull`` on the mass besides the stop's (spring and
    friction, ``s a - x``).

    The stop's history before the start is not known: it is taken as fresh and loaded from
    its face along ``phi_C`` to ``delta`` (the first loading of paper §2.4). Moving in, or at
    rest and pushed in harder than ``phi_C(delta)``, the loading goes on; otherwise the
    overlap rate reverses at the start, and the motion unloads from ``(delta, phi_C)``
    (docs/contact-law.md, "A start inside the stop"). Every method starts from this branch.
    """
    if delta <= 0.0:
        return FIRST_LOADING
    phi = force_and_slope(delta, FIRST_LOADING, stop)[0]
    if v0 > 0.0 or (v0 == 0.0 and pull >= phi):
        return FIRST_LOADING
    return reverse(delta, phi, FIRST_LOADING, stop)

# --- work done on the stop -----------------------------------------------------------------


def _envelope_energy(delta: float, stiffness: float, d_lim: float) -> float:
    """``int_0^delta k0 D s/(D-s) ds = k0 D^2 (-x - log(1-x))``, ``x = delta/D``; infinite
    from the asymptote ``delta = D`` on (an integrator's step may overshoot it)."""
    x = delta / d_lim
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return math.inf
    if x < SERIES_CUTOFF:
        total, term = 0.0, x
        for n in range(2, SERIES_TERMS + 2):
            term *= x
            total += term / n
        g = total
    else:
        g = -x - math.log1p(-x)
    return stiffness * d_lim * d_lim * g


def _classify(delta: float, branch: Branch, stop: HystereticStop) -> str:
    """Which curve the force follows at ``0 < delta < D``: ``"C"``, ``"E"`` or ``"raw"``."""
    d_lim = stop.limit_overlap
    hyper = d_lim * delta / (d_lim - delta)
    raw = _raw_scalar(delta, branch, stop)
    if raw > stop.k_c0 * hyper:
        return "C"
    if raw < stop.k_e0 * hyper:
        return "E"
    return "raw"


def _raw_scalar(delta: float, branch: Branch, stop: HystereticStop) -> float:
    d_lim = stop.limit_overlap
    hyper = d_lim * delta / (d_lim - delta)
    r = branch.delta_r
    if branch.loading:
        c = stop.k_c0 * d_lim * r / (d_lim - r) - branch.phi_r
        return stop.k_c0 * hyper - c * math.exp(min(-stop.beta_c * (delta - r) / d_lim, EXP_CAP))
    c = branch.phi_r - stop.k_e0 * d_lim * r / (d_lim - r)
    return stop.k_e0 * hyper + c * math.exp(min(-stop.beta_e * (r - delta) / d_lim, EXP_CAP))


def clip_breaks(lo: float, hi: float, branch: Branch, stop: HystereticStop) -> list[float]:
    """Overlaps in ``(lo, hi)`` where the transition curve meets the envelope it is clipped to.

    Unloading curves can rise above ``phi_C`` (clip ``f < 0`` with
    ``f = (1 - e) phi_C - c exp(-beta_e (delta_r - s)/D)``, ``e = k_e0/k_c0``); reloading curves
    can fall below ``phi_E`` only behind their reversal point (same ``f`` with the loading
    exponent). ``log f`` has the slope ``D / (s (D - s)) -+ beta / D``, so its monotone pieces
    are split at ``s (D - s) = D^2 / beta`` and each piece holds at most one root.
    """
    d_lim = stop.limit_overlap
    ratio = 1.0 - stop.k_e0 / stop.k_c0
    r = branch.delta_r
    if branch.loading:
        c = stop.k_c0 * d_lim * r / (d_lim - r) - branch.phi_r
        beta, sgn = stop.beta_c, 1.0
    else:
        c = branch.phi_r - stop.k_e0 * d_lim * r / (d_lim - r)
        beta, sgn = stop.beta_e, -1.0
    if c <= 0.0 or ratio <= 0.0:
        return []

    def f(s: float) -> float:
        return ratio * stop.k_c0 * d_lim * s / (d_lim - s) - c * math.exp(
            min(-beta * sgn * (s - branch.delta_r) / d_lim, EXP_CAP)
        )

    splits = [lo]
    if not branch.loading and beta > 4.0:
        half_width = 0.5 * d_lim * math.sqrt(1.0 - 4.0 / beta)
        splits += [p for p in (0.5 * d_lim - half_width, 0.5 * d_lim + half_width) if lo < p < hi]
    splits.append(hi)
    roots = []
    xtol = ROOT_XTOL_REL * d_lim
    for p, q in zip(splits[:-1], splits[1:], strict=False):
        fp, fq = f(p), f(q)
        if fp == 0.0 and p > lo:
            roots.append(p)
        elif fp * fq < 0.0:
            roots.append(brentq(f, p, q, xtol=xtol, rtol=ROOT_RTOL))
    return roots


def _piece_antiderivative(s: float, branch: Branch, stop: HystereticStop, which: str) -> float:
    d_lim = stop.limit_overlap
    if which == "C":
        return _envelope_energy(s, stop.k_c0, d_lim)
    if which == "E":
        return _envelope_energy(s, stop.k_e0, d_lim)
    r = branch.delta_r
    if branch.loading:
        c = stop.k_c0 * d_lim * r / (d_lim - r) - branch.phi_r
        beta = stop.beta_c
        return _envelope_energy(s, stop.k_c0, d_lim) + c * d_lim / beta * math.exp(
            min(-beta * (s - branch.delta_r) / d_lim, EXP_CAP)
        )
    c = branch.phi_r - stop.k_e0 * d_lim * r / (d_lim - r)
    beta = stop.beta_e
    # Capped: the passive law integrates these curves above their anchor too, where a
    # curve with C = 0 (on phi_E) would overflow to 0 * inf.
    return _envelope_energy(s, stop.k_e0, d_lim) + c * d_lim / beta * math.exp(
        min(-beta * (branch.delta_r - s) / d_lim, EXP_CAP)
    )


def branch_work(d0: float, d1: float, branch: Branch, stop: HystereticStop) -> float:
    """Work done on the stop, ``int_{d0}^{d1} phi(s) ds`` along one ``branch`` (closed form).

    Parameters
    ----------
    d0, d1 : float
        Start and end overlap (a length), ``< D``; negative overlaps count as ``0``.
    branch : Branch
    stop : HystereticStop

    Returns
    -------
    float
        Work per unit ``k`` (a length squared); negative when ``d1 < d0``.

    Examples
    --------
    >>> stop = HystereticStop(clearance=0.1, k_c0=1000.0, k_e0=500.0, limit_overlap=0.05)
    >>> round(branch_work(0.0, 0.001, FIRST_LOADING, stop), 12)   # ~ k_c0 d^2 / 2
    0.000506768294
    """
    if d1 < d0:
        return -branch_work(d1, d0, branch, stop)
    lo, hi = max(d0, 0.0), max(d1, 0.0)
    if hi <= lo:
        return 0.0
    if hi >= stop.limit_overlap:
        return math.inf
    if stop.law == "passive":
        return _passive_work(lo, hi, branch, stop)
    points = [lo, *clip_breaks(lo, hi, branch, stop), hi]
    total = 0.0
    for p, q in zip(points[:-1], points[1:], strict=False):
        which = _classify(0.5 * (p + q), branch, stop)
        total += _piece_antiderivative(q, branch, stop, which) - _piece_antiderivative(
            p, branch, stop, which
        )
    return total


def program_work(stop: HystereticStop, turns) -> float:
    """Work done on the stop along the overlap program ``0 -> turns[0] -> ... -> 0``.

    The overlap moves monotonically between successive turning points; at each change of
    direction the branch reverses at the force reached (Eqs. 12-13), and an overlap back at
    ``0`` (separation) starts the next loading on the virgin branch. A closed program that
    returns a negative work shows a law that is not passive (docs/physics.md, "The
    deformable stop"; the two readings compared in docs/contact-law.md).

    Parameters
    ----------
    stop : HystereticStop
    turns : sequence of float
        Turning points of the overlap (lengths in ``[0, D)``).

    Returns
    -------
    float
        ``sum of int phi(delta) d delta`` over the program, per unit ``k``.

    Examples
    --------
    >>> stop = HystereticStop(0.0, k_c0=100.0, k_e0=25.0, limit_overlap=0.1)
    >>> program_work(stop, [0.05]) > 0.0      # one load and unload dissipates
    True
    """
    delta, branch, work = 0.0, FIRST_LOADING, 0.0
    for target in [*turns, 0.0]:
        target = float(target)
        if target == delta:
            continue
        if (target > delta) != branch.loading:
            branch = reverse(delta, float(contact_force(delta, branch, stop)), branch, stop)
        work += branch_work(delta, target, branch, stop)
        delta = target
        if delta <= 0.0:
            branch = FIRST_LOADING
    return work


def _passive_work(lo: float, hi: float, branch: Branch, stop: HystereticStop) -> float:
    """``int_lo^hi phi`` on a branch of the passive law, in closed form: its curves are
    ``phi_C``, or the paper's clipped unloading curve through an anchor point (below ``s+``
    when it is on ``phi_C`` there, with ``phi_C`` above)."""
    d_lim = stop.limit_overlap
    anchor = _passive_anchor(branch, stop)
    if anchor is None:
        return _envelope_energy(hi, stop.k_c0, d_lim) - _envelope_energy(lo, stop.k_c0, d_lim)
    s_plus = leaving_overlap(stop)
    curve, paper = Branch(False, *anchor), _paper_reading(stop)
    capped = hi > s_plus and _work_capped(curve, s_plus, stop)
    if not capped:
        return branch_work(lo, hi, curve, paper)
    below = branch_work(lo, min(hi, s_plus), curve, paper) if lo < s_plus else 0.0
    top = max(lo, s_plus)
    return below + _envelope_energy(hi, stop.k_c0, d_lim) - _envelope_energy(top, stop.k_c0, d_lim)


def _work_capped(curve: Branch, s_plus: float, stop: HystereticStop) -> bool:
    """Whether the work along the passive ``curve`` (the paper's unloading curve through
    its anchor) is taken on ``phi_C`` from ``s+`` up: the law's force just above ``s+`` is
    ``phi_C``'s (:func:`_passive_work`, :class:`BranchPrimitive`)."""
    d_lim = stop.limit_overlap
    return s_plus < d_lim and passive_force_and_slope(
        s_plus * (1.0 + 1e-12), curve, stop)[0] >= stop.k_c0 * d_lim * s_plus / (d_lim - s_plus)


def branch_kinks(branch: Branch, stop: HystereticStop, lo: float, hi: float) -> list[float]:
    """Overlaps in ``(lo, hi)`` where the force along ``branch`` has a kink, ascending: where
    its curve meets the envelope it is clipped to (Eq. 11), and under the passive law ``s+``
    where its curve joins ``phi_C`` (:func:`passive_force_and_slope`). An integrator that
    steps across one does not see it in its error estimate, so it must end a step there."""
    if not hi > lo:
        return []
    if stop.law != "passive":
        return clip_breaks(lo, hi, branch, stop)
    anchor = _passive_anchor(branch, stop)
    if anchor is None:
        return []  # phi_C: smooth
    s_plus = leaving_overlap(stop)
    curve = Branch(False, *anchor)
    capped = _work_capped(curve, s_plus, stop)
    top = min(hi, s_plus) if capped else hi
    kinks = clip_breaks(lo, top, curve, _paper_reading(stop)) if top > lo else []
    if capped and lo < s_plus < hi:
        kinks.append(s_plus)
    return sorted(kinks)


@functools.lru_cache(maxsize=64)
def _paper_reading(stop: HystereticStop) -> HystereticStop:
    """The same stop with the paper's reading (the passive law's curves below ``s+`` are
    its clipped unloading curves)."""
    return dataclasses.replace(stop, law="paper")


def stored_energy(delta: float, phi: float, stop: HystereticStop) -> float:
    """Energy the stop would give back if it unloaded now, from ``(delta, phi)`` to separation.

    The integral of the force along the unloading branch that starts at the current state
    (paper Eq. 12); it is the part of the work done on the stop that is not yet lost.
    ``0`` out of contact.
    """
    if delta <= 0.0:
        return 0.0
    return branch_work(0.0, delta, Branch(False, delta, phi), stop)


def force_on_branches(delta, loading, delta_r, phi_r, stop: HystereticStop,
                      anchor_d=math.nan, anchor_p=math.nan) -> np.ndarray:
    """:func:`contact_force` for arrays of overlaps, each on its own branch.

    ``loading``, ``delta_r`` and ``phi_r`` (and, for the passive law, ``anchor_d`` and
    ``anchor_p``, ``nan`` where a branch has no anchor) are arrays of the fields of
    :class:`Branch`, broadcast against ``delta``; used to evaluate a response's samples in
    one pass.
    """
    delta = np.asarray(delta, dtype=float)
    loading = np.asarray(loading, dtype=bool)
    delta_r = np.asarray(delta_r, dtype=float)
    phi_r = np.asarray(phi_r, dtype=float)
    if stop.law == "passive":
        b = np.broadcast_arrays(delta, loading, delta_r, phi_r, np.asarray(anchor_d, float),
                                np.asarray(anchor_p, float))
        return np.array([passive_force_and_slope(
            float(d), Branch(bool(ld), float(r), float(p),
                             None if math.isnan(ad) else (float(ad), float(ap))), stop)[0]
            for d, ld, r, p, ad, ap in zip(*(x.ravel() for x in b), strict=True)]
        ).reshape(b[0].shape)
    d_lim = stop.limit_overlap
    inside = (delta > 0.0) & (delta < d_lim)
    d = np.where(inside, delta, 0.5 * d_lim)
    dr = np.clip(delta_r, 0.0, d_lim)
    upper = stop.k_c0 * d_lim * d / (d_lim - d)
    lower = stop.k_e0 * d_lim * d / (d_lim - d)
    with np.errstate(over="ignore", invalid="ignore"):
        c_load = stop.k_c0 * d_lim * dr / (d_lim - dr) - phi_r
        c_unload = phi_r - stop.k_e0 * d_lim * dr / (d_lim - dr)
        raw_load = upper - c_load * np.exp(np.minimum(-stop.beta_c * (d - dr) / d_lim, EXP_CAP))
        raw_unload = lower + c_unload * np.exp(np.minimum(-stop.beta_e * (dr - d) / d_lim, EXP_CAP))
        phi = np.clip(np.where(loading, raw_load, raw_unload), lower, upper)
    return np.where(inside, phi, np.where(delta <= 0.0, 0.0, np.inf))


class BranchPrimitive:
    """``F(delta) = int_lo^delta phi(s) ds`` along one branch, for many ``delta`` in
    ``[lo, hi]``: the clip breakpoints are found once (as in :func:`branch_work`), then each
    evaluation is a closed form."""

    def __init__(self, branch: Branch, stop: HystereticStop, lo: float, hi: float) -> None:
        self.branch, self.stop = branch, stop
        lo, hi = max(lo, 0.0), max(hi, 0.0)
        self.lo = lo
        if stop.law == "passive":
            self._passive(lo, hi)
            return
        points = [lo, *(clip_breaks(lo, hi, branch, stop) if hi > lo else []), hi]
        self.points = points
        self.which = []
        self.offsets = []
        total = 0.0
        for p, q in zip(points[:-1], points[1:], strict=False):
            which = _classify(0.5 * (p + q), branch, stop)
            self.which.append(which)
            self.offsets.append(total - _piece_antiderivative(p, branch, stop, which))
            total += _piece_antiderivative(q, branch, stop, which) - _piece_antiderivative(
                p, branch, stop, which
            )
        if not self.which:
            self.which, self.offsets = ["C"], [0.0]

    def _passive(self, lo: float, hi: float) -> None:
        """The passive law's branch as :func:`_passive_work` splits it: ``phi_C``, or the
        paper's curve through the anchor (its own primitive from the face, ``inner``) up to
        ``s+`` and ``phi_C`` above where the curve is on ``phi_C`` there (``cap``: ``s+``,
        else ``inf``); any overlap down to the face is then in range (a stored energy
        needs ``F(0)``). Before, every evaluation searched the clip points again."""
        stop = self.stop
        anchor = _passive_anchor(self.branch, stop)
        self.inner, self.cap = None, math.inf
        if anchor is None:
            self.cap = 0.0
        else:
            s_plus = leaving_overlap(stop)
            curve = Branch(False, *anchor)
            if _work_capped(curve, s_plus, stop):
                self.cap = s_plus
            if self.cap > 0.0:
                self.inner = BranchPrimitive(curve, _paper_reading(stop), 0.0,
                                             min(max(hi, lo), self.cap))
        self.at_lo = self._from_face(lo)

    def _from_face(self, delta: float) -> float:
        """``int_0^delta phi`` along the passive branch (see :meth:`_passive`)."""
        cap = self.cap
        below = self.inner(min(delta, cap)) if self.inner is not None else 0.0
        if delta <= cap:
            return below
        k_c0, d_lim = self.stop.k_c0, self.stop.limit_overlap
        return below + (_envelope_energy(delta, k_c0, d_lim)
                        - _envelope_energy(cap, k_c0, d_lim))

    def _passive_at(self, delta: float) -> float:
        return self._from_face(delta) - self.at_lo

    def __call__(self, delta: float) -> float:
        delta = max(delta, 0.0)
        if self.stop.law == "passive":
            return self._passive_at(delta)
        k = 0
        while k + 1 < len(self.which) and delta > self.points[k + 1]:
            k += 1
        which = self.which[k]
        return self.offsets[k] + _piece_antiderivative(delta, self.branch, self.stop, which)


def _envelope_energy_many(delta: np.ndarray, stiffness: float, d_lim: float) -> np.ndarray:
    """:func:`_envelope_energy` for an array of overlaps in ``[0, D)``."""
    x = np.clip(delta / d_lim, 0.0, None)
    small = x < SERIES_CUTOFF
    out = np.empty_like(x)
    # Each form only where it is used: the series' terms are most of the cost, and only
    # as many as the largest x needs (its relative tail past x^n / n is below x^(n-2)).
    xs = x[small]
    series = np.zeros_like(xs)
    term = xs.copy()
    x_top = float(xs.max()) if len(xs) else 0.0
    terms = SERIES_TERMS
    if 0.0 < x_top < SERIES_CUTOFF:
        terms = min(terms, 3 + math.ceil(math.log(np.finfo(float).eps / 8) / math.log(x_top)))
    for n in range(2, terms + 2):
        term = term * xs
        series += term / n
    out[small] = series
    xd = x[~small]
    out[~small] = -xd - np.log1p(-xd)
    return stiffness * d_lim * d_lim * out


def stored_energy_many(delta, phi, stop: HystereticStop, delta_r=None,
                       phi_r=None) -> np.ndarray:
    """:func:`stored_energy` for arrays of states ``(delta, phi)``, in one vectorised pass.

    With ``delta_r`` and ``phi_r`` (arrays, broadcast against ``delta``), the energy given
    back from ``delta`` along the unloading curve through the reversal point
    ``(delta_r, phi_r)`` instead of a fresh one from ``(delta, phi)``: a state on an
    unloading branch keeps to its branch (``int_0^delta`` of
    ``Branch(False, delta_r, phi_r)``, as :func:`branch_work`). The paper's reading only
    (the passive law's branches keep an anchor).

    The unloading curve through ``(d_r, phi_r)`` is clipped to ``phi_C`` where
    ``f(s) = (k_c0 - k_e0) D s/(D - s) - c exp(-beta_e (d_r - s)/D) < 0``; on the monotone
    pieces of ``log f`` (split at ``s (D - s) = D^2 / beta_e``, as in :func:`clip_breaks`)
    each sign change is bracketed and bisected to the last bit, then the pieces are summed
    in closed form. States below the expansion envelope (``c < 0``, rounding) unload on it.
    """
    delta = np.asarray(delta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    if stop.law == "passive":
        if delta_r is not None:
            # its branches keep an anchor that a reversal point alone does not give
            raise ValueError("delta_r and phi_r apply to the paper's reading only; got "
                             f"law={stop.law!r}")
        # Up to s+ a fresh unloading of the passive law is the paper's, through (delta, phi)
        # (_passive_work): those states in the paper's vectorised pass, the others one by one.
        paper = delta <= leaving_overlap(stop)
        out = np.empty(delta.shape)
        out[paper] = stored_energy_many(delta[paper], phi[paper], _paper_reading(stop))
        out[~paper] = [stored_energy(float(d), float(p), stop)
                       for d, p in zip(delta[~paper], phi[~paper], strict=True)]
        return out
    out = np.zeros(delta.shape)
    d_lim = stop.limit_overlap
    inside = (delta > 0.0) & (delta < d_lim)
    if not np.any(inside):
        return out
    dl, ph = delta[inside], phi[inside]
    if delta_r is None:
        rd = dl
    else:
        rd, ph = (np.broadcast_to(np.asarray(q, dtype=float), delta.shape)[inside]
                  for q in (delta_r, phi_r))
    ke, kc, beta = stop.k_e0 * d_lim, stop.k_c0 * d_lim, stop.beta_e
    c = ph - ke * rd / (d_lim - rd)
    kr = kc - ke

    def f(s, c, rd):
        return kr * s / (d_lim - s) - c * np.exp(np.minimum(-beta * (rd - s) / d_lim, EXP_CAP))

    splits = [np.zeros_like(dl)]
    if beta > 4.0:
        half = 0.5 * d_lim * math.sqrt(1.0 - 4.0 / beta)
        for p in (0.5 * d_lim - half, 0.5 * d_lim + half):
            splits.append(np.clip(np.full_like(dl, p), 0.0, dl))
    splits.append(dl)
    breaks = []
    for p, q in zip(splits[:-1], splits[1:], strict=False):
        fp, fq = f(p, c, rd), f(q, c, rd)
        brk = dl.copy()
        # Bisected only where the sign changes (few states: the others stay off phi_C).
        sub = np.nonzero((fp * fq < 0.0) & (c > 0.0) & (kr > 0.0))[0]
        if len(sub):
            lo, hi, flo, cs, rs = p[sub], q[sub], fp[sub], c[sub], rd[sub]
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                fm = f(mid, cs, rs)
                left = np.sign(fm) == np.sign(flo)
                lo = np.where(left, mid, lo)
                flo = np.where(left, fm, flo)
                hi = np.where(left, hi, mid)
                if np.all(hi - lo <= 2.0 * np.finfo(float).eps * hi):
                    break
            brk[sub] = 0.5 * (lo + hi)
        breaks.append(brk)
    points = np.sort(np.stack([np.zeros_like(dl), *breaks, dl]), axis=0)
    raw_c = np.where(c > 0.0, c, 0.0)

    def raw_primitive(s):
        return _envelope_energy_many(s, stop.k_e0, d_lim) + raw_c * d_lim / beta * np.exp(
            np.minimum(-beta * (rd - s) / d_lim, EXP_CAP)
        )

    total = np.zeros_like(dl)
    for p, q in zip(points[:-1], points[1:], strict=False):
        mid = 0.5 * (p + q)
        on_c = (f(mid, c, rd) < 0.0) & (c > 0.0)
        env_c = _envelope_energy_many(q, stop.k_c0, d_lim) - _envelope_energy_many(
            p, stop.k_c0, d_lim
        )
        raw = raw_primitive(q) - raw_primitive(p)
        total += np.where(q > p, np.where(on_c, env_c, raw), 0.0)
    out[inside] = total
    return out


#: Relative accuracy of the elastic limit contact's duration (a quadrature of
#: ``1 / sqrt(2 (E - V))``, whose difference ``E - V`` near the turning point keeps ~8 digits).
QUAD_RTOL = 1e-8


class ElasticLimit(NamedTuple):
    """What the law makes of a contact loaded from rest along ``phi_C`` with the belt
    pushing (kinetic friction ``+a`` throughout, approach speed below the belt's), as a
    function of its approach speed ``w`` (docs/contact-law.md).

    The unloading curve from a reversal at ``r`` is ``phi_E + (phi_C(r) - phi_E(r))
    exp(-beta_e (r - delta) / D)``; with ``h = delta / (D - delta)`` it stays above
    ``phi_C`` (and is clipped onto it) down to 0 iff ``ln h - beta_e delta / D`` rises on
    ``(0, r]``, i.e. iff ``r (D - r) <= D^2 / beta_e``. So contacts peaking at
    ``r <= r_inf`` are elastic, and those peaking in ``(r_inf, r_deep)`` lose energy at once
    (the curve leaves ``phi_C`` downwards at the reversal), under both readings.

    Attributes
    ----------
    w_inf : float
        Approach speed of the contact peaking at ``r_inf``: slower contacts are elastic;
        ``inf`` when every contact is (``beta_e <= 4``), ``0`` when none is (the spring and
        friction alone carry the mass past ``r_inf``).
    w_deep : float
        Approach speed of the contact peaking at ``r_deep``: contacts between ``w_inf`` and
        ``w_deep`` lose energy (``w_deep = w_inf`` when ``beta_e <= 4``).
    r_inf : float
        Peak overlap of the contact at ``w_inf`` (``nan`` when it is not defined).
    force_peak : float
        ``phi_C(r_inf)`` over ``k`` (a length), the peak force of that contact.
    duration : float
        How long that contact lasts (dimensionless time); ``nan`` when not defined.
    a, clearance : float
        The friction's pull and the stop's face it was found for.
    """

    w_inf: float
    w_deep: float
    r_inf: float
    force_peak: float
    duration: float
    a: float
    clearance: float


def elastic_limit(a: float, clearance: float, stop: HystereticStop) -> ElasticLimit:
    """The contacts a belt pushing with kinetic friction ``+a`` makes elastic
    (:class:`ElasticLimit`): ``w^2 / 2`` is the work against ``phi_C``, the spring and
    friction up to the peak overlap (paper Eq. 14).

    Examples
    --------
    >>> lim = elastic_limit(0.2, 0.24, HystereticStop(0.24, 400.0, 36.0, 0.01, 300.0, 300.0))
    >>> round(lim.w_inf, 6), lim.w_inf < lim.w_deep
    (0.001768, True)
    """
    d_lim = stop.limit_overlap
    disc = 1.0 - 4.0 / stop.beta_e
    if disc <= 0.0:
        return ElasticLimit(math.inf, math.inf, math.nan, math.nan, math.nan, a, clearance)

    def potential(r: float) -> float:
        return (branch_work(0.0, r, FIRST_LOADING, stop)
                + 0.5 * ((clearance + r) ** 2 - clearance**2) - a * r)

    root = math.sqrt(disc)
    r_inf, r_deep = 0.5 * d_lim * (1.0 - root), 0.5 * d_lim * (1.0 + root)
    e_inf, e_deep = potential(r_inf), potential(r_deep)
    if e_inf <= 0.0:
        return ElasticLimit(0.0, math.sqrt(2.0 * max(e_deep, 0.0)), math.nan, math.nan,
                            math.nan, a, clearance)

    def integrand(s: float) -> float:
        # delta = r (1 - s^2) removes the turning point's 1/sqrt singularity; the potential's
        # drop from r to delta is summed as differences (no cancellation near r)
        step = r_inf * s * s
        delta = r_inf - step
        drop = (branch_work(delta, r_inf, FIRST_LOADING, stop)
                + 0.5 * step * (2.0 * clearance + r_inf + delta) - a * step)
        if drop <= 0.0:
            return 0.0
        return 2.0 * r_inf * s / math.sqrt(2.0 * drop)

    half, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=QUAD_RTOL, limit=200)
    force = float(phi_compression(r_inf, stop))
    return ElasticLimit(math.sqrt(2.0 * e_inf), math.sqrt(2.0 * e_deep), r_inf, force,
                        2.0 * half, a, clearance)
