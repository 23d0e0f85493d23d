"""Result values returned by :func:`core.simulate`: transitions, steady state, samples.

All are frozen; arrays are read-only.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import NamedTuple, Protocol

import numpy as np


class Mode(enum.IntEnum):
    """Mode of motion at a sample (paper §2.5)."""

    SLIP = 0
    STICK = 1
    CONTACT = 2


class TransitionKind(str, enum.Enum):
    """Kinds of transition between modes (paper §2.5; docs/physics.md, "Transitions")."""

    SLIP_STICK = "slip->stick"
    STICK_SLIP = "stick->slip"
    SIGN_CHANGE = "sign_change"  # instantaneous adhesion: relative velocity changes sign
    IMPACT = "impact"  # slip->contact->slip with a rigid stop
    STICK_IMPACT = "stick->impact"
    ACCUMULATION = "accumulation"  # Zeno limit point of infinitely many impacts
    REST = "rest"  # mass pressed on the stop for good
    CONTACT = "contact"  # start of a deformable contact
    SEPARATION = "separation"  # end of a deformable contact
    REVERSAL = "reversal"  # overlap rate changes sign inside a deformable contact
    FAILURE = "failure"  # contact force exceeded the stop's strength
    REDUCED = "reduced"  # from here a reduced model advances the motion (stated error in info)

    def __str__(self) -> str:
        return self.value


class Transition(NamedTuple):
    """State at one transition: time ``t``, position ``x``, velocity ``v`` (before it).

    ``v_after`` is the velocity just after (differs from ``v`` only at an impact). A named
    tuple: immutable and cheap to build (long responses store thousands).
    """

    kind: TransitionKind
    t: float
    x: float
    v: float
    v_after: float

    def __str__(self) -> str:
        return f"{self.kind.value} at t={self.t:.6g} (x={self.x:.6g}, x'={self.v:.6g})"


class SteadyKind(str, enum.Enum):
    """What the response settles to (paper Eq. 20; docs/physics.md, "Steady states")."""

    PERIODIC = "periodic"  # fixed point of P^j, reached in finite time
    GRAZING = "grazing"  # impacts with speeds falling as r^h towards a grazing circle
    REST = "rest"  # mass pressed on the stop for good
    EQUILIBRIUM = "equilibrium"  # mass at rest away from the stop
    PURE_SLIP = "pure_slip"  # a slip circle that never sticks nor impacts
    CONTACT_TRAIN = "contact_train"  # contacts of shrinking amplitude (deformable stop)
    NONE = "none"  # nothing found within the horizon
    # (last: a sweep stores the kinds by their place here)
    OSCILLATION = "oscillation"  # loops on a deformable stop swinging at t_end, shrinking

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class Steady:
    """The steady state found from the transition sequence.

    Attributes
    ----------
    kind : SteadyKind
    period : float
        Period (dimensionless time); ``nan`` when not periodic.
    transitions_per_period : int
    sequence : tuple of str
        Kinds of the transitions in one period, in order.
    x_max : float
        Maximum displacement on the steady motion.
    impact_speed : float
        Approach speed at the steady impact (0 for rest, nan if none). Grazing: 0 for a
        rigid stop; on a deformable stop whose law turns slow contacts elastic, the speed
        the impacts tend to (the elastic limit, docs/contact-law.md), whose train of elastic
        contacts also gives ``period`` and ``x_max``.
    t_reached : float
        Time from which the steady state holds (or the accumulation time); ``nan`` if the
        state is only approached asymptotically.
    decay_rate : float
        Contact train: measured ratio of successive contacts' approach speeds (``< 1``
        shrinking); oscillation: measured ratio of successive cycles' amplitudes at the end
        of the run; ``nan`` otherwise.
    amplitude, velocity_amplitude : float
        Oscillation on the stop: half the range of ``x`` and of ``x'`` over its last cycle
        before ``t_end`` (``period``); ``nan`` otherwise.
    rest_amplitude, rest_velocity : float
        Oscillation on the stop: the swings of ``x`` and ``x'`` the rule for rest lets rest
        (``core.deformable.rest.rest_swing``), one of which it exceeds; ``nan`` otherwise.
    """

    kind: SteadyKind
    period: float = math.nan
    transitions_per_period: int = 0
    sequence: tuple[str, ...] = ()
    x_max: float = math.nan
    impact_speed: float = math.nan
    t_reached: float = math.nan
    decay_rate: float = math.nan
    amplitude: float = math.nan
    velocity_amplitude: float = math.nan
    rest_amplitude: float = math.nan
    rest_velocity: float = math.nan

    @property
    def halving_time(self) -> float:
        """Oscillation: the time its amplitude takes to halve at the rate measured at the end
        of the run (``inf`` if it does not shrink there); ``nan`` otherwise."""
        if self.kind is not SteadyKind.OSCILLATION:
            return math.nan
        if not 0.0 < self.decay_rate < 1.0:
            return math.inf
        return self.period * math.log(2.0) / -math.log(self.decay_rate)

    def at_rest_within(self, rest_amplitude: float, rest_velocity: float) -> bool:
        """Rest, or an oscillation on the stop whose swing at ``t_end`` is within these
        swings of the position and velocity: at rest by a looser rule for rest than the one
        it was labelled by (a solve at another ``rtol``)."""
        if self.kind is SteadyKind.REST:
            return True
        return (self.kind is SteadyKind.OSCILLATION and self.amplitude <= rest_amplitude
                and self.velocity_amplitude <= rest_velocity)

    def describe(self, time_scale: float = 1.0, time_unit: str = "",
                 velocity_scale: float = 1.0, velocity_unit: str = "",
                 length_unit: str = "", length_scale: float = 1.0) -> str:
        """One line in words, for the readout; times are shown multiplied by
        ``time_scale`` and followed by ``time_unit`` (e.g. ``1/omega`` and ``" s"``),
        speeds by ``velocity_scale`` and ``velocity_unit``, lengths by ``length_scale``
        and ``length_unit``."""
        if self.kind is SteadyKind.PERIODIC:
            seq = " -> ".join(self.sequence)
            return (
                f"periodic, period {self.period * time_scale:.6g}{time_unit}, "
                f"{self.transitions_per_period} "
                f"transition{'' if self.transitions_per_period == 1 else 's'} per period: {seq}"
            )
        if self.kind is SteadyKind.GRAZING:
            if self.impact_speed > 0.0:
                limit = (f", period {self.period * time_scale:.6g}{time_unit}"
                         if math.isfinite(self.period) else "")
                return (f"grazing approached: impact speeds fall towards "
                        f"{self.impact_speed * velocity_scale:.4g}{velocity_unit}, below which "
                        "the stop's law is elastic (the limit: elastic contacts at that speed"
                        f"{limit}, on a slip circle that just reaches the stop)")
            if math.isfinite(self.t_reached):  # on the touching circle (a plastic impact)
                return (f"grazing: on the slip circle that touches the stop at zero speed, "
                        f"period {self.period * time_scale:.6g}{time_unit} (from t = "
                        f"{self.t_reached * time_scale:.6g}{time_unit})")
            return "grazing: impact speeds fall as r^h towards a slip circle touching the stop"
        if self.kind is SteadyKind.REST:
            if math.isnan(self.t_reached):
                return "rest at the stop, approached asymptotically"
            return f"rest at the stop (from t = {self.t_reached * time_scale:.6g}{time_unit})"
        if self.kind is SteadyKind.EQUILIBRIUM:
            return "equilibrium: the mass stays at rest"
        if self.kind is SteadyKind.CONTACT_TRAIN:
            return (
                "contacts of shrinking amplitude on the stop, approach speed x "
                f"{self.decay_rate:.6g} per contact"
            )
        if self.kind is SteadyKind.OSCILLATION:
            return self._describe_oscillation(time_scale, time_unit, velocity_scale,
                                              velocity_unit, length_unit, length_scale)
        if self.kind is SteadyKind.PURE_SLIP:
            return f"pure slip on a circle, period {self.period * time_scale:.6g}{time_unit}"
        return "no steady state found within the horizon"

    def _describe_oscillation(self, time_scale: float, time_unit: str,
                              velocity_scale: float, velocity_unit: str,
                              length_unit: str, length_scale: float) -> str:
        half = self.halving_time
        decay = (f"shrinking by {100.0 * (1.0 - self.decay_rate):.2g} % per cycle (halving "
                 f"in ~{half * time_scale:.3g}{time_unit} at that rate)"
                 if math.isfinite(half) else "not shrinking at the end of the run")
        return (f"oscillation on the stop, not at rest at t_end: amplitude "
                f"{self.amplitude * length_scale:.3g}{length_unit} in x and "
                f"{self.velocity_amplitude * velocity_scale:.3g}{velocity_unit} in x' "
                f"(rest: below {self.rest_amplitude * length_scale:.3g}{length_unit} and "
                f"{self.rest_velocity * velocity_scale:.3g}{velocity_unit}), period "
                f"{self.period * time_scale:.4g}{time_unit}, {decay}")


class Status(str, enum.Enum):
    """How a solve ended; each member carries its user-facing message."""

    SUCCESS = "success"
    STOP_FAILED = "stop_failed"
    LIMIT_OVERLAP = "limit_overlap"
    INTEGRATION_FAILED = "integration_failed"
    EVENT_LIMIT = "event_limit"
    STEP_LIMIT = "step_limit"
    TIME_BUDGET = "time_budget"

    @property
    def message(self) -> str:
        return _STATUS_MESSAGES[self]


_STATUS_MESSAGES = {
    Status.SUCCESS: "The horizon was reached.",
    Status.STOP_FAILED: "The contact force exceeded the stop's strength: the stop failed.",
    Status.LIMIT_OVERLAP: (
        "The overlap reached the stop's limit overlap: the stop would have to be "
        "penetrated beyond its asymptote. Raise limit_overlap or k_c0."
    ),
    Status.INTEGRATION_FAILED: "The contact integration failed (step size too small).",
    Status.EVENT_LIMIT: (
        "The solver stopped at its limit on the number of events before the horizon; "
        "the result covers the time up to that point."
    ),
    Status.STEP_LIMIT: (
        "The solver stopped at its limit on the number of integration steps before the "
        "horizon; the result covers the time up to that point."
    ),
    Status.TIME_BUDGET: (
        "The solver stopped when its time budget ran out before the horizon; the result "
        "covers the time up to that point. Give it more time or choose a faster method."
    ),
}

#: Keys of :attr:`Result.stats`, the same for every method (all integer counts):
#: ``segments`` closed-form pieces or integrator calls, ``steps`` accepted numerical steps,
#: ``rejected`` rejected steps, ``rhs_evals`` right-hand-side evaluations, ``events``
#: transitions located (stored or not).
STATS_KEYS = ("segments", "steps", "rejected", "rhs_evals", "events")


def make_stats(**counts: int) -> dict[str, int]:
    """The stats dictionary of a :class:`Result`: every key of :data:`STATS_KEYS`, as ``int``.

    >>> make_stats(steps=3)
    {'segments': 0, 'steps': 3, 'rejected': 0, 'rhs_evals': 0, 'events': 0}
    """
    unknown = set(counts) - set(STATS_KEYS)
    if unknown:
        raise ValueError(f"unknown stats keys {sorted(unknown)}; allowed: {STATS_KEYS}")
    return {key: int(counts.get(key, 0)) for key in STATS_KEYS}


class DenseSolution(Protocol):
    """What a method attaches to its :class:`Result` so that it can be evaluated anywhere."""

    def evaluate(self, t: np.ndarray, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity at times ``t``; at a jump (an impact) ``side=-1`` gives the
        left limit (before) and ``side=+1`` the right limit (after)."""
        ...


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class Energy:
    """Cumulative energy terms at the samples, per unit ``k`` (a length squared).

    ``mechanical = (x^2 + x'^2)/2``; ``friction_work`` is the work done by friction on the
    mass; ``belt_input`` the work done by the belt; ``stop_loss`` the energy taken by the
    stop (impacts or hysteresis). Balance: ``mechanical - mechanical[0] = friction_work -
    stop_loss`` (minus the elastic energy stored in a deformable stop).
    """

    mechanical: np.ndarray
    friction_work: np.ndarray
    belt_input: np.ndarray
    stop_loss: np.ndarray
    stop_stored: np.ndarray


def _check_finite_samples(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> None:
    """A result that reports success has finite samples: an overflow in a solve is an
    error, never a success (a pass over the samples, far below the cost of the solve)."""
    for name, values in (("t", t), ("x", x), ("v", v)):
        if not np.all(np.isfinite(values)):
            bad = int(np.flatnonzero(~np.isfinite(values))[0])
            raise FloatingPointError(
                f"the solve overflowed: {name}[{bad}] = {float(values[bad])} is not finite at "
                f"t = {float(t[bad]):.6g}; the inputs lie beyond what the method resolves"
            )


@dataclass(frozen=True)
class Result:
    """Response of the oscillator over ``[0, t_end]``.

    Attributes
    ----------
    t, x, v : ndarray
        Dense samples on the exact solution (plus the exact transition points).
    mode : ndarray of int8
        :class:`Mode` at each sample.
    transitions : tuple of Transition
        The first ``transition_cap`` transitions, and past them the switches into a reduced
        model, rest and a failed stop (``core.transitions.LANDMARKS``); all are counted in
        ``transition_counts``.
    x_max : float
        Exact maximum of ``x`` over ``[0, t_end]``.
    steady : Steady
    status : Status
    contact_force, overlap : ndarray
        ``phi/k`` (a length) and ``x - clearance`` at the samples (deformable stop; zeros
        for others).
    impulses : ndarray, shape (n, 2)
        Rigid stop: time and impulse per unit ``m*omega`` of each stored impact.
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    mode: np.ndarray
    transitions: tuple[Transition, ...]
    transition_counts: dict[str, int]
    n_transitions: int
    x_max: float
    steady: Steady
    status: Status
    energy: Energy
    contact_force: np.ndarray
    overlap: np.ndarray
    impulses: np.ndarray
    method: str = "exact"
    stats: dict[str, float] = field(default_factory=dict)
    #: Method-specific diagnostics that are not counts (e.g. the solver's name, a measured
    #: restitution); the counts live in ``stats``.
    info: dict[str, object] = field(default_factory=dict)
    #: The solution as a function of time (see :meth:`evaluate`); ``None`` if the method
    #: offers only its samples.
    dense: DenseSolution | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("t", "x", "v", "mode", "contact_force", "overlap", "impulses"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        if self.status is Status.SUCCESS:
            _check_finite_samples(self.t, self.x, self.v)

    def evaluate(self, t, side: int = -1) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity at any times in ``[0, t_end]``: exact on closed-form
        segments, the dense interpolant on integrated ones. ``side=-1`` (default) gives the
        left limit at an impact (the velocity before it), ``side=+1`` the right limit."""
        if side not in (-1, 1):
            raise ValueError(f"side must be -1 (left limit) or +1 (right limit); got {side!r}")
        if self.dense is None:
            raise NotImplementedError(f"method {self.method!r} offers no dense solution")
        t = np.asarray(t, dtype=float)
        return self.dense.evaluate(t, side)

    @property
    def success(self) -> bool:
        """True when the solve reached the horizon (``status`` is ``SUCCESS``)."""
        return self.status is Status.SUCCESS

    @property
    def message(self) -> str:
        """How the solve ended, in words; a solve stopped before its horizon says at what
        time it stopped (its samples end there)."""
        if self.status is Status.SUCCESS or not len(self.t):
            return self.status.message
        return f"Stopped at t = {float(self.t[-1]):.6g}. {self.status.message}"

    @property
    def truncated(self) -> bool:
        """True when more transitions happened than are stored."""
        return self.n_transitions > len(self.transitions)

    def sequence(self, last: int | None = None) -> str:
        """Transition kinds joined by arrows, e.g. ``'stick->slip -> impact'``."""
        kinds = [tr.kind.value for tr in self.transitions]
        if last is not None:
            kinds = kinds[-last:]
        return " -> ".join(kinds)
