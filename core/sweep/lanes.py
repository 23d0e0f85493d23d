"""Parameter points of a sweep ("lanes"): validated arrays of the model's lengths.

A sweep varies one or two named parameters of an :class:`~core.params.Oscillator` and its
stop; every other parameter keeps the value of the base scene. Each parameter point becomes
one lane with ``a = mu_k u_s``, ``b = mu_s u_s``, belt speed ``v``, clearance ``x_bar`` and
restitution ``r`` (paper Eqs. 2-8, docs/physics.md), computed with the same floating-point
operations as :class:`~core.params.Oscillator` so that a lane and its scalar scene agree
bit for bit.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop

#: Parameters a sweep may vary, with the range each accepts (shown in error messages).
PARAMETERS = {
    "belt_speed": "[0, inf)",
    "clearance": "[x0, inf), a stop is required",
    "restitution": "[0, 1], a rigid stop is required",
    "mu_s": "[mu_k, inf)",
    "mu_k": "[0, mu_s]",
    "u_s": "(0, inf)",
}
_OSC = ("belt_speed", "mu_s", "mu_k", "u_s")
_STOP = ("clearance", "restitution")


def _allowed() -> str:
    return "; ".join(f"{name} in {rng}" for name, rng in PARAMETERS.items())


def check_parameter(name: str, stop: RigidStop | HystereticStop | None) -> str:
    """The name of a sweepable parameter, or a ``ValueError`` that lists the allowed ones."""
    if name not in PARAMETERS:
        raise ValueError(f"parameter must be one of: {_allowed()}; got {name!r}")
    if name == "clearance" and stop is None:
        raise ValueError("parameter 'clearance' needs a stop; got stop=None")
    if name == "restitution" and not isinstance(stop, RigidStop):
        raise ValueError(
            "parameter 'restitution' needs a RigidStop (a HystereticStop's restitution "
            f"follows from k_e0/k_c0, Eq. 16); got {type(stop).__name__}"
        )
    return name


def _values(name: str, values) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(
            f"values of {name} must be a non-empty 1-D sequence; got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"values of {name} must be finite numbers")
    return arr


@dataclass(frozen=True)
class Lanes:
    """One entry per parameter point: the varied parameters and the lengths of the model.

    ``mu_s, mu_k, u_s, belt_speed, clearance, restitution`` are 1-D arrays of equal length
    (``clearance = inf`` without a stop, ``restitution = 1`` unless the stop is rigid).
    """

    osc: Oscillator
    stop: RigidStop | HystereticStop | None
    mu_s: np.ndarray
    mu_k: np.ndarray
    u_s: np.ndarray
    belt_speed: np.ndarray
    clearance: np.ndarray
    restitution: np.ndarray

    def __len__(self) -> int:
        return len(self.belt_speed)

    @property
    def a(self) -> np.ndarray:
        """``mu_k u_s`` as :attr:`Oscillator.a` computes it."""
        return self.mu_k * self.u_s

    @property
    def b(self) -> np.ndarray:
        """``mu_s u_s`` as :attr:`Oscillator.b` computes it."""
        return self.mu_s * self.u_s

    def take(self, index) -> Lanes:
        """The lanes at ``index`` (a slice or an integer array)."""
        fields = {
            f.name: getattr(self, f.name)[index]
            for f in dataclasses.fields(self)
            if f.name not in ("osc", "stop")
        }
        return Lanes(self.osc, self.stop, **fields)

    def scene(self, i: int) -> tuple[Oscillator, RigidStop | HystereticStop | None]:
        """The scalar scene of lane ``i``, for :func:`core.simulate`."""
        osc = Oscillator(
            mu_s=float(self.mu_s[i]),
            mu_k=float(self.mu_k[i]),
            belt_speed=float(self.belt_speed[i]),
            u_s=float(self.u_s[i]),
        )
        stop = self.stop
        if isinstance(stop, RigidStop):
            stop = RigidStop(
                clearance=float(self.clearance[i]), restitution=float(self.restitution[i])
            )
        elif isinstance(stop, HystereticStop):
            stop = dataclasses.replace(stop, clearance=float(self.clearance[i]))
        return osc, stop


def make_lanes(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None,
    axes: dict[str, np.ndarray],
    x0: float,
) -> Lanes:
    """Lanes for every combination of ``axes`` (row-major: the last axis varies fastest).

    Every lane is checked with the ranges of :data:`PARAMETERS`; the error names the
    parameter, the allowed range and the first offending value.
    """
    if not isinstance(osc, Oscillator):
        raise TypeError(f"osc must be an Oscillator; got {type(osc).__name__}")
    if stop is not None and not isinstance(stop, (RigidStop, HystereticStop)):
        raise TypeError(
            f"stop must be None, a RigidStop or a HystereticStop; got {type(stop).__name__}"
        )
    names = list(axes)
    if len(set(names)) != len(names):
        raise ValueError(f"each parameter may be swept once; got {names}")
    arrays = [_values(check_parameter(n, stop), axes[n]) for n in names]
    grids = np.meshgrid(*arrays, indexing="ij") if len(arrays) > 1 else arrays
    swept = {n: g.ravel() for n, g in zip(names, grids, strict=True)}
    n = len(next(iter(swept.values())))

    def column(name: str, base: float) -> np.ndarray:
        return swept[name] if name in swept else np.full(n, base)

    clearance = stop.clearance if stop is not None else math.inf
    restitution = stop.restitution if isinstance(stop, RigidStop) else 1.0
    lanes = Lanes(
        osc,
        stop,
        mu_s=column("mu_s", osc.mu_s),
        mu_k=column("mu_k", osc.mu_k),
        u_s=column("u_s", osc.u_s),
        belt_speed=column("belt_speed", osc.belt_speed),
        clearance=column("clearance", clearance),
        restitution=column("restitution", restitution),
    )
    _check(lanes, x0)
    return lanes


def _check(lanes: Lanes, x0: float) -> None:
    checks = (
        ("belt_speed", lanes.belt_speed < 0.0, "[0, inf)"),
        ("u_s", lanes.u_s <= 0.0, "(0, inf)"),
        ("mu_k", lanes.mu_k < 0.0, "[0, mu_s]"),
        ("mu_k", lanes.mu_k > lanes.mu_s, "[0, mu_s]"),
        ("restitution", (lanes.restitution < 0.0) | (lanes.restitution > 1.0), "[0, 1]"),
    )
    for name, bad, rng in checks:
        if np.any(bad):
            i = int(np.argmax(bad))
            context = f" (mu_s={lanes.mu_s[i]:.6g})" if name == "mu_k" else ""
            value = getattr(lanes, name)[i]
            raise ValueError(f"{name} must lie in {rng}; got {value:.6g}{context}")
    limit = lanes.stop.limit_overlap if isinstance(lanes.stop, HystereticStop) else 0.0
    inside = (
        x0 - lanes.clearance >= limit if limit > 0.0 else x0 > lanes.clearance
    )
    if np.any(inside):
        i = int(np.argmax(inside))
        raise ValueError(
            f"clearance must lie in [x0, inf) = [{x0:.6g}, inf) so that the start is not "
            f"inside the stop; got {lanes.clearance[i]:.6g}"
        )
