"""The speed/accuracy trade measured for the run on screen (on request, never per release).

Each method (``exact``, ``event``, ``switch``) at each accuracy preset of
:data:`app.solve.presets.ACCURACY` solves the current state again; its wall time is measured now
and its error is the largest distance of its positions from a reference solution at the same
times, over the motion's amplitude. The reference is the exact method at tight tolerances:
closed form for no stop or a rigid stop (rounding only), exact flight with the contact
integrated at ``rtol`` 1e-12 for a deformable stop. The steady state each one finds is shown
too: a method can change the verdict (the switch model at draft on scene 10).

Every solve runs in a solver process (:mod:`app.solve.process`), as the page's own
integrating solves do: measured in the server's threads, scene 10 to ``t_end = 5000`` held
the server's interpreter lock for seconds, and repeated clicks slowed every other page's
replies. A measurement has a budget (:data:`MEASURE_BUDGET_S`), a page runs one at a time
(:class:`TradeRunner`) and the server one after the other.

Examples
--------
>>> from app.state import scene_values
>>> rows = measure(scene_values("5b"), methods=("exact",))
>>> [(r.method, r.accuracy) for r in rows]
[('exact', 'draft'), ('exact', 'standard'), ('exact', 'precise')]
>>> max(r.error for r in rows) < 1e-12
True
"""

from __future__ import annotations

import html
import math
import threading
from collections.abc import Callable, Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
import panel as pn
from panel.io.state import set_curdoc

from app.session_loop import from_any_thread
from app.solve import process as solve_process
from app.solve.measure import position_error, reference_options
from app.solve.presets import ACCURACY, SOLVE_MAX_STEPS, preset_options
from app.solve.trade_solve import Sampled, sampled
from app.state import ACCURACIES, core_inputs
from core import (
    HystereticStop,
    Status,
    Steady,
    SteadyKind,
    method_options,
    rest_swing_of,
    simulate,
)

#: Methods compared (``auto`` is one of them).
METHODS = ("exact", "event", "switch")
#: Times at which the methods are compared (uniform over the horizon).
COMPARE_POINTS = 1000
#: Wall-time budget [s] of one measured solve; a method past it is not tried at the
#: finer presets (a numerical method on a Zeno scene can take minutes).
SOLVE_BUDGET_S = 3.0
#: Wall-time budget [s] of a whole measurement, the reference and every method at every
#: preset: a solve that would end past it is not made (its row says so). Scene 10 to
#: ``t_end = 5000`` took 5-9 s in all; without a budget one click could hold a solver
#: process for minutes.
MEASURE_BUDGET_S = 30.0
#: Share of :data:`MEASURE_BUDGET_S` the reference solve may take: past it nothing is
#: compared and the page says why.
REFERENCE_SHARE = 0.5
#: Time [s] a solve the core stops at its budget gets to hand back what it has before its
#: process is stopped.
STOP_GRACE_S = 0.5
#: Measurements that may wait for the measuring thread, server-wide: past that one more is
#: refused at once (the page says so) instead of queueing behind them.
MEASURE_QUEUE = 2
#: What each method models, in one sentence.
SENTENCES: Mapping[str, str] = {
    "exact": "Slip arcs and stick segments in closed form and Newton's impact law; with a "
             "deformable stop only the contact phase is integrated.",
    "event": "A general-purpose integrator (solve_ivp) on the non-smooth model, stopped at "
             "each stick, slip and contact event: its error shrinks with rtol on most "
             "runs, not on all (a missed or moved event near grazing or in an impact "
             "sequence).",
    "switch": "The paper's switch model: the mass sticks (x'' = 0) while |x' - v| <= eta, "
              "integrated by RKF 4(5); its error follows eta, not rtol.",
}

#: One measuring thread per server: measurements queue rather than load the machine. It
#: only waits: each solve runs in a solver process (:mod:`app.solve.process`), stopped at
#: its deadline.
_executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="fie-trade")
_admitted = [0]  # measurements running or waiting
_admitted_lock = threading.Lock()


class MeasureRefused(RuntimeError):
    """A measurement not started: one already runs for the page, or the server is busy."""


class ReferenceTooSlow(RuntimeError):
    """The reference solve did not finish within its share of the measurement's budget."""


@dataclass(frozen=True)
class TradeRow:
    """One method at one preset: wall time [s], relative error, steady state found."""

    method: str
    accuracy: str
    seconds: float
    error: float
    verdict: str
    note: str = ""


def measure(values: Mapping[str, Any], methods: tuple[str, ...] = METHODS,
            budget_s: float | None = None, *, total_s: float | None = None,
            stop: threading.Event | None = None) -> list[TradeRow]:
    """Solve ``values`` with each method at each preset, within ``total_s`` seconds in all
    (default :data:`MEASURE_BUDGET_S`) and ``budget_s`` per solve (default
    :data:`SOLVE_BUDGET_S`); raises ``ValueError`` on bad input.

    Each solve runs in a solver process (:mod:`app.solve.process`), stopped at its
    deadline; the calling thread only waits. With ``stop`` set (the page closed) the
    running solve is stopped and :class:`app.solve.process.Abandoned` raised. (With the
    processes turned off the solves run in the calling thread, where only the numerical
    methods stop at their budget, and the rest is checked between solves.)

    Raises
    ------
    ReferenceTooSlow
        The reference did not finish within ``REFERENCE_SHARE * total_s``.
    """
    budget_s = SOLVE_BUDGET_S if budget_s is None else budget_s
    total_s = MEASURE_BUDGET_S if total_s is None else total_s
    overall = solve_process.Deadline(total_s)
    osc, stop_, x0, v0, t_end = core_inputs(values)
    t_eval = np.linspace(0.0, t_end, COMPARE_POINTS)
    ref_s = REFERENCE_SHARE * total_s
    ref = _solve((osc, stop_, t_end, x0, v0, t_eval), "exact", reference_options(stop_),
                 min(ref_s, overall.left()), stop)
    if ref is None:
        raise ReferenceTooSlow(
            f"the reference solve (exact method, tight tolerances) did not finish within "
            f"{ref_s:g} s, half the measurement's budget of {total_s:g} s: a shorter "
            "horizon t_end is measured sooner.")
    rows: list[TradeRow] = []
    for method in methods:
        rows += _method_rows(method, (osc, stop_, t_end, x0, v0, t_eval), ref, budget_s,
                             overall, total_s, stop)
    return rows


def _method_rows(method: str, inputs: tuple, ref: Sampled, budget_s: float,
                 overall: solve_process.Deadline, total_s: float,
                 stop: threading.Event | None) -> list[TradeRow]:
    """The rows of ``method`` at each preset, finer ones not tried past a budget."""
    used = method_options(method, inputs[1])
    rows: list[TradeRow] = []
    for accuracy in ACCURACIES:
        within = min(budget_s, overall.left())
        if within <= 0.0:
            rows.append(TradeRow(method, accuracy, math.nan, math.nan, "—",
                                 f"not measured: the measurement's budget of {total_s:g} s "
                                 "ran out"))
            continue
        kwargs = preset_options(ACCURACY[accuracy], used, inputs[0])
        if "time_budget" in used:  # the solve itself stops, not only the wait for it
            kwargs["time_budget"] = within
        if "max_steps" in used:  # stopped by time, as the page's solves
            kwargs["max_steps"] = SOLVE_MAX_STEPS
        try:
            res = _solve(inputs, method, kwargs, within + STOP_GRACE_S, stop)
        except solve_process.Abandoned:
            raise
        except Exception as exc:  # noqa: BLE001 - a method that fails is reported
            rows.append(TradeRow(method, accuracy, math.nan, math.nan, "—",
                                 f"failed: {exc}"))
            continue
        if res is None or res.status == Status.TIME_BUDGET.value:
            finer = ": finer presets not tried" if accuracy != ACCURACIES[-1] else ""
            rows.append(TradeRow(method, accuracy, math.inf, math.nan, "—",
                                 f"over {within:.3g} s{finer}"))
            break
        note = (f"verdict differs from the reference ({ref.verdict})"
                if res.verdict != ref.verdict
                and not rest_alike(res.steady, ref.steady, inputs[0], inputs[1], kwargs)
                else "")
        rows.append(TradeRow(method, accuracy, res.seconds, position_error(res.x, ref.x),
                             res.verdict, note))
    return rows


def rest_alike(steady: Steady, ref: Steady, osc: Any, stop: Any,
                options: Mapping[str, Any]) -> bool:
    """A run at rest on a deformable stop whose tighter reference finds its loops still
    swinging within the run's own rule for rest (the reference's rule is tighter too): the
    same verdict at the run's accuracy."""
    if steady.kind is not SteadyKind.REST or not isinstance(stop, HystereticStop):
        return False
    return ref.at_rest_within(*rest_swing_of(osc, stop, options.get("rtol", 0.0),
                                             options.get("atol", 0.0)))


def _solve(inputs: tuple, method: str, options: dict[str, Any], within: float,
           stop: threading.Event | None) -> Sampled | None:
    """One solve in a solver process, ``None`` if it was stopped at ``within`` seconds;
    :class:`app.solve.process.Abandoned` if ``stop`` was set."""
    if stop is not None and stop.is_set():  # a solve in this thread is not stopped
        raise solve_process.Abandoned("the measurement was cancelled")
    deadline = solve_process.Deadline(within, stop)
    try:
        # ``simulate`` looked up at each call: tests put a probe in its place.
        return solve_process.call(sampled, simulate, *inputs, method, options,
                                  cancelled=deadline)
    except solve_process.Abandoned:
        if stop is not None and stop.is_set():
            raise
        return None


def _admit() -> None:
    with _admitted_lock:
        if _admitted[0] > MEASURE_QUEUE:
            raise MeasureRefused(
                "the server is measuring the trade for other pages; try again in a moment.")
        _admitted[0] += 1


def _release() -> None:
    with _admitted_lock:
        _admitted[0] -= 1


class TradeRunner:
    """One page's measurement: at most one at a time, off the event loop, stopped when the
    page closes (:meth:`cancel`).

    :meth:`start` hands :func:`measure` to the measuring thread and returns; the rows come
    back on the session's event loop (:func:`app.session_loop.from_any_thread`) to
    ``on_done(values, rows)``, or the failure to ``on_failed(exc)``; a cancelled
    measurement calls ``on_failed`` with :class:`app.solve.process.Abandoned`. Without a
    server session (scripts, tests) they are called in the measuring thread.
    """

    def __init__(self, on_done: Callable[[Mapping[str, Any], list[TradeRow]], None],
                 on_failed: Callable[[Exception], None]) -> None:
        self.on_done, self.on_failed = on_done, on_failed
        self.future: Future | None = None
        #: The values being measured (``None``: none runs).
        self.values: Mapping[str, Any] | None = None
        self._stop = threading.Event()

    @property
    def running(self) -> bool:
        """A measurement runs (or waits for the measuring thread) for this page."""
        return self.values is not None

    def start(self, values: Mapping[str, Any]) -> Future:
        """Measure ``values``; :class:`MeasureRefused` if one runs for this page (the
        button is disabled then, but a page can send a click anyway) or the server's
        queue of measurements is full."""
        if self.running:
            raise MeasureRefused("a measurement is already running for this page; its "
                                 "table comes when it is done.")
        _admit()
        self._stop = stop = threading.Event()
        self.values = values = dict(values)
        try:
            future = _executor.submit(measure, values, stop=stop)
        except BaseException:
            _release()
            self.values = None
            raise
        future.add_done_callback(lambda _: _release())
        self.future = future
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:
            future.add_done_callback(lambda f: self._answer(f, stop))
            return future

        def on_loop() -> None:
            with set_curdoc(doc):
                self._answer(future, stop)

        answer = from_any_thread(doc, on_loop)
        future.add_done_callback(lambda _: answer())
        return future

    def cancel(self) -> None:
        """Stop the running measurement (its solve's process is stopped, a waiting one is
        not started); ``on_failed`` gets :class:`app.solve.process.Abandoned`."""
        if not self.running:
            return
        self._stop.set()
        if self.future is not None and self.future.cancel():
            self._finish(self._stop)
            self.on_failed(solve_process.Abandoned("the measurement was cancelled"))

    def _finish(self, stop: threading.Event) -> bool:
        """End the measurement of ``stop``; False if another has started since."""
        if stop is not self._stop:
            return False
        self.values, self.future = None, None
        return True

    def _answer(self, future: Future, stop: threading.Event) -> None:
        if future.cancelled():
            return  # cancel() has told the page
        values = self.values
        if not self._finish(stop):
            return
        try:
            rows = future.result()
        except Exception as exc:  # noqa: BLE001 - the page says why and lives
            self.on_failed(exc)
            return
        self.on_done(values, rows)


def trade_html(rows: list[TradeRow]) -> str:
    """The measured rows as a table (escaped), then one sentence per method."""
    def cell(row: TradeRow) -> str:
        secs = ("—" if math.isnan(row.seconds) else
                "&gt; budget" if math.isinf(row.seconds) else f"{row.seconds * 1e3:.3g} ms")
        err = "—" if math.isnan(row.error) else f"{row.error:.1e}"
        note = f"<b>{html.escape(row.note)}</b>" if row.note else ""
        return (f"<tr><td>{html.escape(row.method)}</td><td>{html.escape(row.accuracy)}</td>"
                f"<td>{secs}</td><td>{err}</td><td>{html.escape(row.verdict)}</td>"
                f"<td>{note}</td></tr>")
    head = ("<tr><th>method</th><th>preset</th><th>wall time</th><th>error</th>"
            "<th>steady state</th><th></th></tr>")
    body = "".join(cell(r) for r in rows)
    sentences = "".join(f"<li><b>{m}</b>: {html.escape(s)}</li>" for m, s in SENTENCES.items()
                        if any(r.method == m for r in rows))
    return (f"<table class='fie-trade'>{head}{body}</table>"
            "<div class='fie-trade-note'>Error: largest distance from the reference "
            f"(exact method, tight tolerances) at {COMPARE_POINTS} times, over the motion's "
            f"amplitude. Times measured now on this server.</div><ul>{sentences}</ul>")
