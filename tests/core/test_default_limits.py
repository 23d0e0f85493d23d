"""A numerical method called without work limits stops at its own default step limit,
whatever the horizon, and says how far it got (core/switch.py, core/event_method.py:
``DEFAULT_MAX_STEPS``). Wall time is measured in benchmarks/default_limits.py, not here."""

from __future__ import annotations

import numpy as np
import pytest

from core import (
    HystereticStop,
    Oscillator,
    RigidStop,
    Status,
    event_method,
    simulate,
    switch,
)
from core.deformable import solver as hysteretic
from core.deformable.state import MAP_CONTACTS_PER_STEP
from core.simulate import MAX_STEPS

#: Scene 5a: an elastic stop and a slow belt, one impact per period (never at rest).
OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
STOP = RigidStop(clearance=0.32, restitution=1.0)
T_END = 1e7


@pytest.mark.parametrize(
    ("method", "steps", "default"),
    [
        ("switch", lambda s: s["steps"] + s["rejected"], switch.DEFAULT_MAX_STEPS),
        ("event", lambda s: s["steps"], event_method.DEFAULT_MAX_STEPS),
    ],
)
def test_a_default_call_stops_at_its_step_limit_and_says_where(method, steps, default):
    """Regression: with no limits given, switch to t_end = 1e7 ran 2e6 steps (37 s) and
    event to 1e6 2e6 steps (154 s) before STEP_LIMIT. The default now stops at the
    method's own limit, with the status and the time reached, the samples covering
    [0, t reached] only; the same call with that limit given explicitly is the same."""
    res = simulate(OSC, STOP, t_end=T_END, method=method)
    assert res.status is Status.STEP_LIMIT and not res.success
    assert steps(res.stats) == default
    t_reached = float(res.t[-1])
    # the scene's period is ~6: the limit is reached after hundreds of cycles at least
    assert 100.0 < t_reached < T_END
    assert np.all(np.isfinite(res.x)) and res.t[0] == 0.0
    # the result says, in words, where it stopped and why
    assert f"Stopped at t = {t_reached:.6g}." in res.message
    assert "limit on the number of integration steps" in res.message
    again = simulate(OSC, STOP, t_end=T_END, method=method, max_steps=default, n_samples=50)
    assert again.status is Status.STEP_LIMIT and float(again.t[-1]) == t_reached


def test_a_given_limit_still_overrides_the_default():
    """``max_steps`` above the default goes further; one below stops sooner."""
    short = simulate(OSC, STOP, t_end=T_END, method="event", max_steps=500, n_samples=50)
    assert short.status is Status.STEP_LIMIT and short.stats["steps"] == 500
    assert 0.0 < float(short.t[-1]) < 0.1 * event_method.DEFAULT_MAX_STEPS


#: A grazing train on the page's deformable stop: ~4.6e4 steps (contact steps, arcs,
#: transitions) per 1e4 of time, never steady; to 1e5 it took 7-13 s with no limit.
GRAZING_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
GRAZING_STOP = HystereticStop(clearance=0.3, k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                              beta_c=300.0, beta_e=300.0)


def test_exact_on_a_deformable_stop_stops_at_its_default_limit_and_says_where():
    """Regression: the exact method on a deformable stop had no work limit short of 2e6
    transitions: a grazing train ran on for a time that grows with the horizon (to 1e9,
    still allowed). A default call now stops at ``core.deformable.solver.DEFAULT_MAX_STEPS``
    steps, at the first transition past it, with the status and the time reached; the
    same call with that limit given is the same."""
    res = simulate(GRAZING_OSC, GRAZING_STOP, t_end=1e5)
    assert res.status is Status.STEP_LIMIT and not res.success
    work = res.info["work_steps"]
    # checked at each transition: one contact's steps (~30 here) past the limit at most
    assert hysteretic.DEFAULT_MAX_STEPS <= work < hysteretic.DEFAULT_MAX_STEPS + 1000
    t_reached = float(res.t[-1])
    # a contact every ~6 time units: thousands of them before the limit
    assert 1e4 < t_reached < 1e5
    assert np.all(np.isfinite(res.x)) and res.t[0] == 0.0
    again = simulate(GRAZING_OSC, GRAZING_STOP, t_end=1e5,
                     max_steps=hysteretic.DEFAULT_MAX_STEPS, n_samples=50)
    assert again.status is Status.STEP_LIMIT and float(again.t[-1]) == t_reached


def test_exact_on_a_deformable_stop_within_the_limit_is_unchanged():
    """A solve that ends before the default limit gives the same result with none."""
    res = simulate(GRAZING_OSC, GRAZING_STOP, t_end=2e3)
    free = simulate(GRAZING_OSC, GRAZING_STOP, t_end=2e3, max_steps=MAX_STEPS)
    assert res.status is Status.SUCCESS is free.status
    assert res.info["work_steps"] < hysteretic.DEFAULT_MAX_STEPS
    np.testing.assert_array_equal(res.t, free.t)
    np.testing.assert_array_equal(res.x, free.x)
    assert res.steady == free.steady


def test_exact_on_a_deformable_stop_takes_max_steps_only():
    """``max_steps`` is checked like the other methods'; ``time_budget`` is refused by name
    (the exact method has no clock: a default call gives the same result anywhere)."""
    short = simulate(GRAZING_OSC, GRAZING_STOP, t_end=1e3, max_steps=300, n_samples=50)
    assert short.status is Status.STEP_LIMIT and 300 <= short.info["work_steps"] < 1300
    with pytest.raises(ValueError, match=r"max_steps must be.*got 0"):
        simulate(GRAZING_OSC, GRAZING_STOP, t_end=10.0, max_steps=0)
    with pytest.raises(TypeError, match="time_budget"):
        simulate(GRAZING_OSC, GRAZING_STOP, t_end=10.0, time_budget=1.0)


def test_a_train_laid_out_by_its_map_counts_against_the_work_limit():
    """Regression: the contacts the contact-to-contact map lays out (a mass pressed on the
    stop, benchmarks/hysteretic_speed.py's cell k_c0 100, beta 10, D 0.1) were not counted:
    7.5e5 to t_end = 1e6 in ~1 s, and to 1e9 arrays of 7.5e8 contacts. They now count one
    step per ``MAP_CONTACTS_PER_STEP``: the map stops where the limit is spent."""
    osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=0.25, u_s=2.0)
    stop = HystereticStop(0.42, 100.0, 50.0, limit_overlap=0.1, beta_c=10.0, beta_e=10.0)
    limit = 20_000
    res = simulate(osc, stop, t_end=1e6, max_steps=limit, n_samples=50)
    assert res.status is Status.STEP_LIMIT
    assert limit <= res.info["work_steps"] < limit + 1000
    # the map's contacts fill what the solve before it left of the limit, no more
    assert res.info["n_contacts"] <= limit * MAP_CONTACTS_PER_STEP
    assert 0.0 < float(res.t[-1]) < 1e6 and np.all(np.isfinite(res.x))
    # within the default limit the same train runs to the horizon
    full = simulate(osc, stop, t_end=1e6, n_samples=50)
    assert full.status is Status.SUCCESS and full.info["n_contacts"] > 5e5
