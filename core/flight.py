"""Exact free flight of the friction oscillator away from the stop (paper §3; docs/physics.md,
"Exact solution").

Slip with ``s = sign(v - x')`` obeys ``x'' + x = s*a`` (paper Eq. 3 with Eq. 4): a clockwise
circle in the phase plane about ``(s*a, 0)``. Stick obeys ``x' = v`` while ``|x| <= b``
(Eqs. 5-6). Every event time below comes from an ``atan2`` on the circle or from the
straight stick line; nothing is found by a numerical root search. The arguments of each
``atan2`` are formed without cancellation (products instead of differences of nearly equal
squares): an event just ahead of the start is never mistaken for one a whole turn away, and
an event near a tangency keeps the accuracy its geometry allows instead of the square root
of the rounding that an ``asin`` of a number next to 1 would leave.

The functions are scalar and use :mod:`math` on purpose: one call costs a few microseconds,
which keeps a whole slider update's solve far below a millisecond.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.params import Oscillator
from core.result import Mode, TransitionKind

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, slots=True)
class Motion:
    """How the mass moves from a state: ``mode`` (SLIP/STICK/CONTACT for rest at the stop)
    and, in slip, the sign ``s`` of the relative velocity ``v - x'``."""

    mode: Mode
    s: int = 0


@dataclass(frozen=True, slots=True)
class Segment:
    """One closed-form piece of the motion, from ``t0`` to ``t1`` (``inf``: for ever).

    Slip: ``x = c + (x0 - c) cos(t - t0) + v0 sin(t - t0)`` with centre ``c = s*a``.
    Stick: ``x = x0 + v0 (t - t0)`` with ``v0 = v``. Rest (CONTACT): ``x = x0``, ``x' = 0``.
    """

    mode: Mode
    t0: float
    t1: float
    x0: float
    v0: float
    centre: float = 0.0

    def state_at(self, t: float) -> tuple[float, float]:
        """Exact state ``(x, x')`` at time ``t`` in ``[t0, t1]``."""
        tau = t - self.t0
        if self.mode is Mode.SLIP:
            dx = self.x0 - self.centre
            c, s = math.cos(tau), math.sin(tau)
            return self.centre + dx * c + self.v0 * s, -dx * s + self.v0 * c
        return self.x0 + self.v0 * tau, self.v0

    def x_max(self) -> float:
        """Exact maximum of ``x`` over the segment (a finite ``t1`` is required)."""
        if self.mode is not Mode.SLIP:
            return max(self.x0, self.state_at(self.t1)[0])
        dx = self.x0 - self.centre
        radius = math.hypot(dx, self.v0)
        theta0 = math.atan2(-self.v0, dx)  # x - c = R cos(theta), x' = -R sin(theta)
        next_top = math.ceil(theta0 / TWO_PI) * TWO_PI  # first theta = 0 (mod 2 pi) ahead
        if self.t1 - self.t0 >= TWO_PI or theta0 + (self.t1 - self.t0) >= next_top:
            return self.centre + radius
        return max(self.x0, self.state_at(self.t1)[0])


@dataclass(frozen=True, slots=True)
class FreeEvent:
    """The event that ends a free-flight segment and the exact state there.

    ``kind`` is one of ``SLIP_STICK``, ``STICK_SLIP``, ``SIGN_CHANGE`` or ``IMPACT``
    (reaching the barrier ``x = clearance`` with ``x' > 0``; a stick segment reaches it with
    ``x' = v``, which the caller reports as ``STICK_IMPACT``).
    """

    kind: TransitionKind
    t: float
    x: float
    v: float


def start_motion(osc: Oscillator, x: float, xdot: float) -> Motion:
    """Mode of motion that starts from the state ``(x, x')`` away from the stop.

    Relative velocity ``u_r = v - x'`` decides (paper Eq. 7): slip with its sign when it is
    not zero; at ``u_r = 0`` the mass sticks when the spring force can be held, ``|x| <= b``,
    and otherwise slips in the direction the spring pushes it relative to the belt.
    """
    v = osc.v
    if xdot < v:
        return Motion(Mode.SLIP, +1)
    if xdot > v:
        return Motion(Mode.SLIP, -1)
    if abs(x) <= osc.b:
        return Motion(Mode.STICK)
    return Motion(Mode.SLIP, +1 if x > 0 else -1)


def after_event(osc: Oscillator, event: FreeEvent, motion: Motion) -> Motion:
    """Motion that follows a friction event (not an impact)."""
    if event.kind is TransitionKind.SLIP_STICK:
        return Motion(Mode.STICK)
    if event.kind is TransitionKind.STICK_SLIP:
        return Motion(Mode.SLIP, +1)  # at x = b the spring pulls the mass back: x' < v
    if event.kind is TransitionKind.SIGN_CHANGE:
        return Motion(Mode.SLIP, -motion.s)
    raise ValueError(f"no friction motion follows a {event.kind.value} event")


def _phase(cross: float, dot: float) -> float:
    """Phase travelled clockwise from a start to a point of its circle, in ``[0, 2 pi)``,
    from ``cross = V0 X1 - X0 V1`` and ``dot = X0 X1 + V0 V1`` (``R^2 sin`` and ``R^2 cos``
    of the phase; ``X = x - c``, ``V = x'``). Accurate to rounding of the phase whenever
    ``cross`` is formed without cancellation near zero, which is what decides whether an
    event lies just ahead or a whole turn away."""
    return math.atan2(cross, dot) % TWO_PI


def stick_line_event(s: int, dx: float, v0: float, v: float) -> tuple[float, float] | None:
    """Phase to the next ``x' = v`` on the slip circle about ``(s a, 0)`` from
    ``(x0, x') = (c + dx, v0)``, and ``x - c`` there; ``None`` if the circle misses it.

    ``x' = v`` is reached rising (``s = +1``) at ``X1 = -h``, falling (``s = -1``) at
    ``X1 = +h``, with ``h^2 = R^2 - v^2 = dx^2 + (v0 - v)(v0 + v)`` (a product, not a
    difference of nearly equal squares). Which side of the stick line the arc starts on
    is settled by geometry, not by a tolerance on the phase: when the acceleration drives
    the relative velocity towards zero (``s dx < 0``) the event lies less than half a turn
    ahead and ``cross`` is written as ``|u_r|`` times positive terms, so a start within
    rounding of the belt speed sticks at once; otherwise a start on the line (after
    stick->slip, or a sign change) is the crossing the arc leaves from, a turn away when
    the circle only touches the line.
    """
    h2 = dx * dx + (v0 - v) * (v0 + v)
    if h2 < 0.0 or (dx == 0.0 and v0 == 0.0):
        return None
    h = math.sqrt(h2)
    approaching = s * dx < 0.0
    if approaching and v + v0 > 0.0:
        # V0 X1 - X0 V1 with X0^2 - h^2 = s (v - v0)(v + v0): every term positive.
        cross = s * (v - v0) * (v * (v + v0) / (h + abs(dx)) + h)
    else:
        cross = -s * v0 * h - dx * v
    dtheta = _phase(cross, -s * dx * h + v0 * v)
    if dtheta == 0.0 and not approaching:
        dtheta = TWO_PI  # the circle leaves the line here and comes back after a turn
    return dtheta, -s * h


def stop_event(dx: float, v0: float, gap: float, x1: float) -> tuple[float, float] | None:
    """Phase to the stop and the approach speed, from ``(x - c, x') = (dx, v0)``, the stop
    ``gap = x_bar - x0 >= 0`` ahead and at ``x1 = x_bar - c``; ``None`` if the circle never
    reaches it moving forward.

    The squared speed ``R^2 - x1^2 = v0^2 - gap (dx + x1)`` is formed without cancellation,
    so a start a few ulps from the stop still finds its (tiny) arc. Moving forward
    (``v0 > 0``) the stop is less than half a turn ahead, and ``cross`` is ``gap`` times
    positive terms (``v0 - speed = gap (dx + x1) / (v0 + speed)``).
    """
    speed2 = v0 * v0 - gap * (dx + x1)
    if not speed2 > 0.0:
        return None
    speed = math.sqrt(speed2)
    if v0 > 0.0:
        cross = gap * (x1 * (dx + x1) / (v0 + speed) + speed)
    else:
        cross = v0 * x1 - dx * speed
    return _phase(cross, dx * x1 + v0 * speed), speed


def free_flight(
    osc: Oscillator,
    t0: float,
    x0: float,
    v0: float,
    motion: Motion,
    barrier: float = math.inf,
) -> tuple[Segment, FreeEvent | None]:
    """Exact motion from ``(x0, v0)`` at ``t0`` up to the next event, or for ever.

    Parameters
    ----------
    osc : Oscillator
    t0, x0, v0 : float
        Start time and state; ``x0 <= barrier``.
    motion : Motion
        Mode at the start (see :func:`start_motion`).
    barrier : float
        The stop's face ``x = clearance``; ``inf`` for no stop.

    Returns
    -------
    segment : Segment
        The closed-form piece; ``t1 = inf`` when no event ever ends it.
    event : FreeEvent or None
        The event at ``segment.t1``; ``None`` when the motion never ends (a slip circle
        that touches neither the stick line nor the stop, or stick on a still belt).

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> seg, ev = free_flight(osc, 0.0, 0.0, 0.0, start_motion(osc, 0.0, 0.0))
    >>> ev.kind.value, round(ev.x, 12)   # Eq. (30): x = a - sqrt(a^2 - v^2)
    ('slip->stick', 0.026794919243)
    """
    v = osc.v
    if motion.mode is Mode.STICK:
        return _stick(osc, t0, x0, v, barrier)
    s = motion.s
    c = s * osc.a
    dx = x0 - c
    best: tuple[float, TransitionKind, float, float] | None = None

    # Relative velocity vanishes, x' = v.
    line = stick_line_event(s, dx, v0, v)
    if line is not None:
        dtheta, x_ev = line[0], c + line[1]
        kind = (
            TransitionKind.SLIP_STICK if abs(x_ev) <= osc.b else TransitionKind.SIGN_CHANGE
        )
        best = (dtheta, kind, x_ev, v)

    # The stop, x = barrier, reached with x' > 0.
    if math.isfinite(barrier):
        hit = stop_event(dx, v0, barrier - x0, barrier - c)
        if hit is not None:
            # On a tie the impact wins: the stop is reached with x' = v.
            if best is None or hit[0] <= best[0]:
                best = (hit[0], TransitionKind.IMPACT, barrier, hit[1])
        elif x0 >= barrier and c > barrier:
            # At the stop with x' = 0 and the force pushing into it: pressed now (speed 0).
            best = (0.0, TransitionKind.IMPACT, barrier, 0.0)

    if best is None:
        return Segment(Mode.SLIP, t0, math.inf, x0, v0, c), None
    dtheta, kind, x_ev, v_ev = best
    t1 = t0 + dtheta
    return Segment(Mode.SLIP, t0, t1, x0, v0, c), FreeEvent(kind, t1, x_ev, v_ev)


def _stick(
    osc: Oscillator, t0: float, x0: float, v: float, barrier: float
) -> tuple[Segment, FreeEvent | None]:
    """Stick along ``x' = v`` until ``x = b`` (stick->slip) or the stop (paper Eqs. 24, 26)."""
    if v <= 0.0:
        return Segment(Mode.STICK, t0, math.inf, x0, 0.0), None
    if barrier <= osc.b:  # at barrier = b the stick reaches the stop with x' = v
        t1 = t0 + max(barrier - x0, 0.0) / v
        return Segment(Mode.STICK, t0, t1, x0, v), FreeEvent(TransitionKind.IMPACT, t1, barrier, v)
    t1 = t0 + max(osc.b - x0, 0.0) / v
    return Segment(Mode.STICK, t0, t1, x0, v), FreeEvent(TransitionKind.STICK_SLIP, t1, osc.b, v)
