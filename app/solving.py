"""The full solve of the state: requested when a solve value changes, run in the solver
processes (:class:`app.solve.runner.SolveRunner`, the latest request wins), and handed to the page
as the state's ``solution`` (its views draw it, under one ``pn.io.hold``: one message).

A solve that fails says why in the page's alert and keeps the last good picture; one that ran
out of time (or that the core stopped before its horizon) offers to solve again with more
time (:func:`app.solve.presets.retry_budget`).
"""

from __future__ import annotations

import logging
from typing import Any

import panel as pn
import param
from bokeh.core.properties import validate

from app.solve.pool import SolveTooSlow
from app.solve.presets import MAX_SOLVE_BUDGET_S, retry_budget
from app.solve.runner import SolveRunner
from app.solve.solution import Solution, cut_short
from app.state import SOLVE_PARAMS, ExplorerState
from core import Status

log = logging.getLogger(__name__)


class Solving(param.Parameterized):
    """The solves of one page.

    Parameters
    ----------
    notices : app.notices.Notices
        Where failures are said and the retry is offered.
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)
    busy = param.Boolean(False, doc="A full solve is running (its plots will be replaced).")

    def __init__(self, notices: Any, **params: Any) -> None:
        super().__init__(**params)
        self.notices = notices
        #: The budget [s] that the run on screen overran (None: it did not).
        self._ran_out: float | None = None
        self._runner = SolveRunner(self.failed, self._busy)
        # After the state's other watchers (the controls show the values, the plots forget
        # the last scene's transition kinds): a cached run is drawn before this returns.
        self.state.param.watch(lambda *events: self.solve(), list(SOLVE_PARAMS), precedence=1)
        # After the notices (which hide the last alert): a run cut short says so whenever
        # it is shown, in the units it is shown in.
        self.state.param.watch(self._shown, "solution", precedence=2)

    def solve(self, budget: float | None = None) -> None:
        """Solve the state (with ``budget`` [s], or its accuracy's); the picture stays until
        the answer comes."""
        if budget is None:
            self._offer_retry(None)
        self._runner.request(self.state.values(), self._solved,
                             **({} if budget is None else {"budget": budget}))

    def retry(self) -> None:
        """Solve the state on screen again with :func:`~app.solve.presets.retry_budget` of the
        budget that ran out."""
        self.solve(retry_budget(self._ran_out or MAX_SOLVE_BUDGET_S))

    def cancel(self) -> None:
        self._runner.cancel()

    def _busy(self, busy: bool) -> None:
        self.busy = busy

    def _solved(self, sol: Solution) -> None:
        # The values come from the solver and the plot code, valid by construction: Bokeh's
        # check of each of the ~100 properties set by the views is skipped (server time on
        # the critical path of every release).
        try:
            with pn.io.hold(), validate(False):
                self.state.solution = sol
        except Exception as exc:  # noqa: BLE001 - a drawing fault must not go unsaid
            log.error("drawing failed", exc_info=exc)
            self.notices.show(f"The picture could not be drawn: {type(exc).__name__}: {exc}")

    def _shown(self, event: param.parameterized.Event) -> None:
        sol = event.new
        if sol is not None and cut_short(sol):
            self._say_cut_short(sol)
        else:
            self._offer_retry(None)

    def failed(self, exc: Exception) -> None:
        """Say why a solve (the run's or a pin's) failed."""
        if isinstance(exc, ValueError):
            self.notices.show(str(exc))
        elif isinstance(exc, SolveTooSlow):
            more = ("" if exc.budget is None or exc.budget < MAX_SOLVE_BUDGET_S else
                    f" Even {exc.budget:g} s were not enough.")
            self.notices.show(f"The solve was too slow: {exc}{more}", lead="Not solved in time:",
                              tail="The plots still show the previous run.")
            self._offer_retry(exc.budget)
        else:
            log.error("solve failed", exc_info=exc)
            self.notices.show(f"The solver failed: {type(exc).__name__}: {exc}")

    def _say_cut_short(self, sol: Solution) -> None:
        """Say that the core stopped ``sol`` before its horizon, and offer more time."""
        res, scales = sol.result, self.state.scales()
        unit = " s" if scales.si else ""
        why = (f"its time budget of {sol.budget:g} s ran out" if res.status is Status.TIME_BUDGET
               else "it reached its limit on integration steps")
        more = ("" if sol.budget < MAX_SOLVE_BUDGET_S else
                " More time cannot be given: a shorter horizon t_end or a looser accuracy "
                "answers sooner.")
        self.notices.show(
            f"the {sol.method} method stopped at t = {float(res.t[-1]) * scales.time:.4g}"
            f"{unit} of t_end = {sol.t_end * scales.time:.4g}{unit}: {why}.{more}",
            lead="Solved only in part:", tail="The plots show the run up to there.")
        self._offer_retry(sol.budget)

    def _offer_retry(self, ran_out: float | None) -> None:
        """Offer to solve again with more time after ``ran_out`` seconds were not enough
        (hide the offer with None, or when the budget cannot grow)."""
        self._ran_out = ran_out
        if ran_out is None or ran_out >= MAX_SOLVE_BUDGET_S:
            self.notices.offer_retry(None)
            return
        self.notices.offer_retry(
            retry_budget(ran_out), self.retry,
            description=f"Solve this run again with up to {retry_budget(ran_out):g} s "
                        "(the plots stay until it is done).")
