"""A motion that starts inside a deformable stop, or at its face at the belt's speed.

References: the event method (a second method, at a tight tolerance), the law's
compression envelope (the stop is taken as loaded along it to the start,
docs/contact-law.md, "A start inside the stop") and the energy balance.
"""

from __future__ import annotations

import numpy as np
import pytest

from core import HystereticStop, Oscillator, TransitionKind, phi_compression, simulate

OSC = Oscillator(0.3, 0.2, 0.1)
TIMES = np.linspace(0.0, 20.0, 41)


def balance(res) -> float:
    e = res.energy
    return float(np.max(np.abs(e.mechanical - e.mechanical[0] - e.friction_work
                               + e.stop_loss + e.stop_stored)))


@pytest.mark.parametrize(
    "clearance,x0,v0",
    [(0.1, 0.11, 0.1),     # at the belt's speed: the exact method crashed (brentq)
     (0.25, 0.26, 0.1),    # the same, not pressed
     (0.25, 0.26, 0.0),    # at rest: the exact method ignored the stop (force 0)
     (0.25, 0.26, -0.05),  # moving out: the same
     (0.1, 0.105, 0.0),    # pressed: the balance missed the stored energy
     (0.25, 0.26, 0.3)],   # moving in faster than the belt
    ids=["belt-speed", "belt-speed-free", "rest", "out", "pressed", "in"],
)
def test_a_start_inside_the_stop_is_the_same_motion_for_every_method(clearance, x0, v0):
    stop = HystereticStop(clearance)
    # Tight: the default's periodic tiling is off by up to 5e-5 in x' on this stop from any
    # start (x0 = 0: 3.2e-5 by t = 40), which is not what is tested here.
    exact = simulate(OSC, stop, 20.0, x0=x0, v0=v0, rtol=1e-12, atol=1e-15)
    # The stop is loaded along phi_C to the start: that is its force there.
    assert exact.contact_force[0] == pytest.approx(
        float(phi_compression(x0 - clearance, stop)), rel=1e-12)
    assert exact.transitions[0].kind is TransitionKind.CONTACT and exact.transitions[0].t == 0.0
    # Against the event method at rtol 1e-10: measured within 3.4e-9 in x' on the pressed
    # stop (the event method's own error); before, 0.1 apart or a crash.
    event = simulate(OSC, stop, 20.0, x0=x0, v0=v0, method="event", rtol=1e-10, atol=1e-13)
    xe, ve = exact.evaluate(TIMES)
    xv, vv = event.evaluate(TIMES)
    np.testing.assert_allclose(xe, xv, atol=1e-7)
    np.testing.assert_allclose(ve, vv, atol=1e-7)
    assert exact.steady.kind is event.steady.kind
    # The balance closes from the start's stored energy (measured 1e-11; before, off by
    # the stored energy at the start, 0.013).
    assert balance(exact) < 1e-9
    assert np.all(np.diff(exact.energy.stop_loss) >= -1e-12)


def test_a_still_belt_holds_a_start_inside_the_stop_where_friction_can():
    # |x0 + phi_C| = 0.29 <= b = 0.3 on a still belt: the mass never moves.
    osc = Oscillator(0.3, 0.2, 0.0)
    stop = HystereticStop(0.25)
    res = simulate(osc, stop, 5.0, x0=0.25004)
    phi = float(phi_compression(0.00004, stop))
    assert res.steady.kind.value == "rest" and res.steady.t_reached == 0.0
    np.testing.assert_array_equal(res.x, 0.25004)
    np.testing.assert_allclose(res.contact_force, phi, rtol=1e-12)
    assert res.info["rest_force"] == pytest.approx(phi, rel=1e-12)


def test_a_start_at_the_face_at_the_belt_s_speed_slips_the_way_the_spring_pushes():
    # x0 = 0.29 > b = 0.25 at x' = v: friction cannot hold, the mass falls behind the belt
    # (friction forward, s = +1). The exact method took s = -1: x'' = -0.49 for -0.09,
    # a spurious sign change, 1.2e-5 off the event method.
    osc = Oscillator(0.25, 0.2, 0.3)
    stop = HystereticStop(0.29, k_c0=100.0, k_e0=50.0, limit_overlap=1.0, law="passive")
    times = np.linspace(0.0, 1.0, 21)
    exact = simulate(osc, stop, 1.0, x0=0.29, v0=0.3)
    event = simulate(osc, stop, 1.0, x0=0.29, v0=0.3, method="event", rtol=1e-10,
                     atol=1e-13)
    assert TransitionKind.SIGN_CHANGE not in {tr.kind for tr in exact.transitions}
    # measured 4e-10 and 6e-10
    np.testing.assert_allclose(exact.evaluate(times)[0], event.evaluate(times)[0], atol=1e-8)
    np.testing.assert_allclose(exact.evaluate(times)[1], event.evaluate(times)[1], atol=1e-8)
    assert balance(exact) < 1e-9


def test_contacts_reached_at_the_belt_s_speed_lose_no_energy_they_do_not_have():
    # mu_s = mu_k and the stop at a: every cycle reaches the face at x' = v exactly. The
    # contact took friction as s = -1 there (a sign change at each contact), and the
    # passive law's stop_loss fell by 4.8e-6 per contact: -0.0138 by t_end = 1e4.
    osc = Oscillator(0.2, 0.2, 0.1)
    stop = HystereticStop(0.2, k_c0=100.0, k_e0=50.0, limit_overlap=1.0, beta_c=100.0,
                          beta_e=100.0, law="passive")
    res = simulate(osc, stop, 100.0, x0=0.2, v0=-0.1)
    assert TransitionKind.SIGN_CHANGE not in {tr.kind for tr in res.transitions}
    # these contacts are elastic (overlaps below D / beta): the loss stays at rounding,
    # measured -7.9e-11 after 29 contacts
    assert np.all(np.diff(res.energy.stop_loss) >= -1e-11)
    assert abs(res.energy.stop_loss[-1]) < 1e-9
    assert balance(res) < 1e-9
