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


@pytest.mark.parametrize(
    ("method", "stop"),
    [("exact", RigidStop(0.25, 0.7)), ("switch", RigidStop(0.25, 0.7)),
     ("event", RigidStop(0.25, 0.7)), ("exact", "hysteretic")],
)
def test_every_method_samples_at_t_eval(method, stop):
    """The driver hands ``t_eval`` to every method (it used to reach the rigid one only)."""
    from core import HystereticStop

    if stop == "hysteretic":
        stop = HystereticStop(0.25, 1000.0, 500.0, limit_overlap=1e-3, beta_c=10, beta_e=10)
    times = np.array([0.0, 3.3, 17.0, 41.5, 50.0])
    res = simulate(SLOW, stop, t_end=50.0, method=method, t_eval=times)
    np.testing.assert_array_equal(res.t, times)
    # Every method's samples are its own dense solution at those times (left limits).
    x, v = res.evaluate(times)
    np.testing.assert_allclose(res.x, x, rtol=0, atol=1e-12)


@pytest.mark.parametrize("method", ["switch", "event"])
def test_work_limits_reach_the_numerical_methods(method):
    from core import Status

    res = simulate(SLOW, RigidStop(0.25, 0.7), t_end=50.0, method=method, max_steps=10)
    assert res.status is Status.STEP_LIMIT
    assert res.t[-1] < 50.0
    with pytest.raises(TypeError, match="max_steps"):
        simulate(SLOW, RigidStop(0.25, 0.7), t_end=50.0, max_steps=10)


#: A start at rest on a stop the belt does not press on (x_bar = 0.25 > a = 0.2): the slip
#: circle about (a, 0) through it only touches the stop.
START_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)


@pytest.mark.parametrize("r", [0.0, 0.7, 1.0])
def test_a_start_at_rest_on_the_stop_is_the_impactless_circle(r):
    """x0 = x_bar, v0 = 0 was "grazing" with no impact at all, while x0 = x_bar - 1e-7 and
    the event method gave pure slip. Grazing is a limit of impacts; a circle that only
    touches the stop from an impactless start is the impactless one (docs/physics.md).
    Reference: the start 1e-7 inside (the label must not jump), the event method, the
    circle's closed form (x_max = x0, period 2 pi), and the sweep's vectorised lanes."""
    from core.sweep import sweep

    stop = RigidStop(0.25, r)
    on = simulate(START_OSC, stop, t_end=40.0, x0=0.25)
    near = simulate(START_OSC, stop, t_end=40.0, x0=0.25 - 1e-7)
    event = simulate(START_OSC, stop, t_end=40.0, x0=0.25, method="event")
    assert on.transition_counts == {}
    assert on.steady.kind is near.steady.kind is event.steady.kind is SteadyKind.PURE_SLIP
    assert on.steady.x_max == 0.25 and on.steady.period == 2.0 * math.pi
    lanes = sweep(START_OSC, stop, "restitution", [r, 0.5 * (1.0 + r)], x0=0.25, t_end=40.0)
    assert all(str(k) == "pure_slip" for k in np.ravel(lanes.labels))


def test_a_start_at_rest_on_a_deformable_stop_is_the_impactless_circle():
    """The deformable stop's exact solver already reads it so: zero overlap, no contact."""
    from core import HystereticStop

    stop = HystereticStop(0.25, 400.0, 36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
    res = simulate(START_OSC, stop, t_end=40.0, x0=0.25)
    assert res.transition_counts == {} and res.steady.kind is SteadyKind.PURE_SLIP


@pytest.mark.parametrize("v0", [-0.05, 0.05])
def test_a_start_on_the_stop_with_speed_impacts_and_grazes(v0):
    """Moving into the stop it impacts at once, moving away it comes back to it: either
    way the impacts die out as r^h towards the touching circle (grazing), in every method."""
    stop = RigidStop(0.25, 0.7)
    labels = {m: simulate(START_OSC, stop, t_end=60.0, x0=0.25, v0=v0, method=m).steady.kind
              for m in ("exact", "event", "switch")}
    assert set(labels.values()) == {SteadyKind.GRAZING}, labels


def test_a_plastic_impact_that_leaves_the_stop_still_grazes():
    """The rule the start at rest must not break: after a plastic impact with x_bar > a
    the mass leaves the stop at zero speed on the touching circle, grazing reached."""
    res = simulate(START_OSC, RigidStop(0.25, 0.0), t_end=40.0, x0=0.25, v0=0.05)
    assert res.transition_counts == {"impact": 1}
    assert res.steady.kind is SteadyKind.GRAZING and res.steady.t_reached == 0.0


def test_a_range_in_an_error_holds_only_values_that_are_taken():
    """t_end = -1 was told "must lie in (0, inf]", yet t_end = inf is refused as not
    finite: an infinite end is printed closed only where it is accepted."""
    from core.validation import check_range

    with pytest.raises(ValueError, match=r"t_end must lie in \(0, 1e\+09\]; got -1"):
        simulate(START_OSC, None, t_end=-1.0)
    with pytest.raises(ValueError, match="t_end must be a finite number"):
        simulate(START_OSC, None, t_end=math.inf)
    with pytest.raises(ValueError, match=r"must lie in \[0, inf\]; got -1"):
        check_range("strength", -1.0, 0.0, allow_inf=True)
    assert check_range("strength", math.inf, 0.0, allow_inf=True) == math.inf
    with pytest.raises(ValueError, match=r"x must lie in \(-inf, 0\]; got 1"):
        check_range("x", 1.0, high=0.0)


# ------------------------- an arc that starts on or next to the stick line: an immediate stick


def energy_residual(res) -> float:
    e = res.energy
    return float(np.max(np.abs(e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss))))


@pytest.mark.parametrize("x0", [0.0, 0.1, -0.1])
@pytest.mark.parametrize("rel", [1e-13, -1e-13, 1e-15, -1e-15, 2.0**-52])
def test_a_start_next_to_the_belt_speed_sticks_at_once(x0, rel):
    """x' = v (1 - rel): slip whose acceleration drives the relative velocity to zero
    (x'' = s a - x0, here towards v from either side), so it sticks after
    ~|u_r| / |x''| <= 1e-13. The phase to the stick line, formed as a difference of two
    atan2 and cut by a tolerance of 1e-12, came out a whole turn: the mass slipped round a
    circle first, and x_max was 0.4236 instead of the limit cycle's 0.3414.
    Reference: the stick time |u_r| / |x''| to first order, the limit cycle's closed form
    x_max = a + sqrt((b - a)^2 + v^2) (docs/physics.md, "Closed-form results")."""
    v0 = SLOW.v * (1.0 - rel)
    s = 1.0 if v0 < SLOW.v else -1.0
    accel = abs(s * SLOW.a - x0)
    res = simulate(SLOW, None, t_end=20.0, x0=x0, v0=v0)
    first = res.transitions[0]
    assert first.kind.value == "slip->stick"
    # |u_r| / |x''| to first order; rounding of the start (an ulp of v) adds ~1e-16 / |x''|.
    assert first.t == pytest.approx(abs(SLOW.v - v0) / accel, rel=1e-3, abs=2e-15)
    limit_top = SLOW.a + math.hypot(SLOW.b - SLOW.a, SLOW.v)
    assert res.x_max == pytest.approx(limit_top, rel=1e-12)


@pytest.mark.parametrize("v", [2e-14, 1e-16, 5e-13 * 0.2])
def test_a_very_slow_belt_sticks_at_once_from_rest(v):
    """From rest on a belt slower than ~5e-13 a the slip->stick comes after asin(v/a) ~ v/a
    (Eq. 30); the solver ran a whole slip circle instead, and with a stop at 0.25 it
    reported an impact at 0.25 while the mass sticks next to 0 and is carried at speed v.
    Reference: Eq. (30), and the stick line x = v t after it."""
    osc = Oscillator(0.3, 0.2, v)
    for stop in (None, RigidStop(0.25, 0.5)):
        res = simulate(osc, stop, t_end=20.0)
        kinds = [tr.kind.value for tr in res.transitions]
        assert kinds == ["slip->stick"]
        assert res.transitions[0].t == pytest.approx(math.asin(v / osc.a), rel=1e-12)
        # Stuck from t ~ v/a on, x <= v t_end; the slip before moves it by ~v^2/a.
        assert res.x_max <= v * 20.0 * (1.0 + 1e-12)


def test_a_start_a_rounding_step_below_the_stop_impacts_at_once():
    """The stop an ulp ahead with x' > 0: the impact is now, not a turn later (the phase to
    the stop is formed as gap times positive terms)."""
    xb = 0.25
    for v0 in (0.05, 1e-3):
        res = simulate(SLOW, RigidStop(xb, 0.7), t_end=10.0, x0=math.nextafter(xb, 0.0), v0=v0)
        first = res.transitions[0]
        assert first.kind.value == "impact"
        assert first.t <= 2.0 * math.ulp(xb) / v0  # the gap over the speed, to rounding


# --------------------------- precision near tangencies: the closed form to rounding, not sqrt(eps)


def _elastic_case_c_state(osc, xb, t):
    """Independent closed form of the elastic case c (docs/physics.md, "Closed-form results")
    at 40 digits: from rest the first slip->stick at Eq. (30), stick to the stop, then the
    rebound arc about (a, 0) through (x_bar, -v) repeated with period 2 atan2(v, a - x_bar)."""
    import mpmath as mp

    with mp.workdps(40):
        a, v, xb = mp.mpf(osc.a), mp.mpf(osc.v), mp.mpf(xb)
        t_hit = mp.asin(v / a) + (xb - (a - mp.sqrt(a * a - v * v))) / v
        period = 2 * mp.atan2(v, a - xb)
        tau = mp.fmod(mp.mpf(t) - t_hit, period)
        d = xb - a
        return float(a + d * mp.cos(tau) - v * mp.sin(tau)), float(period)


@pytest.mark.parametrize(
    ("v", "gap"), [(0.15, 5.6e-9), (0.1, 3.2e-9), (0.19, 5.6e-9), (0.05, 1.8e-9), (0.1, 1e-6)]
)
def test_elastic_cycle_next_to_the_slip_centre_is_exact(v, gap):
    """Elastic stop at x_bar = a - gap (case c): the rebound comes back to the stop exactly
    on the stick line. The crossing of the stick line was an asin of a number within
    ~gap^2/v^2 of 1, off by sqrt(eps): periods up to 6e-10 (relative) off
    2 atan2(v, a - x_bar), a state 2e-7 off at t = 1e4 and an energy balance off by 2e-7.
    Both events now come from the same products and are exactly tied (the impact wins).
    Tolerances: the period is a difference of two event times below ~10, rounded to
    ~1e-15; over t = 1e4 (~3200 periods) the phase then drifts by < 1e-11."""
    osc = Oscillator(0.3, 0.2, v)
    xb = osc.a - gap
    t_end = 1e4
    res = simulate(osc, RigidStop(xb, 1.0), t_end=t_end, t_eval=np.linspace(0.0, t_end, 2001))
    x_ref, period = _elastic_case_c_state(osc, xb, t_end)
    assert res.steady.sequence == ("impact",)
    assert res.steady.period == pytest.approx(period, rel=1e-12)
    assert abs(res.x[-1] - x_ref) < 1e-11
    assert energy_residual(res) < 1e-10


@pytest.mark.parametrize("eps", [1e-7, 1e-9, 1e-5])
def test_stick_slip_cycle_with_mu_s_barely_above_mu_k_is_exact(eps):
    """mu_s = mu_k (1 + eps): the slip arc after stick->slip at (b, v) returns to the stick
    line a hair before (2a - b, v), after pi + 2 atan2(v, b - a). The crossing was an asin
    near 1: period 2.8e-11 off (relative), energy balance off by 5.5e-9 at t = 1e4.
    Reference: the limit cycle's closed form (docs/physics.md, "Closed-form results")."""
    osc = Oscillator(0.2 * (1.0 + eps), 0.2, 0.1)
    a, b, v = osc.a, osc.b, osc.v
    period = 2.0 * (b - a) / v + math.pi + 2.0 * math.atan2(v, b - a)
    res = simulate(osc, None, t_end=1e4)
    assert res.steady.kind is SteadyKind.PERIODIC
    assert res.steady.period == pytest.approx(period, rel=1e-12)
    assert res.steady.x_max == pytest.approx(a + math.hypot(b - a, v), rel=1e-12)
    assert energy_residual(res) < 1e-10


@pytest.mark.parametrize(
    ("osc", "clearance", "t_end"),
    [
        (Oscillator(0.3, 0.2, 0.5), 0.3, 1e9),  # §4.1's elastic impact cycle
        (Oscillator(0.3, 0.2, 0.5), 3.16e-12, 1e4),  # the same with periods of ~1e-5
        (Oscillator(0.3, 0.2, 0.1), 0.2 - 1e-9, 1e5),  # case c next to the slip centre
    ],
)
def test_tiled_elastic_impact_cycle_keeps_the_energy_balance(osc, clearance, t_end):
    """An elastic impact cycle slips about one centre between impacts: friction does no
    work over a period. Its work per period was formed from the arc's end evaluated by
    cos/sin (an ulp off the stop), and tiling it over ~1e9 periods broke the energy balance
    by 8e-9 (t = 1e9) and 1.5e-9 (periods of 1e-5 over t = 1e4). Formed from the event's
    exact position it is zero. Tolerance: the mechanical energy sampled is ~2e-2, each
    sample rounded to ~1e-17; the transient before the cycle adds a few of those."""
    res = simulate(osc, RigidStop(clearance, 1.0), t_end=t_end)
    assert res.steady.kind is SteadyKind.PERIODIC
    assert energy_residual(res) < 1e-15
