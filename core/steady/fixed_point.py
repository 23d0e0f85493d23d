"""Periodic steady states as fixed points of the friction-impact map (paper Eq. 20).

:class:`FixedPointDetector` finds one from transition states: a state that repeats an
earlier one of the same kind, with a period the times can resolve (``> 0``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.result import TransitionKind

#: Two transition states closer than this (relative to the problem's length scale) are the
#: same point of the friction-impact map. The exact solution repeats to a few ulps; 1e-11
#: leaves room for the rounding of long transients without merging distinct states.
FIXED_POINT_RTOL = 1e-11
#: How many earlier transitions of the same kind are compared with each new one.
FIXED_POINT_LOOKBACK = 64
#: A cycle must last more than this many ulps of the time it closes at (a shorter one is a
#: bounce below the resolution of time and cannot be tiled).
PERIOD_ULPS = 1024


@dataclass(frozen=True)
class Cycle:
    """A periodic steady state found by :class:`FixedPointDetector`.

    ``t_then``/``t_now`` are the times of the two equal transition states (``period =
    t_now - t_then > 0``); ``tag_then``/``tag_now`` the caller's tags stored with them
    (e.g. the row of a segment table); ``n_transitions`` the transitions per period.
    """

    t_then: float
    t_now: float
    tag_then: int
    tag_now: int
    n_transitions: int

    @property
    def period(self) -> float:
        return self.t_now - self.t_then


class FixedPointDetector:
    """Fixed point of the friction-impact map ``P^j`` (Eq. 20) from transition states.

    Feed every transition state with :meth:`add`; it returns the :class:`Cycle` when the
    state repeats an earlier one of the same kind, else ``None``. A repeat must hold to
    ``FIXED_POINT_RTOL * scale`` and also to ``FIXED_POINT_RTOL`` of the cycle's own size
    (a sequence converging on a point, as in an accumulation, has consecutive states that
    come within any absolute tolerance without ever repeating), and its period must be
    resolvable in time (more than :data:`PERIOD_ULPS` ulps).

    ``rtol`` replaces ``FIXED_POINT_RTOL`` for states known only to a tolerance: the
    transition states of a numerical method repeat to about its own accuracy, never to
    the few ulps of the exact solution. Such states cannot tell a cycle from a converging
    sequence by the cycle's own size either (a cycle of one impact has the size of its
    own drift); ``min_cycle_size`` (e.g. ``scale``) is then the size the repeat is
    measured against, and an accumulation must be recognised by the caller.

    A deformable stop adds the contact force ``phi`` (over ``k``, a length times the stop's
    stiffness ratio) to the state; it must repeat to ``phi_scale`` times the tolerance.

    Examples
    --------
    >>> det = FixedPointDetector(scale=1.0)
    >>> det.add(TransitionKind.IMPACT, 1.0, 0.3, 0.2) is None
    True
    >>> det.add(TransitionKind.IMPACT, 3.5, 0.3, 0.2).period
    2.5
    """

    def __init__(
        self,
        scale: float,
        rtol: float = FIXED_POINT_RTOL,
        min_cycle_size: float = 0.0,
        phi_scale: float = 1.0,
    ) -> None:
        if not rtol > 0.0:
            raise ValueError(f"rtol must be > 0, got {rtol!r}")
        self.rtol = rtol
        self.tol = rtol * scale
        self.min_cycle_size = min_cycle_size
        self.phi_tol = self.tol * phi_scale
        self.phis: list[float] = []
        #: For each state, how many transitions back each earlier state it repeats lies.
        self.repeats: list[frozenset[int]] = []
        self.states: list[tuple[float, float, float, int]] = []  # (t, x, v, tag)
        self.by_kind: dict[str, list[int]] = {}

    def add(
        self, kind: TransitionKind, t: float, x: float, v: float, tag: int = 0, phi: float = 0.0
    ) -> Cycle | None:
        """Record the state ``(x, v, phi)`` of a transition of ``kind`` at ``t``; the cycle
        it closes with the closest earlier state it repeats, or ``None``."""
        seen = self.by_kind.setdefault(kind.value, [])
        matches = self._matches(seen, t, x, v, phi)
        n_now = len(self.states)
        self.states.append((t, x, v, tag))
        self.phis.append(phi)
        seen.append(n_now)
        self.repeats.append(frozenset(n_now - i for i, _ in matches))
        if not matches:
            return None
        j = min(matches, key=lambda m: m[1])[0]
        t_then, _, _, tag_then = self.states[j]
        return Cycle(t_then, t, tag_then, tag, n_now - j)

    def _matches(
        self, seen: list[int], t: float, x: float, v: float, phi: float
    ) -> list[tuple[int, float]]:
        """The earlier states ``(index, gap)`` that ``(x, v, phi)`` at ``t`` repeats."""
        shortest = PERIOD_ULPS * math.ulp(max(abs(t), 1.0))
        found = []
        for i in seen[-FIXED_POINT_LOOKBACK:]:
            ti, xi, vi, _ = self.states[i]
            gap = abs(xi - x) + abs(vi - v)
            near = abs(xi - x) <= self.tol and abs(vi - v) <= self.tol
            near = near and abs(self.phis[i] - phi) <= self.phi_tol
            if near and t - ti > shortest:
                size = max(abs(st[1] - x) + abs(st[2] - v) for st in self.states[i:])
                if gap <= self.rtol * max(size, self.min_cycle_size):
                    found.append((i, gap))
        return found
