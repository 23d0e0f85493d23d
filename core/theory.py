"""Closed-form results of the paper for the rigid stop (Andreaus & Casini 2002, Secs. 3-4).

Everything here is a pure function of an :class:`~core.params.Oscillator`, an optional
:class:`~core.params.RigidStop` and the initial state ``(x0, v0)``, in the dimensionless
units of SPEC §2: time ``t = omega * tau``, lengths keep their unit, and

    a = mu_k * u_s      (centre of the forward-slip circles)
    b = mu_s * u_s      (static friction limit)
    v = v_dr / omega    (belt speed, a length)

Forward slip (``x' < v``) runs clockwise on circles about ``(a, 0)`` in the phase plane
``(x, x')``; stick runs along the line ``x' = v`` while ``|x| <= b``; an impact at the stop
``x = x_bar`` maps ``x'`` to ``-r x'``. Every steady motion of the paper is made of these
three pieces, so its transition points and period follow from plane geometry. The module
derives them afresh instead of copying the printed formulas, whose symbols are garbled in
the extracted text; where the derivation disagrees with the print, the docstring says so.

Differences from the printed paper (see also SPEC §7):

* Eq. (30): the first slip->stick point from rest is the ``-`` root,
  ``a - sqrt(a^2 - v^2)``.
* §4.1: the period of the fast-belt elastic impact cycle is ``2 arccos(1 - x_bar/a)``.
* Eq. (35): the critical clearance is ``x* = a + v sqrt(1 - r^2)``. After a stick->impact
  at speed ``v`` the rebound circle about ``(a, 0)`` has radius
  ``sqrt((x_bar - a)^2 + r^2 v^2)``; it reaches the stick line ``x' = v`` again iff that
  radius is at least ``v``, i.e. iff ``x_bar >= a + v sqrt(1 - r^2)``. This is also the
  condition under which the square root of Eq. (A.11) is real, and it gives ``x* = a`` for
  ``r = 1``, the elastic boundary between cases b and c (Eqs. 32-33). A value
  ``a + v / sqrt(1 - r^2)`` would be infinite for ``r = 1`` and contradict both.
* Eq. (A.9) is printed identical to Eq. (A.11). In case a the impact speed is not ``v`` but
  ``w = sqrt(v^2 + (b-a)^2 - (x_bar-a)^2)`` (Eq. A.7), so the stick onset is
  ``a - sqrt((x_bar-a)^2 + r^2 w^2 - v^2)``.
* Inelastic case a is periodic only while that square root is real. When ``x* > b`` there is
  a band ``b <= x_bar < x_a`` of case a in which the rebound circle misses the stick line
  and the motion grazes the stop instead (see :func:`classify`).
* §4.6: for natural initial conditions and ``x_bar < a - sqrt(a^2 - v^2)`` the stop is hit
  during the first slip, before any stick. With an elastic stop the steady motion is then
  the impact-slip cycle on the circle of radius ``a`` (as for a fast belt), not the case c
  cycle through ``(x_bar, +-v)``.
* Elastic case c (§4.2): the rebound circle through ``(x_bar, -v)`` comes back to the stop
  exactly on the stick line, at ``(x_bar, v)``; the paper counts one impact and one slip per
  period, and so does :func:`steady_prediction` (``('impact',)``), though the tangency
  lets a numerical solver see a zero-length stick there.
* Sec. 3.2: the steady ``x_max`` jumps at ``v = v*`` by ``sqrt((b-a)^2 + v*^2) - v*``; it is
  continuous there only when ``mu_s = mu_k``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import quad

from core.params import Oscillator, RigidStop
from core.result import SteadyKind, TransitionKind

__all__ = [
    "LimitCycle",
    "Prediction",
    "Regime",
    "RegimeGrid",
    "accumulation_time",
    "classify",
    "classify_grid",
    "critical_speed",
    "first_stick_point",
    "gamma0_radius",
    "impact_sequence",
    "impactless_limit_cycle",
    "is_fast_belt",
    "steady_points",
    "steady_prediction",
    "x_max_impactless",
    "x_star",
]

Point = tuple[float, float]

#: One full turn on a slip circle: the period of pure slip (dimensionless time).
TWO_PI = 2.0 * math.pi

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

_SLIP_STICK = TransitionKind.SLIP_STICK.value
_STICK_SLIP = TransitionKind.STICK_SLIP.value
_IMPACT = TransitionKind.IMPACT.value
_STICK_IMPACT = TransitionKind.STICK_IMPACT.value


# --------------------------------------------------------------------------- values


@dataclass(frozen=True)
class LimitCycle:
    """The stick-slip limit cycle of the impactless motion for a slow belt (Eqs. 23-24).

    Attributes
    ----------
    centre : (float, float)
        Centre ``(a, 0)`` of the slip arc in the phase plane ``(x, x')``.
    radius : float
        ``sqrt((b - a)^2 + v^2)`` (a length).
    stick_start, stick_end : (float, float)
        Ends of the stick segment, ``(2a - b, v)`` and ``(b, v)`` (Eq. 24).
    x_max : float
        Maximum displacement ``a + radius``.
    stick_time, slip_time : float
        Durations of the stick segment, ``2 (b - a) / v``, and of the slip arc,
        ``pi + 2 atan2(v, b - a)`` (dimensionless time).
    period : float
        ``stick_time + slip_time``; ``inf`` when ``v = 0`` (the stick never ends).
    """

    centre: Point
    radius: float
    stick_start: Point
    stick_end: Point
    x_max: float
    stick_time: float
    slip_time: float
    period: float


@dataclass(frozen=True)
class Regime:
    """Which of the paper's regimes a scene belongs to.

    Attributes
    ----------
    belt : {'fast', 'slow'}
        ``v > v*`` or ``v <= v*`` (Eq. 25).
    impact : {'none', 'elastic', 'inelastic', 'plastic'}
        Kind of impact of the steady motion: ``'none'`` when the stop is never reached,
        else by the restitution (``r = 1``, ``0 < r < 1``, ``r = 0``).
    case : {'a', 'b', 'c'} or None
        Slow-belt case of Secs. 4.2/4.4 (Eqs. 31-37); None for a fast belt or no impact.
    impactless : bool
        True when the impactless steady motion never reaches the stop.
    expected_steady : str
        A :class:`core.result.SteadyKind` value: ``'periodic'``, ``'grazing'``, ``'rest'``,
        ``'equilibrium'`` or ``'pure_slip'``.
    description : str
        One sentence for the readout, naming the paper's section and figure.
    """

    belt: str
    impact: str
    case: str | None
    impactless: bool
    expected_steady: str
    description: str


@dataclass(frozen=True)
class RegimeGrid:
    """:func:`classify` at every point of a grid of belt speeds and clearances.

    Arrays of shape ``(len(clearances), len(speeds))``: row ``i`` is ``clearances[i]``,
    column ``j`` is ``speeds[j]``. Each field holds what :class:`Regime`'s field of the same
    name holds, with ``''`` for a case of None.

    Attributes
    ----------
    speeds, clearances : numpy.ndarray
        The grid's belt speeds and clearances (1-D).
    belt, impact, case, expected_steady : numpy.ndarray of str
    impactless : numpy.ndarray of bool
    valid : numpy.ndarray of bool
        False where the stop lies behind the start (``clearance < x0``), which
        :func:`classify` refuses; the other fields are meaningless there.
    """

    speeds: np.ndarray
    clearances: np.ndarray
    belt: np.ndarray
    impact: np.ndarray
    case: np.ndarray
    impactless: np.ndarray
    expected_steady: np.ndarray
    valid: np.ndarray


@dataclass(frozen=True)
class Prediction:
    """Closed-form steady state for natural initial conditions ``x = x' = 0``.

    Attributes
    ----------
    kind : str
        A :class:`core.result.SteadyKind` value.
    period : float
        Period (dimensionless time); ``2 pi`` for pure slip, ``nan`` unless periodic.
    x_max : float
        Maximum displacement on the steady motion (the rest position for equilibrium).
    impact_speed : float
        Approach speed at the steady impact; 0 for grazing and rest, ``nan`` without impact.
    sequence : tuple of str
        :class:`core.result.TransitionKind` values of one period, starting at a stick->slip
        when there is one, else at the impact. For grazing it is the one transition that
        repeats, ``('impact',)``; empty for rest, equilibrium and pure slip.
    accumulation_time : float
        For rest after infinitely many impacts (Zeno): time from the first impact to the
        rest at the stop; 0 after a plastic impact; ``nan`` otherwise.
    """

    kind: str
    period: float
    x_max: float
    impact_speed: float
    sequence: tuple[str, ...]
    accumulation_time: float = math.nan


@dataclass(frozen=True)
class _Analysis:
    """Everything the public functions report, computed once and consistently."""

    belt: str
    impact: str
    case: str | None
    impactless: bool
    kind: SteadyKind
    description: str
    period: float = math.nan
    x_max: float = math.nan
    impact_speed: float = math.nan
    sequence: tuple[str, ...] = ()
    points: dict[str, Point] = field(default_factory=dict)
    first_impact_speed: float = math.nan  # approach speed of the first impact
    accumulation_time: float = math.nan


# --------------------------------------------------------------------------- checks


def _check_oscillator(osc: Oscillator) -> Oscillator:
    if not isinstance(osc, Oscillator):
        raise TypeError(f"osc must be an Oscillator; got {type(osc).__name__}")
    return osc


def _check_stop(stop: RigidStop | None, x0: float) -> RigidStop | None:
    if stop is None:
        return None
    if not isinstance(stop, RigidStop):
        raise TypeError(
            "stop must be a RigidStop or None; the closed forms hold for a rigid stop only "
            f"(got {type(stop).__name__}; for a hysteretic stop use "
            "RigidStop(stop.clearance, stop.equivalent_restitution) as its rigid equivalent)"
        )
    if stop.clearance < x0:
        raise ValueError(
            f"the stop must lie ahead of the start position: clearance={stop.clearance:.6g} "
            f"< x0={x0:.6g}"
        )
    return stop


def _check_state(x0: float, v0: float) -> tuple[float, float]:
    for name, value in (("x0", x0), ("v0", v0)):
        if not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number; got {value!r}")
    return float(x0), float(v0)


# --------------------------------------------------------------------------- impactless


def critical_speed(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> float:
    """Critical belt speed ``v* = sqrt((x0 - a)^2 + v0^2)`` (Eq. 25).

    It is the radius of the slip circle about ``(a, 0)`` through the start.

    Parameters
    ----------
    osc : Oscillator
    x0, v0 : float
        Initial displacement (a length) and velocity (a length, dimensionless time).

    Returns
    -------
    float
        ``v*`` (a length).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> round(critical_speed(osc), 12)
    0.2
    """
    _check_oscillator(osc)
    x0, v0 = _check_state(x0, v0)
    return math.hypot(x0 - osc.a, v0)


def is_fast_belt(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> bool:
    """True for a fast belt, ``v > v*`` (Sec. 3.2): pure slip, no steady stick.

    ``v = v*`` counts as slow: the slip circle then touches the stick line and sticks.

    Examples
    --------
    >>> is_fast_belt(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25))
    True
    """
    return osc.v > critical_speed(osc, x0, v0)


def gamma0_radius(osc: Oscillator) -> float:
    """Radius ``v`` of the region Gamma_0 of Eq. (21), the open disc about ``(a, 0)``.

    Starts inside Gamma_0 are fast-belt starts: their slip circle never reaches ``x' = v``.

    Examples
    --------
    >>> gamma0_radius(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1))
    0.1
    """
    return _check_oscillator(osc).v


def impactless_limit_cycle(osc: Oscillator) -> LimitCycle:
    """The stick-slip limit cycle Gamma_LC of the impactless slow-belt motion (Eqs. 23-24).

    A stick segment at ``x' = v`` from ``(2a - b, v)`` to ``(b, v)``, then a clockwise slip
    arc about ``(a, 0)`` of radius ``R = sqrt((b-a)^2 + v^2)`` back to the segment's start.
    Measured clockwise from ``(b, v)`` to ``(2a - b, v)`` the arc spans ``pi + 2 beta`` with
    ``beta = atan2(v, b - a)``.

    Degenerate cases: ``mu_s = mu_k`` gives a zero-length stick and a full circle (period
    ``2 pi``); ``v = 0`` gives ``period = inf`` (the mass never leaves the stick).

    Examples
    --------
    >>> lc = impactless_limit_cycle(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1))
    >>> round(lc.x_max, 12), [round(c, 12) for c in lc.stick_start]
    (0.341421356237, [0.1, 0.1])
    """
    a, b, v = _check_oscillator(osc).a, osc.b, osc.v
    radius = math.hypot(b - a, v)
    slip_time = math.pi + 2.0 * math.atan2(v, b - a)
    stick_time = 2.0 * (b - a) / v if v > 0 else math.inf
    return LimitCycle(
        centre=(a, 0.0),
        radius=radius,
        stick_start=(2.0 * a - b, v),
        stick_end=(b, v),
        x_max=a + radius,
        stick_time=stick_time,
        slip_time=slip_time,
        period=stick_time + slip_time,
    )


def first_stick_point(osc: Oscillator) -> Point | None:
    """First slip->stick point from natural initial conditions (Eq. 30, minus root).

    From rest at the origin the mass slips on the circle about ``(a, 0)`` of radius ``a``;
    it first reaches ``x' = v`` at ``x = a - sqrt(a^2 - v^2)``. The extracted text prints
    ``+``, the far intersection, which the motion would reach only after passing the top.

    Returns
    -------
    (float, float) or None
        ``(a - sqrt(a^2 - v^2), v)`` when ``v <= a`` (slow belt), else None.

    Examples
    --------
    >>> x, xd = first_stick_point(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.12))
    >>> round(x, 12), xd
    (0.04, 0.12)
    """
    a, v = _check_oscillator(osc).a, osc.v
    if v > a:
        return None
    return (a - math.sqrt((a - v) * (a + v)), v)


def x_max_impactless(osc: Oscillator, x0: float = 0.0, v0: float = 0.0) -> float:
    """Maximum displacement of the impactless steady motion (Sec. 3.2).

    * fast belt: ``a + sqrt((x0 - a)^2 + v0^2)`` (the slip circle through the start);
    * slow belt, ``v > 0``: the limit cycle's ``a + sqrt((b - a)^2 + v^2)``, whatever
      the start;
    * ``v = 0``: the position where the Coulomb-damped oscillation comes to rest.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> round(x_max_impactless(osc), 12)
    0.4
    """
    _check_oscillator(osc)
    x0, v0 = _check_state(x0, v0)
    if is_fast_belt(osc, x0, v0):
        return osc.a + critical_speed(osc, x0, v0)
    if osc.v > 0:
        return impactless_limit_cycle(osc).x_max
    return _rest_position_still_belt(osc, x0, v0)


def _rest_position_still_belt(osc: Oscillator, x0: float, v0: float) -> float:
    """Where the mass stops on a belt at rest (``v = 0``), or ``a + R`` if it never does.

    Each half swing is a half circle about ``(-s a, 0)`` with ``s`` the sign of ``x'``; it
    ends at ``x' = 0``, where the mass sticks iff ``|x| <= b``. Each half swing shrinks the
    amplitude by ``2a``, so the loop ends after at most ``|x0|/(2a) + 2`` swings when
    ``a > 0``; without kinetic friction the first turning point decides.
    """
    a, b = osc.a, osc.b
    if v0 == 0.0 and abs(x0) <= b:
        return x0
    if v0 != 0.0:  # move to the first turning point
        centre = -a if v0 > 0 else a
        radius = math.hypot(x0 - centre, v0)
        x = centre + radius if v0 > 0 else centre - radius
    else:
        x = x0
    while abs(x) > b:
        if a == 0.0:  # frictionless swings never end: report the amplitude
            return abs(x)
        x = 2.0 * a - x if x > 0 else -2.0 * a - x
    return x


# --------------------------------------------------------------------------- rigid stop


def x_star(osc: Oscillator, restitution: float) -> float:
    """Critical clearance ``x* = a + v sqrt(1 - r^2)`` (Eq. 35, rederived).

    For a slow belt with ``x_bar < b`` the mass sticks into the stop at speed ``v`` and
    rebounds at ``r v``; the rebound circle about ``(a, 0)`` reaches the stick line again,
    and the motion is periodic (case b), iff ``x_bar >= x*``. Below ``x*`` the impacts
    repeat with speeds ``r^h v`` (case c). The extracted text's ``a + v / sqrt(1 - r^2)``
    is not what the geometry gives; see the module docstring.

    Parameters
    ----------
    osc : Oscillator
    restitution : float
        ``0 <= r <= 1``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> round(x_star(osc, 0.6), 12), x_star(osc, 1.0) == osc.a
    (0.28, True)
    """
    _check_oscillator(osc)
    r = float(restitution)
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"restitution must lie in [0, 1]; got {restitution!r}")
    return osc.a + osc.v * math.sqrt((1.0 - r) * (1.0 + r))


def accumulation_time(w0: float, r: float, d: float) -> float:
    """Duration of an impact accumulation (Zeno), ``sum_{h>=0} 2 atan(r^h w0 / d)``.

    With the stop at distance ``d = a - x_bar > 0`` behind the slip centre, a rebound at
    speed ``w`` is followed by an arc about ``(a, 0)`` that returns to the stop after
    ``2 atan(w / d)`` (SPEC §3); rebound speeds fall as ``w_h = r^h w0``. The infinitely many
    impacts therefore end after this finite time, and the mass then rests on the stop.

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
    w0, r, d = float(w0), float(r), float(d)
    if not (math.isfinite(w0) and w0 >= 0.0):
        raise ValueError(f"w0 must be a finite speed >= 0; got {w0!r}")
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"r must lie in [0, 1]; got {r!r}")
    if not (math.isfinite(d) and d > 0.0):
        raise ValueError(
            "d = a - x_bar must be positive (impacts accumulate only when the stop lies "
            f"behind the slip centre); got {d!r}"
        )
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


def _arc_to_stick(a: float, x_bar: float, w_out: float, x_stick: float, v: float) -> float:
    """Slip time from the rebound ``(x_bar, -w_out)`` (``x_bar >= a``) to ``(x_stick, v)``.

    Angles on a circle about ``(a, 0)`` are ``theta = atan2(-x', x - a)``, growing at unit
    rate. The rebound point sits at ``delta = atan2(w_out, x_bar - a)`` in ``[0, pi/2]``, the
    stick point (upper left, ``x_stick <= a``) at ``pi + atan2(v, a - x_stick)``.
    """
    return math.pi + math.atan2(v, a - x_stick) - math.atan2(w_out, x_bar - a)


def _impact_slip_cycle(a: float, x_bar: float, w: float) -> float:
    """Period of the cycle impact ``(x_bar, w) -> (x_bar, -w)`` + one slip arc back.

    ``2 pi - 2 atan2(w, x_bar - a)``; for natural initial conditions (``w^2 = x_bar (2a -
    x_bar)``) this is ``2 arccos(1 - x_bar/a)``, twice the printed value of Sec. 4.1.
    """
    if x_bar < a:  # the short arc left of the centre; this form keeps tiny periods exact
        return 2.0 * math.atan2(w, a - x_bar)
    return TWO_PI - 2.0 * math.atan2(w, x_bar - a)


def _impact_label(r: float) -> str:
    if r == 1.0:
        return "elastic"
    return "plastic" if r == 0.0 else "inelastic"


def _analyse(osc: Oscillator, stop: RigidStop | None, x0: float, v0: float) -> _Analysis:
    _check_oscillator(osc)
    x0, v0 = _check_state(x0, v0)
    stop = _check_stop(stop, x0)
    a, b, v = osc.a, osc.b, osc.v
    fast = is_fast_belt(osc, x0, v0)
    belt = "fast" if fast else "slow"
    x_max0 = x_max_impactless(osc, x0, v0)
    if stop is None or stop.clearance >= x_max0:
        return _impactless(osc, x0, v0, belt, x_max0, stop is None)
    x_bar, r = stop.clearance, stop.restitution
    label = _impact_label(r)
    if fast:
        # Squares as products here and in classify_grid: x ** 2 (libm pow) and x * x can
        # differ in the last bit, and a point on a boundary would then be classified
        # differently by the two.
        vc, d = critical_speed(osc, x0, v0), x_bar - a
        w = math.sqrt(max(vc * vc - d * d, 0.0))
        ref = f"Sec. 4.1, Fig. {'4a' if x_bar >= a else '4b'}"
        return _impact_cycle_or_decay(
            osc, stop, w, belt, None, "x_bar < x_max = a + v*", "x_bar < a", ref
        )
    if v == 0.0:
        return _Analysis(
            belt,
            label,
            None,
            False,
            SteadyKind.EQUILIBRIUM,
            "Belt at rest (v = 0): the swings die out and the mass comes to rest "
            "(equilibrium; the closed forms of Sec. 4 assume a moving belt)",
        )
    natural = x0 == 0.0 and v0 == 0.0
    x_stick1 = a - math.sqrt((a - v) * (a + v)) if natural and v <= a else -math.inf
    if x_bar < x_stick1:
        w = math.sqrt(max(x_bar * (2.0 * a - x_bar), 0.0))
        where = "stop hit before the first stick (x_bar < a - sqrt(a^2 - v^2))"
        return _impact_cycle_or_decay(osc, stop, w, belt, "c", where, where, "Sec. 4.6")
    if x_bar >= b:
        return _slow_case_a(osc, stop, label)
    if x_bar >= x_star(osc, r):
        return _slow_case_b(osc, stop, label)
    return _slow_case_c(osc, stop, label)


def _impactless(
    osc: Oscillator, x0: float, v0: float, belt: str, x_max: float, no_stop: bool
) -> _Analysis:
    where = "no stop" if no_stop else "the stop lies beyond x_max"
    if osc.v == 0.0:
        return _Analysis(
            belt,
            "none",
            None,
            True,
            SteadyKind.EQUILIBRIUM,
            f"Belt at rest (v = 0), {where}: the mass comes to rest (equilibrium; the "
            "limit v -> 0 of Sec. 3.1)",
            x_max=x_max,
        )
    if belt == "fast":
        if critical_speed(osc, x0, v0) == 0.0:
            return _Analysis(
                belt,
                "none",
                None,
                True,
                SteadyKind.EQUILIBRIUM,
                f"Fast belt, {where}: the start is the centre (a, 0) of the slip circles, "
                "the mass stays at rest (Sec. 3.1)",
                x_max=x_max,
            )
        return _Analysis(
            belt,
            "none",
            None,
            True,
            SteadyKind.PURE_SLIP,
            f"Fast belt (v > v*), {where}: pure slip on the circle about (a, 0) through "
            "the start, period 2 pi (Sec. 3.1, Eq. 22, Fig. 3a)",
            period=TWO_PI,
            x_max=x_max,
        )
    lc = impactless_limit_cycle(osc)
    return _Analysis(
        belt,
        "none",
        None,
        True,
        SteadyKind.PERIODIC,
        f"Slow belt (v <= v*), {where}: stick-slip limit cycle (Sec. 3.1, Eqs. 23-24, Fig. 3a)",
        period=lc.period,
        x_max=lc.x_max,
        sequence=(_STICK_SLIP, _SLIP_STICK),
        points={"P_stick_start": lc.stick_start, "P_stick_end": lc.stick_end},
    )


def _impact_cycle_or_decay(
    osc: Oscillator,
    stop: RigidStop,
    w: float,
    belt: str,
    case: str | None,
    where: str,
    rest_text: str,
    ref: str,
) -> _Analysis:
    """Impacts on a slip circle that never reaches the stick line (Secs. 4.1, 4.3, 4.6).

    ``w`` is the approach speed of the first impact (Eqs. A.1, A.5). Elastic: the impact-
    slip cycle repeats. Otherwise the rebound speeds fall as ``r^h w`` (:func:`_decay`).
    """
    x_bar = stop.clearance
    if stop.restitution == 1.0 and w > 0.0:
        return _Analysis(
            belt,
            "elastic",
            case,
            False,
            SteadyKind.PERIODIC,
            f"{belt.capitalize()} belt, elastic impact, {where}: periodic impact-slip cycle "
            f"({ref})",
            period=_impact_slip_cycle(osc.a, x_bar, w),
            x_max=x_bar,
            impact_speed=w,
            sequence=(_IMPACT,),
            points={"P_impact_in": (x_bar, w), "P_impact_out": (x_bar, -w)},
            first_impact_speed=w,
        )
    note = ", Sec. 4.6" if case is not None else ""
    return _decay(osc, stop, w, belt, case, "a <= x_bar < x_max", rest_text, note)


def _decay(
    osc: Oscillator,
    stop: RigidStop,
    w: float,
    belt: str,
    case: str | None,
    grazing_text: str,
    rest_text: str,
    note: str = "",
) -> _Analysis:
    """Impact speeds ``r^h w`` with no stick in between (Eqs. A.5-A.6, A.12).

    Grazing when ``x_bar >= a`` (the limit circle about ``(a, 0)`` touches the stop);
    otherwise the impacts accumulate in finite time (:func:`accumulation_time`) and the
    mass rests pressed on the stop. ``w = 0`` means the mass already sits on the stop.
    ``grazing_text`` / ``rest_text`` name the clearance range for the readout.
    """
    a, x_bar, r = osc.a, stop.clearance, stop.restitution
    label = _impact_label(r)
    limit = {"P_limit": (x_bar, 0.0)}
    section = "Sec. 4.3, Fig. 6" if belt == "fast" else "Sec. 4.4, Fig. 7"
    head = f"{belt.capitalize()} belt, {label} impact"
    if x_bar >= a and w > 0.0:
        what = (
            "the mass leaves the stop at zero speed on the slip circle that grazes it"
            if label == "plastic"
            else "impact speeds fall as r^h and the motion tends to the slip circle that "
            "grazes the stop"
        )
        sub = "a" if belt == "fast" else "c"
        return _Analysis(
            belt,
            label,
            case,
            False,
            SteadyKind.GRAZING,
            f"{head}, {grazing_text}: {what} ({section}{sub}{note})",
            x_max=x_bar,
            impact_speed=0.0,
            sequence=(_IMPACT,),
            points=limit,
            first_impact_speed=w,
        )
    if label == "plastic" or w == 0.0:
        what, t_acc = "the mass stays pressed on the stop", 0.0
    else:
        what = "impacts accumulate in finite time, then the mass rests pressed on the stop"
        t_acc = accumulation_time(r * w, r, a - x_bar)
    sub = "b" if belt == "fast" else "d"
    return _Analysis(
        belt,
        label,
        case,
        False,
        SteadyKind.REST,
        f"{head}, {rest_text}: {what} ({section}{sub}{note})",
        x_max=x_bar,
        impact_speed=0.0,
        points=limit,
        first_impact_speed=w,
        accumulation_time=t_acc,
    )


def _slow_case_a(osc: Oscillator, stop: RigidStop, label: str) -> _Analysis:
    """Case a, ``b <= x_bar < x_max`` (Eqs. 31, 34; A.2, A.7-A.9)."""
    a, b, v = osc.a, osc.b, osc.v
    x_bar, r = stop.clearance, stop.restitution
    lc = impactless_limit_cycle(osc)
    w = math.sqrt(max((lc.radius - (x_bar - a)) * (lc.radius + (x_bar - a)), 0.0))  # A.7
    # Rebound circle radius^2 - v^2, the radicand of A.9: (x_bar-a)^2 + r^2 w^2 - v^2 with
    # w^2 = (b-a)^2 + v^2 - (x_bar-a)^2, grouped so that r = 1 gives (b-a)^2 exactly. The
    # rebound circle reaches the stick line x' = v iff it is >= 0.
    d, e = x_bar - a, r * (b - a)
    disc = (1.0 - r) * (1.0 + r) * (d * d - v * v) + e * e
    if disc < 0.0:
        where = (
            "case a (b <= x_bar < x_max) with x* > b, where the rebound circle misses the "
            "stick line"
        )
        return _decay(osc, stop, w, "slow", "a", where, where)
    x_stick = a - math.sqrt(disc)
    stick_time = (b - x_stick) / v
    arc_in = math.atan2(v, b - a) - math.atan2(w, x_bar - a)
    arc_out = _arc_to_stick(a, x_bar, r * w, x_stick, v)
    ref = "Sec. 4.2, Fig. 5a" if label == "elastic" else "Sec. 4.4, Fig. 7a"
    return _Analysis(
        "slow",
        label,
        "a",
        False,
        SteadyKind.PERIODIC,
        f"Slow belt, {label} impact, case a (b <= x_bar < x_max): periodic stick-slip-"
        f"impact-slip cycle ({ref})",
        period=stick_time + arc_in + arc_out,
        x_max=x_bar,
        impact_speed=w,
        sequence=(_STICK_SLIP, _IMPACT, _SLIP_STICK),
        points={
            "P_stick_start": (x_stick, v),
            "P_stick_end": (b, v),
            "P_impact_in": (x_bar, w),
            "P_impact_out": (x_bar, -r * w),
        },
        first_impact_speed=w,
    )


def _slow_case_b(osc: Oscillator, stop: RigidStop, label: str) -> _Analysis:
    """Case b, ``x* <= x_bar < b`` (Eqs. 32, 36; A.3-A.4, A.10-A.11)."""
    a, v = osc.a, osc.v
    x_bar, r = stop.clearance, stop.restitution
    d = x_bar - a
    disc = max(d * d - (1.0 - r) * (1.0 + r) * v * v, 0.0)  # >= 0 above x*
    x_stick = a - math.sqrt(disc)  # A.4 (r = 1: 2a - x_bar), A.11
    if label == "elastic":
        bound, ref = "a", "Sec. 4.2, Fig. 5b"
    else:
        bound, ref = "x*", "Sec. 4.4, Fig. 7b"
    return _Analysis(
        "slow",
        label,
        "b",
        False,
        SteadyKind.PERIODIC,
        f"Slow belt, {label} impact, case b ({bound} <= x_bar < b): periodic stick-"
        f"impact-slip cycle ({ref})",
        period=(x_bar - x_stick) / v + _arc_to_stick(a, x_bar, r * v, x_stick, v),
        x_max=x_bar,
        impact_speed=v,
        sequence=(_STICK_IMPACT, _SLIP_STICK),
        points={
            "P_stick_start": (x_stick, v),
            "P_stick_end": (x_bar, v),
            "P_impact_in": (x_bar, v),
            "P_impact_out": (x_bar, -r * v),
        },
        first_impact_speed=v,
    )


def _slow_case_c(osc: Oscillator, stop: RigidStop, label: str) -> _Analysis:
    """Case c, ``x_bar < a`` (elastic) or ``x_bar < x*`` (Eqs. 33, 37; A.3, A.12).

    The mass sticks into the stop at speed ``v``. Elastic: the rebound circle through
    ``(x_bar, -v)`` returns to ``(x_bar, v)`` exactly on the stick line, so the cycle is one
    impact and one slip arc. Otherwise the impacts decay (:func:`_decay`).
    """
    a, b, v = osc.a, osc.b, osc.v
    x_bar = stop.clearance
    if label != "elastic":
        return _decay(osc, stop, v, "slow", "c", "case c (a <= x_bar < x*)", "case c (x_bar < a)")
    fig = "5d" if x_bar < 2.0 * a - b else "5c"
    return _Analysis(
        "slow",
        label,
        "c",
        False,
        SteadyKind.PERIODIC,
        f"Slow belt, elastic impact, case c (x_bar < a): periodic impact-slip cycle through "
        f"(x_bar, +-v) (Sec. 4.2, Fig. {fig})",
        period=_impact_slip_cycle(a, x_bar, v),
        x_max=x_bar,
        impact_speed=v,
        sequence=(_IMPACT,),
        points={"P_impact_in": (x_bar, v), "P_impact_out": (x_bar, -v)},
        first_impact_speed=v,
    )


# --------------------------------------------------------------------------- public


def classify(osc: Oscillator, stop: RigidStop | None, x0: float = 0.0, v0: float = 0.0) -> Regime:
    """Name the paper's regime of a scene (Secs. 3.2, 4.1-4.4; Eqs. 25, 31-37).

    Boundaries, with ``x_max`` the impactless steady maximum (:func:`x_max_impactless`):

    * no stop, or ``x_bar >= x_max``: impactless; pure slip (fast), the stick-slip limit
      cycle (slow), or equilibrium (``v = 0`` or a start at the centre ``(a, 0)``).
    * fast belt (Secs. 4.1, 4.3): elastic -> periodic impact-slip cycle; otherwise
      grazing for ``x_bar >= a`` and rest at the stop for ``x_bar < a`` (accumulation of
      impacts for ``0 < r < 1``, at once for ``r = 0``).
    * slow belt (Secs. 4.2, 4.4): case a ``b <= x_bar < x_max``; case b ``x* <= x_bar < b``
      (``x* = a`` when elastic); case c below. Case c is periodic when elastic, else
      grazing (``x_bar >= a``) or rest (``x_bar < a``). When ``x* > b`` case b is empty,
      and the lower part of case a grazes too: see the module docstring.
    * ``r = 0`` (plastic) follows the inelastic rules: after the impact the mass sits at
      the stop; it stays there iff ``a >= x_bar``, else leaves on the circle about
      ``(a, 0)`` that touches the stop and sticks again iff ``x_bar - a >= v``.

    The impact cases follow the paper in assuming the mass reaches the stop from its
    natural path (for a slow belt, from the stick phase). Other starts only change the
    fast-belt circle radius here; for a slow belt they may settle on a different,
    coexisting attractor (Sec. 4.5).

    Parameters
    ----------
    osc : Oscillator
    stop : RigidStop or None
    x0, v0 : float
        Initial state; the stop must not lie behind ``x0``.

    Returns
    -------
    Regime

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> reg = classify(osc, RigidStop(clearance=0.29, restitution=0.6))
    >>> reg.belt, reg.impact, reg.case, reg.expected_steady
    ('slow', 'inelastic', 'b', 'periodic')
    """
    an = _analyse(osc, stop, x0, v0)
    return Regime(
        belt=an.belt,
        impact=an.impact,
        case=an.case,
        impactless=an.impactless,
        expected_steady=an.kind.value,
        description=an.description,
    )


def classify_grid(
    osc: Oscillator,
    stop: RigidStop | None,
    speeds: np.ndarray,
    clearances: np.ndarray,
    x0: float = 0.0,
    v0: float = 0.0,
) -> RegimeGrid:
    """:func:`classify` over belt speeds x clearances at once (the regime map).

    The friction (``osc``'s ``a`` and ``b``), the restitution and the start are those
    given; ``osc.belt_speed`` and ``stop.clearance`` are replaced by the grid's values.
    The boundaries are :func:`classify`'s, evaluated with the same floating-point
    arithmetic (the quantities of one speed with ``math`` as :func:`classify` does, the
    comparisons per point with NumPy), so every point gets :func:`classify`'s answer.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> grid = classify_grid(osc, RigidStop(0.3, 0.6), [0.1, 0.25], [0.29, 0.5])
    >>> grid.case.tolist()
    [['b', ''], ['', '']]
    >>> grid.expected_steady.tolist()
    [['periodic', 'grazing'], ['periodic', 'pure_slip']]
    """
    _check_oscillator(osc)
    x0, v0 = _check_state(x0, v0)
    if stop is not None and not isinstance(stop, RigidStop):
        _check_stop(stop, x0)  # raises: the closed forms speak of a rigid stop
    speeds = np.asarray(speeds, dtype=float).ravel()
    clearances = np.asarray(clearances, dtype=float).ravel()
    if not (np.all(np.isfinite(speeds)) and np.all(speeds >= 0.0)):
        raise ValueError("belt_speed must lie in [0, inf) at every point of the grid")
    if not np.all(np.isfinite(clearances)):
        raise ValueError("clearance must be a finite number at every point of the grid")
    a, b = osc.a, osc.b
    vc = math.hypot(x0 - a, v0)  # critical speed, Eq. 25
    shape = (clearances.size, speeds.size)
    V = np.broadcast_to(speeds[None, :], shape)
    X = np.broadcast_to(clearances[:, None], shape)
    fast = V > vc

    # Per speed, as classify computes them: x_max of the impactless motion, the first
    # stick point of a natural start, x* (Eq. 35) and the limit cycle's radius.
    rest = _rest_position_still_belt(osc, x0, v0) if np.any(speeds == 0.0) else math.nan
    r = stop.restitution if stop is not None else 1.0
    natural = x0 == 0.0 and v0 == 0.0
    x_max0 = np.array([a + vc if v > vc else (a + math.hypot(b - a, v) if v > 0 else rest)
                       for v in speeds.tolist()])[None, :]
    x_stick1 = np.array([a - math.sqrt((a - v) * (a + v)) if natural and v <= a
                         else -math.inf for v in speeds.tolist()])[None, :]
    x_st = np.array([a + v * math.sqrt((1.0 - r) * (1.0 + r))
                     for v in speeds.tolist()])[None, :]
    radius = np.array([math.hypot(b - a, v) for v in speeds.tolist()])[None, :]

    belt = np.where(fast, "fast", "slow")
    impactless = np.ones(shape, dtype=bool) if stop is None else X >= x_max0
    valid = np.ones(shape, dtype=bool) if stop is None else X >= x0
    steady = np.where(V == 0.0, "equilibrium",
                      np.where(fast, "equilibrium" if vc == 0.0 else "pure_slip", "periodic"))
    case = np.full(shape, "", dtype="<U1")
    impact = np.full(shape, "none", dtype="<U9")
    if stop is not None:
        hit = ~impactless
        label = _impact_label(r)
        elastic = label == "elastic"
        impact[hit] = label

        def decay(mask: np.ndarray, w_positive: np.ndarray) -> None:
            # _decay: grazing iff x_bar >= a and w > 0, else rest at the stop
            steady[mask] = np.where((X >= a) & w_positive, "grazing", "rest")[mask]

        def periodic_or_decay(mask: np.ndarray, w_positive: np.ndarray) -> None:
            # _impact_cycle_or_decay: the elastic impact-slip cycle needs w > 0
            if elastic:
                steady[mask & w_positive] = "periodic"
                decay(mask & ~w_positive, w_positive)
            else:
                decay(mask, w_positive)

        # Fast belt (Sec. 4.1, 4.3): w of Eq. A.1 on the circle through the start.
        D = X - a
        periodic_or_decay(hit & fast, vc * vc - D * D > 0.0)
        slow = hit & ~fast
        steady[slow & (V == 0.0)] = "equilibrium"
        slow &= V > 0.0
        first = slow & (X < x_stick1)  # stop hit before the first stick (Sec. 4.6)
        case[first] = "c"
        periodic_or_decay(first, X * (2.0 * a - X) > 0.0)
        slow &= ~first
        in_a = slow & (X >= b)  # case a, Eqs. A.7-A.9
        case[in_a] = "a"
        e = r * (b - a)
        disc = (1.0 - r) * (1.0 + r) * (D * D - V * V) + e * e
        steady[in_a & (disc >= 0.0)] = "periodic"
        decay(in_a & (disc < 0.0), (radius - (X - a)) * (radius + (X - a)) > 0.0)
        slow &= ~in_a
        in_b = slow & (X >= x_st)  # case b
        case[in_b] = "b"
        steady[in_b] = "periodic"
        in_c = slow & ~in_b  # case c: sticks into the stop at speed v > 0
        case[in_c] = "c"
        if elastic:
            steady[in_c] = "periodic"
        else:
            decay(in_c, np.ones(shape, dtype=bool))
    return RegimeGrid(
        speeds=speeds, clearances=clearances, belt=belt, impact=impact, case=case,
        impactless=impactless, expected_steady=steady, valid=valid,
    )


def steady_points(osc: Oscillator, stop: RigidStop | None) -> dict[str, Point]:
    """Named transition points ``(x, x')`` of the steady motion (Appendix, Eqs. A.1-A.12).

    For natural initial conditions. Keys, where they exist:

    * ``'P_impact_in'``, ``'P_impact_out'``: state just before / after the steady impact
      (A.1; A.2/A.7-A.8 for case a; A.3/A.10 for cases b and c).
    * ``'P_stick_start'``, ``'P_stick_end'``: ends of the steady stick segment (Eq. 24 for
      the limit cycle; A.9 rederived for case a; A.4/A.11 for case b, whose stick ends at
      the stop).
    * ``'P_limit'``: the point ``(x_bar, 0)`` that the impacts tend to in grazing and rest
      (A.5-A.6, A.12).

    Empty for pure slip and equilibrium (no finite set of cycle points).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> p = steady_points(osc, RigidStop(clearance=0.3, restitution=1.0))
    >>> [round(c, 12) for c in p["P_impact_in"]]
    [0.3, 0.173205080757]
    """
    return dict(_analyse(osc, stop, 0.0, 0.0).points)


def steady_prediction(osc: Oscillator, stop: RigidStop | None) -> Prediction:
    """Closed-form steady state from natural initial conditions (Secs. 3-4).

    Periods are exact sums of stick times ``(x_end - x_start)/v`` and slip-arc angles;
    e.g. the fast-belt elastic cycle has ``2 arccos(1 - x_bar/a)`` (Sec. 4.1 with the
    missing factor 2 restored).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
    >>> pred = steady_prediction(osc, RigidStop(clearance=0.2, restitution=1.0))
    >>> pred.kind, round(pred.period, 12), pred.sequence
    ('periodic', 3.14159265359, ('impact',))
    """
    an = _analyse(osc, stop, 0.0, 0.0)
    return Prediction(
        kind=an.kind.value,
        period=an.period,
        x_max=an.x_max,
        impact_speed=an.impact_speed,
        sequence=an.sequence,
        accumulation_time=an.accumulation_time,
    )


def impact_sequence(osc: Oscillator, stop: RigidStop | None, n: int) -> np.ndarray:
    """Approach speeds of the first ``n`` impacts from natural initial conditions.

    Where no stick separates the impacts (fast belt, Eqs. A.5-A.6; slow case c, A.12),
    ``w_h = r^h w_0`` with ``w_0`` the first approach speed (``sqrt(x_bar (2a - x_bar))``
    for a fast belt, ``v`` after a stick). Zeros mean the mass only touches the stop (or,
    after a rest, stays on it). In the periodic cases every impact is the steady one,
    ``w_h = w_0``. Empty when the stop is never reached.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> impact_sequence(osc, RigidStop(clearance=0.15, restitution=0.5), 3).round(12)
    array([0.1  , 0.05 , 0.025])
    """
    n = int(n)
    if n < 0:
        raise ValueError(f"n must be >= 0; got {n}")
    an = _analyse(osc, stop, 0.0, 0.0)
    if an.impactless or not math.isfinite(an.first_impact_speed):
        return np.zeros(0)
    w0 = an.first_impact_speed
    if an.kind is SteadyKind.PERIODIC:
        return np.full(n, w0)
    r = stop.restitution  # an impact happened, so stop is not None
    return w0 * r ** np.arange(n, dtype=float)
