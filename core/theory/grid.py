"""The one decision tree of the paper's regimes, vectorised over belt speeds x clearances
(Secs. 3.2, 4.1-4.6; Eqs. 25, 31-37; docs/physics.md, "Closed-form results").

:func:`decide` is the only place where a scene is sorted into a regime: the regime map
(:func:`classify_grid`) calls it on the whole grid, and :func:`core.theory.classify`
and the closed forms of :mod:`core.theory.regimes` call it on a single point, so the
map and the readout cannot disagree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.params import Oscillator, RigidStop
from core.theory.impactless import rest_position_still_belt
from core.theory.values import RegimeGrid
from core.validation import check_grid, check_rigid_stop, check_state

#: Branch codes of :func:`decide`: which closed form describes the point.
IMPACTLESS = 0  # the stop is never reached (or there is none)
FAST = 1  # fast belt, impacts on the circle through the start (Secs. 4.1, 4.3)
STILL = 2  # belt at rest with the stop in reach: the swings die out
FIRST_SLIP = 3  # slow belt, the stop is hit before the first stick (Sec. 4.6)
CASE_A = 4  # slow belt, b <= x_bar < x_max (Eqs. 31, 34)
CASE_B = 5  # slow belt, x* <= x_bar < b (Eqs. 32, 36)
CASE_C = 6  # slow belt, x_bar < x* (Eqs. 33, 37)


def impact_label(r: float) -> str:
    """``'elastic'``, ``'inelastic'`` or ``'plastic'`` for the restitution ``r``."""
    if r == 1.0:
        return "elastic"
    return "plastic" if r == 0.0 else "inelastic"


#: Steady-state codes of :func:`decide` and the :class:`core.result.SteadyKind` values
#: they stand for.
PERIODIC, GRAZING, REST, EQUILIBRIUM, PURE_SLIP = range(5)
STEADY_NAMES = ("periodic", "grazing", "rest", "equilibrium", "pure_slip")
#: Slow-belt case per branch code ('' where the paper names none).
CASE_NAMES = ("", "", "", "c", "a", "b", "c")


@dataclass(frozen=True)
class Decision:
    """The regime at every point of a grid, arrays of shape ``(clearances, speeds)``:
    the branch code, the steady-state code, whether the belt is fast and whether the
    stop is out of reach, and whether the start lies before the stop."""

    branch: np.ndarray  # int8 branch code
    steady: np.ndarray  # int8 steady-state code (STEADY_NAMES)
    fast: np.ndarray
    impactless: np.ndarray
    valid: np.ndarray


def decide(
    osc: Oscillator,
    stop: RigidStop | None,
    speeds: np.ndarray,
    clearances: np.ndarray,
    x0: float,
    v0: float,
) -> Decision:
    """Sort every (belt speed, clearance) point into the paper's regimes.

    The friction, the restitution and the start are ``osc``'s, ``stop``'s and
    ``(x0, v0)``; the belt speed and the clearance are the grid's. Inputs are checked by
    the callers. Squares are formed as products (``x * x``, not ``x ** 2``) and the
    quantities of one speed with :mod:`math`, so that one point gives the same answer
    whichever grid it belongs to.
    """
    a, b = osc.a, osc.b
    vc = math.hypot(x0 - a, v0)  # critical speed, Eq. 25
    shape = (clearances.size, speeds.size)
    V = speeds[None, :]
    X = clearances[:, None]
    full = np.ones(shape, dtype=bool)
    fast = (V > vc) & full
    sp = speeds.tolist()

    # Per speed: x_max of the impactless motion, the first stick point of a natural start,
    # x* (Eq. 35) and the limit cycle's radius.
    rest = rest_position_still_belt(osc, x0, v0) if 0.0 in sp else math.nan
    r = stop.restitution if stop is not None else 1.0
    natural = x0 == 0.0 and v0 == 0.0
    x_max0 = np.array(
        [a + vc if v > vc else (a + math.hypot(b - a, v) if v > 0 else rest) for v in sp]
    )[None, :]

    if stop is None:
        impactless = valid = full
    else:
        impactless = (X >= x_max0) & full
        valid = (X >= x0) & full
    moving = np.where(fast, EQUILIBRIUM if vc == 0.0 else PURE_SLIP, PERIODIC)
    steady = np.where(V == 0.0, EQUILIBRIUM, moving).astype(np.int8)
    branch = np.full(shape, IMPACTLESS, dtype=np.int8)
    if stop is not None and not np.all(impactless):
        x_stick1 = np.array(
            [a - math.sqrt((a - v) * (a + v)) if natural and v <= a else -math.inf for v in sp]
        )[None, :]
        x_st = np.array([a + v * math.sqrt((1.0 - r) * (1.0 + r)) for v in sp])[None, :]
        radius = np.array([math.hypot(b - a, v) for v in sp])[None, :]
        _decide_impacts(
            a, b, r, X, V, fast, ~impactless, x_stick1, x_st, radius, vc, branch, steady
        )
    return Decision(branch, steady, fast, impactless, valid)


def _decide_impacts(a, b, r, X, V, fast, hit, x_stick1, x_st, radius, vc, branch, steady):
    """Fill the points where the stop is reached (``branch``, ``steady`` in place)."""
    elastic = r == 1.0
    beyond_centre = X >= a

    def decay(mask: np.ndarray, w_positive: np.ndarray) -> None:
        # Impact speeds r^h w: grazing iff x_bar >= a and w > 0, else rest at the stop
        steady[mask] = np.where(beyond_centre & w_positive & mask, GRAZING, REST)[mask]

    def periodic_or_decay(mask: np.ndarray, w_positive: np.ndarray) -> None:
        # The elastic impact-slip cycle needs w > 0
        if elastic:
            steady[mask & w_positive] = PERIODIC
            decay(mask & ~w_positive, w_positive)
        else:
            decay(mask, w_positive)

    # Fast belt (Sec. 4.1, 4.3): w of Eq. A.1 on the circle through the start.
    D = X - a
    on_fast = hit & fast
    branch[on_fast] = FAST
    periodic_or_decay(on_fast, vc * vc - D * D > 0.0)
    slow = hit & ~fast
    still = slow & (V == 0.0)
    branch[still] = STILL
    steady[still] = EQUILIBRIUM
    slow &= V > 0.0
    first = slow & (X < x_stick1)  # stop hit before the first stick (Sec. 4.6)
    branch[first] = FIRST_SLIP
    periodic_or_decay(first, X * (2.0 * a - X) > 0.0)
    slow &= ~first
    in_a = slow & (X >= b)  # case a, Eqs. A.7-A.9
    branch[in_a] = CASE_A
    e = r * (b - a)
    disc = (1.0 - r) * (1.0 + r) * (D * D - V * V) + e * e
    steady[in_a & (disc >= 0.0)] = PERIODIC
    decay(in_a & (disc < 0.0), (radius - (X - a)) * (radius + (X - a)) > 0.0)
    slow &= ~in_a
    in_b = slow & (X >= x_st)  # case b
    branch[in_b] = CASE_B
    steady[in_b] = PERIODIC
    in_c = slow & ~in_b  # case c: sticks into the stop at speed v > 0
    branch[in_c] = CASE_C
    if elastic:
        steady[in_c] = PERIODIC
    else:
        decay(in_c, np.ones(in_c.shape, dtype=bool))


def classify_grid(
    osc: Oscillator,
    stop: RigidStop | None,
    speeds: np.ndarray,
    clearances: np.ndarray,
    x0: float = 0.0,
    v0: float = 0.0,
) -> RegimeGrid:
    """The regime over belt speeds x clearances at once (the regime map).

    The friction (``osc``'s ``a`` and ``b``), the restitution and the start are those
    given; ``osc.belt_speed`` and ``stop.clearance`` are replaced by the grid's values.
    Every point gets :func:`core.theory.classify`'s answer: both use :func:`decide`.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> grid = classify_grid(osc, RigidStop(0.3, 0.6), [0.1, 0.25], [0.29, 0.5])
    >>> grid.case.tolist()
    [['b', ''], ['', '']]
    >>> grid.expected_steady.tolist()
    [['periodic', 'grazing'], ['periodic', 'pure_slip']]
    """
    x0, v0 = check_state(osc, x0, v0)
    if stop is not None and not isinstance(stop, RigidStop):
        check_rigid_stop(stop, x0)  # raises: the closed forms speak of a rigid stop
    speeds = check_grid("belt_speed", speeds, 0.0)
    clearances = check_grid("clearance", clearances)
    d = decide(osc, stop, speeds, clearances, x0, v0)
    label = "none" if stop is None else impact_label(stop.restitution)
    return RegimeGrid(
        speeds=speeds,
        clearances=clearances,
        belt=np.where(d.fast, "fast", "slow"),
        impact=np.where(d.impactless, "none", label).astype("<U9"),
        case=np.array(CASE_NAMES, dtype="<U1")[d.branch],
        impactless=np.array(d.impactless),
        expected_steady=np.array(STEADY_NAMES)[d.steady],
        valid=np.array(d.valid),
    )
