"""The page's numerical solves keep their own step limit (app/solver.py:
``SOLVE_MAX_STEPS``), not the core's lower defaults: they are stopped by their time
budget, and a retry with more time gets as many more steps."""

from __future__ import annotations

import pytest

import app.solver as solver_module
from app.state import scene_values


class _Asked(Exception):
    pass


def _options_of_solve(monkeypatch, budget):
    def record(*args, **kwargs):
        raise _Asked(kwargs)

    monkeypatch.setattr(solver_module, "_simulate", record)
    values = {**dict(scene_values("5a")), "method": "switch", "t_end": 61.2345}
    with pytest.raises(_Asked) as info:
        solver_module._solve(solver_module._key(values), False, budget)
    return info.value.args[0]


@pytest.mark.parametrize(
    ("budget", "factor"), [(None, 1.0), (solver_module.SOLVE_BUDGET_S, 1.0),
                           (10.0 * solver_module.SOLVE_BUDGET_S, 10.0)])
def test_the_page_passes_its_step_limit(monkeypatch, budget, factor):
    options = _options_of_solve(monkeypatch, budget)
    assert options["max_steps"] == int(solver_module.SOLVE_MAX_STEPS * factor)
    assert options["time_budget"] == (budget or solver_module.SOLVE_BUDGET_S)


def test_the_exact_method_on_a_deformable_stop_runs_to_its_end(monkeypatch):
    """The exact method on a deformable stop does not stop at the page's budget (the page
    waits for it in the background, and a retry joins the same solve): the page and its
    reference lift the core's default work limit (core.deformable.solver.DEFAULT_MAX_STEPS, a
    few seconds), so a long horizon is not cut short for want of steps."""
    def record(*args, **kwargs):
        raise _Asked(kwargs)

    monkeypatch.setattr(solver_module, "_simulate", record)
    values = {**dict(scene_values("10")), "method": "auto", "t_end": 61.2345}
    with pytest.raises(_Asked) as info:
        solver_module._solve(solver_module._key(values), False, None)
    options = info.value.args[0]
    assert options["method"] == "exact" and "time_budget" not in options
    assert options["max_steps"] == solver_module.MAX_STEPS
    stop = solver_module.core_inputs(values)[1]
    assert solver_module.reference_options(stop)["max_steps"] == solver_module.MAX_STEPS
