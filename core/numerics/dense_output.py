"""Dense solutions of the integrating methods: the solution as a function of time.

Each class has ``evaluate(t, side) -> (x, v)`` (the :class:`core.result.DenseSolution`
protocol) over the time the solve covered; at a jump of the velocity (a rigid impact,
paper Eq. 8) ``side=-1`` gives the left limit (before it) and ``side=+1`` the right limit.

* :class:`HermiteDense`: cubic Hermite interpolation of the step points, position with the
  velocity as derivative and velocity with the acceleration (the switch model's RKF 4(5)
  steps, :mod:`core.switch`).
* :class:`PiecewiseDense`: a sequence of pieces, each a function of time on its interval
  (``solve_ivp``'s own dense output on integrated segments, closed forms on stick and rest,
  :mod:`core.event_method`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from core.numerics.hermite import hermite_eval

#: A piece of a dense solution: ``f(t) -> (x, v)`` on an array of times.
Piece = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


def _check_side(side: int) -> str:
    if side not in (-1, 1):
        raise ValueError(f"side must be -1 (left limit) or +1 (right limit); got {side!r}")
    return "left" if side < 0 else "right"


def _check_span(t: np.ndarray, t0: float, t1: float) -> None:
    if t.size and (np.min(t) < t0 or np.max(t) > t1):
        raise ValueError(
            f"t must lie in [{t0:g}, {t1:g}], the time the solve covered; "
            f"got values in [{np.min(t):g}, {np.max(t):g}]"
        )


class HermiteDense:
    """Cubic Hermite interpolation of step points ``(t, x, v, acc)``.

    ``t`` is non-decreasing; a repeated time is a jump (the first point holds the state
    before it). ``acc[i]`` is the acceleration on the interval that starts at point ``i``.
    ``x_upper`` (a rigid stop's face) clips interpolants that round a few ulps beyond it.

    Examples
    --------
    >>> t = np.array([0.0, 1.0, 1.0, 2.0]); x = np.array([0.0, 1.0, 1.0, 0.0])
    >>> v = np.array([1.0, 1.0, -1.0, -1.0])
    >>> d = HermiteDense(t, x, v, np.zeros(4))
    >>> float(d.evaluate(np.array([1.0]), -1)[1][0]), float(d.evaluate(np.array([1.0]), 1)[1][0])
    (1.0, -1.0)
    """

    __slots__ = ("t", "x", "v", "acc", "x_upper")

    def __init__(self, t, x, v, acc, x_upper: float | None = None) -> None:
        self.t = np.asarray(t, dtype=float)
        self.x = np.asarray(x, dtype=float)
        self.v = np.asarray(v, dtype=float)
        self.acc = np.asarray(acc, dtype=float)
        self.x_upper = x_upper

    def evaluate(self, t, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity at times ``t`` (left or right limits, see the class)."""
        where = _check_side(side)
        tq = np.asarray(t, dtype=float)
        _check_span(tq, self.t[0], self.t[-1])
        x = hermite_eval(self.t, self.x, self.v, tq, where)
        if self.x_upper is not None:
            x = np.minimum(x, self.x_upper)
        return x, hermite_eval(self.t, self.v, self.acc, tq, where)


class PiecewiseDense:
    """A solution made of pieces on consecutive intervals ``[t0, t1]``.

    Pieces are added in time order with :meth:`add`; where two meet, ``side=-1`` evaluates
    the earlier one and ``side=+1`` the later one, so a jump between them is kept.

    Examples
    --------
    >>> d = PiecewiseDense()
    >>> d.add(0.0, 1.0, lambda t: (t, np.ones_like(t)))
    >>> d.add(1.0, 2.0, lambda t: (2.0 - t, -np.ones_like(t)))
    >>> [float(d.evaluate(np.array([1.0]), s)[1][0]) for s in (-1, 1)]
    [1.0, -1.0]
    """

    __slots__ = ("starts", "ends", "pieces", "x_upper")

    def __init__(self, x_upper: float | None = None) -> None:
        self.starts: list[float] = []
        self.ends: list[float] = []
        self.pieces: list[Piece] = []
        self.x_upper = x_upper

    def add(self, t0: float, t1: float, piece: Piece) -> None:
        """Append ``piece`` on ``[t0, t1]`` (``t0`` is the end of the previous piece);
        an empty interval adds nothing."""
        if t1 > t0:
            self.starts.append(float(t0))
            self.ends.append(float(t1))
            self.pieces.append(piece)

    @property
    def t_last(self) -> float:
        """End of the last piece (the time the solve reached)."""
        return self.ends[-1] if self.ends else 0.0

    def evaluate(self, t, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity at times ``t`` (left or right limits, see the class)."""
        where = _check_side(side)
        tq = np.asarray(t, dtype=float)
        flat = tq.ravel()
        if not self.pieces:
            raise ValueError("the solve covered no time: nothing to evaluate")
        _check_span(flat, self.starts[0], self.ends[-1])
        if where == "right":
            idx = np.searchsorted(self.starts, flat, side="right") - 1
        else:
            idx = np.searchsorted(self.ends, flat, side="left")
        idx = np.clip(idx, 0, len(self.pieces) - 1)
        x = np.empty(flat.shape)
        v = np.empty(flat.shape)
        order = np.argsort(idx, kind="stable")
        groups = np.split(order, np.flatnonzero(np.diff(idx[order])) + 1)
        for sel in groups:
            if sel.size:
                xi, vi = self.pieces[idx[sel[0]]](flat[sel])
                x[sel], v[sel] = xi, vi
        if self.x_upper is not None:
            x = np.minimum(x, self.x_upper)
        return x.reshape(tq.shape), v.reshape(tq.shape)


class PointTrack:
    """The step points of a solution as an integrator finds them: time, position, velocity,
    acceleration and mode on the interval that starts there, contact force (conventions of
    :mod:`core.dense`)."""

    __slots__ = ("t", "x", "v", "acc", "mode", "phi")

    def __init__(self) -> None:
        self.t: list[float] = []
        self.x: list[float] = []
        self.v: list[float] = []
        self.acc: list[float] = []
        self.mode: list[int] = []
        self.phi: list[float] = []

    def add(self, t: float, x: float, v: float, acc: float, mode: int, phi: float) -> None:
        self.t.append(float(t))
        self.x.append(float(x))
        self.v.append(float(v))
        self.acc.append(float(acc))
        self.mode.append(int(mode))
        self.phi.append(float(phi))


# The pieces are module-level classes, not closures, so that a dense solution pickles (a
# server solves in worker processes and sends the result back).
class _OdePiece:
    __slots__ = ("sol",)

    def __init__(self, sol) -> None:
        self.sol = sol

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        y = np.asarray(self.sol(t), dtype=float).reshape(2, -1)
        return y[0], y[1]

    def __reduce__(self):
        return _OdePiece, (self.sol,)


class _LinePiece:
    __slots__ = ("t0", "x0", "v")

    def __init__(self, t0: float, x0: float, v: float) -> None:
        self.t0, self.x0, self.v = t0, x0, v

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.x0 + self.v * (t - self.t0), np.full(t.shape, self.v)

    def __reduce__(self):
        return _LinePiece, (self.t0, self.x0, self.v)


def ode_piece(sol) -> Piece:
    """A piece from a ``scipy.integrate`` dense output (``sol(t)`` of shape ``(2, n)``)."""
    return _OdePiece(sol)


def line_piece(t0: float, x0: float, v: float) -> Piece:
    """A piece of uniform motion ``x = x0 + v (t - t0)`` (stick on the belt, rest)."""
    return _LinePiece(t0, x0, v)
