"""A piecewise closed-form trajectory and its evaluation at sample times.

The exact solver describes the motion as a table of segments (circle arcs, straight stick
lines, rest at the stop), optionally followed by a periodic continuation. Evaluation is
vectorised: one ``searchsorted`` assigns every sample to its segment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from core.flight import Segment
from core.impact_sequence import ImpactSequence, evaluate_sequence
from core.result import Mode
from core.steady import fold_times
from core.validation import check_side, check_times

#: A time within this many ulps (of the time itself) of a transition is taken to lie on it:
#: the transition times of a repeated cycle are formed as ``t_i + k*period`` and mapped
#: back by ``t - k*period``, which rounds by a few ulps of the horizon. 64 ulps leaves a
#: wide margin and moves a state by ~1e-14 of a time unit at t ~ 1.
EVENT_SNAP_ULPS = 64.0
#: Formula codes of a segment.
CIRCLE = 0  # x = c + (x0 - c) cos(tau) + v0 sin(tau)
LINE = 1  # x = x0 + v0 tau


@dataclass
class SegmentTable:
    """Growing table of segments with the energy terms accumulated at each start.

    Energy terms (per unit ``k``): ``friction_work`` (work of friction on the mass),
    ``belt_input`` (work done by the belt), ``stop_loss`` (kinetic energy removed by impacts).
    """

    t0: list[float] = field(default_factory=list)
    t1: list[float] = field(default_factory=list)
    formula: list[int] = field(default_factory=list)
    mode: list[int] = field(default_factory=list)
    x0: list[float] = field(default_factory=list)
    v0: list[float] = field(default_factory=list)
    centre: list[float] = field(default_factory=list)
    friction: list[float] = field(default_factory=list)  # s*a on slip; nan on stick
    work0: list[tuple[float, float, float]] = field(default_factory=list)
    work: tuple[float, float, float] = (0.0, 0.0, 0.0)
    x_max: float = -math.inf

    def __len__(self) -> int:
        return len(self.t0)

    def add(
        self, seg: Segment, t1: float, belt_speed: float, x1: float | None = None
    ) -> None:
        """Append ``seg`` cut at ``t1`` and accumulate its work terms (paper Eqs. 3-6).

        ``x1``: the position at ``t1`` when an event fixes it exactly (the stop, ``b``, the
        stick line's crossing); the work is then formed from it rather than from the
        rounded ``cos``/``sin`` of ``t1 - t0``. A cycle's work per period, repeated over
        every period tiled, then carries no rounding of the arc's end (an elastic impact
        cycle does no friction work at all)."""
        self.t0.append(seg.t0)
        self.t1.append(t1)
        if seg.mode is Mode.SLIP:
            self.formula.append(CIRCLE)
            self.friction.append(seg.centre)  # the friction force over k is s*a = centre
        else:
            self.formula.append(LINE)
            # Stick: friction balances the spring, f = x. Rest at the stop: f = a (slip).
            self.friction.append(seg.centre if seg.mode is Mode.CONTACT else math.nan)
        self.mode.append(int(seg.mode))
        self.x0.append(seg.x0)
        self.v0.append(seg.v0)
        self.centre.append(seg.centre)
        self.work0.append(self.work)
        cut = Segment(seg.mode, seg.t0, t1, seg.x0, seg.v0, seg.centre)
        self.x_max = max(self.x_max, cut.x_max())
        if x1 is None:
            x1, _ = cut.state_at(t1)
        self.work = _add(self.work, _segment_work(cut, x1, belt_speed))

    def add_loss(self, loss: float) -> None:
        """Kinetic energy removed at an impact: ``(1 - r^2) w^2 / 2`` (paper Eq. 8)."""
        wf, wb, lost = self.work
        self.work = (wf, wb, lost + loss)

    def arrays(self, belt_speed: float) -> dict[str, np.ndarray]:
        """Per-segment coefficients of one formula for every kind of segment:
        ``x = A + B cos(tau) + C sin(tau) + D tau``, and of the work terms
        ``friction = P (x - x0) + Q (x^2 - x0^2)/2``, ``belt = E tau + F tau^2``."""
        w = np.array(self.work0, dtype=float).reshape(-1, 3)
        x0 = np.array(self.x0, dtype=float)
        v0 = np.array(self.v0, dtype=float)
        c = np.array(self.centre, dtype=float)
        mode = np.array(self.mode, dtype=np.int8)
        circle = np.array(self.formula, dtype=np.int8) == CIRCLE
        stick = mode == Mode.STICK
        friction = np.nan_to_num(np.array(self.friction, dtype=float))
        return {
            "t0": np.array(self.t0, dtype=float),
            "mode": mode,
            "x0": x0,
            "A": np.where(circle, c, x0),
            "B": np.where(circle, x0 - c, 0.0),
            "C": np.where(circle, v0, 0.0),
            "D": np.where(circle, 0.0, v0),
            "P": np.where(mode == Mode.SLIP, friction, 0.0),
            "Q": stick.astype(float),
            "E": np.where(stick, belt_speed * x0, friction * belt_speed),
            "F": np.where(stick, 0.5 * belt_speed * belt_speed, 0.0),
            "wf0": w[:, 0],
            "wb0": w[:, 1],
            "loss0": w[:, 2],
        }


def _add(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float]:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def _segment_work(seg: Segment, x1: float, v: float) -> tuple[float, float, float]:
    """Friction work and belt input over one closed-form segment."""
    tau = seg.t1 - seg.t0
    if seg.mode is Mode.SLIP:
        # Friction force s*a is constant: work s*a*(x1 - x0); the belt supplies s*a*v*tau.
        return seg.centre * (x1 - seg.x0), seg.centre * v * tau, 0.0
    if seg.mode is Mode.CONTACT:  # pressed on the stop: x' = 0, friction a, belt a*v
        return 0.0, seg.centre * v * tau, 0.0
    # Stick: friction equals the spring force x; x' = v.
    return (x1 * x1 - seg.x0 * seg.x0) / 2.0, v * (seg.x0 * tau + v * tau * tau / 2.0), 0.0


@dataclass(frozen=True)
class PeriodicTail:
    """The motion after ``t_from`` repeats the piece ``[cycle_t0, cycle_t0 + period)``."""

    t_from: float
    cycle_t0: float
    period: float
    work_per_period: tuple[float, float, float]


def evaluate(
    table: dict[str, np.ndarray],
    times: np.ndarray,
    side: np.ndarray,
    belt_speed: float,
    tail: PeriodicTail | None = None,
) -> dict[str, np.ndarray]:
    """State, mode and cumulative energy terms at ``times``.

    ``side[i]`` is -1 for the state just before a transition at ``times[i]`` (on the segment
    that ends there; both sides of an impact are drawn), +1 for the state just after one,
    0 for a plain sample.
    """
    t = np.asarray(times, dtype=float)
    side = np.asarray(side, dtype=np.int8)
    # One snap for all times, from the largest: the rounding it absorbs grows with the
    # horizon, not with each time.
    snap = EVENT_SNAP_ULPS * math.ulp(max(1.0, float(np.max(np.abs(t)))) if t.size else 1.0)
    wf_off = wb_off = loss_off = 0.0
    if tail is not None:
        t, n = fold_times(t, side, tail.t_from, tail.cycle_t0, tail.period)
        dwf, dwb, dloss = tail.work_per_period
        wf_off, wb_off, loss_off = n * dwf, n * dwb, n * dloss
    t0 = table["t0"]
    # A time at a transition belongs to the segment after it, or before it when asked
    # (side -1); the snap makes that hold when rounding puts it an ulp off the start.
    idx = np.searchsorted(t0, t + side * snap, side="right") - 1
    idx = np.clip(idx, 0, len(t0) - 1)
    tau = t - t0[idx]
    cos_t, sin_t = np.cos(tau), np.sin(tau)
    b, c, d = table["B"][idx], table["C"][idx], table["D"][idx]
    x = table["A"][idx] + b * cos_t + c * sin_t + d * tau
    v = c * cos_t - b * sin_t + d
    x0 = table["x0"][idx]
    dx = x - x0
    friction_work = dx * (table["P"][idx] + 0.5 * table["Q"][idx] * (x + x0))
    belt_input = tau * (table["E"][idx] + table["F"][idx] * tau)
    return {
        "x": x,
        "v": v,
        "mode": table["mode"][idx],
        "friction_work": table["wf0"][idx] + friction_work + wf_off,
        "belt_input": table["wb0"][idx] + belt_input + wb_off,
        "stop_loss": table["loss0"][idx] + loss_off,
    }


@dataclass(frozen=True)
class ExactSolution:
    """The exact solution with no stop or a rigid stop, as a function of time.

    The :class:`~core.result.DenseSolution` of the exact method: the segment table, then
    the periodic continuation (``tail``) or the endless impact sequence (``sequence``), all
    evaluated in closed form. At an impact ``side = -1`` gives the state before it and
    ``side = +1`` the state after it; elsewhere both sides agree.

    Attributes
    ----------
    table : dict of ndarray
        :meth:`SegmentTable.arrays` of the transient (and one period of a cycle).
    belt_speed, t_end, clearance : float
        ``clearance`` is ``inf`` without a stop.
    tail : PeriodicTail or None
    sequence : ImpactSequence or None
    sequence_work : (float, float, float)
        Energy terms accumulated up to the sequence's start, its first impact's loss
        included.
    """

    table: dict[str, np.ndarray]
    belt_speed: float
    t_end: float
    clearance: float = math.inf
    tail: PeriodicTail | None = None
    sequence: ImpactSequence | None = None
    sequence_work: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def sample(self, times: np.ndarray, side: np.ndarray) -> dict[str, np.ndarray]:
        """State, mode and cumulative energy terms at ``times`` (sides per time: -1 the
        left limit, +1 or 0 the right limit)."""
        times = np.asarray(times, dtype=float)
        side = np.asarray(side, dtype=np.int8)
        seq = self.sequence
        if seq is None:
            out = evaluate(self.table, times, side, self.belt_speed, self.tail)
            if math.isfinite(self.clearance):
                # Rounding may put a state a few ulps past the face; the exact solution
                # never is.
                np.minimum(out["x"], self.clearance, out=out["x"])
            return out
        late = (times > seq.t_start) | ((times == seq.t_start) & (side >= 0))
        early = ~late
        out = {
            name: np.empty(len(times), np.int8 if name == "mode" else float)
            for name in ("x", "v", "mode", "friction_work", "belt_input", "stop_loss")
        }
        if np.any(early):
            part = evaluate(self.table, times[early], side[early], self.belt_speed, self.tail)
            for name, values in part.items():
                out[name][early] = values
        if np.any(late):
            part = evaluate_sequence(seq, times[late], self.belt_speed, side[late])
            wf, wb, lost = self.sequence_work
            # sequence_work already holds the loss of the first impact of the sequence.
            first_loss = 0.5 * (1.0 - seq.r**2) * seq.w**2
            offsets = {"friction_work": wf, "belt_input": wb, "stop_loss": lost - first_loss}
            for name, values in part.items():
                out[name][late] = values + offsets.get(name, 0.0)
        # Rounding may put a state a few ulps past the face; the exact solution never is.
        np.minimum(out["x"], self.clearance, out=out["x"])
        return out

    def evaluate(self, t: np.ndarray, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity at times ``t`` in ``[0, t_end]`` (any shape).

        Examples
        --------
        >>> from core import Oscillator, RigidStop, simulate
        >>> res = simulate(Oscillator(0.3, 0.2, 0.5), RigidStop(0.3, 1.0), t_end=10.0)
        >>> t_hit = res.transitions[0].t
        >>> [round(float(res.evaluate(t_hit, side)[1]), 12) for side in (-1, 1)]
        [0.173205080757, -0.173205080757]
        """
        check_side(side)
        t = np.asarray(t, dtype=float)
        flat = check_times("t", t.ravel(), self.t_end)
        out = self.sample(flat, np.full(flat.shape, side, np.int8))
        return out["x"].reshape(t.shape), out["v"].reshape(t.shape)
