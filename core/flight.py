"""Exact free flight of the friction oscillator away from the stop (paper §3; docs/physics.md,
"Exact solution").

Slip with ``s = sign(v - x')`` obeys ``x'' + x = s*a`` (paper Eq. 3 with Eq. 4): a clockwise
circle in the phase plane about ``(s*a, 0)``. Stick obeys ``x' = v`` while ``|x| <= b``
(Eqs. 5-6). Every event time below comes from ``asin``/``acos``/``atan2`` of the circle or
from the straight stick line; nothing is found by a numerical root search.

The functions are scalar and use :mod:`math` on purpose: one call costs a few microseconds,
which keeps a whole slider update's solve far below a millisecond.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.params import Oscillator
from core.result import Mode, TransitionKind

TWO_PI = 2.0 * math.pi

#: An event this close (in phase angle) to the start of a slip arc is the state the arc
#: starts from, not a new event; the arc then runs a full turn. Chosen a few hundred ulps
#: of 2*pi so that rounding of the start state never produces a zero-length arc.
ANGLE_EPS = 1e-12


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


def _angle_ahead(target: float, theta0: float) -> float:
    """Phase travelled from ``theta0`` to ``target`` (mod 2 pi), in ``(0, 2 pi]``."""
    d = (target - theta0) % TWO_PI
    if d < ANGLE_EPS or TWO_PI - d < ANGLE_EPS:
        return TWO_PI
    return d


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
    radius = math.hypot(dx, v0)
    theta0 = math.atan2(-v0, dx)
    best: tuple[float, TransitionKind, float, float] | None = None

    # Relative velocity vanishes, x' = v: -R sin(theta) = v.
    if radius > 0.0 and (s < 0 or radius >= v):
        ratio = min(v / radius, 1.0)
        half_chord = math.sqrt(max(radius * radius - v * v, 0.0))
        if s > 0:  # x' rises to v: cos(theta) < 0
            target, x_ev = math.pi + math.asin(ratio), c - half_chord
        else:  # x' falls to v: cos(theta) > 0
            target, x_ev = -math.asin(ratio), c + half_chord
        dtheta = _angle_ahead(target, theta0)
        kind = (
            TransitionKind.SLIP_STICK if abs(x_ev) <= osc.b else TransitionKind.SIGN_CHANGE
        )
        best = (dtheta, kind, x_ev, v)

    # The stop, x = barrier, reached with x' > 0: R cos(theta) = barrier - c, sin(theta) < 0.
    # The squared impact speed R^2 - (barrier - c)^2 is formed without cancellation, so a
    # start a few ulps from the stop still finds its (tiny) arc.
    if math.isfinite(barrier):
        speed2 = (x0 - barrier) * (x0 + barrier - 2.0 * c) + v0 * v0
        if speed2 > 0.0:
            speed = math.sqrt(speed2)
            # Zero only for a start within rounding of the stop: the impact is then now.
            dtheta = (math.atan2(-speed, barrier - c) - theta0) % TWO_PI
            # On a tie the impact wins: the stop is reached with x' = v.
            if best is None or dtheta <= best[0]:
                best = (dtheta, TransitionKind.IMPACT, barrier, speed)
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
