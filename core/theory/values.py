"""Values the closed forms return: limit cycle, regime, regime grid, prediction."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from core.result import SteadyKind, TransitionKind

Point = tuple[float, float]

#: One full turn on a slip circle: the period of pure slip (dimensionless time).
TWO_PI = 2.0 * math.pi

SLIP_STICK = TransitionKind.SLIP_STICK.value
STICK_SLIP = TransitionKind.STICK_SLIP.value
IMPACT = TransitionKind.IMPACT.value
STICK_IMPACT = TransitionKind.STICK_IMPACT.value

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
class Analysis:
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
