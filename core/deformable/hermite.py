"""Quintic Hermite rows of the contact integration: the interpolant of one step from its
end states, its value and slope, and the first exit of an event function on it."""

from __future__ import annotations

from scipy.optimize import brentq

#: Root tolerance of event times on the step's interpolant (relative to the step).
EVENT_XTOL = 1e-14


#: Points of the grid on which a step's interpolant is scanned for the first sign change
#: of an event function (catches two crossings in one step when they are 1/16 apart).
EVENT_GRID = 16


#: Halvings towards the step's start when it lies on the event's boundary.
EVENT_HALVINGS = 60


def hermite_coeffs(x0, u0, a0, x1, u1, a1, h):
    """Coefficients of the quintic in ``theta = (t - t0)/h`` matching x, x', x'' at ends."""
    d = x1 - x0
    p0, p1, p2 = h * u0, h * u1, h * h * a0
    q2 = h * h * a1
    c3 = 10 * d - 6 * p0 - 4 * p1 - 1.5 * p2 + 0.5 * q2
    c4 = -15 * d + 8 * p0 + 7 * p1 + 1.5 * p2 - q2
    c5 = 6 * d - 3 * p0 - 3 * p1 - 0.5 * p2 + 0.5 * q2
    return (x0, p0, 0.5 * p2, c3, c4, c5)


def first_exit(g) -> float:
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


def poly(c, th):
    return c[0] + th * (c[1] + th * (c[2] + th * (c[3] + th * (c[4] + th * c[5]))))


def dpoly(c, th):
    return c[1] + th * (2 * c[2] + th * (3 * c[3] + th * (4 * c[4] + th * 5 * c[5])))
