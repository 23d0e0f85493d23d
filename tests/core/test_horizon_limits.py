"""Horizons and magnitudes at the edge of what doubles resolve (core/validation.py,
``MAX_T_END``): a horizon past the bound is refused by name, one at the bound is solved to
the spacing of doubles there, and a result never reports success with non-finite samples."""

from __future__ import annotations

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest

from core import HystereticStop, Oscillator, RigidStop, simulate
from core.sweep import sweep
from core.validation import MAX_T_END

#: pi to 60 digits: the reference below reduces a time modulo the period exactly.
PI = Fraction("3.14159265358979323846264338327950288419716939937510582097494")
#: The elastic fast-belt cycle of paper §4.1: a = 0.2, x_bar = 0.3, r = 1, v = 0.5 > a. From
#: rest the mass is on it at once: x = a (1 - cos th), x' = a sin th, impacts at
#: th = 2 pi/3 reverse the speed, so the period is 2 arccos(1 - x_bar/a) = 4 pi/3.
CYCLE_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
CYCLE_STOP = RigidStop(clearance=0.3, restitution=1.0)
#: A deformable stop (the page's Fig. 10 stop) whose motion settles on a tiled cycle.
SOFT = HystereticStop(clearance=0.285, k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                      beta_c=300.0, beta_e=300.0)
SOFT_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)

SCENES = [
    pytest.param(CYCLE_OSC, CYCLE_STOP, "exact", {}, id="rigid-exact"),
    pytest.param(SOFT_OSC, SOFT, "exact", {}, id="deformable-exact"),
    pytest.param(CYCLE_OSC, None, "exact", {}, id="free-exact"),
    pytest.param(CYCLE_OSC, CYCLE_STOP, "switch", {"max_steps": 10}, id="switch"),
    pytest.param(SOFT_OSC, SOFT, "event", {"max_steps": 10}, id="event"),
]


@pytest.mark.parametrize("t_end", [1e17, 1e18, 1e20, 1e100, 1e308])
@pytest.mark.parametrize(("osc", "stop", "method", "opts"), SCENES)
def test_a_horizon_past_the_bound_is_refused_by_name(osc, stop, method, opts, t_end):
    """Regression: a deformable stop at t_end 1e17-1e18 raised a bare 'math domain error',
    at 1e17-1e308 returned success with zeros or non-finite samples; a rigid stop at 1e17
    returned frozen samples as a success."""
    with pytest.raises(ValueError, match=r"t_end must lie in \(0, 1e\+09\]; got "):
        simulate(osc, stop, t_end=t_end, method=method, **opts)


def test_a_sweep_refuses_the_same_horizons_and_starts():
    """The sweep checks its horizon and start as :func:`core.simulate` does."""
    values = np.array([0.3, 0.5])
    with pytest.raises(ValueError, match=r"t_end must lie in \(0, 1e\+09\]"):
        sweep(CYCLE_OSC, CYCLE_STOP, "belt_speed", values, t_end=1e17)
    with pytest.raises(ValueError, match=r"x0 must lie in \[-1e\+100, 1e\+100\]"):
        sweep(CYCLE_OSC, None, "belt_speed", values, x0=1e300)


def _cycle_x(t: float) -> float:
    """x on the elastic cycle at the double ``t``, the phase reduced exactly."""
    r = Fraction(t) + 2 * PI / 3
    r -= math.floor(r / (4 * PI / 3)) * (4 * PI / 3)
    return 0.2 * (1.0 - math.cos(float(r - 2 * PI / 3)))


def test_the_longest_horizon_is_solved_to_the_spacing_of_its_times():
    """At t_end = MAX_T_END every sample and evaluation of the tiled cycle agrees with the
    closed form at the same double ``t``, the phase reduced in exact arithmetic: the time
    itself is known to half a spacing ``ulp(t)`` and the reduction ``t - k T`` rounds to a
    few more, so ``x`` is off by at most its largest speed ``a`` times 4 ulp(t)."""
    res = simulate(CYCLE_OSC, CYCLE_STOP, t_end=MAX_T_END)
    assert res.success
    times = MAX_T_END * np.array([0.31, 0.5, 0.77, 0.999999]) + np.array([0.1, 0.3, 0.7, 0.0])
    tol = 0.2 * 4.0 * math.ulp(MAX_T_END)
    x, _ = res.evaluate(times)
    assert max(abs(xi - _cycle_x(ti)) for xi, ti in zip(x, times, strict=True)) < tol
    late = zip(res.x[-200:], res.t[-200:], strict=True)
    assert max(abs(xi - _cycle_x(ti)) for xi, ti in late) < tol


def test_a_deformable_cycle_at_the_longest_horizon_repeats_its_first_period():
    """A deformable stop's tiled cycle at t_end = MAX_T_END: the state at a late time is the
    state at that time reduced into the first cycle in exact arithmetic, to its largest
    speed (< 0.3) times 4 ulp(t) (as above)."""
    res = simulate(SOFT_OSC, SOFT, t_end=MAX_T_END)
    assert res.success and res.steady.kind.value == "periodic"
    t1, period = Fraction(res.steady.t_reached), Fraction(res.steady.period)
    late = MAX_T_END * np.array([0.31, 0.5, 0.77, 1.0])
    early = np.array([float(t1 + (Fraction(t) - t1) % period) for t in late])
    x_late, _ = res.evaluate(late)
    x_early, _ = res.evaluate(early)
    assert np.all(np.isfinite(res.x))
    assert np.max(np.abs(x_late - x_early)) < 0.3 * 4.0 * math.ulp(MAX_T_END)


def test_success_with_non_finite_samples_is_an_error():
    """Regression: starts and horizons at the edge of doubles returned ``success`` with
    non-finite samples; a Result that says success now has finite ``t``, ``x``, ``v``."""
    res = simulate(CYCLE_OSC, CYCLE_STOP, t_end=10.0)
    x = res.x.copy()
    x[-1] = math.inf
    with pytest.raises(FloatingPointError, match=r"x\[\d+\] = inf is not finite"):
        dataclasses.replace(res, x=x)
    failed = dataclasses.replace(res, x=x, status=type(res.status).TIME_BUDGET)
    assert not failed.success  # a cut-short result may keep what it had


# the step that overshoots evaluates the force past the asymptote: SciPy's RK warns of its nan
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize(("limit_overlap", "v0"), [(1e-100, 0.0), (1e-300, 0.0), (0.01, -1e100)])
def test_an_overlap_past_the_asymptote_ends_the_event_solve_with_a_status(limit_overlap, v0):
    """Regression: a deformable stop with a tiny limit overlap, or a start at -1e100 speed
    (the mass comes back at 1e100), raised a bare 'math domain error' in the event method:
    a step overshot the asymptote ``delta = D`` of the compression envelope and the stop's
    work took the log of a negative number. The work stored there is infinite, and the
    solve reports the overlap or the failed integration instead of a success."""
    stop = dataclasses.replace(SOFT, clearance=0.24, limit_overlap=limit_overlap)
    res = simulate(Oscillator(0.3, 0.2, 0.1), stop, t_end=20.0, v0=v0, method="event",
                   max_steps=20_000)
    assert res.status.value in ("limit_overlap", "integration_failed")
    assert np.all(np.isfinite(res.x))
