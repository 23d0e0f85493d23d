"""Energy terms while the mass rests on a rigid stop, for every method.

At rest on the stop (``x = x_bar``, ``x' = 0``) the belt slides forward under the mass, so
friction is kinetic, ``+a`` (``docs/physics.md``, Rest at the stop): the belt's work grows at
the rate ``a v`` and the friction work, the stop loss and the mechanical energy stay put.
References: the exact method (closed form) and that rate over the rest interval.
"""

from __future__ import annotations

import pytest

from core import Oscillator, RigidStop, TransitionKind, simulate

T_END = 60.0
#: (mu_s, mu_k, v, x_bar, r): rest after an accumulation (Zeno), after a plastic impact, with
#: mu_k = mu_s, and on a faster belt.
REST_SCENES = [
    (0.3, 0.2, 0.07, 0.15, 0.3),
    (0.3, 0.2, 0.07, 0.15, 0.0),
    (0.3, 0.3, 0.07, 0.25, 0.7),
    (0.3, 0.2, 0.1, 0.12, 0.5),
]
#: Event method at rtol 1e-8 over t = 60: the integration error of the energy sums stays
#: well below 1e-7 of their size (measured ~1e-12).
EVENT_REL = 1e-7
#: Switch model: its stick band of half-width eta = 1e-4 v shifts stick velocities and
#: transition points by O(eta), an error ~1e-6 of the sums here; 1e-4 leaves room. The
#: missing reaction this guards against changes the belt's work by 15-25 %.
SWITCH_REL = 1e-4
FIELDS = ("belt_input", "friction_work", "stop_loss", "mechanical")


def _rest_time(res) -> float:
    return next(tr.t for tr in res.transitions if tr.kind is TransitionKind.REST)


@pytest.mark.parametrize(("mu_s", "mu_k", "v", "x_bar", "r"), REST_SCENES)
@pytest.mark.parametrize(("method", "rel"), [("event", EVENT_REL), ("switch", SWITCH_REL)])
def test_energy_at_rest_on_rigid_stop_matches_exact(mu_s, mu_k, v, x_bar, r, method, rel):
    osc, stop = Oscillator(mu_s=mu_s, mu_k=mu_k, belt_speed=v), RigidStop(x_bar, r)
    exact = simulate(osc, stop, t_end=T_END)
    opts = {"rtol": 1e-8, "atol": 1e-11} if method == "event" else {}
    num = simulate(osc, stop, t_end=T_END, method=method, **opts)
    t_rest = _rest_time(exact)
    assert t_rest < T_END / 2  # the scene spends most of the horizon at rest
    scale = exact.energy.belt_input[-1]
    for name in FIELDS:
        assert getattr(num.energy, name)[-1] == pytest.approx(
            getattr(exact.energy, name)[-1], abs=rel * scale
        ), name
    e = num.energy
    balance = e.mechanical[-1] - e.mechanical[0] - (e.friction_work[-1] - e.stop_loss[-1])
    assert balance == pytest.approx(0.0, abs=rel * scale)
    # the belt's work over the rest: kinetic friction a at the belt speed
    rest = num.t >= max(t_rest, _rest_time(num))
    gain = e.belt_input[rest][-1] - e.belt_input[rest][0]
    span = num.t[rest][-1] - num.t[rest][0]
    assert gain == pytest.approx(osc.a * v * span, rel=rel)
    assert num.contact_force[-1] == pytest.approx(osc.a - x_bar, abs=1e-15)
