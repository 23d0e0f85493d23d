"""The one decision tree of the paper's regimes, vectorised over belt speeds x clearances
(Secs. 3.2, 4.1-4.6; Eqs. 25, 31-37; docs/physics.md, "Closed-form results").

One tree (:func:`_tree`) sorts a scene into a regime: the regime map
(:func:`classify_grid`) runs it on the whole grid through :func:`decide` (numpy arrays,
:func:`numpy.select`), and :func:`core.theory.classify` and the closed forms of
:mod:`core.theory.regimes` run it on a single point through :func:`decide_point` (floats,
:func:`first_true`, without the cost of arrays), so the map and the readout cannot
disagree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from core.params import Oscillator, RigidStop
from core.scene_checks import check_rigid_stop, check_state
from core.theory.impactless import rest_position_still_belt
from core.theory.values import RegimeGrid
from core.validation import check_grid

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


class PointDecision(NamedTuple):
    """The regime at one point: branch code, steady-state code, fast belt or not."""

    branch: int
    steady: int
    fast: bool


@dataclass(frozen=True)
class _Scene:
    """What the tree reads of the scene besides the belt speed and the clearance."""

    a: float
    b: float
    r: float
    vc: float  # critical speed, Eq. 25
    x0: float
    natural: bool  # the start is (0, 0)
    has_stop: bool
    rest: float  # where a still belt's oscillation stops (nan unless needed)

    @classmethod
    def of(cls, osc: Oscillator, stop: RigidStop | None, x0: float, v0: float, still: bool):
        return cls(
            a=osc.a,
            b=osc.b,
            r=stop.restitution if stop is not None else 1.0,
            vc=math.hypot(x0 - osc.a, v0),
            x0=x0,
            natural=x0 == 0.0 and v0 == 0.0,
            has_stop=stop is not None,
            rest=rest_position_still_belt(osc, x0, v0) if still else math.nan,
        )

    def speed_terms(self, v: float) -> tuple[float, float, float, float]:
        """Per belt speed, with :mod:`math` so that one point gives the same answer
        whichever grid it belongs to: the impactless ``x_max``, the first stick point of a
        natural start (``-inf`` if none), ``x*`` (Eq. 35) and the limit cycle's radius."""
        a, b, vc, r = self.a, self.b, self.vc, self.r
        x_max = a + vc if v > vc else (a + math.hypot(b - a, v) if v > 0 else self.rest)
        x_stick1 = a - math.sqrt((a - v) * (a + v)) if self.natural and v <= a else -math.inf
        return x_max, x_stick1, a + v * math.sqrt((1.0 - r) * (1.0 + r)), math.hypot(b - a, v)


def first_true(conditions, choices, default):
    """The choice of the first true condition, else ``default``: :func:`numpy.select` on
    one point, without the cost of arrays."""
    for condition, choice in zip(conditions, choices, strict=True):
        if condition:
            return choice
    return default


def _tree(scene: _Scene, X, V, terms, select):
    """The decision tree, on arrays (``select = numpy.select``) or on floats
    (``select = first_true``): ``(branch, steady, fast, impactless, valid)``.

    Each code is the first rule that holds, so no rule needs the negation of another:
    the stop is out of reach; the belt is fast (Secs. 4.1, 4.3: impacts on the circle
    through the start); the belt is still; the stop is hit before the first stick (Sec.
    4.6); cases a, b, c of a slow belt (Eqs. 31-37). Squares are products (``x * x``, not
    ``x ** 2``), as in the closed forms.
    """
    a, b, vc = scene.a, scene.b, scene.vc
    x_max, x_stick1, x_st, radius = terms
    fast = V > vc
    impactless = (X >= x_max) | (not scene.has_stop)
    valid = (X >= scene.x0) | (not scene.has_stop)
    branch = select(
        [impactless, fast, V == 0.0, X < x_stick1, X >= b, X >= x_st],
        [IMPACTLESS, FAST, STILL, FIRST_SLIP, CASE_A, CASE_B],
        CASE_C,
    )
    D = X - a
    # Does the first impact come at a speed w > 0 (Eqs. A.1, A.5, A.7)? In case c the mass
    # sticks into the stop at speed v > 0.
    w_positive = select(
        [branch == FAST, branch == FIRST_SLIP, branch == CASE_A],
        [vc * vc - D * D > 0.0, X * (2.0 * a - X) > 0.0, (radius - D) * (radius + D) > 0.0],
        True,
    )
    # Case a: the rebound circle reaches the stick line iff the radicand of A.9 is >= 0
    e, r = scene.r * (b - a), scene.r
    disc = (1.0 - r) * (1.0 + r) * (D * D - V * V) + e * e
    elastic = r == 1.0
    steady = select(
        [
            impactless & (V == 0.0),
            impactless & fast,
            impactless,
            branch == STILL,
            branch == CASE_B,
            (branch == CASE_A) & (disc >= 0.0),
            (branch == CASE_C) & elastic,
            ((branch == FAST) | (branch == FIRST_SLIP)) & elastic & w_positive,
            # otherwise the impact speeds r^h w decay: grazing iff x_bar >= a and w > 0;
            # a plastic impact at x_bar = a leaves the mass at rest at the centre (a, 0) of
            # the slip circles, on the stop (rest iff a - x_bar >= 0: docs/physics.md,
            # "Rest at the stop")
            ((X > a) | ((X == a) & (r > 0.0))) & w_positive,
        ],
        [
            EQUILIBRIUM,
            EQUILIBRIUM if vc == 0.0 else PURE_SLIP,  # a fast start at the centre rests
            PERIODIC,
            EQUILIBRIUM,
            PERIODIC,
            PERIODIC,
            PERIODIC,
            PERIODIC,
            GRAZING,
        ],
        REST,
    )
    return branch, steady, fast, impactless, valid


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
    the callers. :func:`decide_point` runs the same tree on one point.
    """
    sp = speeds.tolist()
    scene = _Scene.of(osc, stop, x0, v0, still=0.0 in sp)
    terms = np.array([scene.speed_terms(v) for v in sp], dtype=float).reshape(-1, 4)
    shape = (clearances.size, speeds.size)
    out = _tree(scene, clearances[:, None], speeds[None, :], terms.T[:, None, :], np.select)
    branch, steady, fast, impactless, valid = (np.broadcast_to(x, shape) for x in out)
    return Decision(
        branch.astype(np.int8), steady.astype(np.int8), fast.copy(), impactless.copy(),
        valid.copy(),
    )


def decide_point(
    osc: Oscillator, stop: RigidStop | None, x0: float, v0: float
) -> PointDecision:
    """:func:`decide` at the scene's own belt speed and clearance (``0`` without a stop),
    through the same tree on floats."""
    v = osc.v
    x_bar = stop.clearance if stop is not None else 0.0
    scene = _Scene.of(osc, stop, x0, v0, still=v == 0.0)
    branch, steady, fast, _, _ = _tree(scene, x_bar, v, scene.speed_terms(v), first_true)
    return PointDecision(int(branch), int(steady), bool(fast))


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
