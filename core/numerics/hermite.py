"""Cubic Hermite interpolation on integration steps, and roots of it.

A step from ``(t0, y0)`` to ``(t0 + h, y1)`` with derivatives ``d0, d1`` is interpolated by
the cubic Hermite polynomial in ``s = (t - t0) / h``. Position is interpolated with the
velocity as derivative, velocity with the acceleration. Scalar forms serve event location
inside one step; vector forms (:func:`hermite_eval`, :func:`hermite_max`) serve sampling of
the whole solution, where a repeated time marks a jump (a rigid impact).
"""

from __future__ import annotations

import numpy as np

#: Iterations of the safeguarded root search on a step's interpolant (bisection halves the
#: bracket each time: 2**-60 of a step is below double precision).
ROOT_ITER = 60
#: Relative width of the bracket at which the root search stops.
ROOT_XTOL = 4e-16


def hermite(
    s: float, h: float, y0: float, d0: float, y1: float, d1: float, shift: float = 0.0
) -> float:
    """Cubic Hermite interpolant on a step at fraction ``s`` in ``[0, 1]``, minus ``shift``
    (the end value ``y1`` is then given already shifted).

    >>> hermite(0.5, 1.0, 0.0, 0.0, 1.0, 3.0)   # y = s**3
    0.125
    """
    s2 = s * s
    s3 = s2 * s
    y0 = y0 - shift
    return y0 + (3 * s2 - 2 * s3) * (y1 - y0) + h * ((s3 - 2 * s2 + s) * d0 + (s3 - s2) * d1)


def hermite_dx(s: float, h: float, x0: float, v0: float, x1: float, v1: float) -> float:
    """``dx/dt`` of the cubic Hermite interpolant of ``x`` (same sign as ``d/ds``)."""
    s2 = s * s
    return (
        (6 * s2 - 6 * s) * x0
        + (3 * s2 - 4 * s + 1) * h * v0
        + (-6 * s2 + 6 * s) * x1
        + (3 * s2 - 2 * s) * h * v1
    ) / h


def root(g, lo: float, hi: float, g_lo: float, g_hi: float) -> float:
    """Root of ``g`` in ``[lo, hi]`` with ``g_lo, g_hi`` of opposite signs (Illinois method).

    >>> round(root(lambda s: s * s - 0.25, 0.0, 1.0, -0.25, 0.75), 12)
    0.5
    """
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
        if hi - lo <= ROOT_XTOL * max(abs(hi), 1.0):
            break
    return lo if abs(g_lo) < abs(g_hi) else hi


def x_crossing(h: float, x0: float, v0: float, x1: float, v1: float, level: float) -> float | None:
    """Fraction of the step where the Hermite ``x`` first rises through ``level``, or None.

    Also finds a crossing inside the step that the end points miss: ``x`` rises above
    ``level`` and falls back (a maximum inside the step), and a rebound that leaves
    ``level`` and comes back within the step.

    >>> round(x_crossing(1.0, 0.0, 1.0, 1.0, 1.0, 0.5), 12)
    0.5
    """
    g0 = x0 - level
    if g0 > 0.0:
        return None

    def g(s: float) -> float:
        return hermite(s, h, x0, v0, x1, v1) - level

    def dx(s: float) -> float:
        return hermite_dx(s, h, x0, v0, x1, v1)

    if g0 == 0.0:
        # leaving the level (after an impact): a short rebound arc can come back inside the
        # same step; look for the crossing after the interpolant's minimum
        if v0 >= 0.0 or x1 <= level or v1 <= 0.0:
            return None
        s_low = root(dx, 0.0, 1.0, v0, v1)
        g_low = g(s_low)
        return root(g, s_low, 1.0, g_low, x1 - level) if g_low < 0.0 else None
    if x1 > level:
        return root(g, 0.0, 1.0, g0, x1 - level)
    if v0 > 0.0 and v1 < 0.0:
        s_top = root(dx, 0.0, 1.0, v0, v1)
        g_top = g(s_top)
        if g_top > 0.0:
            return root(g, 0.0, s_top, g0, g_top)
    return None


def locate_interval(t: np.ndarray, tq: np.ndarray, side: str) -> np.ndarray:
    """Index of the interval ``[t[i], t[i+1]]`` holding each query.

    ``side="right"`` picks the interval that starts at the last of repeated times (after a
    jump), ``"left"`` the one that ends at the first (before it).
    """
    idx = np.searchsorted(t, tq, side=side) - 1
    return np.clip(idx, 0, len(t) - 2)


def _fraction(
    t: np.ndarray, tq: np.ndarray, side: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Interval index, fraction ``s`` in ``[0, 1]`` and length of each query's interval
    (``s = 0`` on a zero-width interval, a jump)."""
    i = locate_interval(t, tq, side)
    t0 = t[i]
    h = t[i + 1] - t0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.where(h > 0.0, (tq - t0) / h, 0.0), 0.0, 1.0)
    return i, s, h


def hermite_eval(
    t: np.ndarray,
    y: np.ndarray,
    dy: np.ndarray,
    tq: np.ndarray,
    side: str = "right",
) -> np.ndarray:
    """Piecewise cubic Hermite interpolation of ``y`` (derivative ``dy``) at ``tq``.

    ``side="right"`` takes the state after a jump at a repeated time, ``"left"`` the state
    before it. Zero-width intervals (jumps) are never interpolated across.

    Examples
    --------
    >>> t = np.array([0.0, 1.0]); y = t**3; dy = 3 * t**2
    >>> float(hermite_eval(t, y, dy, np.array([0.5]))[0])   # exact for a cubic
    0.125
    """
    if len(t) == 1:
        return np.full(np.shape(tq), y[0], dtype=float)
    i, s, h = _fraction(t, tq, side)
    s2, s3 = s * s, s * s * s
    # written as y0 + (y1 - y0) * h01 + ...: a constant stays exactly constant
    h10 = s3 - 2 * s2 + s
    h01 = -2 * s3 + 3 * s2
    h11 = s3 - s2
    return y[i] + h01 * (y[i + 1] - y[i]) + h * (h10 * dy[i] + h11 * dy[i + 1])


def linear_eval(t: np.ndarray, y: np.ndarray, tq: np.ndarray, side: str) -> np.ndarray:
    """Piecewise linear interpolation that respects jumps (see :func:`hermite_eval`)."""
    if len(t) == 1:
        return np.full(np.shape(tq), y[0], dtype=float)
    i, s, _ = _fraction(t, tq, side)
    return y[i] + s * (y[i + 1] - y[i])


def hermite_max(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> float:
    """Largest value of the cubic Hermite interpolant of ``x`` (derivative ``v``).

    Interior maxima are looked for only on intervals where ``v`` falls from positive to
    non-positive; integrators that insert their maxima as points make this a plain ``max``.
    """
    best = float(np.max(x))
    if len(t) < 2:
        return best
    h = np.diff(t)
    sel = np.flatnonzero((h > 0.0) & (v[:-1] > 0.0) & (v[1:] <= 0.0))
    if sel.size == 0:
        return best
    x0, x1, hh = x[sel], x[sel + 1], h[sel]
    m0, m1 = hh * v[sel], hh * v[sel + 1]
    # d/ds of the Hermite cubic: A s^2 + B s + C
    qa = 6 * x0 + 3 * m0 - 6 * x1 + 3 * m1
    qb = -6 * x0 - 4 * m0 + 6 * x1 - 2 * m1
    qc = m0
    disc = np.maximum(qb * qb - 4 * qa * qc, 0.0)
    sq = np.sqrt(disc)
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = np.where(qa != 0.0, (-qb - sq) / (2 * qa), -qc / qb)
        r2 = np.where(qa != 0.0, (-qb + sq) / (2 * qa), -qc / qb)
    for r in (r1, r2):
        s = np.clip(np.nan_to_num(r, nan=0.0), 0.0, 1.0)
        s2, s3 = s * s, s * s * s
        val = (
            (2 * s3 - 3 * s2 + 1) * x0
            + (s3 - 2 * s2 + s) * m0
            + (-2 * s3 + 3 * s2) * x1
            + (s3 - s2) * m1
        )
        best = max(best, float(np.max(val)))
    return best
