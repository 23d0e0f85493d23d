"""Regression tests of the exact solver, each named after the defect it guards.

References: finiteness and the definition of a period (defect 2), the impactless limit
cycle and scale invariance of the dimensionless equations (defect 3; docs/physics.md,
"Dimensionless form").
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import Oscillator, RigidStop, SteadyKind, simulate
from core.steady import pressed_on_stop, rest_force

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)


# ------------------------------------------------- defect 2: a zero period gave NaN samples


@pytest.mark.parametrize("v0", [1e-20, 1e-100, 5.46e-153])
def test_zero_period_bounce_is_rest_not_nan(v0):
    """An elastic bounce on a still belt, pressed on the stop, of speed v0: its period
    ~2 v0 / a is below the resolution of time. Once it was taken for a cycle of period 0
    and 502 of 504 samples were NaN."""
    osc = Oscillator(mu_s=1.0, mu_k=1.0, belt_speed=0.0)
    res = simulate(osc, RigidStop(0.0, 1.0), t_end=100.0, x0=0.0, v0=v0)
    assert np.all(np.isfinite(res.x)) and np.all(np.isfinite(res.v))
    assert res.steady.kind is SteadyKind.REST
    # The bounce rises v0^2 / (2 a) off the stop: below any sample's resolution.
    np.testing.assert_array_equal(res.x, 0.0)


def test_period_below_time_resolution_is_not_tiled():
    """Found by a random search: a stick->impact at belt speed 1e-12 against a stop
    pressed by a = 1 bounces with period ~2e-12; tiling it over t = 30 (1e13 periods)
    broke the energy balance by 3e-4."""
    osc = Oscillator(mu_s=1.0, mu_k=1.0, belt_speed=1e-12)
    res = simulate(osc, RigidStop(1e-12, 1.0), t_end=30.0, n_samples=500)
    e = res.energy
    residual = np.max(np.abs(e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss)))
    assert residual < 1e-20  # the kinetic energy involved is ~1e-24
    assert res.steady.kind is SteadyKind.REST
    assert not (res.steady.kind is SteadyKind.PERIODIC and res.steady.period <= 0.0)


# ------------------------------------- defect 3: false rest when the stop pulls away (x_bar > a)


def test_no_false_rest_one_rounding_step_inside_the_impactless_amplitude():
    """The slow-belt limit cycle reaches x = a + R; a stop 1e-15 inside is touched at a
    speed ~2e-8, which was taken for an accumulation although x_bar > a."""
    a, b, v = SLOW.a, SLOW.b, SLOW.v
    reach = a + math.hypot(b - a, v)
    res = simulate(SLOW, RigidStop(reach - 1e-15, 0.7), t_end=100.0)
    assert res.steady.kind is SteadyKind.PERIODIC
    assert res.steady.x_max == pytest.approx(reach, rel=1e-12)


def test_no_false_rest_for_a_tiny_static_deflection():
    """u_s = 1e-7 scales every length by 1e-7 (belt speed 1 is v = 1e7 u_s): the same
    grazing response as u_s = 1 with v = 1e7 and the stop at 0.25."""
    tiny = simulate(
        Oscillator(0.3, 0.2, 1.0, u_s=1e-7), RigidStop(2.5e-8, 0.7), t_end=100.0
    )
    unit = simulate(Oscillator(0.3, 0.2, 1e7), RigidStop(0.25, 0.7), t_end=100.0)
    assert unit.steady.kind is SteadyKind.GRAZING
    assert tiny.steady.kind is SteadyKind.GRAZING
    np.testing.assert_allclose(tiny.x / 1e-7, unit.x, rtol=0.0, atol=1e-9)


def test_tiny_elastic_bounce_pressed_by_the_belt_stays_periodic():
    """Pressed (x_bar < a) with r = 1 and lengths of 1e-8: the elastic impact cycle of
    §4.1, period 2 acos(1 - x_bar/a), must not be cut short as rest."""
    osc = Oscillator(0.3, 0.2, 1.0, u_s=1e-7)
    res = simulate(osc, RigidStop(1.5e-8, 1.0), t_end=50.0)
    assert res.steady.kind is SteadyKind.PERIODIC
    assert res.steady.period == pytest.approx(2 * math.acos(1 - 1.5e-8 / osc.a), rel=1e-9)


@pytest.mark.parametrize(
    ("osc", "reach"),
    [
        (SLOW, SLOW.a + math.hypot(SLOW.b - SLOW.a, SLOW.v)),  # slow belt: a + R
        (Oscillator(0.3, 0.2, 0.5), 0.4),  # fast belt: the circle 2a through the origin
    ],
    ids=["slow", "fast"],
)
@pytest.mark.parametrize("r", [0.0, 0.7, 1.0])
def test_continuous_through_the_grazing_tangency(osc, reach, r):
    """Stops a few rounding steps to 1e-9 either side of the tangency: the trajectory
    moves by O(sqrt(delta)) (the impact speed is sqrt(2 R delta)), never to rest."""
    grid = np.linspace(0.0, 60.0, 1201)
    base = simulate(osc, None, t_end=60.0, t_eval=grid)
    for delta in (-1e-9, -1e-12, -1e-15, -4e-16, 0.0, 1e-15, 1e-9):
        res = simulate(osc, RigidStop(reach + delta, r), t_end=60.0, t_eval=grid)
        assert res.steady.kind is not SteadyKind.REST
        # sqrt(2 * 0.5 * 1e-9) ~ 3e-5 per grazing impact, a few impacts within t = 60.
        assert np.max(np.abs(res.x - base.x)) < 1e-3


def test_pressed_rule_and_rest_force():
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    assert pressed_on_stop(osc, 0.2) and not pressed_on_stop(osc, 0.2 + 1e-15)
    assert rest_force(osc, 0.05) == pytest.approx(0.15, rel=1e-15)
    assert rest_force(osc, 0.3) == 0.0
    still = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.0)
    assert rest_force(still, -0.5) == pytest.approx(0.2, rel=1e-15)  # -x_bar - b


# -------------------------------------- defect 5: too many events is a status, not an error


def test_event_limit_returns_the_response_up_to_there():
    """rigid raised RuntimeError at its event limit; now it returns what it has."""
    from core.result import Status
    from core.rigid import simulate_rigid

    full = simulate(SLOW, RigidStop(0.29, 0.7), t_end=100.0)
    short = simulate_rigid(
        SLOW, RigidStop(0.29, 0.7), 100.0, 0.0, 0.0, n_samples=500, transition_cap=100,
        max_events=5,
    )
    assert short.status is Status.EVENT_LIMIT and not short.success
    assert short.steady.kind is SteadyKind.NONE
    t_last = short.t[-1]
    assert 0.0 < t_last < 100.0
    assert t_last >= short.transitions[-1].t  # the last event may be an impact not yet applied
    # The part it covers is the full response there.
    x, v = full.evaluate(short.t[short.t < t_last], 1)
    np.testing.assert_allclose(short.x[short.t < t_last], x, rtol=0.0, atol=1e-14)
    assert short.stats["events"] == short.n_transitions <= 5


# ---------------------------------------------------------- defect 6: ignored options


@pytest.mark.parametrize(
    ("method", "stop", "option"),
    [
        ("exact", None, "rtol"),
        ("exact", RigidStop(0.3, 0.5), "atol"),
        ("exact", RigidStop(0.3, 0.5), "eta"),
        ("event", RigidStop(0.3, 0.5), "eta"),
        ("exact", "hysteretic", "eta"),
    ],
)
def test_an_option_the_method_does_not_use_is_refused(method, stop, option):
    from core import HystereticStop

    if stop == "hysteretic":
        stop = HystereticStop(0.3)
    with pytest.raises(TypeError, match=option):
        simulate(SLOW, stop, t_end=10.0, method=method, **{option: 1e-6})


@pytest.mark.parametrize("value", [2.7, 2.0, "100", True])
def test_n_samples_must_be_an_integer(value):
    with pytest.raises(ValueError, match="n_samples must be an integer"):
        simulate(SLOW, None, t_end=10.0, n_samples=value)


@pytest.mark.parametrize("t_eval", [[0.0, 11.0], [[0.0, 1.0]], [0.0, math.nan]])
def test_t_eval_is_checked_once_for_every_method(t_eval):
    for method in ("exact", "event", "switch"):
        with pytest.raises(ValueError, match="t_eval"):
            simulate(SLOW, None, t_end=10.0, method=method, t_eval=t_eval)


def test_stats_are_integer_counts_and_diagnostics_are_info():
    from core.result import STATS_KEYS

    res = simulate(Oscillator(0.3, 0.2, 0.5), RigidStop(0.1, 0.6), t_end=50.0)
    assert tuple(res.stats) == STATS_KEYS
    assert all(type(v) is int for v in res.stats.values())
    assert res.stats["events"] == res.n_transitions
    assert res.info["impacts_evaluated"] > 10
