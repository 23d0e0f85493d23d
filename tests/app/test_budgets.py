"""Budgets of the page's long work. 'Measure the trade' runs in the solver processes, within
a budget, one at a time per page; a sweep states its budget before it starts, stops at it
with what it has, and a sweep estimated past it is refused; both stop when the page closes.

The probes below stand in for ``core.simulate`` (or ``core.sweep.sweep``); a solver process
gets them by reference (module-level functions and classes of this module), and the slow
ones record their process id in the file they carry (a test's own).
"""

from __future__ import annotations

import importlib
import os
import pathlib
import time
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import panel as pn
import pytest
from bokeh.document import Document
from panel.io.state import set_curdoc

from app import sweep_budget
from app.bifurcation import ChunkedSweep, SweepSpec, check_spec, default_range
from app.solve import process as solve_process
from app.solve import trade
from app.state import scene_values
from core import simulate as core_simulate
from tests.app.processes import alive

#: How long [s] a probe's slow solve sleeps: far past every budget used here, so that a
#: measurement that returns before it kept to its budget (the sleeping process was stopped).
SLEEP_S = 20.0
#: How long [s] a test waits for a process to start or to end (a fresh solver process
#: imports this module first; a stopped one is reaped by a thread).
WAIT_S = 30.0


@dataclass(frozen=True)
class _SlowExact:
    """The exact method (the reference) records its process in ``path``, then sleeps;
    others are the core's."""

    path: str

    def __call__(self, osc, stop, t_end, *args, method, **kwargs):
        if method == "exact":
            pathlib.Path(self.path).write_text(str(os.getpid()))
            time.sleep(SLEEP_S)
        return core_simulate(osc, stop, t_end, *args, method=method, **kwargs)


def _slow_numerical(osc, stop, t_end, *args, method, **kwargs):
    """``event`` and ``switch`` sleep, past their own time budget; ``exact`` is the
    core's."""
    if method != "exact":
        time.sleep(SLEEP_S)
    return core_simulate(osc, stop, t_end, *args, method=method, **kwargs)


class _InChild(RuntimeError):
    """Raised by :func:`_raise_pid` with the id of the process it ran in."""


def _raise_pid(*args, **kwargs):
    raise _InChild(os.getpid())


def _pid() -> int:
    return os.getpid()


def _warm() -> None:
    """Start the solver processes, and have the next solve's import this module (a fresh
    one takes a second: past the small budgets used here)."""
    solve_process.warm_up(wait=True)
    solve_process.call(_pid)


def _values(t_end: float = 60.0) -> dict:
    """Scene 5b (a rigid stop: the closed form is the reference)."""
    return {**scene_values("5b"), "t_end": t_end}


def _wait_for(condition, what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, what
        time.sleep(0.01)


def _started(path: pathlib.Path) -> int:
    """The process id a probe recorded in ``path``, once it has."""
    _wait_for(lambda: path.exists() and path.read_text(), "the probe never started")
    return int(path.read_text())


@pytest.fixture
def probe_file(tmp_path) -> pathlib.Path:
    """The file a slow probe records its process in."""
    return tmp_path / "probe-pid"


def test_a_measurement_solves_in_a_solver_process_not_the_server_s(monkeypatch):
    """Defect: the reference and every preset's solve ran in the server process (scene 10
    to t_end = 5000: 5 s holding the server's interpreter lock; repeated clicks pushed
    other pages' p95 move latency from 65 ms to 1.2 s)."""
    solve_process.warm_up(wait=True)
    monkeypatch.setattr(trade, "simulate", _raise_pid)
    with pytest.raises(_InChild) as info:
        trade.measure(_values())
    assert info.value.args[0] != os.getpid()


def test_a_reference_past_its_share_of_the_budget_stops_and_says_why(monkeypatch,
                                                                     probe_file):
    """Defect: a measurement had no budget; its reference solve (not budgeted by the core)
    ran as long as it took. It is stopped at half the measurement's budget, its process
    too."""
    solve_process.warm_up(wait=True)
    monkeypatch.setattr(trade, "simulate", _SlowExact(str(probe_file)))
    with pytest.raises(Exception, match=r"did not finish within 0\.5 s") as info:
        trade.measure(_values(), total_s=1.0)
    assert type(info.value).__name__ == "ReferenceTooSlow"
    pid = _started(probe_file)
    _wait_for(lambda: not alive(pid), "the stopped reference's process still runs")


def test_solves_past_the_measurement_s_budget_are_not_made_and_their_rows_say_so(
        monkeypatch):
    """Each solve is stopped at its own budget (a method past it is not tried at the finer
    presets) and none is started past the whole measurement's: the rows say which."""
    _warm()
    monkeypatch.setattr(trade, "simulate", _slow_numerical)
    rows = trade.measure(_values(), methods=("event", "switch"), budget_s=0.5, total_s=1.0)
    notes = [(r.method, r.accuracy, r.note) for r in rows]
    assert notes[0] == ("event", "draft", "over 0.5 s: finer presets not tried"), notes
    # The event method's draft solve was stopped at 0.5 s plus its grace: the measurement's
    # 1 s was used up, so no switch solve was started.
    assert [n[:2] for n in notes[1:]] == [("switch", a) for a in ("draft", "standard",
                                                                  "precise")]
    assert all(n[2] == "not measured: the measurement's budget of 1 s ran out"
               for n in notes[1:]), notes
    assert "not measured" in trade.trade_html(rows)


def test_a_second_measurement_of_a_page_is_refused_while_one_runs(monkeypatch, probe_file):
    """Defect: every click started another measurement (the button is disabled while one
    runs, but a page can send clicks anyway). A second is refused with a message; the
    button comes back when the first ends, here cancelled."""
    from app.explorer import Explorer

    solve_process.warm_up(wait=True)
    monkeypatch.setattr(trade, "simulate", _SlowExact(str(probe_file)))
    ex = Explorer()
    label = ex.measure.label
    ex.measure.clicks += 1
    pid = _started(probe_file)
    assert ex.measure.disabled and "at most 30 s" in ex.measure.label
    ex.measure.clicks += 1  # a page can send a click to a disabled button
    assert ex.alert.visible
    assert "Not measured:</b> a measurement is already running for this page" in \
        ex.alert.object
    assert probe_file.read_text() == str(pid)  # no second solve started
    ex.close()  # the page closed: its measurement is cancelled
    _wait_for(lambda: not ex.measure.disabled, "the button stayed disabled")
    assert ex.measure.label == label
    assert not ex.alert.visible  # "already running" no longer holds
    _wait_for(lambda: not alive(pid), "the cancelled measurement's process still runs")


def test_with_the_solver_processes_off_a_cancelled_measurement_makes_no_further_solve(
        monkeypatch):
    """In the calling thread a solve cannot be stopped; a cancelled measurement starts no
    other (it had gone on through every method and preset)."""
    import threading

    monkeypatch.setenv(solve_process.SWITCH, "off")
    stop = threading.Event()
    stop.set()
    with pytest.raises(solve_process.Abandoned):
        trade.measure(_values(), stop=stop)


def test_the_server_refuses_measurements_past_its_queue(monkeypatch, probe_file):
    """One measuring thread per server: past :data:`app.solve.trade.MEASURE_QUEUE` waiting, the
    next page's measurement is refused at once instead of queueing."""
    solve_process.warm_up(wait=True)
    monkeypatch.setattr(trade, "simulate", _SlowExact(str(probe_file)))
    runners = [trade.TradeRunner(lambda v, r: None, lambda e: None)
               for _ in range(trade.MEASURE_QUEUE + 2)]
    try:
        for runner in runners[:-1]:
            runner.start(_values())
        pid = _started(probe_file)  # the first runs, the others wait
        with pytest.raises(trade.MeasureRefused, match="measuring the trade for other pages"):
            runners[-1].start(_values())
    finally:
        for runner in runners:
            runner.cancel()
    _wait_for(lambda: not alive(pid), "the cancelled measurement's process still runs")


def test_a_closed_page_stops_its_measurement_and_frees_its_solver_process(monkeypatch,
                                                                          probe_file):
    """Defect: a measurement went on after its page closed. The server's end of the
    session (its destroyed callbacks) stops it, and its solver process."""
    solve_process.warm_up(wait=True)
    monkeypatch.setattr(trade, "simulate", _SlowExact(str(probe_file)))
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
    ex = template.explorer
    ex.measure.clicks += 1
    pid = _started(probe_file)
    assert ex.measure.disabled  # while it runs
    for callback in list(doc.session_destroyed_callbacks):
        callback(SimpleNamespace(destroyed=True))
    _wait_for(lambda: not alive(pid), "the closed page's measurement still runs")
    _wait_for(lambda: not ex.measure.disabled, "the measurement did not end")


# --- sweeps ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class _SleepySweep:
    """Stands in for ``core.sweep.sweep`` in a solver process: records its process in
    ``path``, then sleeps."""

    path: str

    def __call__(self, osc, stop, parameter, values, **options):
        pathlib.Path(self.path).write_text(str(os.getpid()))
        time.sleep(SLEEP_S)
        raise AssertionError("the sweep was not stopped")


class _Session:
    """A server session's document as the sweep uses it: its next-tick callbacks are kept
    (and not run: the sweep stays where it is)."""

    session_context = SimpleNamespace(destroyed=False)

    def add_next_tick_callback(self, fn) -> None:
        pass


def _opened(scene: str = "5a"):
    from app.explorer import Explorer
    from app.state import ExplorerState

    ex = Explorer(ExplorerState(scene=scene, **scene_values(scene)))
    ex.open_sweeps.clicks += 1
    return ex


def test_a_sweep_estimated_past_its_budget_is_refused_with_the_points_that_fit():
    """Defect: a sweep had no budget; a deformable stop's 200,000 points (~0.1 s each)
    would have run for hours while the tab was open. The estimate (points times the cost
    of a point) is checked before it starts."""
    values = scene_values("10")
    lo, hi = default_range(values, "belt_speed")
    most = sweep_budget.max_points(closed=False, t_end=values["t_end"])
    # the largest count whose estimate fits the budget
    cost = sweep_budget.INTEGRATED_S_PER_TIME * values["t_end"]
    assert most * cost <= sweep_budget.SWEEP_BUDGET_S < (most + 1) * cost
    with pytest.raises(ValueError, match=rf"points must be at most {most} for this run.*"
                                         r"got 200000"):
        check_spec(values, "belt_speed", lo, hi, 200_000, "impact_speed")
    check_spec(values, "belt_speed", lo, hi, most, "impact_speed")
    # The closed form (a rigid stop): 200,000 points fit.
    closed = scene_values("5a")
    check_spec(closed, "belt_speed", *default_range(closed, "belt_speed"), 200_000,
               "impact_speed")


def test_a_sweep_s_card_states_its_budget_before_it_starts(monkeypatch):
    ex = _opened()
    view = ex.sweeps
    said = []  # the card's status when the sweep starts
    monkeypatch.setattr(view.job, "start", lambda *a, **k: said.append(view.status.object))
    view.points.value = 2000
    view.start()
    estimate = sweep_budget.estimate_s(2000, closed=True, t_end=200.0)
    assert len(said) == 1
    assert (f">Sweeping 2000 values of belt speed v (about {estimate:.2g} s; at most "
            f"{sweep_budget.SWEEP_BUDGET_S:g} s: stops with what it has)…<") in said[0]


def test_a_sweep_stopped_at_its_budget_keeps_what_it_has_and_says_so(monkeypatch):
    ex = _opened()
    view = ex.sweeps
    monkeypatch.setattr(sweep_budget, "SWEEP_BUDGET_S", 1e-6)  # over after the first chunk
    monkeypatch.setattr(sweep_budget, "check_cost", lambda *a, **k: None)
    view.points.value = 5000
    view.start()  # no session: the chunks run before it returns
    first = len(view.data.swept)
    assert 0 < first < 5000 and not view.job.running and view.stop.disabled
    assert len(view.source.data["x"]) == len(view.data.x) > 0  # what it has is drawn
    status = view.status.object
    assert f"Stopped at the sweep's budget of 1e-06 s after {first} of 5000 values" in status
    assert "the diagram shows what it has" in status
    assert f"swept up to {view.data.swept.max():.4g}" in status


def _sleep_in_a_solver_process(task, chunk, cancelled):
    return solve_process.call(_SleepySweep(task), None, None, "belt_speed", chunk,
                              cancelled=cancelled)


def test_a_chunk_running_past_the_sweep_s_budget_is_stopped(probe_file):
    """A chunk in a solver process that outlives the budget (by a chunk's aim) is stopped;
    the sweep says it was cut, not that it failed."""
    _warm()
    cut, failed = [], []
    job = ChunkedSweep(_sleep_in_a_solver_process, lambda *a: pytest.fail("no chunk ends"),
                       failed.append, lambda done, total: cut.append((done, total)))
    job.start(str(probe_file), np.arange(10.0), 10, scene_values("10"), target_s=0.2,
              budget_s=0.3)
    assert cut == [(0, 10)] and failed == [] and not job.running
    pid = _started(probe_file)
    _wait_for(lambda: not alive(pid), "the chunk's process still runs")


def test_a_closed_page_stops_its_sweep_and_frees_its_solver_process(monkeypatch,
                                                                    probe_file):
    """Defect: a sweep's running chunk went on after its page closed (the next chunk was
    not submitted only once the session was gone). The server's end of the session stops
    it, and its solver process."""
    from app import bifurcation

    _warm()
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
    ex = template.explorer
    ex.open_sweeps.clicks += 1  # scene 5a, closed form: swept at once
    session = _Session()
    monkeypatch.setattr(type(pn.state), "curdoc", property(lambda self: session))
    monkeypatch.setattr(bifurcation.sweeps, "sweep", _SleepySweep(str(probe_file)))
    values = {**scene_values("10"), "t_end": 60.0}
    spec = SweepSpec(values, "belt_speed", 0.01, 0.1, 10, "impact_speed")
    ex.sweeps.job.start(spec, spec.grid(), 1, values, 2.0, 60.0)
    pid = _started(probe_file)
    assert ex.sweeps.job.running
    for callback in list(doc.session_destroyed_callbacks):
        callback(SimpleNamespace(destroyed=True))
    _wait_for(lambda: not alive(pid), "the closed page's sweep still runs")


def test_a_simulated_map_estimated_past_the_budget_is_refused(monkeypatch):
    """The simulated regime map is a sweep too: a deformable stop's 16 x 16 cells to
    t = 5000 (~2,000 s by the estimate) are not started, and the card says why."""
    ex = _opened()
    view = ex.sweeps
    values = {**scene_values("10"), "t_end": 5000.0}
    monkeypatch.setattr(view, "_values", lambda: values)
    view.sim_layer.value = True
    most = sweep_budget.max_points(closed=False, t_end=5000.0)
    assert "The regime map is not simulated: its 16 x 16 cells exceed the sweep's budget" \
        in view.map_status.object
    assert f"at most {most} for this run" in view.map_status.object
    assert not view.map_job.running and view.map_job.submitted == 0
