"""An independent reference for the exact solver: the non-smooth model integrated piece by
piece by DOP853 with event location and dense output, sharing nothing with ``core``.

Slip ``x'' + x = s a`` runs until the relative velocity vanishes or the stop is reached,
stick ``x' = v`` until ``x = b`` (or the stop), and Newton's law ``x'(+) = -r x'(-)`` acts at
the stop (docs/physics.md, "Exact solution" and "Rigid impacts").
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


class Reference:
    """Piecewise DOP853 solution: ``pieces`` of (t0, t1, function of t -> (x, v))."""

    #: Impacts followed at most: past ~8 Zeno rebounds (speeds below 1e-3) event location
    #: on arcs of shrinking length stops being reliable in the reference itself.
    MAX_IMPACTS = 8

    def __init__(self, osc, stop, t_end, max_impacts=MAX_IMPACTS):
        self.pieces = []
        self.impacts = []  # (t, v_before, v_after)
        a, b, v = osc.a, osc.b, osc.v
        xb = stop.clearance if stop else math.inf
        r = stop.restitution if stop else 1.0
        t, y = 0.0, np.array([0.0, 0.0])
        stick, s = False, 1.0
        while t < t_end and len(self.impacts) < max_impacts:
            if stick:
                t1 = min(t + (min(b, xb) - y[0]) / v, t_end)
                x_start, t_start = y[0], t
                self.pieces.append(
                    (t, t1, lambda tt, x_start=x_start, t_start=t_start: (
                        x_start + v * (tt - t_start), np.full_like(tt, v)))
                )
                y, t = np.array([x_start + v * (t1 - t), v]), t1
                if y[0] >= xb:
                    self.impacts.append((t, v, -r * v))
                    y = np.array([xb, -r * v])
                stick, s = False, 1.0
                continue

            def rel(_t, yy):
                return yy[1] - v

            rel.terminal, rel.direction = True, s

            def wall(_t, yy):
                return yy[0] - xb

            wall.terminal, wall.direction = True, 1
            sol = solve_ivp(
                lambda _t, yy, s=s: [yy[1], -yy[0] + s * a],
                (t, t_end),
                y,
                method="DOP853",
                rtol=1e-12,
                atol=1e-14,
                events=[rel] + ([wall] if xb < math.inf else []),
                dense_output=True,
            )
            f = sol.sol
            self.pieces.append((t, sol.t[-1], lambda tt, f=f: tuple(f(tt))))
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status != 1:
                break
            if len(sol.t_events) > 1 and len(sol.t_events[1]):
                self.impacts.append((t, y[1], -r * y[1]))
                y = np.array([xb, -r * y[1]])
                s = 1.0
            elif abs(y[0]) <= b:
                stick, y[1] = True, v
            else:
                s = -s
        self.t_last = t

    def __call__(self, tt):
        x, xd = np.full_like(tt, np.nan), np.full_like(tt, np.nan)
        for t0, t1, f in self.pieces:
            inside = (tt >= t0) & (tt <= t1)
            if np.any(inside):
                x[inside], xd[inside] = f(tt[inside])
        return x, xd
