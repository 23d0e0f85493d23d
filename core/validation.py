"""Input checks at the boundary of the core: one clear ``ValueError`` per bad value.

This module is the one place that writes the core's messages about bad input. Every
message names the parameter, the allowed range and the value received, so the app can
show it to the user unchanged.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

#: Largest magnitude of a length or speed the core takes (in its dimensionless units: lengths
#: in units of ``u_s``, speeds in ``omega u_s``). Their squares (energies, the slip circles'
#: radii) stay finite below it; a start at ``x0 = 1e300`` ran to ``x_max = inf`` reported as
#: a success.
MAX_MAGNITUDE = 1e100
#: Largest stiffness ratio ``k_c0 = k_c0/k`` (and ``k_e0``) of a deformable stop the core
#: takes. Every method finishes on stops up to it (tests/core/test_hysteretic.py); at
#: ``k_c0 = 1e300`` the switch model overflowed and the others failed without a word about
#: the stiffness. The page's own bound is lower.
MAX_STOP_STIFFNESS = 1e12
#: Largest rate ``beta_c``, ``beta_e`` of approach to an envelope the core takes. At
#: ``beta = 1e300`` the event method ran for minutes on one contact; past ``beta ~ 1e3`` a
#: contact's loops are already on their envelope (docs/contact-law.md).
MAX_BETA = 1e6
#: Longest horizon ``t_end`` (dimensionless time ``omega tau``) the core takes, and so the
#: latest time ``Result.evaluate`` and ``t_eval`` take (both lie in ``[0, t_end]``). A time
#: near ``t`` is only known to the spacing of doubles there, ``t * 2.2e-16``, and a sample's
#: ``x`` is off by its speed times that: at ``t = 1e9`` the spacing is 1.2e-7 of the time
#: scale ``1/omega`` (measured errors 2.5e-8 on a rigid stop's tiled cycle, 3e-9 on a
#: deformable stop's, ``benchmarks/horizon_fidelity.py``), at 1e12 already 1.2e-4 (as coarse
#: as the page's draft accuracy), at 1e15 0.12 and at 1e16 2: past ~1e15 the samples'
#: phase is meaningless, and past 1e16 the solvers returned zeros, frozen samples or a bare
#: math domain error. The bound keeps every sample's phase to ~1e-7 of the time scale.
MAX_T_END = 1e9


def check_horizon(t_end: float) -> float:
    """The horizon ``t_end``: within ``(0, MAX_T_END]``.

    Examples
    --------
    >>> check_horizon(1e17)
    Traceback (most recent call last):
    ...
    ValueError: t_end must lie in (0, 1e+09]; got 1e+17
    """
    return check_range("t_end", t_end, 0.0, MAX_T_END, low_open=True)


def check_size(name: str, value: float, low: float = -MAX_MAGNITUDE, **kw) -> float:
    """:func:`check_range` of a length or speed: within ``[low, MAX_MAGNITUDE]``."""
    return check_range(name, value, low, MAX_MAGNITUDE, **kw)


def check_finite(name: str, value: float) -> float:
    """Return ``value`` as float, or raise if it is not a finite real number."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number; got {value!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number; got {value!r}")
    return value


def check_range(
    name: str,
    value: float,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    low_open: bool = False,
    high_open: bool = False,
    allow_inf: bool = False,
) -> float:
    """Check ``low <= value <= high`` (open ends where asked) and return ``value``.

    Examples
    --------
    >>> check_range("restitution", 0.5, 0.0, 1.0)
    0.5
    """
    if allow_inf and isinstance(value, (int, float)) and value == math.inf:
        value = math.inf
    else:
        value = check_finite(name, value)
    below = value <= low if low_open else value < low
    above = value >= high if high_open else value > high
    if below or above:
        # an infinite end is in the range only where allow_inf lets +inf through
        left = "(" if low_open or low == -math.inf else "["
        right = ")" if high_open or (high == math.inf and not allow_inf) else "]"
        raise ValueError(
            f"{name} must lie in {left}{_fmt(low)}, {_fmt(high)}{right}; "
            f"got {_fmt_beside(value, low, high)}"
        )
    return value


def _fmt(x: float) -> str:
    if x == math.inf:
        return "inf"
    if x == -math.inf:
        return "-inf"
    return f"{x:.6g}"


def _fmt_beside(x: float, *bounds: float) -> str:
    """``x`` in six digits, or in all of its digits where six would read as one of the
    ``bounds`` it misses (``got 5000`` beside ``[0.1, 5000]`` for 5000.0000001).

    >>> _fmt_beside(5000.0000001, 0.1, 5000.0), _fmt_beside(0.5, 0.0, 1.0)
    ('5000.0000001', '0.5')
    """
    text = _fmt(x)
    return repr(x) if any(text == _fmt(b) for b in bounds) else text


def check_start(x0: float, clearance: float, limit_overlap: float | None = None) -> None:
    """The start must not lie beyond a rigid stop (``x0 <= clearance``), nor beyond a
    deformable stop's limit overlap (``x0 < clearance + limit_overlap``).

    Examples
    --------
    >>> check_start(0.4, 0.3)
    Traceback (most recent call last):
    ...
    ValueError: x0 must not lie beyond the stop (...): x0 <= clearance = 0.3; got x0 = 0.4
    """
    if limit_overlap is None:
        if x0 > clearance:
            raise ValueError(
                "x0 must not lie beyond the stop (the stop must lie ahead of the start "
                f"position): x0 <= clearance = {clearance:.6g}; got x0 = {x0:.6g}"
            )
    elif x0 - clearance >= limit_overlap:
        raise ValueError(
            "x0 must overlap the stop by less than its limit overlap: "
            f"x0 < clearance + limit_overlap = {clearance + limit_overlap:.6g}; got {x0:.6g}"
        )


def check_integer(name: str, value: object, low: int, high: int) -> int:
    """Return ``value`` as ``int`` if it is an integer in ``[low, high]``; a float such as
    ``2.7`` (or ``2.0``) is refused rather than rounded.

    Examples
    --------
    >>> check_integer("n_samples", 2000, 2, 10_000_000)
    2000
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(
            f"{name} must be an integer in [{low}, {high}]; got {value!r} "
            f"({type(value).__name__})"
        )
    value = int(value)
    if not low <= value <= high:
        raise ValueError(f"{name} must be an integer in [{low}, {high}]; got {value}")
    return value


def check_times(name: str, times: object, t_end: float, *, empty: bool = True) -> np.ndarray:
    """Return ``times`` as a 1-D float array of finite, non-decreasing times in
    ``[0, t_end]`` (and at least one of them unless ``empty``)."""
    try:
        t = np.asarray(times, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 1-D array of times in [0, t_end]") from None
    if t.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of times in [0, t_end]; got {t.ndim}-D")
    if t.size == 0 and not empty:
        raise ValueError(f"{name} must hold at least one time in [0, t_end]; got none")
    outside = ~np.isfinite(t) | (t < 0.0) | (t > t_end)
    if np.any(outside):
        raise ValueError(
            f"{name} must lie in [0, t_end={_fmt(t_end)}]; got {t[outside][0]!r}"
        )
    if np.any(np.diff(t) < 0.0):
        raise ValueError(f"{name} must be non-decreasing; got {t!r}")
    return t


def check_options(method: str, used: tuple[str, ...], given: dict[str, object]) -> None:
    """Refuse an option the chosen method does not use, naming it (as ``solve_ivp`` warns
    about extraneous options) instead of dropping it."""
    for name, value in given.items():
        if value is not None and name not in used:
            uses = ", ".join(used) if used else "none of the tuning options"
            raise TypeError(
                f"{name} is not used by method {method!r} here (it uses {uses}); "
                f"leave {name} unset"
            )


def check_choice(name: str, value: object, allowed: tuple) -> None:
    """``value`` must be one of ``allowed``."""
    if value not in allowed:
        raise ValueError(
            f"{name} must be one of {', '.join(str(a) for a in allowed)}; got {value!r}"
        )


def check_side(side: object) -> None:
    """The side of a one-sided limit: -1 (left, before a jump) or +1 (right, after it)."""
    if side not in (-1, 1):
        raise ValueError(f"side must be -1 (left limit) or +1 (right limit); got {side!r}")


def check_grid(name: str, values: np.ndarray, low: float = -math.inf) -> np.ndarray:
    """A 1-D float array of finite values ``>= low`` (the axis of a regime map)."""
    values = np.asarray(values, dtype=float).ravel()
    bad = ~np.isfinite(values) | (values < low)
    if np.any(bad):
        raise ValueError(
            f"{name} must lie in [{_fmt(low)}, inf) at every point of the grid; "
            f"got {values[bad][0]!r}"
        )
    return values
