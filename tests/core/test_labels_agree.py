"""The numerical methods label the steady state as the exact solution does.

On a small grid of deformable-stop scenes (pressed, ``clearance < a``, and not) the switch
and event methods are compared with the exact solution:

* a label that is impossible for a pressed stop is never given: no slip circle about
  ``(a, 0)`` touches a stop at ``x_bar < a`` without crossing it, so neither ``grazing``
  nor ``pure_slip`` can be the limit (:func:`core.steady.pressed_on_stop`);
* wherever the trajectories agree (largest gap between the sampled positions over the
  horizon below ``AGREE`` of the motion's amplitude), the labels agree. One pair is the
  same label to a method's tolerance: a train of contacts whose approach speed falls by
  less than ``SLOW_TRAIN`` per contact repeats itself to the numerical tolerance over the
  window the search looks at, so ``periodic`` for it is the exact ``contact_train`` seen at
  that accuracy.
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
#: Relative fall of the contact speed per contact below which a train is a fixed point to a
#: numerical method's steady tolerance (1e3 rtol of the state scale, ``core.dense``; with
#: the switch model's stick band it reaches ~1e-2).
SLOW_TRAIN = 1e-2
T_END = 30.0
IMPOSSIBLE_WHEN_PRESSED = {SteadyKind.GRAZING, SteadyKind.PURE_SLIP}

GRID = list(itertools.product((0.1, 0.25, 0.5), (0.1, 0.3, 0.55, 0.8), (1.0, 100.0)))


def _scene(belt_speed, clearance, beta):
    osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=belt_speed, u_s=2.0)
    stop = HystereticStop(
        clearance=clearance, k_c0=1e3, k_e0=5e2, limit_overlap=1e-1, beta_c=beta, beta_e=beta
    )
    return osc, stop


def _same_label(exact, numerical) -> bool:
    if exact.kind is numerical.kind:
        return True
    slow = exact.kind is SteadyKind.CONTACT_TRAIN and abs(1.0 - exact.decay_rate) < SLOW_TRAIN
    return slow and numerical.kind is SteadyKind.PERIODIC


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
            assert _same_label(exact.steady, res.steady), (method, exact.steady, res.steady, gap)
