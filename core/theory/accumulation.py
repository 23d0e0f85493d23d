"""Duration of an impact accumulation (Zeno), summed in closed form (Eqs. A.5-A.6, A.12;
docs/physics.md, "Zeno and grazing sums")."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad

from core.validation import check_range

#: ``accumulation_time``: scaled speeds ``y = w/d`` at or below this are summed by the
#: power series of ``atan`` (which converges like ``y^2`` per term).
SERIES_Y_LOW = 0.5
#: ``accumulation_time``: scaled speeds above this are summed through
#: ``atan(y) = pi/2 - atan(1/y)`` and the same series in ``1/y``.
SERIES_Y_HIGH = 2.0
#: ``accumulation_time``: the series stops once a term is below this fraction of the sum.
SERIES_RTOL = 0.5 * np.finfo(float).eps
#: ``accumulation_time``: hard cap on series terms (``y <= 0.5`` needs about 27).
SERIES_MAX_TERMS = 200
#: ``accumulation_time``: terms with ``SERIES_Y_LOW < y <= SERIES_Y_HIGH`` are summed
#: explicitly, in numpy chunks of this many terms to bound memory for ``r`` near 1.
EXPLICIT_CHUNK = 1 << 20
#: Above this many terms the middle band is summed by Euler-Maclaurin (r within ~1e-5 of 1).
EULER_MACLAURIN_TERMS = 100_000


def accumulation_time(w0: float, r: float, d: float) -> float:
    """Duration of an impact accumulation (Zeno), ``sum_{h>=0} 2 atan(r^h w0 / d)``.

    With the stop at distance ``d = a - x_bar > 0`` behind the slip centre, a rebound at
    speed ``w`` is followed by an arc about ``(a, 0)`` that returns to the stop after
    ``2 atan(w / d)`` (docs/physics.md, "Zeno and grazing sums"); rebound speeds fall as
    ``w_h = r^h w0``. The infinitely many impacts therefore end after this finite time, and
    the mass then rests on the stop.

    The sum is evaluated in three bands of the scaled speed ``y_h = r^h w0 / d``, so that its
    cost stays bounded for ``r`` near 1 where the plain sum needs ``~1/(1 - r)`` terms per
    decade of ``y``:

    * ``y <= 1/2`` (the infinite tail, from ``y_H``): with ``atan(y) = sum_k (-1)^k
      y^(2k+1)/(2k+1)`` and the geometric sum over ``h``,
      ``sum_{h>=H} atan(y_h) = sum_k (-1)^k y_H^(2k+1) / ((2k+1) (1 - r^(2k+1)))``; the
      denominators are evaluated as ``-expm1((2k+1) log r)`` to keep their precision for
      ``r`` near 1. The terms fall like ``y_H^2``.
    * ``y > 2`` (the first terms): ``atan(y) = pi/2 - atan(1/y)`` and the same series in
      ``z = 1/y < 1/2``, summed over a finite geometric range of ``h``.
    * ``1/2 < y <= 2``: summed term by term (``log(4) / (1 - r)`` terms, vectorised).

    Parameters
    ----------
    w0 : float
        First rebound speed, ``>= 0``.
    r : float
        Restitution, ``0 <= r <= 1`` (``r = 1`` diverges: ``inf`` unless ``w0 = 0``).
    d : float
        Distance ``a - x_bar`` from the stop to the slip centre, ``> 0``.

    Returns
    -------
    float
        Accumulation time (dimensionless).

    Examples
    --------
    >>> round(accumulation_time(1.0, 0.0, 1.0), 12) == round(math.pi / 2, 12)
    True
    >>> math.isfinite(accumulation_time(0.3, 0.999999, 0.01))
    True
    """
    w0 = check_range("w0", w0, 0.0)
    r = check_range("r", r, 0.0, 1.0)
    # Impacts accumulate only when the stop lies behind the slip centre.
    d = check_range("d = a - x_bar", d, 0.0, low_open=True)
    if w0 == 0.0:
        return 0.0
    if r == 1.0:
        return math.inf
    y0 = w0 / d
    if r == 0.0:
        return 2.0 * math.atan(y0)
    log_r = math.log(r)
    # log(y0), finite where w0 / d overflows (a subnormal d: a stop at the slip centre).
    log_y0 = math.log(w0) - math.log(d)

    def y_at(h: int) -> float:
        """``y0 r^h``, the ratio of the ``h``-th rebound."""
        y = y0 * r**h
        return y if math.isfinite(y) else math.exp(log_y0 + h * log_r)

    total = 0.0
    # Band y > SERIES_Y_HIGH: h = 0 .. n_high-1.
    n_high = 0
    if y0 > SERIES_Y_HIGH:
        n_high = math.ceil((math.log(SERIES_Y_HIGH) - log_y0) / log_r)
        # Guard the rounding of the ceil: the first excluded term must be <= the bound.
        while y_at(n_high) > SERIES_Y_HIGH:
            n_high += 1
        while n_high > 0 and y_at(n_high - 1) <= SERIES_Y_HIGH:
            n_high -= 1
        z_last = 1.0 / y_at(n_high - 1)  # the largest z = 1/y of the band
        total += n_high * (math.pi / 2) - _atan_geometric_series(z_last, log_r, n_high)
    # Band SERIES_Y_LOW < y <= SERIES_Y_HIGH: explicit terms.
    y = y_at(n_high)
    n_mid = 0
    if y > SERIES_Y_LOW:
        n_mid = math.ceil(math.log(SERIES_Y_LOW / y) / log_r)
        while y * r**n_mid > SERIES_Y_LOW:
            n_mid += 1
        while n_mid > 0 and y * r ** (n_mid - 1) <= SERIES_Y_LOW:
            n_mid -= 1
        if n_mid > EULER_MACLAURIN_TERMS:
            total += _atan_band_euler_maclaurin(y, log_r, n_mid)
        else:
            for start in range(0, n_mid, EXPLICIT_CHUNK):
                h = np.arange(start, min(start + EXPLICIT_CHUNK, n_mid), dtype=float)
                total += float(np.sum(np.arctan(y * np.exp(h * log_r))))
    # Band y <= SERIES_Y_LOW: the infinite tail.
    total += _atan_geometric_series(y * r**n_mid, log_r, None)
    return 2.0 * total


def _atan_band_euler_maclaurin(y: float, log_r: float, n: int) -> float:
    """``sum_{h=0}^{n-1} atan(y r^h)`` by Euler-Maclaurin, for ``r`` so close to 1 that the
    band holds more than :data:`EULER_MACLAURIN_TERMS` terms.

    With ``lam = -log r``: the integral ``(1/lam) int_{y_n}^{y} atan(u)/u du`` plus the end
    corrections ``(f(0) - f(n))/2 + (f'(n) - f'(0))/12``, ``f'(h) = -lam u/(1 + u^2)``. The
    next term is of order ``lam^3``, below 1e-15 of the sum for ``lam < 1e-5``.
    """
    lam = -log_r
    y_end = y * math.exp(-lam * n)
    integral, _ = quad(lambda u: math.atan(u) / u, y_end, y, epsabs=0.0, epsrel=1e-13)

    def slope(u: float) -> float:
        return -lam * u / (1.0 + u * u)

    ends = 0.5 * (math.atan(y) - math.atan(y_end)) + (slope(y_end) - slope(y)) / 12.0
    return integral / lam + ends


def _atan_geometric_series(y: float, log_r: float, n_terms: int | None) -> float:
    """``sum_{j=0}^{n-1} atan(y r^j)`` (``n = inf`` for None) for ``0 <= y <= 1/2``.

    Expands ``atan`` in its power series and sums the geometric series over ``j`` first:
    ``sum_k (-1)^k y^(2k+1)/(2k+1) * (1 - r^((2k+1) n)) / (1 - r^(2k+1))``.
    """
    total = 0.0
    y2 = y * y
    power = y
    for k in range(SERIES_MAX_TERMS):
        m = 2 * k + 1
        geometric = -math.expm1(m * n_terms * log_r) if n_terms is not None else 1.0
        term = power / m * geometric / -math.expm1(m * log_r)
        total += -term if k % 2 else term
        if term <= SERIES_RTOL * abs(total):
            break
        power *= y2
    return total


def accumulation_times(w0: np.ndarray, r: float, d: float) -> np.ndarray:
    """:func:`accumulation_time` at each of the rebound speeds ``w0`` (same ``r``, ``d``).

    Speeds with ``w0 / d <= 1/2`` (the tail of a long sequence) are summed together, by the
    series of :func:`accumulation_time`'s last band over arrays; the others one by one.

    Examples
    --------
    >>> w = np.array([0.01, 0.3])
    >>> bool(np.allclose(accumulation_times(w, 0.9, 0.1),
    ...                  [accumulation_time(x, 0.9, 0.1) for x in w], rtol=1e-14))
    True
    """
    w0 = np.asarray(w0, dtype=float)
    out = np.empty(w0.shape)
    y = w0 / d
    small = (y <= SERIES_Y_LOW) & (0.0 < r < 1.0)
    if np.any(small):
        out[small] = 2.0 * _atan_geometric_arrays(y[small], math.log(r))
    for i in np.flatnonzero(~small):
        out.flat[i] = accumulation_time(float(w0.flat[i]), r, d)
    return out


def _atan_geometric_arrays(y: np.ndarray, log_r: float) -> np.ndarray:
    """``sum_{j>=0} atan(y r^j)`` for ``0 <= y <= 1/2``, elementwise
    (:func:`_atan_geometric_series` over arrays)."""
    total = np.zeros(y.shape)
    y2 = y * y
    power = y.copy()
    for k in range(SERIES_MAX_TERMS):
        m = 2 * k + 1
        term = power / (m * -math.expm1(m * log_r))
        total += -term if k % 2 else term
        if np.all(term <= SERIES_RTOL * np.abs(total)):
            break
        power *= y2
    return total
