"""solve_ivp with event location on the non-smooth model (core.event_method).

No regularisation: the only error is the integration error, so the closed forms of
docs/physics.md, "Closed-form results" hold to a small multiple of the tolerance. Tolerances
below are justified per test.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from core import HystereticStop, Oscillator, RigidStop, SteadyKind, TransitionKind, simulate
from core.deformable.law import (
    FIRST_LOADING,
    branch_kinks,
    force_and_slope,
    phi_compression,
    reverse,
)
from core.event_method import SOLVERS, simulate_event

A, B = 0.2, 0.3
FAST = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
TIGHT = {"rtol": 1e-11, "atol": 1e-13, "solver": "DOP853"}
#: At rtol 1e-11 over a few tens of time units DOP853's global error stays below ~1e-9.
CLOSE = 1e-9


def test_fast_belt_pure_slip():
    res = simulate_event(FAST, t_end=20.0, **TIGHT)
    assert res.x_max == pytest.approx(2 * A, abs=CLOSE)
    assert res.x[-1] == pytest.approx(A - A * math.cos(20.0), abs=CLOSE)
    assert res.steady.kind is SteadyKind.PURE_SLIP
    assert res.method == "event"


def test_first_stick_point_and_limit_cycle():
    res = simulate_event(SLOW, t_end=40.0, **TIGHT)
    first = res.transitions[0]
    assert first.kind is TransitionKind.SLIP_STICK
    assert first.x == pytest.approx(A - math.sqrt(A * A - SLOW.v**2), abs=CLOSE)  # Eq. 30
    assert first.v == SLOW.v  # the event state is projected onto x' = v
    assert res.x_max == pytest.approx(A + math.hypot(B - A, SLOW.v), abs=CLOSE)
    assert res.steady.kind is SteadyKind.PERIODIC
    assert res.steady.sequence == ("slip->stick", "stick->slip")


def test_elastic_fast_belt_impact():
    c = 0.3
    res = simulate_event(FAST, RigidStop(c, 1.0), t_end=30.0, **TIGHT)
    impacts = [tr for tr in res.transitions if tr.kind is TransitionKind.IMPACT]
    speed = math.sqrt(c * (2 * A - c))
    period = 2 * math.acos(1 - c / A)
    assert len(impacts) >= 3
    for tr in impacts:
        assert tr.v == pytest.approx(speed, abs=CLOSE)
    np.testing.assert_allclose(np.diff([tr.t for tr in impacts]), period, atol=CLOSE)
    assert res.steady.period == pytest.approx(period, abs=CLOSE)


SCENES = [
    (FAST, None),
    (SLOW, None),
    (FAST, RigidStop(0.3, 1.0)),
    (SLOW, RigidStop(0.3, 1.0)),
    (SLOW, RigidStop(0.25, 0.7)),
    (FAST, RigidStop(0.25, 0.7)),
    (SLOW, RigidStop(0.35, 0.5)),
    (SLOW, RigidStop(0.1, 0.0)),
    (SLOW, RigidStop(0.15, 0.7)),
]


@pytest.mark.parametrize("osc,stop", SCENES)
def test_agrees_with_exact_solver(osc, stop):
    exact = simulate(osc, stop, t_end=40.0)
    res = simulate_event(osc, stop, t_end=40.0, **TIGHT)
    # Zeno scenes: the event method stops bouncing below rest_speed (fewer impacts), the
    # accumulation time and the final rest agree.
    assert res.x[-1] == pytest.approx(exact.x[-1], abs=1e-7)
    assert res.v[-1] == pytest.approx(exact.v[-1], abs=1e-7)
    assert res.x_max == pytest.approx(exact.x_max, abs=1e-8)
    assert res.steady.kind is exact.steady.kind
    firsts = [tr for tr in exact.transitions if tr.kind is not TransitionKind.ACCUMULATION]
    for p, q in zip(firsts[:10], res.transitions[:10], strict=False):
        assert p.kind is q.kind
        assert q.t == pytest.approx(p.t, abs=1e-8)


@pytest.mark.parametrize("c,r", [(0.3, 1.0), (0.25, 0.7), (0.15, 0.7), (0.05, 0.9)])
def test_rigid_stop_never_penetrated(c, r):
    for osc in (FAST, SLOW):
        res = simulate_event(osc, RigidStop(c, r), t_end=60.0, rtol=1e-6, atol=1e-9)
        assert np.all(res.x <= c)


def test_grazing_crossing_inside_one_step_is_found():
    # c > a, r < 1: impacts with speeds falling as r^h; late ones rise above the stop and
    # fall back inside one step of a loose tolerance. Each maximum is an event, so none is
    # missed and no sample passes the stop.
    res = simulate_event(FAST, RigidStop(0.25, 0.7), t_end=100.0, rtol=1e-3, atol=1e-6)
    assert np.all(res.x <= 0.25)
    assert res.steady.kind is SteadyKind.GRAZING


def test_zeno_accumulation_time():
    stop = RigidStop(0.15, 0.7)
    exact = simulate(SLOW, stop, t_end=50.0)
    res = simulate_event(SLOW, stop, t_end=50.0, **TIGHT)
    t_ex = next(tr.t for tr in exact.transitions if tr.kind is TransitionKind.ACCUMULATION)
    t_ev = next(tr.t for tr in res.transitions if tr.kind is TransitionKind.ACCUMULATION)
    assert t_ev == pytest.approx(t_ex, abs=1e-8)
    assert res.transitions[-1].kind is TransitionKind.REST


@pytest.mark.parametrize("solver", SOLVERS)
def test_every_solver_runs(solver):
    res = simulate_event(SLOW, RigidStop(0.3, 0.8), t_end=15.0, solver=solver, rtol=1e-8)
    exact = simulate(SLOW, RigidStop(0.3, 0.8), t_end=15.0)
    # rtol 1e-8 for every method; implicit ones are less accurate per step: 1e-5 is loose
    assert res.x_max == pytest.approx(exact.x_max, abs=1e-5)
    assert res.info["solver"] == solver


def test_hysteretic_stop_contact_sequence():
    stop = HystereticStop(0.25)
    res = simulate_event(SLOW, stop, t_end=20.0, **TIGHT)
    kinds = [tr.kind for tr in res.transitions]
    i = kinds.index(TransitionKind.CONTACT)
    # clearance < b: the stick reaches the stop, slips inside the contact, turns, separates
    assert kinds[i : i + 4] == [
        TransitionKind.CONTACT,
        TransitionKind.STICK_SLIP,
        TransitionKind.REVERSAL,
        TransitionKind.SEPARATION,
    ]
    assert np.all(res.contact_force >= 0.0) and res.contact_force.max() > 0.0
    assert np.all(res.overlap < stop.limit_overlap)
    e = res.energy
    resid = e.mechanical - e.mechanical[0] - e.friction_work + e.stop_loss + e.stop_stored
    # the energy terms are trapezoid sums over the step points: second order, not exact
    assert np.max(np.abs(resid)) < 1e-3 * np.max(e.mechanical)


def test_hysteretic_strength_failure_is_reported():
    from core import Status

    stop = HystereticStop(0.25, strength=0.5)
    res = simulate_event(FAST, stop, t_end=20.0)
    assert res.status is Status.STOP_FAILED
    assert res.transitions[-1].kind is TransitionKind.FAILURE


def test_bad_input_is_rejected():
    with pytest.raises(ValueError, match="solver"):
        simulate_event(SLOW, solver="Euler")
    with pytest.raises(ValueError, match="x0"):
        simulate_event(SLOW, RigidStop(0.1), x0=0.2)


# --- work limits, too many events, t_eval, dense output, stats --------------------------------

IMPACTS = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)


def _consistent(res) -> None:
    n = len(res.t)
    assert all(len(a) == n for a in (res.x, res.v, res.mode, res.energy.mechanical))
    assert np.all(np.diff(res.t) >= 0.0) and np.all(np.isfinite(res.x))
    assert all(tr.t <= res.t[-1] for tr in res.transitions)


def test_step_limit_returns_the_result_so_far():
    from core import Status

    res = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=50.0, max_steps=20)
    assert res.status is Status.STEP_LIMIT and not res.success
    assert res.stats["steps"] == 20
    assert 0.0 < res.t[-1] < 50.0
    _consistent(res)


@pytest.mark.parametrize("belt_speed", [1e-5, 1e-9])
def test_slow_belt_finishes_in_few_steps(belt_speed):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=belt_speed)
    stop = RigidStop(0.25, 0.7)
    res = simulate_event(osc, stop, t_end=100.0, max_steps=1_000)
    exact = simulate(osc, stop, t_end=100.0)
    assert res.success
    assert res.sequence() == exact.sequence() == "slip->stick"
    # stick is closed-form: x(100) to the integration error of the first slip arc
    assert res.x[-1] == pytest.approx(exact.x[-1], abs=1e-12)


def test_time_budget_returns_the_result_so_far():
    from core import Status

    # a budget far below one step's cost: the solve stops at its first check
    res = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=1e4, time_budget=1e-9)
    assert res.status is Status.TIME_BUDGET
    assert res.t[-1] < 1e4
    _consistent(res)


def test_too_many_events_is_an_event_limit():
    """Too many events stop the solve with EVENT_LIMIT and the result so far (it was
    INTEGRATION_FAILED)."""
    from core import Status

    res = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=50.0, max_events=4)
    assert res.status is Status.EVENT_LIMIT
    assert res.stats["segments"] == 4
    assert 0.0 < res.t[-1] < 50.0
    _consistent(res)
    full = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=50.0)
    # the truncated solve is the start of the full one
    n = len(res.transitions)
    assert n >= 2
    assert [tr.t for tr in res.transitions] == [tr.t for tr in full.transitions[:n]]


def test_stats_are_integer_counts_with_the_shared_keys():
    from core.result import STATS_KEYS

    res = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=20.0)
    assert tuple(res.stats) == STATS_KEYS
    assert all(isinstance(v, int) for v in res.stats.values())
    assert res.stats["events"] == res.n_transitions > 0
    assert res.stats["steps"] > 0 and res.stats["rhs_evals"] > res.stats["steps"]
    assert res.info["solver"] == "RK45"


def test_t_eval_samples_exactly_there():
    t_eval = np.sort(np.random.default_rng(1).uniform(0.0, 30.0, 257))
    res = simulate_event(SLOW, RigidStop(0.25, 0.7), t_end=30.0, t_eval=t_eval, **TIGHT)
    np.testing.assert_array_equal(res.t, t_eval)
    exact = simulate(SLOW, RigidStop(0.25, 0.7), t_end=30.0, t_eval=t_eval)
    # DOP853's own interpolant at rtol 1e-11: measured 1e-11 over 40 time units
    np.testing.assert_allclose(res.x, exact.x, atol=CLOSE)
    np.testing.assert_allclose(res.v, exact.v, atol=CLOSE)
    with pytest.raises(ValueError, match="t_eval"):
        simulate_event(SLOW, t_end=30.0, t_eval=[0.0, 31.0])
    with pytest.raises(ValueError, match="t_eval"):
        simulate_event(SLOW, t_end=30.0, t_eval=[[0.0, 1.0]])


@pytest.mark.parametrize(
    "osc,stop",
    [(SLOW, RigidStop(0.25, 0.7)), (FAST, RigidStop(0.3, 1.0)), (SLOW, RigidStop(0.15, 0.7))],
    ids=["inelastic", "elastic", "zeno"],
)
@pytest.mark.parametrize("rtol", [1e-6, 1e-8])
def test_dense_solution_matches_the_closed_form(osc, stop, rtol):
    res = simulate_event(osc, stop, t_end=40.0, rtol=rtol, atol=rtol * 1e-2)
    tq = np.linspace(0.0, 40.0, 3001)
    exact = simulate(osc, stop, t_end=40.0, t_eval=tq)
    x, v = res.evaluate(tq)
    # global error of a tolerance-proportional RK45 (and its interpolant) over 40 time
    # units: measured up to 8 rtol; 100 rtol leaves room without hiding an O(1) error
    np.testing.assert_allclose(x, exact.x, atol=100 * rtol)
    np.testing.assert_allclose(v, exact.v, atol=100 * rtol)
    # the samples are the interpolant's values
    times, counts = np.unique(res.t, return_counts=True)
    once = np.isin(res.t, times[counts == 1])  # not a jump (sampled on both sides)
    xs, vs = res.evaluate(res.t[once], side=1)
    np.testing.assert_array_equal(xs, res.x[once])
    np.testing.assert_array_equal(vs, res.v[once])
    # one-sided limits at an impact: the velocity before and after (Eq. 8)
    impacts = [tr for tr in res.transitions if tr.kind in IMPACTS]
    assert impacts
    for tr in impacts:
        assert res.evaluate([tr.t], side=-1)[1][0] == tr.v
        if abs(tr.v_after) > 1e-3:  # not the last one of a Zeno train (rest follows)
            assert res.evaluate([tr.t], side=1)[1][0] == tr.v_after
    with pytest.raises(ValueError, match="t must lie"):
        res.evaluate([41.0])


@pytest.mark.parametrize("solver", ["RK45", "DOP853"])
def test_error_is_proportional_to_rtol(solver):
    """Tolerance proportionality: the transition times on an inelastic stick-slip-impact
    scene against the exact solver, over rtol 1e-5 ... 1e-9 (atol = 1e-3 rtol)."""
    stop = RigidStop(0.25, 0.7)
    exact = simulate(SLOW, stop, t_end=50.0)
    rtols = np.array([1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
    errs = []
    for rtol in rtols:
        res = simulate_event(SLOW, stop, t_end=50.0, rtol=rtol, atol=rtol * 1e-3, solver=solver)
        n = min(len(exact.transitions), len(res.transitions), 10)
        pairs = zip(exact.transitions[:n], res.transitions[:n], strict=True)
        errs.append(max(abs(p.t - q.t) for p, q in pairs))
    slope = float(np.polyfit(np.log(rtols), np.log(errs), 1)[0])
    # measured 0.94 (RK45) and 0.96 (DOP853): SciPy's controllers keep the global error
    # proportional to rtol; a lost event or a wrong restart would break the line
    assert 0.8 < slope < 1.15, (slope, errs)


def test_a_speed_that_passes_the_belt_s_and_comes_back_in_one_step_is_found():
    """Defect: entering each contact at 0.9999974 v, the mass reaches the belt's speed within
    2.6e-6 and sticks for 2 ms; the step's speed passed v and came back inside it, so the
    event method slipped on with friction the wrong way (1 stick of 60 at rtol 1e-10)."""
    osc, stop = Oscillator(0.3, 0.2, 0.1), HystereticStop(0.1)
    res = simulate(osc, stop, 100.0, method="event", rtol=1e-10, atol=1e-13)
    exact = simulate(osc, stop, 100.0, rtol=1e-12, atol=1e-15)
    counts = res.transition_counts
    assert counts[TransitionKind.SLIP_STICK.value] == counts[TransitionKind.CONTACT.value]
    assert counts == exact.transition_counts
    # measured 4.7e-10 (the event method's own error at rtol 1e-10)
    assert res.steady.period == pytest.approx(exact.steady.period, abs=1e-8)


#: A contact whose unloading curve is clipped back onto phi_C before separation (a kink of
#: the force), sliding towards the stop throughout (seed 1055 of a random search).
KINKED = (Oscillator(mu_s=0.5, mu_k=0.18, belt_speed=0.075, u_s=1.5),
          HystereticStop(clearance=0.135, k_c0=1276.0, k_e0=518.0, limit_overlap=0.0236,
                         beta_c=19.4, beta_e=20.4, law="passive"))


@pytest.mark.parametrize("law", ["paper", "passive"])
def test_a_contact_s_kinks_are_stepped_to_not_over(law):
    """Defect: a step across the kink where the unloading curve is clipped back onto
    ``phi_C`` (and across the face, where the force was cut to 0) does not see it in its
    error estimate: each separation speed was ~3e-7 relative off at rtol 1e-8, and a train
    of 130 contacts 3e-6 off by t = 40 (1e-3 of the scale on other random scenes). Steps
    now end on the kink, and the force past the face is phi_C continued (as in the exact
    method)."""
    osc, stop = KINKED[0], replace(KINKED[1], law=law)
    runs = [simulate(osc, stop, 40.0, method="event", rtol=1e-8, atol=1e-11),
            simulate(osc, stop, 40.0, rtol=1e-12, atol=1e-15)]
    ev, ref = ([tr for tr in r.transitions if tr.kind is TransitionKind.SEPARATION][0]
               for r in runs)
    # measured 4.6e-9 relative (2.7e-7 before) and 5e-10 in time
    assert ev.v == pytest.approx(ref.v, rel=5e-8)
    assert ev.t == pytest.approx(ref.t, abs=1e-8)
    # measured 2.3e-7 after 134 transitions (3.2e-6 before): the train's phase
    assert runs[0].x[-1] == pytest.approx(runs[1].x[-1], abs=1e-6)


def test_kinks_of_a_branch_are_where_its_force_bends():
    """``branch_kinks``: the force along the branch is smooth between them, and its slope
    jumps at each (one-sided difference quotients)."""
    stop = KINKED[1]
    for law in ("paper", "passive"):
        st = replace(stop, law=law)
        d_r = 0.4 * st.limit_overlap
        phi_r = float(phi_compression(d_r, st))
        unloading = reverse(d_r, phi_r, FIRST_LOADING, st)
        kinks = branch_kinks(unloading, st, 0.0, d_r * (1 - 1e-9))
        assert kinks, law
        for k in kinks:
            h = 1e-7 * st.limit_overlap
            left = (force_and_slope(k, unloading, st)[0]
                    - force_and_slope(k - h, unloading, st)[0]) / h
            right = (force_and_slope(k + h, unloading, st)[0]
                     - force_and_slope(k, unloading, st)[0]) / h
            assert abs(left - right) > 1e-3 * max(abs(left), abs(right)), (law, k)


@pytest.mark.parametrize("law", ["paper", "passive"])
@pytest.mark.parametrize("clearance", [0.24, 0.15])  # Fig. 10 (a train), Fig. 11 (pressed)
def test_the_energy_split_on_a_deformable_stop_is_the_law_s(law, clearance):
    """Defect: the work done on the stop was the trapezoid rule over the solver's steps:
    the balance closed to 2e-6 to 5e-6 of the belt's input on Figs. 10 and 11, the passive
    law's loss dipped by up to 4.8e-7, and the final loss was 6e-4 off the exact method's.
    The work is now the law's primitive along each branch (StopWork)."""
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    stop = HystereticStop(clearance=clearance, k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                          beta_c=300.0, beta_e=300.0, law=law)
    res = simulate(osc, stop, 60.0, method="event", rtol=1e-8, atol=1e-11, n_samples=3000)
    exact = simulate(osc, stop, 60.0, rtol=1e-10, atol=1e-13, n_samples=3000)
    e = res.energy
    budget = e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss - e.stop_stored)
    scale = np.max(np.abs(e.belt_input))
    # measured 6e-10 and 1.3e-10 at the end (the states' own integration error)
    assert np.max(np.abs(budget)) < 1e-8 * scale
    if law == "passive":  # no closed program returns energy: the loss never falls
        loss = np.asarray(e.stop_loss)
        assert np.all(np.diff(loss) >= -1e-15 * scale)
    # the same loss as the exact method's (4 digits measured, the trajectories' agreement)
    assert e.stop_loss[-1] == pytest.approx(exact.energy.stop_loss[-1], rel=1e-5)


def test_the_stored_energy_while_unloading_is_the_current_branch_s():
    """Defect: the event method's stored energy at a sample was that of a fresh unloading
    from the sample's ``(delta, phi)``; on an unloading branch clipped onto the compression
    envelope the stop gives back what its current branch does. On this stiff, thin stop
    (issue's case: k_c0 = 1000, D = 1e-3, beta = 10) the stored energy was 2.2e-4 off the
    exact method's at t = 19.42 (13 % of it), and the loss with it."""
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    stop = HystereticStop(clearance=0.25, k_c0=1000.0, k_e0=500.0, limit_overlap=1e-3,
                          beta_c=10.0, beta_e=10.0)
    te = np.linspace(0.0, 20.0, 6001)
    res = simulate(osc, stop, 20.0, method="event", rtol=1e-9, atol=1e-12, t_eval=te)
    exact = simulate(osc, stop, 20.0, rtol=1e-12, atol=1e-15, t_eval=te)
    assert np.max(np.abs(res.x - exact.x)) < 1e-7  # the same motion: measured 2.2e-9
    # measured 3.4e-9 (the states' difference through the stiff law's slope)
    assert np.max(np.abs(res.energy.stop_stored - exact.energy.stop_stored)) < 1e-7
    assert np.max(np.abs(res.energy.stop_loss - exact.energy.stop_loss)) < 1e-7
