"""The shared transition log and steady-state tools (core.transitions, core.steady)."""

from __future__ import annotations

import numpy as np
import pytest

from core.result import SteadyKind, Transition, TransitionKind
from core.steady import FixedPointDetector, fold_times, pressed_steady
from core.transitions import TransitionLog

IMPACT, SLIP_STICK = TransitionKind.IMPACT, TransitionKind.SLIP_STICK


@pytest.mark.parametrize("cap", [1, 3, 10, 10_000])
def test_tiling_counts_every_repeat_whatever_the_cap(cap):
    """A cycle of two transitions at 0.25 and 0.75 of a period 1, repeated to t = 100.3:
    transitions at k + 0.25 and k + 0.75 for k = 0..99, and 100.25: 201, stored or
    counted."""
    log = TransitionLog(cap)
    log.add(IMPACT, 0.25, 0.1, 0.2, -0.1)
    log.add(SLIP_STICK, 0.75, 0.1, 0.2)
    cycle = [tr for tr in log.stored]
    if len(cycle) < 2:  # a cycle must be stored to be tiled (rigid stores at least that)
        assert log.total == 2
        return
    log.tile(cycle, 1.0, 100.3)
    assert log.total == 201
    assert log.counts["impact"] == 101 and log.counts["slip->stick"] == 100
    assert len(log.stored) == min(cap, 201)
    times = [tr.t for tr in log.stored]
    assert times == sorted(times)
    np.testing.assert_allclose(times[2:4], [1.25, 1.75][: len(times) - 2], rtol=1e-15)


def test_bulk_impacts_are_stored_up_to_the_cap_and_all_counted():
    log = TransitionLog(cap=3)
    log.add_impacts([1.0, 2.0, 3.0, 4.0, 5.0], 0.3, [0.5, 0.25, 0.125, 0.0625, 0.03], 0.5)
    assert len(log.stored) == 3 and log.total == 5
    assert log.stored[1].v_after == -0.125
    assert log.impulses[0] == (1.0, 0.75)  # (1 + r) w


def test_detector_needs_a_resolvable_period():
    det = FixedPointDetector(scale=1.0)
    assert det.add(IMPACT, 1.0, 0.3, 0.2) is None
    assert det.add(IMPACT, 1.0 + 1e-14, 0.3, 0.2) is None  # 45 ulps: not a period
    cycle = det.add(IMPACT, 4.0, 0.3, 0.2)
    assert cycle is not None and cycle.period == 3.0 and cycle.n_transitions == 2


def test_detector_ignores_a_converging_sequence():
    """States r^k w approach a point without repeating (an accumulation)."""
    det = FixedPointDetector(scale=1.0)
    found = [det.add(IMPACT, float(k), 0.1, 0.5**k) for k in range(60)]
    assert all(c is None for c in found)


def test_fold_times_tiles_and_takes_both_limits_at_boundaries():
    t_from, cycle_t0, period = 5.0, 3.0, 2.0
    t = np.array([4.0, 5.0, 6.0, 7.0, 7.0, 100.5])
    side = np.array([1, 1, 1, -1, 1, 1])
    folded, n = fold_times(t, side, t_from, cycle_t0, period)
    np.testing.assert_array_equal(folded, [4.0, 3.0, 4.0, 5.0, 3.0, 4.5])
    np.testing.assert_array_equal(n, [0.0, 1.0, 1.0, 1.0, 2.0, 48.0])
    # Rounding a few ulps off a boundary still lands on it.
    folded, n = fold_times(np.array([7.0 - 4e-15, 7.0 + 4e-15]), np.array([1, 1]), 5.0, 3.0, 2.0)
    np.testing.assert_array_equal(folded, [3.0, 3.0])


def test_detector_rtol_accepts_a_repeat_to_a_numerical_tolerance():
    # A one-impact cycle whose state drifts by 1e-9 per period (a numerical method's
    # global error): no repeat to the exact tolerance (1e-11), a repeat to rtol 1e-6
    # once the cycle is measured against the state scale, as the numerical methods do.
    exact = FixedPointDetector(scale=1.0)
    loose = FixedPointDetector(scale=1.0, rtol=1e-6, min_cycle_size=1.0)
    found_exact = found_loose = None
    for k in range(4):
        state = (TransitionKind.IMPACT, 2.0 * k, 0.3, 0.2 + 1e-9 * k)
        found_exact = exact.add(*state) or found_exact
        found_loose = loose.add(*state) or found_loose
    assert found_exact is None
    assert found_loose is not None and found_loose.period == 2.0
    # every earlier state within the tolerance is recorded as repeated, n transitions back
    assert loose.repeats[-1] == frozenset({1, 2, 3})


def test_detector_rejects_a_non_positive_rtol():
    with pytest.raises(ValueError, match="rtol"):
        FixedPointDetector(scale=1.0, rtol=0.0)


def test_numerical_steady_search_uses_the_detector_and_needs_whole_periods():
    # dense's search: periodic only when each transition of two whole periods repeats the
    # one j transitions earlier; a near-duplicate pair inside a period (same kind, states
    # within the tolerance, 1e-5 apart in time) is not a period of its own.
    from core.result import Mode, SteadyKind, Transition
    from core.steady import steady_from_transitions

    def tr(kind, t, x, v):
        return Transition(kind, t, x, v, v)

    period = []
    for p in range(4):
        t0 = 3.0 * p
        period += [
            tr(TransitionKind.SLIP_STICK, t0, 0.1, 0.5),
            tr(TransitionKind.STICK_SLIP, t0 + 1.0, 0.2, 0.5),
            tr(TransitionKind.STICK_SLIP, t0 + 1.0 + 1e-5, 0.2, 0.5 + 1e-9),
        ]
    steady = steady_from_transitions(
        period, scale=1.0, rtol=1e-6, t_end=12.0, final_mode=int(Mode.SLIP), final_v=0.5
    )
    assert steady.kind is SteadyKind.PERIODIC
    assert steady.transitions_per_period == 3
    assert steady.period == pytest.approx(3.0, rel=1e-12)


@pytest.mark.parametrize("n_reversals", [40, 41])
def test_creeping_dying_loops_are_rest_whatever_the_last_reversal(n_reversals):
    """Loops that die while their centre creeps (the paper's loops, docs/contact-law.md):
    in closed form the amplitude falls by 0.3 % per half cycle and the centre moves by 2 %
    of it, so the swings alternate in size by ~4 % and a ratio of single swings reads
    growth every other reversal (it was labelled ``none`` at one parity). Per cycle the
    amplitude falls by ~0.6 %, far above SWING_STEADY: rest, approached."""
    amp = 1e-6 * 0.997 ** np.arange(n_reversals)
    centre = 0.42 - 0.02 * np.concatenate(([0.0], np.cumsum(amp[:-1])))
    xs = centre + amp * (-1.0) ** np.arange(n_reversals)
    tail = [Transition(TransitionKind.REVERSAL, 0.1 * k, float(x), 0.0, 0.0)
            for k, x in enumerate(xs)]
    steady = pressed_steady(tail)
    assert steady.kind is SteadyKind.REST
    # the geometric mean of the swing ratios over a cycle: the closed form's 0.997
    assert steady.decay_rate == pytest.approx(0.997, abs=1e-4)


def test_loops_of_a_lossless_law_are_periodic_whatever_their_drift():
    """Loops made of reversals alone on a law that dissipates nothing there (the passive
    law retraces its curve) keep their size; a measured shrink of 1e-5 per cycle (what the
    roundoff of the law's curve gives on k_c0 = 100, beta = 100, D = 0.01) is the numbers'
    drift. The same swings from a law that dissipates are rest, approached."""
    n = 41
    amp = 1.5e-3 * (1.0 - 0.5e-5) ** np.arange(n)
    xs = 0.4224 + amp * (-1.0) ** np.arange(n)
    tail = [Transition(TransitionKind.REVERSAL, 0.29 * k, float(x), 0.0, 0.0)
            for k, x in enumerate(xs)]
    lossless = pressed_steady(tail, lossless=True)
    assert lossless.kind is SteadyKind.PERIODIC
    assert lossless.period == pytest.approx(0.58, rel=1e-12)
    assert pressed_steady(tail).kind is SteadyKind.REST
    # A separation among the loops measured: not loops of reversals alone.
    tail[-3] = tail[-3]._replace(kind=TransitionKind.SEPARATION)
    assert pressed_steady(tail, lossless=True).kind is not SteadyKind.PERIODIC
