"""The speed/accuracy trade measured for the run on screen (on request, never per release).

Each method (``exact``, ``event``, ``switch``) at each accuracy preset of
:data:`app.solver.ACCURACY` solves the current state again; its wall time is measured now
and its error is the largest distance of its positions from a reference solution at the same
times, over the motion's amplitude. The reference is the exact method at tight tolerances:
closed form for no stop or a rigid stop (rounding only), exact flight with the contact
integrated at ``rtol`` 1e-12 for a deformable stop. The steady state each one finds is shown
too: a method can change the verdict (the switch model at draft on scene 10).

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
import time
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from concurrent.futures import TimeoutError as FutureTimeout
from dataclasses import dataclass
from typing import Any

import numpy as np

from app.solver import (
    ACCURACY,
    SOLVE_MAX_STEPS,
    position_error,
    preset_options,
    reference_options,
)
from app.state import ACCURACIES, core_inputs
from core import HystereticStop, Steady, SteadyKind, method_options, simulate
from core.hysteretic_reduced import rest_swing_of

#: Methods compared (``auto`` is one of them).
METHODS = ("exact", "event", "switch")
#: Times at which the methods are compared (uniform over the horizon).
COMPARE_POINTS = 1000
#: Wall-time budget [s] of one measured solve; a method past it is not tried at the
#: finer presets (a numerical method on a Zeno scene can take minutes).
SOLVE_BUDGET_S = 3.0
#: What each method models, in one sentence.
SENTENCES: Mapping[str, str] = {
    "exact": "Slip arcs and stick segments in closed form and Newton's impact law; with a "
             "deformable stop only the contact phase is integrated.",
    "event": "A general-purpose integrator (solve_ivp) on the non-smooth model, stopped at "
             "each stick, slip and contact event: its error follows rtol.",
    "switch": "The paper's switch model: the mass sticks (x'' = 0) while |x' - v| <= eta, "
              "integrated by RKF 4(5); its error follows eta, not rtol.",
}

#: One worker per server: measurements queue rather than load the machine; a solve past
#: its budget finishes there in the background.
_executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="fie-trade")


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
            budget_s: float = SOLVE_BUDGET_S) -> list[TradeRow]:
    """Solve ``values`` with each method at each preset; raises ``ValueError`` on bad input.

    Runs in the calling thread, each solve waited for at most ``budget_s`` on a worker.
    """
    osc, stop, x0, v0, t_end = core_inputs(values)
    t_eval = np.linspace(0.0, t_end, COMPARE_POINTS)
    ref = simulate(osc, stop, t_end, x0, v0, t_eval=t_eval, method="exact",
                   **reference_options(stop))
    x_ref = _at(ref, t_eval)
    rows: list[TradeRow] = []
    for method in methods:
        for accuracy in ACCURACIES:
            acc = ACCURACY[accuracy]
            used = method_options(method, stop)
            kwargs = preset_options(acc, used, osc)
            if "time_budget" in used:  # the solve itself stops, not only the wait for it
                kwargs["time_budget"] = budget_s
            if "max_steps" in used:  # stopped by time, as the page's solves
                kwargs["max_steps"] = SOLVE_MAX_STEPS

            def run(m=method, kw=kwargs):
                start = time.perf_counter()
                res = simulate(osc, stop, t_end, x0, v0, t_eval=t_eval, method=m, **kw)
                return time.perf_counter() - start, res

            future = _executor.submit(run)
            try:
                seconds, res = future.result(timeout=budget_s)
            except FutureTimeout:
                finer = ": finer presets not tried" if accuracy != ACCURACIES[-1] else ""
                rows.append(TradeRow(method, accuracy, math.inf, math.nan, "—",
                                     f"over {budget_s:g} s{finer}"))
                break
            except Exception as exc:  # noqa: BLE001 - a method that fails is reported
                rows.append(TradeRow(method, accuracy, math.nan, math.nan, "—",
                                     f"failed: {exc}"))
                continue
            error = position_error(_at(res, t_eval), x_ref)
            verdict = res.steady.kind.value
            note = (f"verdict differs from the reference ({ref.steady.kind.value})"
                    if verdict != ref.steady.kind.value
                    and not _rest_alike(res.steady, ref.steady, osc, stop, kwargs) else "")
            rows.append(TradeRow(method, accuracy, seconds, error, verdict, note))
    return rows


def _rest_alike(steady: Steady, ref: Steady, osc: Any, stop: Any,
                options: Mapping[str, Any]) -> bool:
    """A run at rest on a deformable stop whose tighter reference finds its loops still
    swinging within the run's own rule for rest (the reference's rule is tighter too): the
    same verdict at the run's accuracy."""
    if steady.kind is not SteadyKind.REST or not isinstance(stop, HystereticStop):
        return False
    return ref.at_rest_within(*rest_swing_of(osc, stop, options.get("rtol", 0.0),
                                             options.get("atol", 0.0)))


def _at(res, t_eval: np.ndarray) -> np.ndarray:
    """Positions of ``res`` at the times ``t_eval`` it was asked for (it adds its exact
    transition times to them)."""
    t = np.asarray(res.t)
    idx = np.clip(np.searchsorted(t, t_eval), 0, len(t) - 1)
    if np.array_equal(t[idx], t_eval):
        return np.asarray(res.x)[idx]
    return np.interp(t_eval, t, np.asarray(res.x))  # a result cut short: what it has


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
