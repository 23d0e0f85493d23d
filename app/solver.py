"""The app's only door to the core: state values in, a :class:`Solution` out, cached.

:data:`ACCURACY` is the one place where the accuracy presets of the page map to method
settings; update it from measurements (``benchmarks/``) without touching anything else.

Examples
--------
>>> from app.state import scene_values
>>> sol = solve(scene_values("5b"))
>>> sol.result.steady.kind.value, sol.regime.case
('periodic', 'b')
"""

from __future__ import annotations

import functools
import importlib.util
import logging
import math
import os
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from concurrent.futures import TimeoutError as FutureTimeout
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
import panel as pn
from panel.io.state import set_curdoc

from app import solve_process
from app.sampling import samples_for
from app.session_loop import from_any_thread
from app.state import SOLVE_PARAMS, core_inputs
from core import (
    FIRST_LOADING,
    MAX_STEPS,
    HystereticStop,
    Mode,
    Result,
    RigidStop,
    Status,
    Steady,
    contact_force,
    effective_restitutions,
    eta_bounds,
    method_options,
    reverse,
    simulate,
    theory,
)

log = logging.getLogger(__name__)

#: How a solve that stopped early says so: the page offers to retry it with more time.
CUT_SHORT = (Status.TIME_BUDGET, Status.STEP_LIMIT)

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
#: (:func:`integrates`) has its error measured instead (:func:`measure_run`); a preview,
#: or a run whose measurement did not fit in its budget, says "not measured".
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
#: Solves that integrate (a deformable stop's contact, ``event``, ``switch``) and may run at
#: once, per server process, each in a worker process (:mod:`app.solve_process`):
#: they stop themselves at their budget (the core's ``time_budget``), and a solve every
#: requester has given up (a newer slider move) is stopped at once.
SOLVE_WORKERS = 2
#: Integrating solves that may wait for a worker; past that further ones are refused at
#: once (the server is saturated) instead of queueing behind them.
SOLVE_QUEUE = 4
#: Workers of the closed-form solves (rigid stop, no stop: below ~2 ms each), in a pool of
#: their own so that they never wait behind an integrating solve.
CLOSED_FORM_WORKERS = 2
#: A solve still running after this long [s] marks the plots it will replace as busy.
BUSY_DELAY_S = 0.15
#: Cached solves kept (shared by all sessions of the server process).
CACHE_ITEMS = 256
#: Grid of the regime map: cells along belt speed and clearance.
MAP_CELLS = 128
#: Regime maps kept, least recently used first out (shared by the server's sessions).
MAP_CACHE_ITEMS = 32
_MAP_CACHE: OrderedDict[tuple, dict[str, Any]] = OrderedDict()
_MAP_LOCK = threading.Lock()
#: Periods of the overlap program of paper Fig. 2b, and samples per period.
PROGRAM_PERIODS = 4
PROGRAM_SAMPLES_PER_PERIOD = 200
#: Peak overlap of the program's first cycle, as a fraction of the limit overlap ``D``.
PROGRAM_PEAK = 0.75
#: Amplitude left at the end of the program (fraction of the first).
PROGRAM_DECAY = 0.25


@dataclass(frozen=True)
class Program:
    """The stop driven by a prescribed overlap (paper Fig. 2b): ``s``, overlap, force."""

    s: np.ndarray
    overlap: np.ndarray
    force: np.ndarray


@dataclass(frozen=True)
class Theory:
    """Closed-form references for the current parameters (:mod:`core.theory`)."""

    regime: Any
    critical_speed: float
    fast: bool
    gamma0_radius: float
    limit_cycle: Any
    x_max_impactless: float
    x_star: float
    points: Mapping[str, tuple[float, float]]
    restitution: float  # r of the stop, or r_eq = sqrt(k_e0/k_c0) (Eq. 16)


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
    program : Program or None
    theory : Theory or None
        ``None`` when the theory does not apply (it raised).
    method : str
        The core method used.
    solve_time : float
        Wall time of the core call [s] (of the original call when served from the cache).
    error_estimate : float
        Relative error of the run (:func:`reference_error`), measured for a full solve
        that integrates (:func:`integrates`); ``nan`` where it was not measured (a preview,
        a closed form, a measurement that did not fit in the budget): no preset's figure
        holds on random scenes (:data:`ACCURACY`).
    error_measured : bool
        Whether ``error_estimate`` was measured for this run.
    reference_steady : Steady or None
        The steady state the exact method finds for the same run (the solve the error was
        measured against, :func:`measure_run`); ``None`` where none was measured.
    measure_skipped : bool
        A full run that integrates whose error was not measured: the exact solve it is
        measured against did not fit in the rest of the run's budget (:func:`measure_run`).
    restitution_measured : ndarray
        Rebound / approach speed of each deformable contact (empty otherwise).
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
    program: Program | None
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


class SolveTooSlow(RuntimeError):
    """A solve did not finish within its budget, or the server's workers are saturated (its
    message says what to do).

    Attributes
    ----------
    budget : float or None
        The budget [s] the solve overran; ``None`` when the workers were saturated (more
        time would not help).
    """

    def __init__(self, message: str, budget: float | None = None) -> None:
        super().__init__(message)
        self.budget = budget


def retry_budget(budget: float) -> float:
    """The budget [s] of a retry after a solve overran ``budget``.

    >>> retry_budget(2.0), retry_budget(20.0), retry_budget(60.0)
    (20.0, 60.0, 60.0)
    """
    return min(budget * RETRY_FACTOR, MAX_SOLVE_BUDGET_S)


def cut_short(solution: Solution) -> bool:
    """Whether the core stopped ``solution`` before its horizon for want of time or steps."""
    return solution.result is not None and solution.result.status in CUT_SHORT


def _key(values: Mapping[str, Any]) -> tuple:
    return tuple((name, values[name]) for name in SOLVE_PARAMS)


def _budget(preview: bool, budget: float | None) -> float:
    if budget is not None:
        return budget
    return PREVIEW_BUDGET_S if preview else SOLVE_BUDGET_S


def _too_slow(values: Mapping[str, Any], budget: float) -> SolveTooSlow:
    return SolveTooSlow(
        f"the {values['method']} method did not finish within {budget:g} s (it goes on in "
        "the background; asking again once it is done is instant). A shorter horizon "
        "t_end, a looser accuracy or, for a rigid stop, the 'auto' method (closed form) "
        "answers at once.", budget)


def _budgeted(values: Mapping[str, Any]) -> bool:
    """Whether the core method of ``values`` stops itself at a time budget (then a larger
    budget is another computation; else it only waits longer for the same one)."""
    method = choose_method(values["method"], values["stop_type"])
    return "time_budget" in method_options(method, None)


def solve(values: Mapping[str, Any], *, preview: bool = False,
          budget: float | None = None) -> Solution:
    """Solve the state ``values`` in the worker pool and wait for it (for scripts and tests;
    the page uses :class:`SolveRunner`, which does not wait).

    Parameters
    ----------
    values : Mapping
        State values (:data:`app.state.SOLVE_PARAMS`).
    preview : bool
        A cheap solve while a slider is dragged: few samples, draft accuracy, no theory.
    budget : float, optional
        Wall-time budget [s] (default :data:`SOLVE_BUDGET_S`, or :data:`PREVIEW_BUDGET_S`
        for a preview); a numerical method stops at it and returns what it has
        (``Status.TIME_BUDGET``), with a step limit in the same proportion.

    Raises
    ------
    ValueError
        Invalid inputs, with the core's message.
    SolveTooSlow
        The solve did not finish within ``budget`` (it goes on in the background and is
        cached when done), or the workers are saturated.
    """
    budget = _budget(preview, budget)
    future = submit(values, preview=preview, budget=budget)
    try:
        return future.result(timeout=budget)
    except FutureTimeout:
        raise _too_slow(values, budget) from None


class _Lane:
    """A pool of worker threads for one kind of solve; one future per distinct solve,
    shared by every session that asks for it while it runs.

    With ``isolated``, each solve runs in a worker process
    (:mod:`app.solve_process`; the worker thread only waits), and a running solve that
    every session asking for it has given up is stopped.
    """

    def __init__(self, name: str, workers: int, queue: int | None, *,
                 isolated: bool = False) -> None:
        self.executor = ThreadPoolExecutor(max_workers=workers,
                                           thread_name_prefix=f"fie-{name}")
        self.limit = None if queue is None else workers + queue
        self.isolated = isolated
        self.futures: dict[tuple, Future] = {}
        #: Per solve: how many requests wait for it, and the event that stops it.
        self.waiters: dict[tuple, int] = {}
        self.stops: dict[tuple, threading.Event] = {}
        self.lock = threading.Lock()

    def submit(self, key: tuple, preview: bool, budget: float | None = None) -> Future:
        """The running (or queued) solve of ``key``, or a new one; ``budget`` (``None``:
        the default) is part of what is solved when the method stops at its budget."""
        item = (key, preview, budget)
        with self.lock:
            future = self.futures.get(item)
            if future is not None:
                self.waiters[item] += 1
                return future
            if self.limit is not None and len(self.futures) >= self.limit:
                raise SolveTooSlow(
                    "the server is busy with other long solves; try again in a moment, or "
                    "choose a shorter horizon t_end or a looser accuracy.")
            stop = threading.Event()
            future = self.executor.submit(self._run, key, preview, budget, stop)
            self.futures[item], self.waiters[item], self.stops[item] = future, 1, stop

        def done(_: Future) -> None:
            with self.lock:
                self._forget(item, future)

        future.add_done_callback(done)
        return future

    def _run(self, key: tuple, preview: bool, budget: float | None,
             stop: threading.Event) -> Solution:
        # A preview stays in this thread: the core stops it at its budget (a quarter of a
        # second), less than a child process would add to every drag step (~30 ms).
        _WORKER.isolated, _WORKER.stop = self.isolated and not preview, stop
        try:
            # Looked up at each call: tests replace it with a slow stand-in.
            return _solve_cached(key, preview, budget)
        finally:
            _WORKER.isolated, _WORKER.stop = False, None

    def _forget(self, item: tuple, future: Future) -> None:
        if self.futures.get(item) is future:
            del self.futures[item], self.waiters[item], self.stops[item]

    def drop(self, key: tuple, preview: bool, future: Future,
             budget: float | None = None) -> None:
        """One request no longer waits for ``future``: when none does, a solve that has
        not started is cancelled and a running one in a child process is stopped (a new
        request for it starts afresh)."""
        item = (key, preview, budget)
        with self.lock:
            if self.futures.get(item) is not future:
                return
            self.waiters[item] -= 1
            if self.waiters[item] > 0:
                return
            stop = self.stops[item]
            if self.isolated:
                self._forget(item, future)
        # Outside the lock: a cancelled future runs its done callbacks (which take it) here.
        if not future.cancel() and self.isolated:
            stop.set()


#: The worker thread's solve: whether it runs in a child process, and what stops it.
_WORKER = threading.local()
_WORKER.isolated, _WORKER.stop, _WORKER.deadline = False, None, None


_closed_form = _Lane("closed-form", CLOSED_FORM_WORKERS, None)
_integrating = _Lane("integrating", SOLVE_WORKERS, SOLVE_QUEUE, isolated=True)


def _lane(values: Mapping[str, Any]) -> _Lane:
    closed = (choose_method(values["method"], values["stop_type"]) == "exact"
              and values["stop_type"] != "hysteretic")
    return _closed_form if closed else _integrating


def _lane_budget(values: Mapping[str, Any], preview: bool, budget: float | None
                 ) -> float | None:
    """The budget that tells two solves of ``values`` apart: ``None`` for the default, or
    for a method that does not stop at its budget (a retry then joins the running solve)."""
    if budget is None or budget == _budget(preview, None) or not _budgeted(values):
        return None
    return budget


def submit(values: Mapping[str, Any], *, preview: bool = False,
           budget: float | None = None) -> Future:
    """The solve of ``values`` as a future: done at once when cached, else running (or
    queued) in a worker thread. Solves that integrate and closed-form ones have pools of
    their own; a solve already running for another session is shared. A cached solution
    that stopped short (:func:`cut_short`) is not the answer to a larger ``budget``.

    Raises
    ------
    SolveTooSlow
        The integrating workers and their queue are full.
    """
    key = _key(values)
    budget = _lane_budget(values, preview, budget)
    with _CACHE_LOCK:
        cached = _CACHE.get((key, preview))
    if cached is not None and (budget is None or not cut_short(cached)):
        future: Future = Future()
        future.set_result(cached)
        return future
    return _lane(values).submit(key, preview, budget)


def executor_for(values: Mapping[str, Any]) -> ThreadPoolExecutor:
    """The worker pool that solves ``values`` (closed form or integrating): for other work
    of the same kind, such as a parameter sweep's chunks (:mod:`app.bifurcation`)."""
    return _lane(values).executor


def forget(values: Mapping[str, Any], future: Future, *, preview: bool = False,
           budget: float | None = None) -> None:
    """The caller no longer needs ``future`` (a newer request replaced it): a solve nobody
    else waits for is cancelled if it has not started, stopped if it runs in a child
    process."""
    _lane(values).drop(_key(values), preview, future, _lane_budget(values, preview, budget))


class SolveRunner:
    """One session's solves: the latest request wins, the event loop never waits.

    :meth:`request` hands the solve to the worker pool and returns. The answer comes back
    on the session's event loop (:func:`app.session_loop.from_any_thread`) and goes to
    ``on_solved`` unless a newer request has been made since (a stale answer is dropped; a
    stale solve that has not started is cancelled). A solve still running after
    :data:`BUSY_DELAY_S` calls ``on_busy(True)`` (and ``on_busy(False)`` when it ends or is
    replaced); one still running at its budget calls ``on_failed`` with
    :class:`SolveTooSlow`. Without a server session (scripts, tests) a request is answered
    before it returns.

    Parameters
    ----------
    on_failed : callable(Exception)
        Called with what the solve raised (``ValueError`` for invalid inputs).
    on_busy : callable(bool), optional
    preview : bool
        Solve previews (:func:`solve`).
    """

    def __init__(self, on_failed: Callable[[Exception], None],
                 on_busy: Callable[[bool], None] | None = None, *, preview: bool = False
                 ) -> None:
        self.on_failed, self.on_busy, self.preview = on_failed, on_busy, preview
        self._token = 0
        self._pending: tuple[Mapping[str, Any], Future, float] | None = None
        self._busy = False

    @property
    def pending(self) -> bool:
        """A request is waiting for its answer."""
        return self._pending is not None

    def request(self, values: Mapping[str, Any], on_solved: Callable[[Solution], None],
                budget: float | None = None) -> None:
        """Solve ``values`` within ``budget`` seconds (default :data:`SOLVE_BUDGET_S`, or
        :data:`PREVIEW_BUDGET_S` for previews) and call ``on_solved(solution)`` with the
        answer (see the class docstring)."""
        self.cancel()
        token = self._token
        budget = _budget(self.preview, budget)
        try:
            future = submit(values, preview=self.preview, budget=budget)
        except Exception as exc:  # noqa: BLE001 - whatever it is, the caller reports it
            self.on_failed(exc)
            return
        doc = pn.state.curdoc
        if future.done() or doc is None or doc.session_context is None:
            self._answer(future, on_solved, values, budget)
            return
        self._pending = (values, future, budget)

        def back_on_the_loop(fn: Callable[[], None]) -> Callable[[], None]:
            def run() -> None:
                if token == self._token:
                    with set_curdoc(doc):
                        fn()
            return run

        def finished() -> None:
            self._pending = None
            self._set_busy(False)
            self._answer(future, on_solved, values, budget)

        def overdue() -> None:
            if not future.done():
                self.cancel()
                self.on_failed(_too_slow(values, budget))

        def busy() -> None:
            if not future.done():
                self._set_busy(True)

        answer = from_any_thread(doc, back_on_the_loop(finished))
        future.add_done_callback(lambda _: answer())
        if self.on_busy is not None:
            doc.add_timeout_callback(back_on_the_loop(busy), BUSY_DELAY_S * 1000)
        doc.add_timeout_callback(back_on_the_loop(overdue),
                                 (budget + _budget_grace()) * 1000)

    def cancel(self) -> None:
        """Drop the pending request, if any (its answer will be ignored)."""
        self._token += 1
        if self._pending is not None:
            values, future, budget = self._pending
            self._pending = None
            forget(values, future, preview=self.preview, budget=budget)
        self._set_busy(False)

    def _set_busy(self, busy: bool) -> None:
        if self.on_busy is not None and busy != self._busy:
            self._busy = busy
            self.on_busy(busy)

    def _answer(self, future: Future, on_solved: Callable[[Solution], None],
                values: Mapping[str, Any], budget: float) -> None:
        try:
            solution = future.result(timeout=budget)
        except FutureTimeout:
            self.on_failed(_too_slow(values, budget))
        except Exception as exc:  # noqa: BLE001 - the server must survive any solve
            self.on_failed(exc)
        else:
            on_solved(solution)


#: Extra time [s] a solve gets past its budget before the page calls it too slow, when the
#: core stops it at the budget itself (then it answers with what it has by then).
BUDGET_GRACE_S = 0.5


def _budget_grace() -> float:
    return BUDGET_GRACE_S

_CACHE: OrderedDict[tuple, Solution] = OrderedDict()
_CACHE_LOCK = threading.Lock()


def _solve_cached(key: tuple, preview: bool, budget: float | None = None) -> Solution:
    """Solve ``key`` within ``budget`` (runs in a worker) and keep the answer in the cache
    (not one the core cut short at its budget: asking again may get further)."""
    solution = _solve(key, preview, budget)
    if solution.result is None or solution.result.status is not Status.TIME_BUDGET:
        with _CACHE_LOCK:
            _CACHE[(key, preview)] = solution
            _CACHE.move_to_end((key, preview))
            while len(_CACHE) > CACHE_ITEMS:
                _CACHE.popitem(last=False)
    return solution


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


def _solve(key: tuple, preview: bool, budget: float | None = None) -> Solution:
    values = MappingProxyType(dict(key))
    osc, stop, x0, v0, t_end = core_inputs(values)
    accuracy = ACCURACY[PREVIEW_ACCURACY if preview else values["accuracy"]]
    method = choose_method(values["method"], values["stop_type"])
    n_samples = PREVIEW_SAMPLES if preview else accuracy["n_samples"]
    if not preview and (method != "exact" or isinstance(stop, HystereticStop)):
        # Drawn from its samples (app/sampling.py): dense enough for any horizon (a
        # preview stays cheap).
        n_samples = samples_for(t_end, n_samples)
    start = time.perf_counter()
    options: dict[str, Any] = {}
    if values.get("program") and isinstance(stop, HystereticStop):
        program, result = overlap_program(stop), None
    else:
        program = None
        used = method_options(method, stop)
        # The preset's tolerances, for the options this method uses (core refuses others);
        # the numerical methods stop at their budget themselves.
        options = preset_options(accuracy, used, osc)
        if "time_budget" in used:
            options["time_budget"] = _budget(preview, budget)
        if "max_steps" in used and "time_budget" not in used:
            options["max_steps"] = UNBUDGETED_MAX_STEPS
        elif "max_steps" in used:
            # A retry with more time may take as many more steps.
            options["max_steps"] = int(SOLVE_MAX_STEPS * max(1.0, (budget or 0.0)
                                                              / SOLVE_BUDGET_S))
        result = _simulate(osc, stop, t_end, x0, v0, n_samples=n_samples, method=method,
                           **options)
    solve_time = time.perf_counter() - start
    verdict, skipped, error, measured = None, False, math.nan, False
    if result is not None and not preview and integrates(method, stop):
        # No preset's error holds on random scenes (ACCURACY): the run's is measured.
        run = measure_run(result, osc, stop, x0, v0,
                          _budget(preview, budget) - solve_time - MEASURE_MARGIN_S)
        if run is None:
            skipped = True
        elif math.isfinite(run[0]):
            (error, verdict), measured = run, True
    return Solution(
        values=values, osc=osc, stop=stop, x0=x0, v0=v0, t_end=t_end,
        result=result, program=program,
        theory=None if preview else theory_for(osc, stop, x0, v0),
        method=method, solve_time=solve_time,
        error_estimate=error, error_measured=measured, reference_steady=verdict,
        measure_skipped=skipped,
        restitution_measured=measured_restitution(result),
        preview=preview, budget=_budget(preview, budget),
    )


def integrates(method: str, stop: Any) -> bool:
    """Whether ``method`` integrates on ``stop`` (a closed form does not: its error is
    rounding): ``event``, ``switch``, and ``exact`` on a deformable stop's contact."""
    return method != "exact" or isinstance(stop, HystereticStop)


def position_error(x: np.ndarray, x_ref: np.ndarray) -> float:
    """Largest distance of positions ``x`` from the reference's at the same times, over the
    reference's amplitude about its mean (the trade table's measure, app.trade)."""
    scale = max(float(np.max(np.abs(x_ref - x_ref.mean()))), 1e-300)
    return float(np.max(np.abs(np.asarray(x) - x_ref))) / scale


#: Tolerances of the exact method's integrated contact when it is the reference a
#: numerical method's run on a deformable stop is measured against (app.trade's too).
REFERENCE_RTOL, REFERENCE_ATOL = 1e-12, 1e-14


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
    ``ref``, the exact method over the same span (:func:`_reference`: the closed form for
    no stop or a rigid stop, or the exact flight with the contact integrated at
    :data:`REFERENCE_RTOL` for a deformable stop; a reduced model's stated bound there is
    added). Past the reference's end (it reached the stop's limit overlap earlier: its
    motion ends there) the samples are compared with its last position: a run that ended
    1e-15 later had been called unmeasured, one that went on is far off; ``nan`` only
    where the reference cannot be evaluated."""
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


#: Time [s] a run's measurement leaves of its budget: the stopped child's exit and the
#: theory's closed forms after it.
MEASURE_MARGIN_S = 0.1


class _Deadline:
    """Stops a solve in a child process (:func:`app.solve_process.call`'s ``cancelled``)
    ``seconds`` from now, or when ``also`` (the run's own stop) is set."""

    def __init__(self, seconds: float, also: threading.Event | None = None) -> None:
        self.at, self.also = time.monotonic() + seconds, also

    def is_set(self) -> bool:
        return time.monotonic() >= self.at or (self.also is not None and self.also.is_set())


def measure_run(result: Result, osc: Any, stop: Any, x0: float, v0: float,
                within: float) -> tuple[float, Steady | None] | None:
    """A run's error (:func:`reference_error`, ``nan`` where there is no motion to
    compare) and the steady state the exact method finds over its span (``None`` with no
    error: a method can change the verdict, e.g. a mass resting on the stop's face
    at ``x_bar = a``, where the exact solution's rebounds die out over ever equal arcs:
    grazing), or ``None`` if the exact solve does not finish ``within`` seconds (the rest of
    the run's budget).

    The exact solve is not budgeted by the core; measured after the run without a deadline
    it made the answer late (0.6 s for scene 10's stop to t_end = 5000), and the page called
    a run that had finished within its budget "too slow". In a child process
    (:mod:`app.solve_process`) it is stopped at the deadline; in the calling thread (the
    child processes turned off) it cannot be, and runs to its end."""
    t = np.asarray(result.t, float)
    if not len(t) or not t[-1] > 0.0:
        return math.nan, None
    _WORKER.deadline = _Deadline(within, getattr(_WORKER, "stop", None))
    try:
        ref = _reference(osc, stop, float(t[-1]), x0, v0)
        error = reference_error(result, ref)
        return error, ref.steady if math.isfinite(error) else None
    except solve_process.Abandoned:
        return None
    finally:
        _WORKER.deadline = None


@functools.lru_cache(maxsize=2)
def _reference(osc: Any, stop: Any, t_end: float, x0: float, v0: float) -> Result:
    """The exact method's solve that :func:`reference_error` measures against, kept for the
    other methods and presets of the same scene (45 ms on scene 10's stop, as long as a
    switch solve at standard); two, so that a class's sessions on other scenes do not
    hold more."""
    return _simulate(osc, stop, t_end, x0, v0, n_samples=2, method="exact",
                     **reference_options(stop))


def _simulate(*args: Any, **kwargs: Any) -> Result:
    """:func:`core.simulate`, in a worker process when the worker thread's lane is
    isolated (:mod:`app.solve_process`)."""
    if getattr(_WORKER, "isolated", False):
        # ``simulate`` looked up at each call: the isolation test replaces it.
        # a measurement's deadline (measure_run), else the run's own stop
        cancelled = getattr(_WORKER, "deadline", None) or _WORKER.stop
        return solve_process.call(simulate, *args, cancelled=cancelled, **kwargs)
    return simulate(*args, **kwargs)


def equivalent_rigid(stop) -> RigidStop | None:
    """The rigid stop the theory speaks of: the stop itself, or for a hysteretic stop the
    equivalent rigid stop with ``r_eq = sqrt(k_e0/k_c0)`` (paper Eq. 16)."""
    if isinstance(stop, HystereticStop):
        return RigidStop(clearance=stop.clearance, restitution=stop.equivalent_restitution)
    return stop


def theory_for(osc, stop, x0: float, v0: float) -> Theory | None:
    """Closed-form references, or ``None`` if the theory does not cover the inputs."""
    rigid = equivalent_rigid(stop)
    r = rigid.restitution if rigid is not None else 1.0
    try:
        return Theory(
            regime=theory.classify(osc, rigid, x0, v0),
            critical_speed=theory.critical_speed(osc, x0, v0),
            fast=theory.is_fast_belt(osc, x0, v0),
            gamma0_radius=theory.gamma0_radius(osc),
            limit_cycle=theory.impactless_limit_cycle(osc) if osc.v > 0 else None,
            x_max_impactless=theory.x_max_impactless(osc, x0, v0),
            x_star=theory.x_star(osc, r),
            points=MappingProxyType(theory.steady_points(osc, rigid)),
            restitution=r,
        )
    except (ValueError, ZeroDivisionError, OverflowError):
        return None


def measured_restitution(result: Result | None) -> np.ndarray:
    """Rebound over approach speed of each finished deformable contact
    (docs/contact-law.md, "Restitution against impact speed"), from
    :func:`core.deformable.solver.effective_restitutions`; empty without a result."""
    if result is None:
        return np.zeros(0)
    return effective_restitutions(result)


def overlap_program(stop: HystereticStop) -> Program:
    """Contact force under the overlap program of paper Fig. 2b, from the core's law.

    The overlap ``delta(s) = A(s) (1 - cos s) / 2`` rises from zero and returns to it
    each period while the amplitude ``A`` falls linearly from ``PROGRAM_PEAK * D`` to
    ``PROGRAM_DECAY`` of that; a reversal is stored at each turn of the overlap rate and a
    new contact starts on the compression envelope (:mod:`core.deformable.law`).
    """
    n = PROGRAM_PERIODS * PROGRAM_SAMPLES_PER_PERIOD + 1
    s = np.linspace(0.0, 2.0 * math.pi * PROGRAM_PERIODS, n)
    amplitude = PROGRAM_PEAK * stop.limit_overlap * (
        1.0 - (1.0 - PROGRAM_DECAY) * s / s[-1]
    )
    delta = amplitude * (1.0 - np.cos(s)) / 2.0
    force = np.zeros(n)
    branch = FIRST_LOADING
    for i in range(1, n):
        rising = delta[i] > delta[i - 1]
        if delta[i] <= 0.0:
            branch = FIRST_LOADING
        elif rising != branch.loading:
            branch = reverse(delta[i - 1], force[i - 1], branch)
        force[i] = float(contact_force(delta[i], branch, stop))
    return Program(s=s, overlap=delta, force=force)


def regime_map(values: Mapping[str, Any], *, compute: bool = True,
               frame: tuple[float, float, float] | None = None) -> dict[str, Any] | None:
    """Regime codes over a (belt speed, clearance) grid for the current friction, stop and
    start (:func:`core.theory.classify`); cached on what the map depends on.

    A new map is :data:`MAP_CELLS` squared classifications at once (~4 ms at 128 x 128,
    :func:`core.theory.classify_grid`); with ``compute=False`` only a cached one is
    returned, else ``None`` (the page then draws the rest first). ``frame`` gives the axes
    ``(v_hi, x_lo, x_hi)`` (default :func:`map_ranges` of ``values``).
    """
    key = tuple(
        (name, values[name])
        for name in ("mu_s", "mu_k", "u_s", "stop_type", "restitution", "k_c0", "k_e0",
                     "limit_overlap", "beta_c", "beta_e", "x0", "v0")
    )
    v_hi, x_lo, x_hi = frame if frame is not None else map_ranges(values)
    key += (("v_hi", v_hi), ("x_lo", x_lo), ("x_hi", x_hi))
    with _MAP_LOCK:
        data = _MAP_CACHE.get(key)
        if data is not None:
            _MAP_CACHE.move_to_end(key)
    if data is not None or not compute:
        return data
    data = _compute_regime_map(key)
    with _MAP_LOCK:
        _MAP_CACHE[key] = data
        while len(_MAP_CACHE) > MAP_CACHE_ITEMS:
            _MAP_CACHE.popitem(last=False)
    return data


def map_ranges(values: Mapping[str, Any]) -> tuple[float, float, float]:
    """Axes of the regime map: belt speed ``[0, v_hi]``, clearance ``[x_lo, x_hi]``.

    Twice the critical speed of the start, and clearances from the start to a fifth past
    the largest impactless excursion; widened to keep the current point inside.
    """
    a = values["mu_k"] * values["u_s"]
    b = values["mu_s"] * values["u_s"]
    v_crit = math.hypot(values["x0"] - a, values["v0"])
    v_hi = _nice(max(2.0 * v_crit, 1.25 * values["belt_speed"], 1e-3))
    x_hi = max(a + max(v_crit, math.hypot(b - a, v_hi)), 1.1 * values["clearance"])
    x_lo = values["x0"]
    return v_hi, x_lo, _nice(x_lo + 1.2 * (x_hi - x_lo)) if x_hi > x_lo else x_lo + 1.0


def _nice(x: float) -> float:
    """Round up to 1, 2, 2.5 or 5 times a power of ten (stable axes while dragging)."""
    if x <= 0:
        return 1.0
    exp = math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * 10**exp >= x * (1 - 1e-12):
            return m * 10**exp
    return 10.0 ** (exp + 1)


def _compute_regime_map(key: tuple) -> dict[str, Any]:
    values = dict(key)
    v_hi, x_lo, x_hi = values["v_hi"], values["x_lo"], values["x_hi"]
    speeds = (np.arange(MAP_CELLS) + 0.5) * v_hi / MAP_CELLS
    clearances = x_lo + (np.arange(MAP_CELLS) + 0.5) * (x_hi - x_lo) / MAP_CELLS
    cells, names = _regime_cells(values, speeds, clearances)
    # Regimes numbered in the order they first appear going up each speed's column.
    found, first, inverse = np.unique(cells.T.ravel(), return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    codes = rank[inverse].reshape(MAP_CELLS, MAP_CELLS).T.astype(np.int32)
    return {"codes": np.ascontiguousarray(codes), "labels": [names[c] for c in found[order]],
            "v_hi": v_hi, "x_lo": x_lo, "x_hi": x_hi}


def regime_labels(values: Mapping[str, Any], speeds, clearances) -> np.ndarray:
    """Short words for the regime (e.g. ``'slow, inelastic, case b'``) at every belt speed
    (columns) and clearance (rows), the rest of ``values`` fixed
    (:func:`core.theory.classify_grid`); ``'invalid'`` where the theory refuses the inputs."""
    cells, names = _regime_cells(values, speeds, clearances)
    found, inverse = np.unique(cells, return_inverse=True)
    return np.array([names[c] for c in found])[inverse].reshape(cells.shape)


#: Case letters and the steady states a map label names, by their code in _regime_cells.
_CASES, _SETTLES = ("", "a", "b", "c"), ("", "grazing", "rest")


def _regime_cells(values: Mapping[str, Any], speeds, clearances
                  ) -> tuple[np.ndarray, dict[int, str]]:
    """An integer per grid cell that names its regime, and the words of each integer.

    The parameters other than belt speed and clearance are checked once, with the grid's
    largest speed and clearance (a stop behind the start is refused cell by cell).
    """
    shape = (len(clearances), len(speeds))
    try:
        osc, stop, x0, v0, _ = core_inputs({
            **values, "belt_speed": float(np.max(speeds)),
            "clearance": float(np.max(clearances)), "t_end": 1.0, "program": False})
        grid = theory.classify_grid(osc, equivalent_rigid(stop), speeds, clearances, x0, v0)
    except ValueError:
        return np.zeros(shape, dtype=np.int64), {0: "invalid"}
    impacts = ("none", *sorted(set(np.unique(grid.impact).tolist()) - {"none"}))
    case = sum(k * (grid.case == c) for k, c in enumerate(_CASES) if c)
    settles = sum(k * (grid.expected_steady == e) for k, e in enumerate(_SETTLES) if e)
    impact = sum(k * (grid.impact == name) for k, name in enumerate(impacts) if k)
    fields = (grid.valid, grid.impactless, grid.belt == "fast", case, settles, impact)
    cells = np.zeros(shape, dtype=np.int64)
    for digit, radix in zip(fields, (2, 2, 2, 4, 3, len(impacts)), strict=True):
        cells = cells * radix + np.asarray(digit, dtype=np.int64)
    cells = np.where(grid.valid, cells, 0)  # one code for every refused cell
    names = {}
    for cell in np.unique(cells).tolist():
        rest, impact_k = divmod(cell, len(impacts))
        rest, settle_k = divmod(rest, 3)
        rest, case_k = divmod(rest, 4)
        rest, fast = divmod(rest, 2)
        valid, impactless = divmod(rest, 2)
        belt = "fast" if fast else "slow"
        if not valid:
            words = ["invalid"]
        elif impactless:
            words = [belt, "no impact"]
        else:
            words = [belt, impacts[impact_k]]
            words += [f"case {_CASES[case_k]}"] if case_k else []
            words += [_SETTLES[settle_k]] if settle_k else []
        names[cell] = ", ".join(words)
    return cells, names


def mode_intervals(result: Result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Start, end and mode of each run of equal modes in the samples (for mode bands)."""
    mode = np.asarray(result.mode)
    t = np.asarray(result.t)
    if len(t) == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=np.int8)
    change = np.flatnonzero(np.diff(mode) != 0) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [len(t) - 1]))
    return t[starts], t[ends], mode[starts]


__all__ = [
    "ACCURACY", "Mode", "Program", "SolveRunner", "SolveTooSlow", "Solution", "Theory",
    "choose_method", "cut_short", "executor_for", "forget", "retry_budget", "submit",
    "mode_intervals",
    "overlap_program", "preset_options", "regime_labels", "regime_map", "solve",
]
