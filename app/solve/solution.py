"""One solve of the page's state: the core's run (or the stop's overlap program), its error
measured where it integrates, and the theory's closed forms, as one :class:`Solution`.

:func:`compute` is the work a worker of :class:`app.solve.pool.Solver` does; it calls the
core through the :class:`app.solve.process.Caller` it is given (in a child process, or in
the worker's thread).

>>> from app.state import scene_values
>>> sol = compute(solve_key(scene_values("5b")), budget=2.0)
>>> sol.result.steady.kind.value, sol.regime.case
('periodic', 'b')
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from app.sampling import samples_for
from app.solve.measure import MEASURE_MARGIN_S, KeepReference, integrates, measure_run
from app.solve.presets import (
    ACCURACY,
    PREVIEW_ACCURACY,
    PREVIEW_SAMPLES,
    UNBUDGETED_MAX_STEPS,
    choose_method,
    preset_options,
    step_limit,
)
from app.solve.process import Caller
from app.solve.theory import Theory, theory_for
from app.state import SOLVE_PARAMS, core_inputs
from core import (
    HystereticStop,
    OverlapProgram,
    Result,
    Status,
    Steady,
    effective_restitutions,
    method_options,
    overlap_program,
)
from core import simulate as core_simulate

#: How a solve that stopped early says so: the page offers to retry it with more time.
CUT_SHORT = (Status.TIME_BUDGET, Status.STEP_LIMIT)
#: The core called in the calling thread (scripts, tests).
IN_THREAD = Caller(core_simulate)


@dataclass(frozen=True)
class Solution:
    """What one solve gives the view.

    Attributes
    ----------
    values : Mapping
        The state values solved for.
    osc, stop, x0, v0, t_end
        The core inputs built from them.
    result : Result or None
        ``None`` for the overlap program of Fig. 2b.
    program : OverlapProgram or None
        The stop driven by the overlap program of paper Fig. 2b
        (:func:`core.overlap_program`), ``None`` for a run.
    theory : Theory or None
        ``None`` when the theory does not apply (it raised).
    method : str
        The core method used.
    solve_time : float
        Wall time of the core call [s] (of the original call when served from the cache).
    error_estimate : float
        Relative error of the run (:func:`app.solve.measure.reference_error`), measured
        for a full solve that integrates (:func:`app.solve.measure.integrates`); ``nan``
        where it was not measured (a preview, a closed form, a measurement that did not
        fit in the budget): no preset's figure holds on random scenes
        (:data:`app.solve.presets.ACCURACY`).
    error_measured : bool
        Whether ``error_estimate`` was measured for this run.
    reference_steady : Steady or None
        The steady state the exact method finds for the same run (the solve the error was
        measured against, :func:`app.solve.measure.measure_run`); ``None`` where none was measured.
    measure_skipped : bool
        A full run that integrates whose error was not measured: the exact solve it is
        measured against did not fit in the rest of the run's budget
        (:func:`app.solve.measure.measure_run`).
    restitution_measured : ndarray
        Rebound / approach speed of each deformable contact
        (:func:`core.effective_restitutions`; empty otherwise).
    preview : bool
    budget : float
        The wall-time budget [s] the solve had (a numerical method stops at it).
    """

    values: Mapping[str, Any]
    osc: Any
    stop: Any
    x0: float
    v0: float
    t_end: float
    result: Result | None
    program: OverlapProgram | None
    theory: Theory | None
    method: str
    solve_time: float
    error_estimate: float
    restitution_measured: np.ndarray = field(default_factory=lambda: np.zeros(0))
    error_measured: bool = False
    reference_steady: Steady | None = None
    measure_skipped: bool = False
    preview: bool = False
    budget: float = math.nan

    @property
    def regime(self):
        """The theory's regime, or ``None``."""
        return self.theory.regime if self.theory is not None else None


def cut_short(solution: Solution) -> bool:
    """Whether the core stopped ``solution`` before its horizon for want of time or steps."""
    return solution.result is not None and solution.result.status in CUT_SHORT


def solve_key(values: Mapping[str, Any]) -> tuple:
    """What a solve of ``values`` depends on, as a hashable key: its
    :data:`app.state.SOLVE_PARAMS` in order (:func:`compute` takes it)."""
    return tuple((name, values[name]) for name in SOLVE_PARAMS)


def compute(key: tuple, preview: bool = False, *, budget: float,
            simulate: Caller = IN_THREAD,
            kept: KeepReference | None = None) -> Solution:
    """Solve the state ``key`` (:func:`solve_key`) within ``budget`` seconds.

    Parameters
    ----------
    key : tuple
    preview : bool
        A cheap solve while a slider is dragged: few samples, draft accuracy, no theory,
        no measurement.
    budget : float
        Wall-time budget [s]: a numerical method stops at it (``Status.TIME_BUDGET``),
        with a step limit in proportion (:func:`app.solve.presets.step_limit`), and the
        run's measurement gets what is left of it.
    simulate : Caller
        How :func:`core.simulate` is called (in a child process or here, and what stops it).
    kept : callable, optional
        Keeps the reference solves of the measurements
        (:meth:`app.solve.cache.SolveCache.reference`).
    """
    values = MappingProxyType(dict(key))
    osc, stop, x0, v0, t_end = core_inputs(values)
    method = choose_method(values["method"], values["stop_type"])
    start = time.perf_counter()
    if values.get("program") and isinstance(stop, HystereticStop):
        program, result = overlap_program(stop), None
    else:
        program = None
        result = simulate(osc, stop, t_end, x0, v0, method=method,
                          **run_options(values, method, stop, osc, preview, budget))
    solve_time = time.perf_counter() - start
    # No preset's error holds on random scenes (ACCURACY): a full run that integrates has
    # its error measured, within what is left of its budget.
    measures = result is not None and not preview and integrates(method, stop)
    run = (measure_run(result, osc, stop, x0, v0, budget - solve_time - MEASURE_MARGIN_S,
                       simulate, kept) if measures else None)
    measured = run is not None and math.isfinite(run[0])
    return Solution(
        values=values, osc=osc, stop=stop, x0=x0, v0=v0, t_end=t_end,
        result=result, program=program,
        theory=None if preview else theory_for(osc, stop, x0, v0),
        method=method, solve_time=solve_time,
        error_estimate=run[0] if measured else math.nan, error_measured=measured,
        reference_steady=run[1] if measured else None,
        measure_skipped=measures and run is None,
        restitution_measured=restitutions(result),
        preview=preview, budget=budget,
    )


def restitutions(result: Result | None) -> np.ndarray:
    """Rebound over approach speed of each finished deformable contact
    (:func:`core.effective_restitutions`; docs/contact-law.md, "Restitution against impact
    speed"); empty without a run (the overlap program)."""
    return np.zeros(0) if result is None else effective_restitutions(result)


def run_options(values: Mapping[str, Any], method: str, stop: Any, osc: Any,
                preview: bool, budget: float) -> dict[str, Any]:
    """The options of the core's run of ``values``: its samples, the preset's tolerances
    for the options ``method`` uses (the core refuses others), and its work limits."""
    accuracy = ACCURACY[PREVIEW_ACCURACY if preview else values["accuracy"]]
    n_samples = PREVIEW_SAMPLES if preview else accuracy["n_samples"]
    if not preview and integrates(method, stop):
        # Drawn from its samples (app/sampling.py): dense enough for any horizon (a
        # preview stays cheap).
        n_samples = samples_for(values["t_end"], n_samples)
    used = method_options(method, stop)
    options = {"n_samples": n_samples, **preset_options(accuracy, used, osc)}
    # The numerical methods stop at their budget themselves; the exact method on a
    # deformable stop runs to its end (the page waits for it in the background).
    if "time_budget" in used:
        options["time_budget"] = budget
        if "max_steps" in used:
            options["max_steps"] = step_limit(budget)
    elif "max_steps" in used:
        options["max_steps"] = UNBUDGETED_MAX_STEPS
    return options
