"""The reduced model of a shrinking train of contacts of a pressed mass
(:class:`core.deformable.reduced_train.Train`) against the step-by-step solve it replaces.

The belt ``Oscillator(0.45, 0.30, 0.25, u_s=2.0)`` (a = 0.6) presses the mass on a stop
whose face is at 0.42: the mass bounces on it in ever smaller contacts, thousands of them
(docs/contact-law.md, a mass pressed on the stop).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import HystereticStop, Oscillator, TransitionKind
from core.deformable import train_map
from core.deformable.reduced_train import fit_train_decay
from core.deformable.rest import TRAIN_PER_RTOL
from core.deformable.solver import simulate_hysteretic

PRESSING = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=0.25, u_s=2.0)
FACE = 0.42
#: The app's "standard" preset (app/solve/presets.py).
STANDARD = {"rtol": 1e-8, "atol": 1e-11}
T_END = 30.0
#: Cells (k_c0, beta, D; k_e0 = k_c0 / 2) of benchmarks/hysteretic_speed.py whose trains
#: were integrated contact by contact (18 s and 12 s at t_end = 100 before the model).
CELLS = [(1e5, 100.0, 1e-3), (1e5, 1000.0, 1e-2)]


def _stop(k_c0, beta, d) -> HystereticStop:
    return HystereticStop(FACE, k_c0, 0.5 * k_c0, limit_overlap=d, beta_c=beta, beta_e=beta)


def _scale(stop) -> float:
    return max(PRESSING.a, PRESSING.b, PRESSING.v, stop.clearance, stop.limit_overlap)


@pytest.fixture(scope="module", params=CELLS, ids=lambda c: f"{c[0]:g},{c[1]:g},{c[2]:g}")
def pair(request):
    stop = _stop(*request.param)
    # The contact-to-contact map (core/deformable/train_map.py) takes these trains first; it is
    # held back here (as where too few contacts are left for its nodes) so that the fitted
    # loss law these tests are about is what runs.
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(train_map, "MIN_GAIN", math.inf)
        reduced = simulate_hysteretic(PRESSING, stop, T_END, 0.0, 0.0, **STANDARD)
    full = simulate_hysteretic(PRESSING, stop, T_END, 0.0, 0.0, reduce=False,
                               transition_cap=1_000_000, **STANDARD)
    return stop, reduced, full


def _switch(res):
    switch = [tr for tr in res.transitions if tr.kind is TransitionKind.REDUCED]
    assert switch, "the train was not handed to its reduced model"
    return switch[0]


def test_reduced_train_agrees_with_the_full_solve_within_its_stated_bound(pair):
    stop, reduced, full = pair
    sw = _switch(reduced)
    bound = reduced.info["reduced_error"]
    t = np.linspace(sw.t, T_END, 40_001)
    x_r, v_r = reduced.dense.evaluate(t)
    x_f, v_f = full.dense.evaluate(t)
    # Stated bounds (Train's docstring): the position within the band at the switch, the
    # velocity within twice the approach speed there (the phase of the train).
    assert np.abs(x_r - x_f).max() <= bound
    assert np.abs(v_r - v_f).max() <= 2.0 * sw.v
    # Identical up to the switch: the largest displacement is the first contact's.
    assert reduced.x_max == pytest.approx(full.x_max, abs=1e-12)
    before = reduced.t < sw.t
    assert np.abs(reduced.x[before] - full.dense.evaluate(reduced.t[before])[0]).max() < 1e-12
    # The envelope (the largest speed over the last unit of time, the approach speed) is
    # what the model advances: the loss law fitted over 32 contacts extrapolates it to within
    # 10 % over the next ~500 contacts (measured 7 % at t = 40 on the first cell).
    late = t > T_END - 1.0
    assert np.abs(v_r[late]).max() == pytest.approx(np.abs(v_f[late]).max(), rel=0.1)
    # So many contacts are modelled, not skipped: the count agrees to the same 10 %.
    assert reduced.info["n_contacts"] == pytest.approx(full.info["n_contacts"], rel=0.1)


def test_train_is_not_handed_over_before_its_band_is_below_the_threshold(pair):
    """The band the reference moves in from the switch on is below ``TRAIN_PER_RTOL rtol``
    of the scale: a switch made earlier (a wider train) fails this."""
    stop, reduced, full = pair
    sw = _switch(reduced)
    threshold = TRAIN_PER_RTOL * STANDARD["rtol"] * _scale(stop)
    assert reduced.info["reduced_band"] <= threshold
    x_f, v_f = full.dense.evaluate(np.linspace(sw.t, T_END, 40_001))
    assert np.ptp(x_f) <= threshold
    # ... and the stated band covers it (it is the band at the switch), and the stated
    # error in the state also the velocity (both speeds within the approach speed).
    assert np.ptp(x_f) <= reduced.info["reduced_band"] * 1.05
    assert reduced.info["reduced_error"] == pytest.approx(2.0 * abs(sw.v), rel=1e-12)
    assert np.abs(v_f).max() <= 1.05 * abs(sw.v)


def test_reduced_train_keeps_the_energy_balance_and_a_true_label(pair):
    stop, reduced, _ = pair
    e = reduced.energy
    lhs = e.mechanical - e.mechanical[0]
    # The balance closes to the integration tolerance (rtol 1e-8 over ~1000 contacts).
    assert np.abs(lhs - (e.friction_work - e.stop_loss - e.stop_stored)).max() < 1e-6
    # Losses never fall back (rounding of cumulative sums of size ~0.1: 1e-15).
    assert np.diff(e.stop_loss).min() > -1e-15
    assert reduced.steady.kind.value == "contact_train"
    assert 0.0 < reduced.steady.decay_rate < 1.0


@pytest.mark.parametrize(("n", "limit"), [(1.0, 0.0), (2.0, 0.0), (6.0, 0.003)])
def test_loss_law_is_recovered_from_its_own_train(n, limit):
    """Contacts built with the law ``w_k - w_{k+1} = c (w_k - w_inf)^n`` give it back, and
    its closed form extrapolates them 25 times as far as the 40 contacts it saw."""
    c = {1.0: 0.05, 2.0: 2.0, 6.0: 1e9}[n]
    w = [0.005]
    for _ in range(1000):
        w.append(w[-1] - c * (w[-1] - limit) ** n)
    w = np.array(w)
    law = fit_train_decay(w[:41])
    assert law.n == pytest.approx(n, rel=0.05)
    # Within 5 % of what the train loses over those 1000 contacts: the map and its
    # continuous form differ by a fraction of one loss per contact, and near a limit the
    # limit itself is only known to ~1e-3 of w from 40 contacts losing 5e-4 of w.
    model = law.speed(w[0], np.arange(len(w)))
    assert np.abs(model - w).max() <= 0.05 * (w[0] - w[-1])


def test_train_that_dies_out_rests_at_the_pressed_equilibrium():
    """A stiff stop with a loss per contact that stays a fixed fraction (``beta`` so large
    that every overlap leaves the compression envelope; ``k_e0 = 0.9 k_c0``): the approach
    speed falls geometrically to zero and the train ends at rest on the stop."""
    stop = HystereticStop(FACE, 1e6, 9e5, limit_overlap=1e-3, beta_c=1e5, beta_e=1e5)
    reduced = simulate_hysteretic(PRESSING, stop, 100.0, 0.0, 0.0, **STANDARD)
    full = simulate_hysteretic(PRESSING, stop, 100.0, 0.0, 0.0, reduce=False, **STANDARD)
    sw = _switch(reduced)
    rests = [tr.t for tr in reduced.transitions if tr.kind is TransitionKind.REST]
    full_rests = [tr.t for tr in full.transitions if tr.kind is TransitionKind.REST]
    assert reduced.steady.kind.value == full.steady.kind.value == "rest"
    assert len(rests) == 1 and rests[0] > sw.t
    # Rest at the equilibrium: the stop's force balances the kinetic friction, phi = a - x
    # (to the root's tolerance, 1e-16 of the scale; 1e-9 relative is the promise).
    assert reduced.info["rest_force"] == pytest.approx(PRESSING.a - reduced.x[-1], rel=1e-9)
    # ... which is where the full solve rests, within the rest amplitude (10 rtol of the
    # scale) its last loops leave.
    assert abs(reduced.x[-1] - full.x[-1]) <= 10.0 * STANDARD["rtol"] * _scale(stop)
    # The time of rest: the model ends the train once its band is within the rest
    # amplitude and its approach speed within half of it; the full solve's last contacts
    # stop separating (t = 46.43) and die out as loops on the stop, which rest once their
    # swing is within the rest amplitude in the position and in the velocity (omega, ~1377
    # here, times the position's). Those loops die like 1/k: their velocity's swing falls
    # from 3.2e-7 at the model's rest to 9e-8 at the full solve's, 1.52 later (0.58 when
    # the rule read the position alone, and the full solve rested with its loops still
    # swinging at 5e-7).
    assert rests[0] == pytest.approx(full_rests[0], abs=2.0)
    # Whichever rests first, the rest is the motion to the preset's error (1e-6 of the
    # scale): the loops the full solve follows past the model's rest stay within it.
    t = np.linspace(rests[0], full_rests[0], 2001)
    x_full, v_full = full.dense.evaluate(t)
    assert max(np.abs(x_full - reduced.x[-1]).max(), np.abs(v_full).max()) <= (
        1e-6 * _scale(stop))
    t = np.linspace(sw.t, rests[0], 20_001)
    assert np.abs(reduced.dense.evaluate(t)[0] - full.dense.evaluate(t)[0]).max() <= (
        reduced.info["reduced_error"])
