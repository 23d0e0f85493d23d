"""The server's solves: worker threads (integrating solves each in a child process), one
future per distinct solve shared by every session that asks for it, and the cache of their
answers.

:data:`SOLVER` is the server's :class:`Solver`, shared by all its sessions; :func:`solve`
asks it and waits (for scripts and tests; the page uses :class:`app.solve.runner.SolveRunner`,
which does not wait). A test makes a :class:`Solver` of its own, with its own cache and, if it
needs one, a probe in place of :func:`core.simulate` or of :func:`app.solve.solution.compute`.

>>> from app.state import scene_values
>>> sol = solve(scene_values("5b"))
>>> sol.result.steady.kind.value, sol.regime.case
('periodic', 'b')
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from concurrent.futures import TimeoutError as FutureTimeout
from typing import Any

from app.solve import solution as solution_module
from app.solve.cache import SolveCache
from app.solve.presets import PREVIEW_BUDGET_S, SOLVE_BUDGET_S, budgeted, choose_method
from app.solve.process import Caller
from app.solve.solution import Solution, cut_short, solve_key
from core import simulate as core_simulate

#: Solves that integrate (a deformable stop's contact, ``event``, ``switch``) and may run at
#: once, per server process, each in a worker process (:mod:`app.solve.process`):
#: they stop themselves at their budget (the core's ``time_budget``), and a solve every
#: requester has given up (a newer slider move) is stopped at once.
SOLVE_WORKERS = 2
#: Integrating solves that may wait for a worker; past that further ones are refused at
#: once (the server is saturated) instead of queueing behind them.
SOLVE_QUEUE = 4
#: Workers of the closed-form solves (rigid stop, no stop: below ~2 ms each), in a pool of
#: their own so that they never wait behind an integrating solve.
CLOSED_FORM_WORKERS = 2
#: How long [s] a thread keeps the interpreter lock once another thread asks for it
#: (:func:`sys.setswitchinterval`; Python's default is 5 ms): see
#: :func:`hand_the_lock_back_soon`.
SWITCH_INTERVAL_S = 0.0005


def hand_the_lock_back_soon() -> None:
    """Let a thread keep the interpreter lock at most :data:`SWITCH_INTERVAL_S` once
    another asks for it (for the whole server process).

    The closed-form solves run in threads of the server, beside the sessions' event loop.
    The loop gives the lock up at every socket read and write and every large array
    operation; a solver thread then takes it, and with Python's default interval the loop
    waits up to 5 ms to have it back, each time. In a class's first burst of moves, when
    the solver threads are busy, the replies stalled in the middle of pure Python, waiting
    for the lock (benchmarks/results/2026-11-29-switch-interval.md: traces, and paired
    classes of 60 with each interval).
    """
    sys.setswitchinterval(SWITCH_INTERVAL_S)


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


def too_slow(values: Mapping[str, Any], budget: float) -> SolveTooSlow:
    """What the page says of a solve of ``values`` still running at its ``budget``."""
    return SolveTooSlow(
        f"the {values['method']} method did not finish within {budget:g} s (it goes on in "
        "the background; asking again once it is done is instant). A shorter horizon "
        "t_end, a looser accuracy or, for a rigid stop, the 'auto' method (closed form) "
        "answers at once.", budget)


class Lane:
    """A pool of worker threads for one kind of solve; one future per distinct solve,
    shared by every request for it while it runs.

    With ``isolated``, a full solve runs in a worker process (:mod:`app.solve.process`;
    the worker thread only waits), and a running solve that every request has given up is
    stopped.
    """

    def __init__(self, name: str, workers: int, queue: int | None, *,
                 isolated: bool = False) -> None:
        self.executor = ThreadPoolExecutor(max_workers=workers,
                                           thread_name_prefix=f"fie-{name}")
        self.limit = None if queue is None else workers + queue
        self.isolated = isolated
        self._futures: dict[tuple, Future] = {}
        #: Per solve: how many requests wait for it, and the event that stops it.
        self._waiters: dict[tuple, int] = {}
        self._stops: dict[tuple, threading.Event] = {}
        self._lock = threading.Lock()

    def submit(self, item: tuple, work: Callable[[threading.Event], Solution]) -> Future:
        """The running (or queued) solve of ``item``, or ``work(stop)`` in a worker thread,
        ``stop`` set when every request for it has given up."""
        with self._lock:
            future = self._futures.get(item)
            if future is not None:
                self._waiters[item] += 1
                return future
            if self.limit is not None and len(self._futures) >= self.limit:
                raise SolveTooSlow(
                    "the server is busy with other long solves; try again in a moment, or "
                    "choose a shorter horizon t_end or a looser accuracy.")
            stop = threading.Event()
            future = self.executor.submit(work, stop)
            self._futures[item], self._waiters[item], self._stops[item] = future, 1, stop

        def done(_: Future) -> None:
            with self._lock:
                self._forget(item, future)

        future.add_done_callback(done)
        return future

    def _forget(self, item: tuple, future: Future) -> None:
        if self._futures.get(item) is future:
            del self._futures[item], self._waiters[item], self._stops[item]

    def drop(self, item: tuple, future: Future) -> None:
        """One request no longer waits for ``future``: when none does, a solve that has
        not started is cancelled and a running one in a child process is stopped (a new
        request for it starts afresh)."""
        with self._lock:
            if self._futures.get(item) is not future:
                return
            self._waiters[item] -= 1
            if self._waiters[item] > 0:
                return
            stop = self._stops[item]
            if self.isolated:
                self._forget(item, future)
        # Outside the lock: a cancelled future runs its done callbacks (which take it) here.
        if not future.cancel() and self.isolated:
            stop.set()

    def shutdown(self) -> None:
        """Let the worker threads end once their work is done (cancels none)."""
        self.executor.shutdown(wait=False)


class Solver:
    """Solves of the page's states in worker threads, closed-form ones and integrating
    ones in pools of their own, and their answers kept.

    Parameters
    ----------
    cache : SolveCache, optional
        Where answers and reference solves are kept (default: a new one).
    simulate : callable
        :func:`core.simulate`, or a module-level stand-in (it is sent to the child
        processes by reference).
    compute : callable
        One solve, :func:`app.solve.solution.compute` (a test may wrap it).
    budget_s : float
        Wall-time budget [s] of a full solve (:data:`app.solve.presets.SOLVE_BUDGET_S`).
    """

    def __init__(self, *, cache: SolveCache | None = None,
                 simulate: Callable[..., Any] = core_simulate,
                 compute: Callable[..., Solution] = solution_module.compute,
                 budget_s: float = SOLVE_BUDGET_S) -> None:
        self.cache = SolveCache() if cache is None else cache
        self.simulate, self.compute, self.budget_s = simulate, compute, budget_s
        self.closed_form = Lane("closed-form", CLOSED_FORM_WORKERS, None)
        self.integrating = Lane("integrating", SOLVE_WORKERS, SOLVE_QUEUE, isolated=True)

    def budget(self, preview: bool, budget: float | None = None) -> float:
        """``budget``, or the default of a preview or a full solve [s]."""
        if budget is not None:
            return budget
        return PREVIEW_BUDGET_S if preview else self.budget_s

    def lane(self, values: Mapping[str, Any]) -> Lane:
        """The pool that solves ``values``: closed form or integrating."""
        closed = (choose_method(values["method"], values["stop_type"]) == "exact"
                  and values["stop_type"] != "hysteretic")
        return self.closed_form if closed else self.integrating

    def executor_for(self, values: Mapping[str, Any]) -> ThreadPoolExecutor:
        """The worker pool that solves ``values`` (closed form or integrating): for other
        work of the same kind, such as a parameter sweep's chunks (:mod:`app.bifurcation`)."""
        return self.lane(values).executor

    def _item(self, values: Mapping[str, Any], preview: bool, budget: float | None
              ) -> tuple:
        """What tells two solves of ``values`` apart: the state, preview or not, and the
        budget where it is not the default and the method stops at it (else a retry joins
        the running solve)."""
        if budget == self.budget(preview) or not budgeted(values):
            budget = None
        return solve_key(values), preview, budget

    def submit(self, values: Mapping[str, Any], *, preview: bool = False,
               budget: float | None = None) -> Future:
        """The solve of ``values`` as a future: done at once when cached, else running (or
        queued) in a worker thread; a solve already running for another session is
        shared. A cached solution that stopped short (:func:`~app.solve.solution.cut_short`)
        is not the answer to a larger ``budget``.

        Raises
        ------
        SolveTooSlow
            The integrating workers and their queue are full.
        """
        item = key, preview, own_budget = self._item(values, preview, budget)
        cached = self.cache.get(key, preview)
        if cached is not None and (own_budget is None or not cut_short(cached)):
            future: Future = Future()
            future.set_result(cached)
            return future
        lane = self.lane(values)
        return lane.submit(item, lambda stop: self._work(item, lane, stop))

    def _work(self, item: tuple, lane: Lane, stop: threading.Event) -> Solution:
        """Solve ``item`` (in a worker thread) and keep the answer."""
        key, preview, budget = item
        # A preview stays in this thread: the core stops it at its budget (a quarter of a
        # second), less than a child process would add to every drag step (~30 ms).
        caller = Caller(self.simulate, isolated=lane.isolated and not preview,
                        cancelled=stop)
        solution = self.compute(key, preview, budget=self.budget(preview, budget),
                                simulate=caller, kept=self.cache.reference)
        self.cache.keep(key, preview, solution)
        return solution

    def forget(self, values: Mapping[str, Any], future: Future, *, preview: bool = False,
               budget: float | None = None) -> None:
        """The caller no longer needs ``future`` (a newer request replaced it): a solve
        nobody else waits for is cancelled if it has not started, stopped if it runs in a
        child process."""
        self.lane(values).drop(self._item(values, preview, budget), future)

    def solve(self, values: Mapping[str, Any], *, preview: bool = False,
              budget: float | None = None) -> Solution:
        """Solve ``values`` and wait for it (see :func:`solve`)."""
        budget = self.budget(preview, budget)
        future = self.submit(values, preview=preview, budget=budget)
        try:
            return future.result(timeout=budget)
        except FutureTimeout:
            raise too_slow(values, budget) from None

    def shutdown(self) -> None:
        """Let the worker threads end (a test's solver, once it is done)."""
        self.closed_form.shutdown()
        self.integrating.shutdown()


#: The server's solver, shared by all sessions of the process.
SOLVER = Solver()


def solve(values: Mapping[str, Any], *, preview: bool = False,
          budget: float | None = None) -> Solution:
    """Solve the state ``values`` with :data:`SOLVER` and wait for it.

    Parameters
    ----------
    values : Mapping
        State values (:data:`app.state.SOLVE_PARAMS`).
    preview : bool
        A cheap solve while a slider is dragged: few samples, draft accuracy, no theory.
    budget : float, optional
        Wall-time budget [s] (default :data:`app.solve.presets.SOLVE_BUDGET_S`, or
        :data:`app.solve.presets.PREVIEW_BUDGET_S` for a preview); a numerical method stops
        at it and returns what it has (``Status.TIME_BUDGET``), with a step limit in the
        same proportion.

    Raises
    ------
    ValueError
        Invalid inputs, with the core's message.
    SolveTooSlow
        The solve did not finish within ``budget`` (it goes on in the background and is
        cached when done), or the workers are saturated.
    """
    return SOLVER.solve(values, preview=preview, budget=budget)


def executor_for(values: Mapping[str, Any]) -> ThreadPoolExecutor:
    """:meth:`Solver.executor_for` of :data:`SOLVER`."""
    return SOLVER.executor_for(values)
