"""The trade-off table's verdict note (app.solve.trade), without solving."""

from __future__ import annotations

from app.solve.trade import rest_alike
from core import HystereticStop, Oscillator, RigidStop
from core.deformable.rest import rest_swing_of
from core.result import Steady, SteadyKind

OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
STOP = HystereticStop(0.15, 400.0, 36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
STANDARD = {"rtol": 1e-8, "atol": 1e-11}


def _swinging(scale: float) -> Steady:
    """A reference's oscillation on the stop swinging at ``scale`` times the standard
    preset's rule for rest (its own rule, at rtol 1e-12, is 1e4 times tighter)."""
    rest_x, rest_v = rest_swing_of(OSC, STOP, **STANDARD)
    return Steady(SteadyKind.OSCILLATION, period=0.17, decay_rate=0.9998,
                  amplitude=scale * rest_x, velocity_amplitude=scale * rest_v,
                  rest_amplitude=1e-4 * rest_x, rest_velocity=1e-4 * rest_v)


def test_a_rest_whose_reference_swings_within_the_run_s_rule_is_the_same_verdict():
    """A preset's rest and a tighter reference's loops swinging within that preset's rule
    for rest are one verdict at the preset's accuracy; beyond it, or on a rigid stop, or
    against another label, they differ."""
    rest = Steady(SteadyKind.REST, t_reached=500.0)
    assert rest_alike(rest, _swinging(0.5), OSC, STOP, STANDARD)
    assert not rest_alike(rest, _swinging(2.0), OSC, STOP, STANDARD)
    assert not rest_alike(rest, _swinging(0.5), OSC, RigidStop(0.15, 0.5), STANDARD)
    periodic = Steady(SteadyKind.PERIODIC, period=1.0)
    assert not rest_alike(periodic, _swinging(0.5), OSC, STOP, STANDARD)
