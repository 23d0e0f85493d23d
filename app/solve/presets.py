"""What a solve of the page is given: its accuracy preset's settings, its wall-time budget
and step limit, and the core method each choice of the page runs.

:data:`ACCURACY` is the one place where the accuracy presets of the page map to method
settings; update it from measurements (``benchmarks/``) without touching anything else.

>>> choose_method("auto", "rigid"), retry_budget(2.0)
('exact', 20.0)
"""

from __future__ import annotations

import importlib.util
import logging
import math
import os
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from core import MAX_STEPS, eta_bounds, method_options

log = logging.getLogger(__name__)

#: Accuracy presets -> method settings. ``n_samples`` is the display resolution of the full
#: solve.
#:
#: No preset has an error figure the page quotes for a run it has not measured: none of
#: those it quoted holds on random scenes (benchmarks/accuracy_claims.py, 1,200 random
#: scenes per family at t = 100; benchmarks/results/accuracy_claims.md). At standard,
#: ``event`` exceeded its 1e-6 on 130 of 1,200 rigid stops (up to 1.2e-3), ``switch`` its
#: 3e-3 on 654 (up to 1.9; 259 beyond the rule max(3e-3, 20 eta/v)), and the exact
#: method's integrated contact on a deformable stop its 1e-6 on 35 (up to 2.4e-2, where a
#: contact's end moves the transitions after it). A full solve that integrates
#: (:func:`app.solve.measure.integrates`) has its error measured instead
#: (:func:`app.solve.measure.measure_run`); a preview, or a run whose measurement did not
#: fit in its budget, says "not measured".
#:
#: ``error`` holds the figures validated by that benchmark (0 failures on >= 1,000 random
#: scenes), by method (``contact`` for the exact method's integrated contact); none now.
#: tests/app/test_accuracy_figures.py holds it equal to the benchmark's results.
ACCURACY: Mapping[str, Mapping[str, Any]] = MappingProxyType({
    "draft": MappingProxyType({
        "rtol": 1e-5, "atol": 1e-8, "eta": 1e-3, "n_samples": 800,
        "error": MappingProxyType({}),
    }),
    "standard": MappingProxyType({
        "rtol": 1e-8, "atol": 1e-11, "eta": 1e-4, "n_samples": 1600,
        "error": MappingProxyType({}),
    }),
    "precise": MappingProxyType({
        "rtol": 1e-10, "atol": 1e-13, "eta": 1e-6, "n_samples": 3000,
        "error": MappingProxyType({}),
    }),
})
#: Samples of a preview solve while a slider is dragged (one per few screen pixels).
PREVIEW_SAMPLES = 400
#: Accuracy preset of the previews.
PREVIEW_ACCURACY = "draft"
#: Wall-time budget [s] of a full solve, whatever its method: past it the page says so and
#: keeps its picture. The numerical methods can take minutes on a Zeno scene (scene 7c with
#: ``event``) and the deformable stop's integrated contact seconds on a stiff, sharp stop;
#: the closed form for a rigid stop needs milliseconds. ``FIE_SOLVE_BUDGET_S`` in the
#: server's environment sets another (a slow classroom machine may want more).
SOLVE_BUDGET_S = 2.0
#: Step limit of the numerical methods in a solve of :data:`SOLVE_BUDGET_S`: the page stops
#: them by time, so far above what fits in the budget (the core's own defaults are lower:
#: they bound a call that gives no budget).
SOLVE_MAX_STEPS = 2_000_000
#: Step limit of the exact method on a deformable stop, which does not stop at the page's
#: budget (the page waits for it in the background): the largest the core takes, so that
#: it runs to its end as it did before it had a default limit (and a cut-short result,
#: whose retry would join the same solve, is not offered).
UNBUDGETED_MAX_STEPS = MAX_STEPS
#: A retry of a solve that ran out of time or steps gets this many times the budget (and
#: the step limit) of the attempt before, up to :data:`MAX_SOLVE_BUDGET_S`.
RETRY_FACTOR = 10.0
#: Largest budget [s] a retry may ask for: a class waits no longer than this.
MAX_SOLVE_BUDGET_S = 60.0


def _budget_from_environment(default: float) -> float:
    """``FIE_SOLVE_BUDGET_S`` if it is a number of seconds in (0, MAX_SOLVE_BUDGET_S], else
    ``default`` (a bad value is logged with the allowed range)."""
    raw = os.environ.get("FIE_SOLVE_BUDGET_S")
    if raw is None:
        return default
    try:
        value = float(raw)
    except ValueError:
        value = math.nan
    if not 0.0 < value <= MAX_SOLVE_BUDGET_S:
        log.warning("FIE_SOLVE_BUDGET_S must be a number of seconds in (0, %g]; got %r: "
                    "using %g s", MAX_SOLVE_BUDGET_S, raw, default)
        return default
    return value


SOLVE_BUDGET_S = _budget_from_environment(SOLVE_BUDGET_S)
#: Budget [s] of a preview solve (a late preview is just skipped).
PREVIEW_BUDGET_S = 0.25


def retry_budget(budget: float) -> float:
    """The budget [s] of a retry after a solve overran ``budget``.

    >>> retry_budget(2.0), retry_budget(20.0), retry_budget(60.0)
    (20.0, 60.0, 60.0)
    """
    return min(budget * RETRY_FACTOR, MAX_SOLVE_BUDGET_S)


def choose_method(method: str, stop_type: str) -> str:
    """The core method for the page's choice.

    ``auto`` is ``exact`` (closed form) for no stop or a rigid stop. For a hysteretic stop
    it is ``exact`` (exact flight, integrated contact) where the core provides it, else the
    paper's switch model.
    """
    if method != "auto":
        return method
    if stop_type == "hysteretic" and importlib.util.find_spec("core.deformable.solver") is None:
        return "switch"
    return "exact"


def budgeted(values: Mapping[str, Any]) -> bool:
    """Whether the core method of ``values`` stops itself at a time budget (then a larger
    budget is another computation; else it only waits longer for the same one)."""
    method = choose_method(values["method"], values["stop_type"])
    return "time_budget" in method_options(method, None)


def preset_options(accuracy: Mapping[str, Any], used: tuple[str, ...], osc: Any
                   ) -> dict[str, Any]:
    """A preset's values (:data:`ACCURACY`) of the options a method ``used``; the switch
    model's band within those the core takes on this belt (:func:`core.eta_bounds`: a slow
    belt gets a narrower band than the preset's, a fast one a wider)."""
    options = {k: accuracy[k] for k in used if k in accuracy}
    if "eta" in options:
        low, high = eta_bounds(osc, accuracy["rtol"])
        options["eta"] = min(max(options["eta"], low), high)
    return options


def step_limit(budget: float) -> int:
    """Step limit of a numerical solve of ``budget`` seconds: :data:`SOLVE_MAX_STEPS`, in
    proportion past :data:`SOLVE_BUDGET_S` (a retry with more time may take as many more
    steps)."""
    return int(SOLVE_MAX_STEPS * max(1.0, budget / SOLVE_BUDGET_S))
