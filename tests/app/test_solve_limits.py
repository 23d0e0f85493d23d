"""The page's numerical solves keep their own step limit (app/solve/presets.py:
``SOLVE_MAX_STEPS``), not the core's lower defaults: they are stopped by their time
budget, and a retry with more time gets as many more steps."""

from __future__ import annotations

import pytest

from app.solve.measure import reference_options
from app.solve.presets import SOLVE_BUDGET_S, SOLVE_MAX_STEPS
from app.solve.process import Caller
from app.solve.solution import compute, solve_key
from app.state import core_inputs, scene_values
from core import MAX_STEPS


class _Asked(Exception):
    pass


def _record(*args, **kwargs):
    raise _Asked(kwargs)


def _options_of_solve(values: dict, budget: float) -> dict:
    """The options the page's solve of ``values`` passes to the core."""
    with pytest.raises(_Asked) as info:
        compute(solve_key(values), False, budget=budget, simulate=Caller(_record))
    return info.value.args[0]


@pytest.mark.parametrize(("budget", "factor"), [(SOLVE_BUDGET_S, 1.0),
                                                (0.5 * SOLVE_BUDGET_S, 1.0),
                                                (10.0 * SOLVE_BUDGET_S, 10.0)])
def test_the_page_passes_its_step_limit(budget, factor):
    options = _options_of_solve({**dict(scene_values("5a")), "method": "switch"}, budget)
    assert options["max_steps"] == int(SOLVE_MAX_STEPS * factor)
    assert options["time_budget"] == budget


def test_the_exact_method_on_a_deformable_stop_runs_to_its_end():
    """The exact method on a deformable stop does not stop at the page's budget (the page
    waits for it in the background, and a retry joins the same solve): the page and its
    reference lift the core's default work limit (core.deformable.solver.DEFAULT_MAX_STEPS, a
    few seconds), so a long horizon is not cut short for want of steps."""
    values = {**dict(scene_values("10")), "method": "auto"}
    options = _options_of_solve(values, SOLVE_BUDGET_S)
    assert options["method"] == "exact" and "time_budget" not in options
    assert options["max_steps"] == MAX_STEPS
    assert reference_options(core_inputs(values)[1])["max_steps"] == MAX_STEPS
