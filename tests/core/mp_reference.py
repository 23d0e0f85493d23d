"""An independent event-driven solution of the rigid-stop oscillator in 40-digit arithmetic.

Written from docs/physics.md ("Exact solution", "Rigid impacts", "Rest at the stop") with
mpmath, not from core: each slip arc is a circle about ``(s a, 0)`` whose phase
``phi`` (``x - c = R cos(phi)``, ``x' = -R sin(phi)``, ``phi`` grows at unit rate) meets
the stick line at ``asin`` and the stop at ``acos``; stick is the line ``x' = v``; an
impact applies Newton's law (Eq. 8). Periodicity is found the plain way, as a transition
state that repeats to 1e-25 of the length scale (40 digits keep a state to ~1e-35), and the
rest of the horizon is that period repeated. Impact sequences are followed impact by impact
up to an event cap.

Each decision the float solution also takes (which event comes first, whether a circle
reaches the stick line or the stop, stick or sign change at ``|x| = b``, rest or bounce)
records its margin. A margin below the rounding the float solution carries there makes it
ill-conditioned: :attr:`MpSolution.conditioned_until` is the number of transitions before
the first such decision. Exact ties (margins below 1e-30, which 40 digits cannot tell from
zero) follow the documented rules instead: the impact wins a tie with the stick line, a
circle that only touches the stop at zero speed does not hit it, ``|x| = b`` sticks. An
impact ends in rest by the documented rule (docs/physics.md, "Rest at the stop"), with its
threshold :data:`core.steady.REST_SPEED`.

Each transition also carries a slack: how far in time the rounding of a float solution may
have moved it (:data:`ROUNDING`), which the comparison adds to its tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mpmath as mp

from core.steady import REST_SPEED

DIGITS = 40
#: Below this (relative) a margin is an exact tie of the geometry: 40 digits resolve ~1e-38.
EXACT = mp.mpf("1e-30")
#: Margins below which the float solution may decide otherwise. Phases and positions carry
#: ~1e-15 of rounding, so a competition between events closer than 1e-9 (radians, or of the
#: length scale for |x| = b) is left undecided. At a tangency, ``h^2 = R^2 - w^2`` is a
#: fraction m of its terms' size S (:meth:`MpReference._size`); the event lies at
#: ``h = sqrt(m S)``, which rounding of ~eps S moves by eps sqrt(S / m): below m = 1e-11
#: that exceeds the 1e-10 the test compares to.
PHASE_MARGIN = mp.mpf("1e-9")
LENGTH_MARGIN = mp.mpf("1e-9")
SQUARE_MARGIN = mp.mpf("1e-11")
#: A cycle closes when a transition state repeats to this fraction of the length scale.
REPEAT = mp.mpf("1e-25")
#: A stick from a computed position x0 to x = b takes (b - x0) / v: the rounding of x0
#: (x0 = c - h after a slip, an ulp of the length scale) moves its end by ~2^-52 scale / v,
#: and every later time with it.
#: Likewise an event near a tangency, where the float solution forms h^2 = R^2 - w^2 to
#: ~eps of its terms' size S, moves by ~eps S / (h R) in phase. Four ulps are allowed for
#: each (:attr:`MpSolution.slack`).
ROUNDING = 4 * mp.mpf(2) ** -52


@dataclass
class Piece:
    """One closed-form piece from ``t0`` to ``t1``: kind 'slip' (centre c), 'stick', 'rest'."""

    kind: str
    t0: mp.mpf
    t1: mp.mpf
    x0: mp.mpf
    v0: mp.mpf
    c: mp.mpf = mp.mpf(0)

    def state(self, t):
        tau = t - self.t0
        if self.kind == "slip":
            dx = self.x0 - self.c
            return (self.c + dx * mp.cos(tau) + self.v0 * mp.sin(tau),
                    -dx * mp.sin(tau) + self.v0 * mp.cos(tau))
        return self.x0 + self.v0 * tau, self.v0

    def x_max(self, t_end):
        t1 = min(self.t1, t_end)
        if self.kind != "slip":
            return max(self.x0, self.state(t1)[0])
        dx = self.x0 - self.c
        radius = mp.sqrt(dx * dx + self.v0 * self.v0)
        phi0 = mp.atan2(-self.v0, dx)
        to_top = (-phi0) % (2 * mp.pi)  # phase to x = c + R
        if to_top <= t1 - self.t0:
            return self.c + radius
        return max(self.x0, self.state(t1)[0])


@dataclass
class MpSolution:
    """The reference over ``[0, t_end]`` (or up to ``t_stop`` when the event cap ends it)."""

    transitions: list[tuple[str, mp.mpf, mp.mpf, mp.mpf]] = field(default_factory=list)
    #: For each transition, how far rounding may have moved its time (sticks, tangencies).
    slack: list[mp.mpf] = field(default_factory=list)
    pieces: list[Piece] = field(default_factory=list)
    conditioned_until: float = float("inf")
    t_stop: mp.mpf = mp.inf
    period: mp.mpf | None = None  # the repeated cycle [cycle_t0, cycle_t0 + period)
    cycle_t0: mp.mpf = mp.mpf(0)
    cycle_end: mp.mpf = mp.mpf(0)
    cycle: list = field(default_factory=list)  # the transitions of one period, with slack
    cycle_slack: mp.mpf = mp.mpf(0)

    def state(self, t):
        """``(x, x')`` at ``t`` (the right limit at an impact)."""
        with mp.workdps(DIGITS):
            t = mp.mpf(t)
            if self.period is not None and t > self.cycle_end:
                t = self.cycle_t0 + (t - self.cycle_end) % self.period
            for piece in reversed(self.pieces):
                if piece.t0 <= t:
                    return piece.state(t)
        raise ValueError("no piece at t")

    def x_max(self, t_end):
        with mp.workdps(DIGITS):
            return max(p.x_max(mp.mpf(t_end)) for p in self.pieces if p.t0 <= t_end)

    def tiled(self, count, t_end):
        """The first ``count`` transitions before ``t_end``, the cycle's repeated after
        it, each with its time's slack."""
        out = [(*tr, sl) for tr, sl in zip(self.transitions, self.slack, strict=True)]
        if self.period is not None:
            with mp.workdps(DIGITS):
                k = 1
                while len(out) < count and self.cycle and out[-1][1] < t_end:
                    out += [(kd, t + k * self.period, x, v, sl + k * self.cycle_slack)
                            for kd, t, x, v, sl in self.cycle]
                    k += 1
        return [tr for tr in out if tr[1] < t_end][:count]

    def slack_at(self, t):
        """How far rounding may have moved the motion in time by ``t``."""
        if not self.slack:
            return mp.mpf(0)
        if self.period is None or t <= self.cycle_end:
            return self.slack[-1]
        return self.slack[-1] + (t - self.cycle_end) / self.period * self.cycle_slack


class MpReference:
    """Event-driven solve at :data:`DIGITS` digits; ``xb = None`` for no stop."""

    def __init__(self, a, b, v, xb, r, x0, v0, t_end, max_events=150):
        with mp.workdps(DIGITS):
            self.a, self.b, self.v = mp.mpf(a), mp.mpf(b), mp.mpf(v)
            self.xb = None if xb is None else mp.mpf(xb)
            self.r = mp.mpf(r)
            self.scale = max(self.a, self.b, self.v, abs(self.xb or 0), abs(mp.mpf(x0)),
                             abs(mp.mpf(v0)))
            self.t_end = mp.mpf(t_end)
            self.sol = MpSolution()
            self.slack = mp.mpf(0)
            self._run(mp.mpf(x0), mp.mpf(v0), max_events)

    # ----------------------------------------------------------------- bookkeeping

    def _margin(self, value, threshold, exact_tie=True):
        """Record a decision's margin; True when it is an exact tie. ``exact_tie=False``:
        the float solution cannot see this tie exactly (a tangency reached from a computed
        state, whose rounding moves the event by ~sqrt(eps)), so it is ill-conditioned."""
        value = abs(value)
        if value < EXACT and exact_tie:
            return True
        if value < threshold:
            self.sol.conditioned_until = min(self.sol.conditioned_until,
                                             len(self.sol.transitions))
        return value < EXACT

    def _log(self, kind, t, x, v):
        self.sol.transitions.append((kind, t, x, v))
        self.sol.slack.append(self.slack)

    def _mode(self, x, xd):
        """Eq. 7: slip with the sign of v - x', or stick when |x| <= b at x' = v."""
        if xd < self.v:
            return 1
        if xd > self.v:
            return -1
        return 0 if abs(x) <= self.b else (1 if x > 0 else -1)

    def _size(self, radius, other):
        """What rounding of ``radius^2 - other^2`` is measured against: the squares, and
        the rounding of the state by ~eps of the length scale times the radius."""
        return radius * radius + other * other + self.scale * radius

    def _phase_slack(self, excess, radius, other):
        """How far rounding may move the phase of an event at ``sqrt(excess)`` from the
        centre line: ~eps of the terms' size in ``excess``, over ``2 sqrt(excess) R``."""
        if excess <= 0:
            return mp.mpf(0)  # an exact tangency: ill-conditioned anyway (see _margin)
        return ROUNDING * self._size(radius, other) / (mp.sqrt(excess) * radius)

    def _pressed(self):
        return self.a >= self.xb

    # --------------------------------------------------------------------- events

    def _slip_events(self, s, x0, v0):
        """(phase, kind, x, v) of the next event of the slip arc, or None."""
        c = s * self.a
        dx = x0 - c
        radius = mp.sqrt(dx * dx + v0 * v0)
        phi0 = mp.atan2(-v0, dx)
        line = hit = None
        if radius > 0:
            excess = radius * radius - self.v * self.v
            # A start on the line (stick->slip, sign change) has h = |x - c| exactly.
            tangent = v0 != self.v and self._margin(
                excess / self._size(radius, self.v), SQUARE_MARGIN, exact_tie=False
            )
            if excess >= 0 or tangent:
                ratio = min(self.v / radius, mp.mpf(1))
                target = mp.pi + mp.asin(ratio) if s > 0 else -mp.asin(ratio)
                phase = (target - phi0) % (2 * mp.pi)
                if v0 == self.v and phase < EXACT:
                    phase = 2 * mp.pi  # the arc leaves the line here
                x_ev = c + radius * mp.cos(target)
                stick_tie = self._margin((abs(x_ev) - self.b) / self.scale, LENGTH_MARGIN)
                kind = "slip->stick" if abs(x_ev) <= self.b or stick_tie else "sign_change"
                exact = v0 == self.v  # h = |x - c| exactly
                line = (phase, kind, x_ev, self.v,
                        0 if exact else self._phase_slack(excess, radius, self.v))
        if self.xb is not None and radius > 0:
            gap = self.xb - c
            excess = radius * radius - gap * gap
            # A start at the stop (a rebound) has the impact speed |x'| exactly.
            touch = x0 != self.xb and self._margin(
                excess / self._size(radius, gap), SQUARE_MARGIN, exact_tie=False
            )
            if excess > 0 and not touch:
                target = -mp.acos(gap / radius)
                phase = (target - phi0) % (2 * mp.pi)
                exact = x0 == self.xb  # the speed is |x'| exactly
                hit = (phase, "impact", self.xb, mp.sqrt(excess),
                       0 if exact else self._phase_slack(excess, radius, gap))
        if line and hit:
            tie = self._margin((hit[0] - line[0]) / (2 * mp.pi), PHASE_MARGIN)
            return hit if hit[0] <= line[0] or tie else line
        return hit or line

    def _run(self, x, xd, max_events):
        sol, t = self.sol, mp.mpf(0)
        seen: dict[str, list[tuple]] = {}
        mode = self._mode(x, xd)
        if self.xb is not None and x >= self.xb:
            if xd > 0:  # riding with the belt into the stop is a stick->impact
                mode = "stick->impact" if mode == 0 else "impact"
            elif xd == 0 and self.v > 0 and self._pressed():
                mode = "rest"
                self._log("rest", t, x, mp.mpf(0))
        for _ in range(max_events):
            if mode == "rest":
                sol.pieces.append(Piece("rest", t, mp.inf, self.xb, mp.mpf(0)))
                return
            if mode in ("impact", "stick->impact"):
                x, xd, mode = self._impact(t, xd, stuck=mode == "stick->impact")
                if mode == "rest":
                    continue
            else:
                step = self._stick(t, x) if mode == 0 else self._slip(t, x, xd, mode)
                if step is None:
                    return  # the horizon comes first
                t, kind, x, xd = step
                if kind in ("impact", "stick->impact"):
                    mode = kind
                    continue
                self._log(kind, t, x, xd)
                mode = {"slip->stick": 0, "stick->slip": 1}.get(kind, -mode)
            if self._repeats(seen, t, x, xd):
                return
        sol.t_stop = t

    def _stick(self, t, x):
        """Stick along x' = v to x = b (stick->slip), or to a stop at or before b."""
        to_stop = self.xb is not None and self.xb <= self.b
        end = self.xb if to_stop else self.b
        t1 = t + (end - x) / self.v if self.v > 0 else mp.inf
        self.sol.pieces.append(Piece("stick", t, t1, x, self.v))
        if self.v > 0:
            self.slack += ROUNDING * self.scale / self.v
        if t1 >= self.t_end:
            return None
        return t1, "stick->impact" if to_stop else "stick->slip", end, self.v

    def _slip(self, t, x, xd, s):
        event = self._slip_events(s, x, xd)
        t1 = t + event[0] if event else mp.inf
        self.sol.pieces.append(Piece("slip", t, t1, x, xd, s * self.a))
        if t1 >= self.t_end:
            return None
        self.slack += event[4]
        return t1, event[1], event[2], event[3]

    def _impact(self, t, w, stuck):
        """Newton's law (Eq. 8), or rest when the mass stays pressed on the stop."""
        xb = self.xb
        d = abs(self.a - xb)
        threshold = REST_SPEED * mp.sqrt(d * max(abs(xb), d))
        if self._pressed() and (w == 0 or w <= threshold):
            self._margin((w - threshold) / threshold, mp.mpf("1e-3"))
            if w > 0:
                self._log("accumulation", t, xb, w)
            self._log("rest", t, xb, mp.mpf(0))
            return xb, mp.mpf(0), "rest"
        self._log("stick->impact" if stuck else "impact", t, xb, w)
        after = -self.r * w
        if after == 0 and self.v > 0 and self._pressed():
            self._log("rest", t, xb, mp.mpf(0))
            return xb, w, "rest"
        self.sol.pieces.append(Piece("slip", t, t, xb, after, self.a))  # the rebound state
        return xb, after, self._mode(xb, after)

    def _repeats(self, seen, t, x, xd):
        """Close a cycle when the last transition's state repeats an earlier one of its
        kind (an impact's state is the approach speed, the others the state itself)."""
        kind, _, _, v_logged = self.sol.transitions[-1]
        now = len(self.sol.transitions) - 1
        tol = REPEAT * self.scale
        earlier = seen.setdefault(kind, [])
        for t_then, x_then, v_then, then in earlier:
            if abs(x_then - x) <= tol and abs(v_then - v_logged) <= tol and t - t_then > tol:
                self.sol.period = t - t_then
                self.sol.cycle_t0, self.sol.cycle_end = t_then, t
                self.sol.cycle = [
                    (*tr, sl) for tr, sl in zip(self.sol.transitions[then + 1 : now + 1],
                                                self.sol.slack[then + 1 : now + 1], strict=True)
                ]
                self.sol.cycle_slack = self.sol.slack[now] - self.sol.slack[then]
                return True
        earlier.append((t, x, v_logged, now))
        return False
