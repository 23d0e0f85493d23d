"""A run's error, measured against the exact method over the same span: the reference
solve, its options, and the distance between the two.

No accuracy preset's error figure holds on random scenes (:data:`app.solve.presets.ACCURACY`),
so a full run that integrates (:func:`integrates`) has its error measured instead
(:func:`measure_run`), and the trade table (:mod:`app.solve.trade`) measures the same way.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from app.solve.presets import UNBUDGETED_MAX_STEPS
from app.solve.process import Abandoned, Caller
from core import HystereticStop, Result, Steady, method_options

#: Tolerances of the exact method's integrated contact when it is the reference a
#: numerical method's run on a deformable stop is measured against (the trade table's too).
REFERENCE_RTOL, REFERENCE_ATOL = 1e-12, 1e-14
#: Time [s] a run's measurement leaves of its budget: the stopped child's exit and the
#: theory's closed forms after it.
MEASURE_MARGIN_S = 0.1

#: ``keep(inputs, make)``: the reference solve of ``inputs`` kept, or ``make()``'s
#: (:meth:`app.solve.cache.SolveCache.reference`).
KeepReference = Callable[[tuple, Callable[[], Result]], Result]


def integrates(method: str, stop: Any) -> bool:
    """Whether ``method`` integrates on ``stop`` (a closed form does not: its error is
    rounding): ``event``, ``switch``, and ``exact`` on a deformable stop's contact."""
    return method != "exact" or isinstance(stop, HystereticStop)


def position_error(x: np.ndarray, x_ref: np.ndarray) -> float:
    """Largest distance of positions ``x`` from the reference's at the same times, over the
    reference's amplitude about its mean (the trade table's measure too).

    >>> round(position_error(np.array([0.0, 1.1]), np.array([0.0, 1.0])), 12)
    0.2
    """
    scale = max(float(np.max(np.abs(x_ref - x_ref.mean()))), 1e-300)
    return float(np.max(np.abs(np.asarray(x) - x_ref))) / scale


def reference_options(stop: Any) -> dict[str, float]:
    """The exact method's options as a reference: the tight tolerances and no step limit
    in practice where it takes them (a deformable stop's contact; the reference is stopped
    at the page's deadline, not cut short), none for a closed form."""
    return {k: v for k, v in (("rtol", REFERENCE_RTOL), ("atol", REFERENCE_ATOL),
                              ("max_steps", UNBUDGETED_MAX_STEPS))
            if k in method_options("exact", stop)}


def reference_name(stop: Any) -> str:
    """What :func:`reference_error` measures against, in words."""
    if isinstance(stop, HystereticStop):
        return f"the exact method at rtol {REFERENCE_RTOL:g}"
    return "the closed form"


def reference_error(result: Result, ref: Result) -> float:
    """:func:`position_error` of a numerical ``result`` at its own sample times against
    ``ref``, the exact method over the same span (the closed form for no stop or a rigid
    stop, or the exact flight with the contact integrated at :data:`REFERENCE_RTOL` for a
    deformable stop; a reduced model's stated bound there is added). Past the reference's
    end (it reached the stop's limit overlap earlier: its motion ends there) the samples
    are compared with its last position: a run that ended 1e-15 later had been called
    unmeasured, one that went on is far off; ``nan`` only where the reference cannot be
    evaluated."""
    t = np.asarray(result.t, float)
    try:
        x_ref, _ = ref.evaluate(np.minimum(t, float(ref.t[-1])))
    except ValueError:
        return math.nan
    x_ref = np.asarray(x_ref, float)
    error = position_error(np.asarray(result.x, float), x_ref)
    bound = ref.info.get("reduced_error", 0.0)
    if bound > 0.0:
        error += bound / max(float(np.max(np.abs(x_ref - x_ref.mean()))), 1e-300)
    return error


def reference(simulate: Caller, osc: Any, stop: Any, t_end: float, x0: float, v0: float
              ) -> Result:
    """The exact method's solve that :func:`reference_error` measures against."""
    return simulate(osc, stop, t_end, x0, v0, n_samples=2, method="exact",
                    **reference_options(stop))


def measure_run(result: Result, osc: Any, stop: Any, x0: float, v0: float, within: float,
                simulate: Caller, kept: KeepReference | None = None
                ) -> tuple[float, Steady | None] | None:
    """A run's error (:func:`reference_error`, ``nan`` where there is no motion to
    compare) and the steady state the exact method finds over its span (``None`` with no
    error: a method can change the verdict, e.g. a mass resting on the stop's face
    at ``x_bar = a``, where the exact solution's rebounds die out over ever equal arcs:
    grazing), or ``None`` if the exact solve does not finish ``within`` seconds (the rest of
    the run's budget).

    The exact solve is not budgeted by the core; measured after the run without a deadline
    it made the answer late (0.6 s for scene 10's stop to t_end = 5000), and the page called
    a run that had finished within its budget "too slow". Called in a child process
    (``simulate.isolated``) it is stopped at the deadline; in the calling thread it cannot
    be, and runs to its end.

    ``kept(key, make)`` may keep the reference for the other methods and presets of the
    same scene (:meth:`app.solve.cache.SolveCache.reference`): ``make()`` solves it.
    """
    t = np.asarray(result.t, float)
    if not len(t) or not t[-1] > 0.0:
        return math.nan, None
    inputs = (osc, stop, float(t[-1]), x0, v0)

    def make() -> Result:
        return reference(simulate.until(within), *inputs)

    try:
        ref = kept(inputs, make) if kept is not None else make()
    except Abandoned:
        return None
    error = reference_error(result, ref)
    return error, ref.steady if math.isfinite(error) else None
