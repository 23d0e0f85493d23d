"""Shared pieces of the deformable-stop solver (:mod:`core.deformable.solver`): the Dormand-Prince
5(4) pair and its step controller, the quintic Hermite rows that describe the contact phases
densely, event location on a step, the transition log."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from scipy.optimize import brentq

from core.deformable.law import (
    LIMIT_MARGIN,
    Branch,
)

# Dormand-Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Norsett & Wanner, Table II.5.2).
_C2, _C3, _C4, _C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9


_A21 = 1 / 5


_A31, _A32 = 3 / 40, 9 / 40


_A41, _A42, _A43 = 44 / 45, -56 / 15, 32 / 9


_A51, _A52, _A53, _A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729


_A61, _A62, _A63, _A64, _A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656


_B1, _B3, _B4, _B5, _B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84


_E1, _E3, _E4, _E5, _E6, _E7 = (
    71 / 57600,
    -71 / 16695,
    71 / 1920,
    -17253 / 339200,
    22 / 525,
    -1 / 40,
)


#: Positions (doubles) the band ``(d_max, D)`` where a contact counts as reaching the limit
#: overlap holds at least: a step is rejected past ``D`` (the asymptote) and the event needs
#: an accepted step ending inside the band, which the controller's factors (0.2 to 5) find
#: only if the band is several position spacings wide. With ``LIMIT_MARGIN D`` alone, a stop
#: at clearance 0.24 with ``D = 1e-12`` had a band of 1e-18 between positions 2.8e-17 apart:
#: the steps shrank to nothing and grew back past ``D`` without end.
LIMIT_BAND_SPACINGS = 16


def limit_band(clearance: float, limit_overlap: float) -> float:
    """``d_max``: the overlap at which a contact counts as reaching the limit ``D``,
    ``(1 - LIMIT_MARGIN) D`` (:data:`core.deformable.law.LIMIT_MARGIN`) or lower where positions
    near the stop are too coarse for that band (:data:`LIMIT_BAND_SPACINGS`); ``<= 0`` when
    ``D`` itself is below their resolution (a contact then ends at the limit at once).

    Examples
    --------
    >>> limit_band(0.24, 0.01) == (1.0 - LIMIT_MARGIN) * 0.01
    True
    >>> limit_band(0.24, 1e-12) < (1.0 - LIMIT_MARGIN) * 1e-12
    True
    """
    spacing = math.ulp(abs(clearance) + limit_overlap)
    return min((1.0 - LIMIT_MARGIN) * limit_overlap,
               limit_overlap - LIMIT_BAND_SPACINGS * spacing)


#: Step-size controller: safety factor and bounds of the growth per step (standard values).
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 5.0


#: First step of a contact as a fraction of its period ``2 pi / sqrt(1 + k)``.
FIRST_STEP_FRACTION = 0.01


#: Steps below this fraction of the time scale mean the contact cannot be resolved.
MIN_STEP_FRACTION = 1e-14


#: Two transition states closer than this (relative to the length scale) are the same point
#: of the friction-impact map. Cycles with a stick phase restart from an exact state and
#: repeat to rounding; a looser value (1e-7 was tried) took the slowly shrinking oscillation
#: on the stop of Fig. 11 (amplitude ~1e-7, change per cycle ~1e-10) and the decaying
#: contacts of Fig. 10 for periodic motions, and the energy balance of the repeated cycle
#: then drifted (2.5e-5 at t = 1000). Contact cycles without a stick phase are integrated to
#: ~1e-8 per cycle and are not taken for fixed points: the horizon is then computed.
FIXED_POINT_RTOL = 1e-10


#: Root tolerance of event times on the step's interpolant (relative to the step).
EVENT_XTOL = 1e-14


#: Points of the grid on which a step's interpolant is scanned for the first sign change
#: of an event function (catches two crossings in one step when they are 1/16 apart).
EVENT_GRID = 16


#: Halvings towards the step's start when it lies on the event's boundary.
EVENT_HALVINGS = 60


#: Transitions inspected for the asymptotic steady state when no fixed point is found.
STEADY_TAIL = 64


_HERMITE, _LINE, _REST, _ARC, _OSC, _TRAIN = 0, 1, 2, 3, 4, 5


@dataclass
class _Contact:
    """Dense description of the contact phases: one row per integration step or line.

    Rows hold the quintic Hermite data of a step (or a stick line / rest), the branch
    index, and the energy terms at the row's start.
    """

    kind: list[int] = field(default_factory=list)
    t0: list[float] = field(default_factory=list)
    t1: list[float] = field(default_factory=list)
    data: list[tuple[float, ...]] = field(default_factory=list)
    branch: list[int] = field(default_factory=list)
    friction: list[float] = field(default_factory=list)  # s*a in slip, nan in stick
    work0: list[tuple[float, float, float]] = field(default_factory=list)  # wf, wb, W_stop
    branches: list[Branch] = field(default_factory=list)
    branch_start: list[tuple[float, float]] = field(default_factory=list)  # (delta0, W0)

    def add(self, kind, t0, t1, data, friction, work0) -> None:
        self.kind.append(kind)
        self.t0.append(t0)
        self.t1.append(t1)
        self.data.append(data)
        self.branch.append(len(self.branches) - 1)
        self.friction.append(friction)
        self.work0.append(work0)


@dataclass
class _State:
    t: float
    x: float
    v: float
    work: tuple[float, float, float]  # friction work, belt input, work done on the stop


def _hermite_coeffs(x0, u0, a0, x1, u1, a1, h):
    """Coefficients of the quintic in ``theta = (t - t0)/h`` matching x, x', x'' at ends."""
    d = x1 - x0
    p0, p1, p2 = h * u0, h * u1, h * h * a0
    q2 = h * h * a1
    c3 = 10 * d - 6 * p0 - 4 * p1 - 1.5 * p2 + 0.5 * q2
    c4 = -15 * d + 8 * p0 + 7 * p1 + 1.5 * p2 - q2
    c5 = 6 * d - 3 * p0 - 3 * p1 - 0.5 * p2 + 0.5 * q2
    return (x0, p0, 0.5 * p2, c3, c4, c5)


def _first_exit(g) -> float:
    """First ``theta`` in ``(0, 1]`` where ``g`` (positive inside the mode, negative at 1)
    changes sign. The step may start on the boundary (``g(0) = 0``, e.g. at the face when a
    contact begins), so the start is never taken as the event: the bracket's left end is
    the last point found inside on a grid of ``EVENT_GRID`` points, refined towards 0."""
    prev = 0.0
    for k in range(1, EVENT_GRID + 1):
        th = k / EVENT_GRID
        if g(th) <= 0.0:
            break
        prev = th
    lo = prev
    if lo == 0.0 and not g(0.0) > 0.0:
        lo = th
        for _ in range(EVENT_HALVINGS):
            lo *= 0.5
            if g(lo) > 0.0:
                break
        else:
            return th  # the mode is left at once
    if lo >= th:
        return th
    return brentq(g, lo, th, xtol=EVENT_XTOL)


def _poly(c, th):
    return c[0] + th * (c[1] + th * (c[2] + th * (c[3] + th * (c[4] + th * c[5]))))


def _dpoly(c, th):
    return c[1] + th * (2 * c[2] + th * (3 * c[3] + th * (4 * c[4] + th * 5 * c[5])))
