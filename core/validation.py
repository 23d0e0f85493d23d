"""Input checks at the boundary of the core: one clear ``ValueError`` per bad value.

Every message names the parameter, the allowed range and the value received, so the
app can show it to the user unchanged.
"""

from __future__ import annotations

import math


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
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        raise ValueError(
            f"{name} must lie in {left}{_fmt(low)}, {_fmt(high)}{right}; got {_fmt(value)}"
        )
    return value


def _fmt(x: float) -> str:
    if x == math.inf:
        return "inf"
    if x == -math.inf:
        return "-inf"
    return f"{x:.6g}"


def check_start(x0: float, clearance: float, limit_overlap: float | None = None) -> None:
    """The start must not lie inside a rigid stop (``x0 <= clearance``), nor beyond a
    deformable stop's limit overlap (``x0 < clearance + limit_overlap``)."""
    if limit_overlap is None:
        if x0 > clearance:
            raise ValueError(
                f"x0 must not lie inside the stop: x0 <= clearance={clearance:.6g}; got {x0:.6g}"
            )
    elif x0 - clearance >= limit_overlap:
        raise ValueError(
            "x0 must overlap the stop by less than its limit overlap: "
            f"x0 < clearance + limit_overlap = {clearance + limit_overlap:.6g}; got {x0:.6g}"
        )
