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
