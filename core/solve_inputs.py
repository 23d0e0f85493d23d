"""The inputs every solve shares (scene, horizon, start, sampling), checked in one place.

Each method (:func:`core.simulate` and the methods it hands over to) is written as a
function of one checked :class:`SolveInputs` and its own options; :func:`solve_entry` gives
it the public signature ``(osc, stop=None, t_end=100.0, x0=0.0, v0=0.0, *, n_samples=2000,
transition_cap=10_000, t_eval=None, **options)``, so that signature and its checks are
written once.
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop
from core.result import Result
from core.scene_checks import check_oscillator, check_stop
from core.steady import pressed_on_stop
from core.validation import check_horizon, check_integer, check_size, check_start, check_times

#: Bounds of the sampling density and the transition store.
MAX_SAMPLES = 10_000_000
MAX_TRANSITION_CAP = 10_000_000


@dataclass(frozen=True)
class SolveInputs:
    """One solve's scene and sampling, checked (:func:`check_solve_inputs`).

    Attributes
    ----------
    osc, stop
        The oscillator (paper Eqs. 1-6) and the obstacle (Eq. 8, Eqs. 9-13, or ``None``).
    t_end : float
        Horizon (dimensionless time), in ``(0, MAX_T_END]``
        (:data:`core.validation.MAX_T_END`, 1e9: where a sample's time is still resolved
        to ~1e-7 of the time scale).
    x0, v0 : float
        Initial state; ``x0 <= clearance`` (rigid stop), ``x0 - clearance < D``
        (deformable stop).
    n_samples : int
        Uniform samples in ``[0, t_end]`` (the transition points are added).
    transition_cap : int
        Transitions stored at most; all are counted.
    t_eval : ndarray or None
        Sample at these non-decreasing times in ``[0, t_end]`` instead.
    """

    osc: Oscillator
    stop: RigidStop | HystereticStop | None
    t_end: float
    x0: float
    v0: float
    n_samples: int
    transition_cap: int
    t_eval: np.ndarray | None


def check_solve_inputs(
    osc, stop, t_end, x0, v0, n_samples, transition_cap, t_eval
) -> SolveInputs:
    """The inputs as a :class:`SolveInputs`, or a ``ValueError`` naming the one out of range.

    Examples
    --------
    >>> from core import Oscillator, RigidStop
    >>> check_solve_inputs(Oscillator(0.3, 0.2, 0.1), RigidStop(0.3), 10.0, 0.4, 0.0,
    ...                    2000, 100, None)
    Traceback (most recent call last):
    ...
    ValueError: x0 must not lie beyond the stop (...): x0 <= clearance = 0.3; got x0 = 0.4
    """
    check_oscillator(osc)
    check_stop(stop)
    t_end = check_horizon(t_end)
    x0 = check_size("x0", x0)
    v0 = check_size("v0", v0)
    if stop is not None:
        soft = isinstance(stop, HystereticStop)
        check_start(x0, stop.clearance, stop.limit_overlap if soft else None)
    return SolveInputs(
        osc,
        stop,
        t_end,
        x0,
        v0,
        check_integer("n_samples", n_samples, 2, MAX_SAMPLES),
        check_integer("transition_cap", transition_cap, 0, MAX_TRANSITION_CAP),
        None if t_eval is None else check_times("t_eval", t_eval, t_end, empty=False),
    )


def solve_entry(method: Callable[..., Result]) -> Callable[..., Result]:
    """``method(inputs: SolveInputs, **options)`` as a function of the public signature.

    The returned function takes ``(osc, stop=None, t_end=100.0, x0=0.0, v0=0.0, *,
    n_samples=2000, transition_cap=10_000, t_eval=None, **options)``, checks the shared
    inputs with :func:`check_solve_inputs` and passes ``options`` on (an unknown one raises
    the usual ``TypeError``). Its signature, as ``inspect`` and ``help`` show it, lists
    the shared inputs and then ``method``'s own options.
    """

    # the entry's own annotations and signature stay: they describe the shared inputs
    @functools.wraps(method, assigned=("__module__", "__name__", "__qualname__", "__doc__"),
                     updated=())
    def entry(
        osc: Oscillator,
        stop: RigidStop | HystereticStop | None = None,
        t_end: float = 100.0,
        x0: float = 0.0,
        v0: float = 0.0,
        *,
        n_samples: int = 2000,
        transition_cap: int = 10_000,
        t_eval: np.ndarray | None = None,
        **options,
    ) -> Result:
        inputs = check_solve_inputs(osc, stop, t_end, x0, v0, n_samples, transition_cap, t_eval)
        return method(inputs, **options)

    shared = list(inspect.signature(entry, follow_wrapped=False).parameters.values())[:-1]
    own = list(inspect.signature(method).parameters.values())[1:]
    entry.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
        shared + own, return_annotation=inspect.signature(method).return_annotation
    )
    return entry


@dataclass(frozen=True)
class StopFacts:
    """What a numerical method reads off the stop once: its kind, face and restitution,
    and whether the mass is pressed on it (the project's one rule, docs/physics.md).

    Attributes
    ----------
    rigid, soft : bool
        A :class:`~core.params.RigidStop`, a :class:`~core.params.HystereticStop`.
    c : float
        The clearance (the stop's face); ``inf`` without a stop.
    r : float
        The restitution of a rigid stop (Eq. 8); 1 otherwise.
    pressed : bool
        :func:`core.steady.pressed_on_stop`: the spring and friction push the mass
        against the face, so it may come to rest there.
    """

    rigid: bool
    soft: bool
    c: float
    r: float
    pressed: bool

    @classmethod
    def of(cls, osc: Oscillator, stop: RigidStop | HystereticStop | None) -> StopFacts:
        rigid = isinstance(stop, RigidStop)
        c = stop.clearance if stop is not None else math.inf
        return cls(
            rigid=rigid,
            soft=isinstance(stop, HystereticStop),
            c=c,
            r=stop.restitution if rigid else 1.0,
            pressed=stop is not None and pressed_on_stop(osc, c),
        )
