"""Event location on a SciPy solver advanced step by step (the loop of ``solve_ivp``).

:class:`SegmentIntegrator` steps a :class:`scipy.integrate.OdeSolver` of a state
``y = (x, x')`` until a terminal event, the end of the solver's span or a work limit. At each
step end the event functions are evaluated; one whose sign changes in its direction is
located by :func:`scipy.optimize.brentq` on the step's interpolant, as ``solve_ivp`` does,
except that an event function that is exactly zero at the step's start has its root there
(``solve_ivp`` hands that bracket to ``brentq``, which fails when an implicit method's
interpolant does not reproduce the step's start to the last bit: LSODA in a deformable
contact, after a reversal sets ``x' = 0``).
Non-terminal events (maxima of ``x``) and the step ends are handed to a callback as points.

An event may mark a kink of the right-hand side (``kink``): a step that crosses one is not
kept (its error estimate does not see the kink) and the segment ends at the step's start,
with the kink's time located on that step's interpolant as the ``target`` the caller
integrates to in a segment of its own, so that no step straddles the kink.

Optionally a ``level`` of ``x`` is watched for a crossing that rises above it and falls back
inside one step (no sign change at the step ends): a maximum of ``x`` beyond the level
betrays it, and it is located between the step start and that maximum. A ``speed`` of
``x'`` is watched the same way, betrayed by the turn of ``x'`` (:data:`TURN_EVENT`, a
non-terminal event the caller adds: ``x'' = 0``) beyond it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import OdeSolution
from scipy.optimize import brentq

from core.numerics.dense_output import Piece, ode_piece
from core.numerics.limits import WorkLimit
from core.result import Status

#: Absolute and relative time tolerance of an event time (those of ``solve_ivp``).
EVENT_XTOL = 4.0 * np.finfo(float).eps
EVENT_RTOL = 4.0 * np.finfo(float).eps
#: Absolute time tolerance of a crossing the event functions missed.
MISSED_XTOL = 1e-15
#: Names of the events that a missed crossing of the watched level of ``x`` (the stop)
#: and speed (the belt's) are reported as.
LEVEL_EVENT = "stop"
SPEED_EVENT = "ur"
#: Name of the non-terminal event at a maximum of ``x`` (``x' = 0`` falling).
TOP_EVENT = "top"
#: Name of the non-terminal event where ``x'`` turns (``x'' = 0``).
TURN_EVENT = "turn"


@dataclass(frozen=True)
class Watch:
    """A level of component ``index`` of the state (0: ``x``, 1: ``x'``) that a step may
    cross and cross back, ``sign`` the side it is crossed to; the extremum event ``turn``
    betrays it, and the crossing is reported as the event ``name``."""

    index: int
    level: float
    sign: float
    turn: str
    name: str


@dataclass(frozen=True)
class Event:
    """An event function ``g(t, y)``: fires where ``g`` crosses zero in ``direction``
    (``+1`` rising, ``-1`` falling); a terminal one ends the segment.

    >>> Event("top", lambda t, y: y[1], -1.0).fires(0.5, -0.5)
    True
    """

    name: str
    g: Callable[[float, np.ndarray], float] | None
    direction: float
    terminal: bool = True
    kink: bool = False

    def fires(self, g_old: float, g_new: float) -> bool:
        """Whether the event fires between two step ends (the rule of ``solve_ivp``)."""
        if self.direction > 0:
            return g_old <= 0.0 <= g_new
        return g_old >= 0.0 >= g_new


@dataclass(frozen=True)
class SegmentEnd:
    """How a segment ended: at time ``t`` in state ``y``, by ``event`` (its name, or
    ``None`` at the end of the span or a stop), with ``status`` set when the solve must stop
    (a work limit or a failed step); ``steps`` taken; ``piece`` the dense solution on
    ``[t0, t]`` (``None`` if no step was taken); ``target`` the time of a kink ahead (an
    event with ``kink`` set, located on the step that crossed it and was not kept)."""

    t0: float
    t: float
    y: np.ndarray
    event: str | None
    status: Status | None
    steps: int
    piece: Piece | None
    target: float | None = None


class SegmentIntegrator:
    """Steps ``solver`` with ``events`` (see the module docstring).

    Parameters
    ----------
    solver : scipy.integrate.OdeSolver
        Set up on the segment's span; its state is ``(x, x')``.
    events : list of Event
    limit : WorkLimit
        Checked before every step against the steps of the whole solve.
    on_point : callable
        ``on_point(t, y)`` for every step end and maximum before the segment's end.
    level : float, optional
        Level of ``x`` to watch for a crossing missed inside one step.
    speed : (float, float), optional
        ``(v, sign)``: a speed of ``x'`` to watch the same way, crossed upwards for
        ``sign = 1``; reported as the event ``"ur"`` (the belt's speed reached).
    """

    def __init__(
        self,
        solver,
        events: list[Event],
        limit: WorkLimit,
        on_point: Callable[[float, np.ndarray], None],
        level: float | None = None,
        speed: tuple[float, float] | None = None,
    ) -> None:
        self.solver, self.events, self.limit = solver, events, limit
        self.on_point = on_point
        self.watches = []
        if level is not None:
            self.watches.append(Watch(0, level, 1.0, TOP_EVENT, LEVEL_EVENT))
        if speed is not None:
            self.watches.append(Watch(1, speed[0], speed[1], TURN_EVENT, SPEED_EVENT))
        self.t0 = float(solver.t)
        self.ts = [self.t0]
        self.interps: list = []
        self.steps = 0

    def integrate(self, steps_before: int) -> SegmentEnd:
        """Advance to the segment's end; ``steps_before`` steps of the solve were taken."""
        solver = self.solver
        g_old = [ev.g(solver.t, solver.y) for ev in self.events]
        while True:
            stopped = self.limit.reached(steps_before + self.steps)
            if stopped is not None:
                return self.end(float(solver.t), solver.y, None, stopped)
            y_old = np.array(solver.y, dtype=float)
            solver.step()
            if solver.status == "failed":
                return self.end(float(solver.t), solver.y, None, Status.INTEGRATION_FAILED)
            self.steps += 1
            sol = solver.dense_output()
            t_old, t_new, y_new = float(solver.t_old), float(solver.t), solver.y
            g_new = [ev.g(t_new, y_new) for ev in self.events]
            try:
                hits = self.crossings(sol, t_old, t_new, g_old, g_new)
            except ValueError:
                # the interpolant of an implicit method (LSODA) did not reproduce the sign
                # change its step end points showed
                return self.end(t_old, sol(t_old), None, Status.INTEGRATION_FAILED)
            first = next(((t_hit, ev) for t_hit, ev in hits if ev.terminal), None)
            if first is not None and first[1].kink and first[0] > t_old:
                # the step crossed a kink: not kept; the caller steps to it afresh
                end = self.end(t_old, y_old, first[1].name, None)
                return dataclasses.replace(end, target=first[0])
            self.ts.append(t_new)
            self.interps.append(sol)
            for t_hit, ev in hits:
                if ev.terminal:
                    return self.end(t_hit, sol(t_hit), ev.name, None)
                self.on_point(t_hit, sol(t_hit))
            self.on_point(t_new, y_new)
            if solver.status == "finished":
                return self.end(t_new, y_new, None, None)
            g_old = g_new

    def crossings(self, sol, t_old: float, t_new: float, g_old, g_new) -> list:
        """The events that fire on the step, as ``(time, event)`` in time order."""
        hits = []
        for ev, g0, g1 in zip(self.events, g_old, g_new, strict=True):
            if ev.fires(g0, g1):
                t_root = t_old
                if g0 != 0.0:
                    t_root = brentq(
                        lambda tt, ev=ev: ev.g(tt, sol(tt)),
                        t_old,
                        t_new,
                        xtol=EVENT_XTOL,
                        rtol=EVENT_RTOL,
                    )
                hits.append((t_root, ev))
        hits.sort(key=lambda p: p[0])
        missed = [m for w in self.watches if (m := self.missed_crossing(sol, t_old, hits, w))]
        if missed:
            first = min(missed, key=lambda p: p[0])
            hits = [h for h in hits if h[0] < first[0]] + [first]
        return hits

    @staticmethod
    def missed_crossing(sol, t_old: float, hits, w: Watch) -> tuple[float, Event] | None:
        """A crossing of the watched level that went past it and came back inside the
        step: betrayed by an extremum beyond the level (the event ``w.turn``)."""
        if any(ev.name == w.name for _, ev in hits):
            return None
        for t_top, ev in hits:
            if (ev.name == w.turn and w.sign * (sol(t_top)[w.index] - w.level) > 0.0
                    and w.sign * (sol(t_old)[w.index] - w.level) <= 0.0):
                t_c = brentq(
                    lambda tt: sol(tt)[w.index] - w.level,
                    t_old,
                    t_top,
                    xtol=MISSED_XTOL,
                    rtol=EVENT_RTOL,
                )
                return t_c, Event(w.name, None, w.sign)
        return None

    def end(self, t: float, y, event: str | None, status: Status | None) -> SegmentEnd:
        piece = ode_piece(OdeSolution(self.ts, self.interps)) if self.interps else None
        y = np.array(y, dtype=float)
        return SegmentEnd(self.t0, float(t), y, event, status, self.steps, piece)
