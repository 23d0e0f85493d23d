"""The numerical methods label the steady state as the exact solution does.

On a small grid of deformable-stop scenes (pressed, ``clearance < a``, and not) the switch
and event methods are compared with the exact solution:

* a label that is impossible for a pressed stop is never given: no slip circle about
  ``(a, 0)`` touches a stop at ``x_bar < a`` without crossing it, so neither ``grazing``
  nor ``pure_slip`` can be the limit (:func:`core.steady.pressed_on_stop`);
* wherever the trajectories agree (largest gap between the sampled positions over the
  horizon below ``AGREE`` of the motion's amplitude), the labels agree. A train of
  contacts that loses energy is not periodic to any method, however slowly its speeds
  fall (the law labels it, ``core.steady.train_steady``); a numerical method's tolerance
  once let ``periodic`` stand for the exact ``contact_train``.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from core import HystereticStop, Oscillator, simulate
from core.result import SteadyKind
from core.steady import pressed_on_stop

#: Trajectories agree when their sampled positions differ by less than this fraction of the
#: amplitude: the methods' default tolerances give ~1e-4 over this horizon, a different
#: attractor or a phase slip gives O(1).
AGREE = 1e-2
T_END = 30.0
IMPOSSIBLE_WHEN_PRESSED = {SteadyKind.GRAZING, SteadyKind.PURE_SLIP}

GRID = list(itertools.product((0.1, 0.25, 0.5), (0.1, 0.3, 0.55, 0.8), (1.0, 100.0)))


def _scene(belt_speed, clearance, beta):
    osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=belt_speed, u_s=2.0)
    stop = HystereticStop(
        clearance=clearance, k_c0=1e3, k_e0=5e2, limit_overlap=1e-1, beta_c=beta, beta_e=beta
    )
    return osc, stop


@pytest.mark.parametrize(("belt_speed", "clearance", "beta"), GRID)
def test_numerical_labels_agree_with_exact(belt_speed, clearance, beta):
    osc, stop = _scene(belt_speed, clearance, beta)
    pressed = pressed_on_stop(osc, clearance)
    exact = simulate(osc, stop, T_END, method="exact")
    t = exact.t
    amplitude = float(np.max(np.abs(exact.x)))
    for method in ("switch", "event"):
        res = simulate(osc, stop, T_END, method=method, t_eval=t)
        label = res.steady.kind
        if pressed:
            assert label not in IMPOSSIBLE_WHEN_PRESSED, (method, label)
        gap = float(np.max(np.abs(res.x - exact.x[: len(res.x)])))
        if len(res.x) == len(t) and gap < AGREE * amplitude:
            assert exact.steady.kind is res.steady.kind, (method, exact.steady, res.steady, gap)


#: The paper's scenes 10 and 11 (the explorer's Figs. 10-11): a train of contacts falling
#: towards the elastic speed (x_bar = 0.24 > a) and loops on a pressed stop dying out
#: (x_bar = 0.15 < a).
FIG_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)


def _fig_stop(clearance):
    return HystereticStop(clearance, 400.0, 36.0, limit_overlap=0.01, beta_c=300.0,
                          beta_e=300.0)


@pytest.mark.parametrize("method", ["exact", "event", "switch"])
def test_a_falling_train_is_grazing_towards_the_elastic_speed_in_every_method(method):
    """Fig. 10: the approach speeds fall ~4 % per contact (3.4e-3 -> 3.0e-3 by t = 80).
    switch called it "periodic, period 6.23" (its tolerance, with the stick band's floor,
    is loose enough to take a train losing 4 % per contact for a fixed point), event
    "grazing ... as r^h towards a slip circle touching the stop" (the rigid stop's). Each
    now names the elastic speed w_inf the train tends to, as exact does."""
    from core.deformable.law import elastic_limit

    res = simulate(FIG_OSC, _fig_stop(0.24), 80.0, method=method)
    speeds = [tr.v for tr in res.transitions if tr.kind.value == "contact"]
    assert speeds[-1] < 0.99 * speeds[-3]  # still falling, by far more than any tolerance
    w_inf = elastic_limit(0.2, 0.24, _fig_stop(0.24)).w_inf
    assert res.steady.kind is SteadyKind.GRAZING, res.steady.describe()
    assert res.steady.impact_speed == w_inf
    assert f"{w_inf:.4g}" in res.steady.describe()


#: Fig. 11's loops at t_end = 80 swing by ~6e-8 in x (~50 loops on from the switch's
#: recorded ones), 2 to 20 times what the rule for rest lets rest at rtol 1e-8 and 1e-9.
FIG11_T_END = 80.0
#: The methods' amplitudes at t_end agree to this fraction: their states differ by ~1e-9
#: (rtol 1e-8 of a 0.3 scale, less the loops' own 6e-8), the switch model's the most.
FIG11_AMPLITUDE_AGREE = 0.05


@pytest.mark.parametrize("method", ["exact", "event", "switch"])
def test_loops_dying_on_a_pressed_stop_are_an_oscillation_in_every_method(method):
    """Fig. 11: loops on the stop shrink towards rest. switch and event called them
    "periodic, 1 transition per period: reversal" (one reversal is half a loop, and loops
    smaller than the tolerance match each other); then every method called them "rest at
    the stop, approached asymptotically" while they still swung at t_end by 20 times the
    rule's amplitude at rtol 1e-8. Each now says what happens there: an oscillation
    dying out, with the same amplitude, decay and cycle as the exact method's."""
    kw = {"rtol": 1e-8, "atol": 1e-11}
    res = simulate(FIG_OSC, _fig_stop(0.15), FIG11_T_END, method=method, **kw)
    exact = simulate(FIG_OSC, _fig_stop(0.15), FIG11_T_END, **kw)
    for steady in (res.steady, exact.steady):
        assert steady.kind is SteadyKind.OSCILLATION, steady.describe()
        assert steady.amplitude > steady.rest_amplitude
        assert 0.0 < steady.decay_rate < 1.0
    assert res.steady.amplitude == pytest.approx(exact.steady.amplitude,
                                                 rel=FIG11_AMPLITUDE_AGREE)
    # the cycle to the reversals' timing: a reversal is an extremum of x, located to the
    # velocity's error over the acceleration there (event: ~3e-6 in time, 2e-5 of the cycle)
    assert res.steady.period == pytest.approx(exact.steady.period, rel=1e-4)


def test_a_slowly_losing_train_is_never_a_fixed_point():
    """A train whose contacts lose energy by the law (speeds between w_inf and w_deep) is
    not periodic however little it loses: exact called Fig. 10's train periodic at
    t_end = 1e6 (speeds 0.33 % above w_inf, losing 2e-8 per contact) after calling it
    grazing at 1e5. Here a train losing 1e-12 of its speed per contact, within every
    tolerance of the fixed-point detector, read with the law and without it."""
    from core.deformable.law import elastic_limit
    from core.result import Transition, TransitionKind
    from core.steady import steady_from_transitions

    limit = elastic_limit(0.2, 0.24, _fig_stop(0.24))
    w, t, tail = 1.0033 * limit.w_inf, 0.0, []
    for _ in range(32):
        tail += [Transition(TransitionKind.CONTACT, t, 0.24, w, w),
                 Transition(TransitionKind.REVERSAL, t + 0.036, 0.24 + limit.r_inf, 0.0, 0.0),
                 Transition(TransitionKind.SEPARATION, t + 0.072, 0.24, -w, -w)]
        t, w = t + 6.267, w * (1.0 - 1e-12)
    kw = {"scale": 0.3, "rtol": 1e-11, "t_end": t, "final_mode": 0, "final_v": 0.0}
    assert steady_from_transitions(tail, **kw).kind is SteadyKind.PERIODIC
    steady = steady_from_transitions(tail, **kw, limit=limit)
    assert steady.kind is SteadyKind.GRAZING and steady.impact_speed == limit.w_inf
    # below w_inf the same train is elastic: periodic whatever its drift
    slow = [tr._replace(v=0.5 * tr.v, v_after=0.5 * tr.v_after) for tr in tail]
    assert steady_from_transitions(slow, **kw, limit=limit).kind is SteadyKind.PERIODIC


#: Scene 7d (x_bar = 0.15 < a = 0.2, slow belt) with a stop that is nearly elastic: the
#: stick->impact rebound misses the stick line, so impacts alone follow, slip on the circle
#: about (a, 0) between them, with approach speeds falling as r^h to an accumulation
#: (exact: rest at t = 2416.70 for r = 0.999).
ZENO_OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)


@pytest.mark.parametrize(("method", "r"), [("switch", 0.999), ("event", 0.999),
                                           ("event", 0.99999)])
def test_a_decaying_impact_sequence_is_not_periodic(method, r):
    """switch called r = 0.999 "periodic, period 1.8712, one impact per period" and event
    r = 0.99999 "periodic 1.90081": the speeds fall by 1 - r per impact, inside the
    fixed-point tolerance of a method at rtol ~1e-6. Slip on one circle does no net
    friction work over a closed cycle, so impacts that lose energy cannot repeat."""
    from core import RigidStop

    stop = RigidStop(0.15, r)
    res = simulate(ZENO_OSC, stop, 40.0, method=method)
    impacts = [tr for tr in res.transitions if tr.kind.value == "impact"]
    assert len(impacts) >= 10
    # the r^h law, read off the method's own impacts (to its integration error, ~1e-6)
    ratios = np.array([b.v / a.v for a, b in zip(impacts[-8:], impacts[-7:], strict=False)])
    np.testing.assert_allclose(ratios, r, atol=1e-5)
    assert res.steady.kind is not SteadyKind.PERIODIC, res.steady.describe()
    exact = simulate(ZENO_OSC, stop, 40.0)
    assert exact.steady.kind is SteadyKind.REST and exact.steady.t_reached > 40.0


def test_inelastic_impacts_alone_are_never_a_fixed_point():
    """Impacts at the rebound arcs' closed-form times (docs/physics.md, Zeno and grazing
    sums) losing 1e-9 of their speed each, within a loose detector tolerance: not
    periodic; the same train with r = 1 is."""
    from core.result import Transition, TransitionKind
    from core.steady import steady_from_transitions

    def train(r):
        w, t, tail = 0.05, 0.0, []
        for _ in range(32):
            tail.append(Transition(TransitionKind.IMPACT, t, 0.15, w, -r * w))
            w *= r
            t += 2.0 * np.arctan(w / 0.05)
        return tail, t

    kw = {"scale": 0.3, "rtol": 1e-6, "final_mode": 0, "final_v": 0.0}
    tail, t = train(1.0 - 1e-9)
    assert steady_from_transitions(tail, t_end=t, **kw).kind is not SteadyKind.PERIODIC
    assert steady_from_transitions(tail, t_end=t, pressed=True, **kw).kind is SteadyKind.NONE
    tail, t = train(1.0)
    assert steady_from_transitions(tail, t_end=t, **kw).kind is SteadyKind.PERIODIC


def test_a_cycle_through_a_reset_state_is_periodic_after_one_repeat():
    """A slow belt carries the stuck mass onto the stop at its own speed in every cycle, so
    each cycle starts from the same state to the bit. Two cycles of 41 time units fit in
    ``t_end = 100``: the exact method said "periodic" (its states repeat to rounding), the
    event method "none" (it asked for two repeats at its tolerance), though the two
    trajectories agree to 6e-9. A repeat to rounding over one period now suffices."""
    osc = Oscillator(mu_s=0.1037, mu_k=0.05853, belt_speed=0.006038, u_s=2.7647)
    stop = HystereticStop(clearance=0.277, k_c0=1984.0, k_e0=57.58, limit_overlap=0.012524,
                          beta_c=2.315, beta_e=3.015, law="passive")
    runs = [simulate(osc, stop, 100.0, 0.0, -0.02438, method=m) for m in ("exact", "event")]
    assert [r.steady.kind for r in runs] == [SteadyKind.PERIODIC] * 2
    # the same cycle: period to the event method's error (1.4e-7 measured at rtol 1e-8)
    assert runs[1].steady.period == pytest.approx(runs[0].steady.period, rel=1e-6)
    assert runs[1].steady.transitions_per_period == runs[0].steady.transitions_per_period
