"""One session's solves: the latest request wins, and the answer is handed to the session
on its event loop, which never waits for a solve."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from typing import Any

import panel as pn
from panel.io.state import set_curdoc

from app.session_loop import from_any_thread
from app.solve import pool
from app.solve.pool import Solver, too_slow
from app.solve.solution import Solution

#: A solve still running after this long [s] marks the plots it will replace as busy.
BUSY_DELAY_S = 0.15
#: Extra time [s] a solve gets past its budget before the page calls it too slow, when the
#: core stops it at the budget itself (then it answers with what it has by then).
BUDGET_GRACE_S = 0.5



class SolveRunner:
    """One session's solves: the latest request wins, the event loop never waits.

    :meth:`request` hands the solve to the worker pool and returns. The answer comes back
    on the session's event loop (:func:`app.session_loop.from_any_thread`) and goes to
    ``on_solved`` unless a newer request has been made since (a stale answer is dropped; a
    stale solve that has not started is cancelled). A solve still running after
    :data:`BUSY_DELAY_S` calls ``on_busy(True)`` (and ``on_busy(False)`` when it ends or is
    replaced); one still running at its budget calls ``on_failed`` with
    :class:`app.solve.pool.SolveTooSlow`. Without a server session (scripts, tests) a
    request is answered before it returns.

    Parameters
    ----------
    on_failed : callable(Exception)
        Called with what the solve raised (``ValueError`` for invalid inputs).
    on_busy : callable(bool), optional
    preview : bool
        Solve previews (:func:`app.solve.pool.solve`).
    solver : Solver, optional
        Who solves (default: the server's, :data:`app.solve.pool.SOLVER`, looked up at
        each request).
    """

    def __init__(self, on_failed: Callable[[Exception], None],
                 on_busy: Callable[[bool], None] | None = None, *, preview: bool = False,
                 solver: Solver | None = None) -> None:
        self.on_failed, self.on_busy, self.preview = on_failed, on_busy, preview
        self._solver = solver
        self._token = 0
        self._pending: tuple[Solver, Mapping[str, Any], Future, float] | None = None
        self._busy = False

    @property
    def solver(self) -> Solver:
        """Who solves this session's requests."""
        return pool.SOLVER if self._solver is None else self._solver

    @property
    def pending(self) -> bool:
        """A request is waiting for its answer."""
        return self._pending is not None

    def request(self, values: Mapping[str, Any], on_solved: Callable[[Solution], None],
                budget: float | None = None) -> None:
        """Solve ``values`` within ``budget`` seconds (default the solver's,
        :meth:`app.solve.pool.Solver.budget`) and call ``on_solved(solution)`` with the
        answer (see the class docstring)."""
        self.cancel()
        token = self._token
        solver = self.solver
        budget = solver.budget(self.preview, budget)
        try:
            future = solver.submit(values, preview=self.preview, budget=budget)
        except Exception as exc:  # noqa: BLE001 - whatever it is, the caller reports it
            self.on_failed(exc)
            return
        doc = pn.state.curdoc
        if future.done() or doc is None or doc.session_context is None:
            self._answer(future, on_solved, values, budget)
            return
        self._pending = (solver, values, future, budget)

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
                self.on_failed(too_slow(values, budget))

        def busy() -> None:
            if not future.done():
                self._set_busy(True)

        answer = from_any_thread(doc, back_on_the_loop(finished))
        future.add_done_callback(lambda _: answer())
        if self.on_busy is not None:
            doc.add_timeout_callback(back_on_the_loop(busy), BUSY_DELAY_S * 1000)
        doc.add_timeout_callback(back_on_the_loop(overdue),
                                 (budget + BUDGET_GRACE_S) * 1000)

    def cancel(self) -> None:
        """Drop the pending request, if any (its answer will be ignored)."""
        self._token += 1
        if self._pending is not None:
            solver, values, future, budget = self._pending
            self._pending = None
            solver.forget(values, future, preview=self.preview, budget=budget)
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
            self.on_failed(too_slow(values, budget))
        except Exception as exc:  # noqa: BLE001 - the server must survive any solve
            self.on_failed(exc)
        else:
            on_solved(solution)
