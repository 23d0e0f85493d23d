"""The public entry points show every option they take (``help``, ``inspect``), with its
default, although the shared ones are written once (core/solve_inputs.py,
core.sweep.plan_grid); and an option nobody takes is refused by name."""

from __future__ import annotations

import dataclasses
import inspect

import pytest

from core import Oscillator, simulate
from core.deformable.solver import simulate_hysteretic
from core.event_method import EventOptions, simulate_event
from core.rigid import simulate_rigid
from core.sweep import sweep, sweep_grid
from core.sweep.distributed import sweep_distributed
from core.switch import SwitchOptions, simulate_switch

SHARED = {"stop": None, "t_end": 100.0, "x0": 0.0, "v0": 0.0, "n_samples": 2000,
          "transition_cap": 10_000, "t_eval": None}


def defaults(fn) -> dict:
    return {n: p.default for n, p in inspect.signature(fn).parameters.items()
            if p.default is not p.empty}


@pytest.mark.parametrize(
    ("fn", "own"),
    [
        (simulate, {"method": "exact", "rtol": None, "atol": None, "eta": None,
                    "max_steps": None, "time_budget": None}),
        (simulate_switch, {"rtol": 1e-6, "atol": 1e-9, "eta": None, "rest_speed": None}),
        (simulate_event, {"rtol": 1e-8, "atol": 1e-10, "solver": "RK45"}),
        (simulate_hysteretic, {"rtol": 1e-9, "atol": 1e-12, "arcs": True, "reduce": True}),
        (simulate_rigid, {}),
    ],
    ids=lambda x: getattr(x, "__name__", ""),
)
def test_solve_entries_list_the_shared_inputs_and_their_own_options(fn, own):
    params = inspect.signature(fn).parameters
    assert list(params)[:5] == ["osc", "stop", "t_end", "x0", "v0"]
    assert defaults(fn).items() >= {**SHARED, **own}.items()
    assert not any(p.kind is p.VAR_KEYWORD for p in params.values())


def test_solve_entry_refuses_an_unknown_option_by_name():
    with pytest.raises(TypeError, match="solver"):
        simulate(Oscillator(0.3, 0.2, 0.1), solver="RK45")
    with pytest.raises(TypeError, match="eta"):
        simulate_event(Oscillator(0.3, 0.2, 0.1), eta=1e-6)


SWEEP_OPTIONS = {"quantity": None, "t_end": 200.0, "method": "exact", "x0": 0.0, "v0": 0.0}


@pytest.mark.parametrize("fn", [sweep, sweep_grid, sweep_distributed], ids=lambda f: f.__name__)
def test_sweeps_list_their_options(fn):
    assert defaults(fn).items() >= SWEEP_OPTIONS.items()
    for name in SWEEP_OPTIONS:
        assert inspect.signature(fn).parameters[name].kind is inspect.Parameter.KEYWORD_ONLY


def test_sweep_refuses_an_unknown_option_by_name():
    with pytest.raises(TypeError, match="t_stop"):
        sweep(Oscillator(0.3, 0.2, 0.1), None, "belt_speed", [0.1], t_stop=10.0)


@pytest.mark.parametrize(("fn", "options"), [(simulate_event, EventOptions),
                                             (simulate_switch, SwitchOptions)],
                         ids=lambda x: x.__name__)
def test_a_methods_options_are_its_dataclass_fields_with_their_defaults(fn, options):
    """The options are declared once (core.method_entry.takes_options): the entry's own
    options are the dataclass's fields, in order, with the same defaults."""
    own = list(inspect.signature(fn).parameters.values())[len(SHARED) + 1:]
    assert [(p.name, p.default, p.kind) for p in own] == [
        (f.name, f.default, inspect.Parameter.KEYWORD_ONLY) for f in dataclasses.fields(options)]
