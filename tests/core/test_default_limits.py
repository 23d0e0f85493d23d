"""A numerical method called without work limits stops at its own default step limit,
whatever the horizon, and says how far it got (core/switch.py, core/event_method.py:
``DEFAULT_MAX_STEPS``). Wall time is measured in benchmarks/default_limits.py, not here."""

from __future__ import annotations

import numpy as np
import pytest

from core import Oscillator, RigidStop, Status, event_method, simulate, switch

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
