"""``Result.evaluate`` of the exact solver against an independent integration.

The reference (tests/core/ivp_reference.py) is the non-smooth model integrated piece by
piece by DOP853 with event location and dense output, sharing nothing with the solver.
"""

from __future__ import annotations

import numpy as np
import pytest

from core import Oscillator, RigidStop, TransitionKind, simulate
from tests.core.ivp_reference import Reference

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
FAST = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)

#: DOP853 at rtol 1e-12 with event location carries ~1e-11 per event; a few dozen events
#: over the compared window keep the state within 1e-8.
REFERENCE_TOL = 1e-8
#: Times closer than this to a reference impact are not compared at random: the two
#: impact times differ by ~1e-11 and the velocity jumps there.
JUMP_GUARD = 1e-6

SCENES = [
    (SLOW, None),
    (FAST, RigidStop(0.3, 1.0)),
    (SLOW, RigidStop(0.32, 1.0)),
    (SLOW, RigidStop(0.29, 0.7)),
    (FAST, RigidStop(0.3, 0.8)),
    (FAST, RigidStop(0.1, 0.6)),
    (SLOW, RigidStop(0.25, 0.7)),
]
IDS = ["slow-no-stop", "fast-elastic", "case-a", "case-b", "fast-grazing", "zeno", "case-c"]


@pytest.mark.parametrize(("osc", "stop"), SCENES, ids=IDS)
def test_evaluate_agrees_with_independent_integration(osc, stop):
    t_end = 40.0
    ref = Reference(osc, stop, t_end)
    res = simulate(osc, stop, t_end=t_end)
    rng = np.random.default_rng(7)
    tt = np.sort(rng.uniform(0.0, ref.t_last, 400))
    hits = np.array([imp[0] for imp in ref.impacts])
    if len(hits):
        tt = tt[np.min(np.abs(tt[:, None] - hits[None, :]), axis=1) > JUMP_GUARD]
    x_ref, v_ref = ref(tt)
    for side in (-1, 1):
        x, v = res.evaluate(tt, side)
        np.testing.assert_allclose(x, x_ref, atol=REFERENCE_TOL)
        np.testing.assert_allclose(v, v_ref, atol=REFERENCE_TOL)
    # Both sides of every impact the reference found, at the solver's own impact times.
    mine = [
        tr for tr in res.transitions
        if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
    ][: len(ref.impacts)]
    assert len(mine) == len(ref.impacts)
    for tr, (t_ref, w_ref, after_ref) in zip(mine, ref.impacts, strict=True):
        assert tr.t == pytest.approx(t_ref, abs=REFERENCE_TOL)
        (xl, vl), (xr, vr) = res.evaluate(tr.t, -1), res.evaluate(tr.t, 1)
        assert float(xl) == pytest.approx(stop.clearance, abs=1e-14)
        assert float(xr) == pytest.approx(stop.clearance, abs=1e-14)
        assert float(vl) == pytest.approx(w_ref, abs=REFERENCE_TOL)
        assert float(vr) == pytest.approx(after_ref, abs=REFERENCE_TOL)


@pytest.mark.parametrize(("osc", "stop"), SCENES, ids=IDS)
def test_evaluate_gives_both_limits_of_every_stored_impact(osc, stop):
    """Newton's law between the two one-sided limits at every impact, including the
    repeated cycle (times formed as t + k*period) and the summed impact sequences."""
    res = simulate(osc, stop, t_end=300.0, transition_cap=100_000)
    impacts = [
        tr for tr in res.transitions
        if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
    ]
    if stop is None:
        assert not impacts
        return
    assert impacts
    t = np.array([tr.t for tr in impacts])
    _, before = res.evaluate(t, -1)
    _, after = res.evaluate(t, 1)
    # The transition log and the evaluation compute the same arcs by different routes
    # (event angles vs. the cycle's tiling): they agree to rounding of the phase.
    np.testing.assert_allclose(before, [tr.v for tr in impacts], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(after, [tr.v_after for tr in impacts], rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize(("osc", "stop"), SCENES, ids=IDS)
def test_evaluate_matches_the_samples(osc, stop):
    """A sample drawn on one side of a transition is the evaluation on that side (in an
    impact sequence the samples before impacts once held the rebound velocity)."""
    res = simulate(osc, stop, t_end=200.0)
    side = np.ones(len(res.t), np.int8)
    side[:-1][np.diff(res.t) == 0.0] = -1  # the first of two samples at a time: before
    x, v = np.empty_like(res.t), np.empty_like(res.t)
    for s in (-1, 1):
        x[side == s], v[side == s] = res.evaluate(res.t[side == s], s)
    # Same formulas; the samples' plain times are not snapped to transitions (1e-14 s).
    np.testing.assert_allclose(x, res.x, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(v, res.v, rtol=0.0, atol=1e-12)


def test_evaluate_tiles_the_cycle():
    """In the periodic steady state the solution repeats with the period found."""
    res = simulate(SLOW, RigidStop(0.29, 0.7), t_end=1000.0)
    period, start = res.steady.period, res.steady.t_reached
    tt = np.linspace(start, start + period, 101)[:-1]
    for k in (1, 7, 50):
        for side in (-1, 1):
            x0, v0 = res.evaluate(tt, side)
            xk, vk = res.evaluate(tt + k * period, side)
            # k periods shift the times by up to ~1e3, whose rounding (1e-13) moves the
            # state by as much.
            np.testing.assert_allclose(xk, x0, atol=1e-11)
            np.testing.assert_allclose(vk, v0, atol=1e-11)


def test_evaluate_keeps_the_shape_and_checks_its_arguments():
    res = simulate(FAST, RigidStop(0.3, 0.8), t_end=10.0)
    x, v = res.evaluate(np.zeros((2, 3)), 1)
    assert x.shape == v.shape == (2, 3)
    with pytest.raises(ValueError, match="side"):
        res.evaluate(1.0, 0)
    with pytest.raises(ValueError, match="t must lie in"):
        res.evaluate([1.0, 11.0], 1)
