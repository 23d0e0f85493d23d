"""The cycle a steady motion repeats (core.steady.steady_cycle), for every label that has one:
the solution over any later period is the first period again, to rounding for a periodic
state (Eq. 20) and within the stated resolution for grazing and pure slip."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from core import Oscillator, RigidStop, SteadyKind, simulate
from core.steady import cycle_transitions, first_cycle_end, settled_time, steady_cycle

T_END = 300.0
#: The resolution ``(dx, dv)`` the cycle of an approached limit is asked for: transitions
#: within half of it count as settled.
STEP = (1e-4, 1e-4)
#: A periodic state repeats its fixed point to a few ulps (core.steady.FIXED_POINT_RTOL):
#: its repeats agree with its first period to 1e-9 of the scale after ~100 periods of
#: rounding in the event times.
PERIODIC_TOL = 1e-9
#: Samples of the first period an approached limit's repeats are compared with: chords of
#: at most ~1e-4 of a slip circle of radius 0.2 (2 pi 0.2 / 20000 = 6e-5).
ORBIT_SAMPLES = 20_001

SCENES = {
    # elastic impacts on a stop inside the slip circle: periodic (paper §4)
    "periodic": (Oscillator(0.3, 0.2, 0.5), RigidStop(0.3, 1.0), SteadyKind.PERIODIC),
    # inelastic impacts: speeds fall as r^h towards a slip circle grazing the stop
    "grazing": (Oscillator(0.3, 0.2, 0.1), RigidStop(0.25, 0.7), SteadyKind.GRAZING),
    # a belt faster than the critical speed and no stop: one slip circle for ever
    "pure slip": (Oscillator(0.3, 0.2, 0.5), None, SteadyKind.PURE_SLIP),
}


@pytest.mark.parametrize("name", ["periodic"])
def test_a_periodic_motion_repeats_its_cycle_to_the_horizon(name):
    osc, stop, kind = SCENES[name]
    res = simulate(osc, stop, T_END)
    assert res.steady.kind is kind
    cycle = steady_cycle(res, T_END, STEP)
    assert cycle == (res.steady.t_reached, res.steady.period)
    s = np.linspace(0.0, cycle.period, 97)
    x0, v0 = res.evaluate(cycle.t0 + s)
    repeats = int((T_END - cycle.t0) / cycle.period) - 1
    for k in (1, repeats // 2, repeats):
        xk, vk = res.evaluate(cycle.t0 + k * cycle.period + s)
        gap = max(float(np.max(np.abs(xk - x0))), float(np.max(np.abs(vk - v0))))
        assert gap <= PERIODIC_TOL, (k, gap)


@pytest.mark.parametrize("name", ["grazing", "pure slip"])
def test_an_approached_limit_retraces_its_cycle_within_the_resolution(name):
    """Later periods trace the first one's orbit in the phase plane to within half a step
    (the times of an approach keep changing, so the motion is compared as a curve)."""
    osc, stop, kind = SCENES[name]
    res = simulate(osc, stop, T_END)
    assert res.steady.kind is kind
    cycle = steady_cycle(res, T_END, STEP)
    assert cycle is not None and cycle.period > 0.0 and cycle.t0 + cycle.period < T_END
    x0, v0 = res.evaluate(cycle.t0 + np.linspace(0.0, cycle.period, ORBIT_SAMPLES))
    chord = float(np.max(np.hypot(np.diff(x0), np.diff(v0))))
    orbit = cKDTree(np.c_[x0 / STEP[0], v0 / STEP[1]])
    repeats = int((T_END - cycle.t0) / cycle.period) - 1
    assert repeats >= 2
    for k in (1, repeats // 2, repeats):
        xk, vk = res.evaluate(cycle.t0 + k * cycle.period + np.linspace(0.0, cycle.period, 301))
        dist, _ = orbit.query(np.c_[xk / STEP[0], vk / STEP[1]])
        assert float(dist.max()) <= 0.5 + 0.5 * chord / min(STEP), (k, float(dist.max()))


def test_the_first_cycle_ends_after_the_motion_has_settled():
    osc, stop, _ = SCENES["grazing"]
    res = simulate(osc, stop, T_END)
    t_settled = settled_time(res, STEP)
    assert 0.0 < t_settled < T_END
    assert first_cycle_end(res, T_END, STEP) == pytest.approx(t_settled + 2.0 * math.pi)
    # a coarser resolution settles no later
    assert settled_time(res, (1e-2, 1e-2)) <= t_settled


def test_no_cycle_where_the_motion_comes_to_rest_or_never_settles():
    res = simulate(Oscillator(0.3, 0.2, 0.0), None, 50.0)  # equilibrium from the start
    assert res.steady.kind is SteadyKind.EQUILIBRIUM
    assert steady_cycle(res, 50.0, STEP) is None
    assert cycle_transitions(res) == []


def test_the_transitions_of_a_period_are_its_sequence():
    osc, stop, _ = SCENES["periodic"]
    res = simulate(osc, stop, T_END)
    cycle = cycle_transitions(res, stop)
    assert tuple(tr.kind.value for tr in cycle) == res.steady.sequence
    assert all(tr.t > res.steady.t_reached for tr in cycle)
    assert cycle[-1].t - res.steady.t_reached == pytest.approx(res.steady.period, rel=1e-12)


def test_a_grazing_limit_is_one_impact_of_speed_zero_at_the_peak():
    osc, stop, _ = SCENES["grazing"]
    res = simulate(osc, stop, T_END)
    [impact] = cycle_transitions(res, stop)
    assert impact.kind.value == "impact" and math.isnan(impact.t)
    assert (impact.x, impact.v, impact.v_after) == (res.steady.x_max, 0.0, 0.0)
