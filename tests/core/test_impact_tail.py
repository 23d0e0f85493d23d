"""An endless impact sequence past its explicitly evaluated impacts (core.impact_sequence).

With ``r`` near 1 an accumulation or a grazing approach has more impacts above the speed
floor than :data:`core.impact_sequence.MAX_ARCS`. The samples after the last explicit
impact were the limit (rest at the stop, status SUCCESS) while the mass still bounced: at
``r = 1 - 1e-6`` from t = 1.107e6 to the accumulation at 1.832e6. The reference here is the
same sequence with every arc evaluated explicitly (a cumulative sum of the closed-form arc
durations), against the bisection over closed-form partial sums that places the later ones.
"""

from __future__ import annotations

import numpy as np
import pytest

import core.impact_sequence as impact_sequence
from core import Mode, Oscillator, RigidStop, SteadyKind, simulate

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
#: The explicit reference sums ~1e4-1e6 arc durations one after another: its times carry
#: ~sqrt(n) ulps of t (a few 1e-12 at t ~ 1e4, ~1e-9 at t ~ 1e6), and the closed-form
#: partial sums ~1 ulp of t; a state moves by at most its speed times that.
ULPS_OF_T = 64 * np.finfo(float).eps
FIELDS = ("belt_input", "friction_work", "stop_loss", "mechanical")


def _pair(monkeypatch, stop, t_end, cap, t_eval, full_cap=10**6):
    """The scene with at most ``cap`` explicit impacts, and with up to ``full_cap``
    (more than happen before ``t_end``)."""
    monkeypatch.setattr(impact_sequence, "MAX_ARCS", cap)
    cut = simulate(SLOW, stop, t_end=t_end, t_eval=t_eval)
    monkeypatch.setattr(impact_sequence, "MAX_ARCS", full_cap)
    full = simulate(SLOW, stop, t_end=t_end, t_eval=t_eval)
    assert cut.info["impacts_evaluated"] == cap < full.info["impacts_evaluated"]
    return cut, full


@pytest.mark.parametrize(
    ("x_bar", "t_end"),
    [(0.1, 3000.0), (0.203, 2e4), (0.2, 2e4)],
    ids=["accumulation", "grazing", "grazing-at-centre"],
)
def test_impacts_past_the_explicit_ones_are_exact(monkeypatch, x_bar, t_end):
    """r = 0.999: ~3e4 impacts above the floor; 2000 explicit, the rest in closed form."""
    grid = np.linspace(0.0, t_end, 1001)
    cut, full = _pair(monkeypatch, RigidStop(x_bar, 0.999), t_end, 2000, grid)
    tol = ULPS_OF_T * t_end
    np.testing.assert_allclose(cut.x, full.x, rtol=0, atol=tol)
    np.testing.assert_allclose(cut.v, full.v, rtol=0, atol=tol)
    np.testing.assert_array_equal(cut.mode, full.mode)
    for name in FIELDS:
        np.testing.assert_allclose(getattr(cut.energy, name), getattr(full.energy, name),
                                   rtol=0, atol=tol, err_msg=name)
    assert cut.transition_counts == full.transition_counts
    assert cut.steady.kind is full.steady.kind


def test_the_state_a_million_impacts_in_is_not_rest(monkeypatch):
    """r = 1 - 1e-6, x_bar = 0.1 < a: evaluate(1.3e6) was (0.1, 0) with status SUCCESS, the
    rest that comes only at t = 1831930.74. The mass is at (0.097367, 0.013602) there,
    between impacts of speed ~0.0268."""
    stop = RigidStop(0.1, 0.999999)
    res = simulate(SLOW, stop, t_end=5e6)
    assert res.steady.kind is SteadyKind.REST
    assert res.steady.t_reached == pytest.approx(1831930.74, abs=0.01)
    x, v = res.evaluate([1.3e6])
    assert abs(x[0] - 0.097367) < 1e-6 and abs(v[0] - 0.013602) < 1e-6
    # the reference: every arc up to t = 1.4e6 explicit (1.5e6 impacts)
    grid = np.linspace(1.0e6, 1.4e6, 401)
    cut, full = _pair(monkeypatch, stop, 1.4e6, 1_000_000, grid, full_cap=1_600_000)
    np.testing.assert_allclose(cut.x, full.x, rtol=0, atol=ULPS_OF_T * 1.4e6)
    np.testing.assert_allclose(cut.v, full.v, rtol=0, atol=ULPS_OF_T * 1.4e6)
    tail = res.t > 1.2e6
    tail &= res.t < 1.8e6
    assert np.all(res.mode[tail] == Mode.SLIP) and np.all(res.x[tail] < 0.1)
    # at rest, every impact has taken its share of the kinetic energy
    e = res.energy
    balance = e.mechanical[-1] - e.mechanical[0] - (e.friction_work[-1] - e.stop_loss[-1])
    assert abs(balance) < 1e-12
