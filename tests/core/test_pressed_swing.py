"""Loops on a pressed deformable stop: rest only where they are at rest within the rule.

Under the paper's law the loops of a mass pressed on the stop shrink slowly (like ``1/k``
after ``k`` cycles). Read off the last reversals, any shrinking loops were labelled "rest at
the stop, approached asymptotically", while at ``t_end`` they still swung by up to 1.1e-4 of
the length scale (the rule for rest lets 1e-7 rest at rtol 1e-8), with a force imbalance
``|a - x - phi|`` up to 6e-2 of it (``benchmarks/results/pressed_swing_2026-11-29.txt``).
Now the label is rest only where the swing at ``t_end`` is within the rule's thresholds
(:func:`core.deformable.rest.rest_swing`: ``10 rtol`` of the scale in the position,
``100 rtol`` in the velocity), else an oscillation on the stop with its amplitude there and
its decay per cycle (``SteadyKind.OSCILLATION``).

Reference: the same stop with every loop followed (no reduced model) at rtol 1e-11; its swing
is measured over the last cycle before ``t_end`` on a grid finer than the label's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import HystereticStop, Oscillator, simulate
from core.deformable.decay import END_AMPLITUDE_MARGIN
from core.deformable.rest import rest_swing
from core.deformable.solver import simulate_hysteretic
from core.result import SteadyKind

#: The app's standard preset (app/solve/presets.py).
PRESET = {"rtol": 1e-8, "atol": 1e-11}
#: Every transition stored (the loops' last reversals give their cycle at t_end).
REFERENCE = {"rtol": 1e-11, "atol": 1e-14, "reduce": False, "n_samples": 200,
             "transition_cap": 1_000_000}
#: Points of the reference's last cycle: a sampled sine's half range misses its amplitude
#: by ``1 - cos(pi / n)``, 1.2e-6 here (the label samples 256 points: 7.5e-5).
POINTS = 2048
#: The stated amplitude against the reference's: the loops are followed at rtol 1e-8 or
#: carried by a reduced model whose amplitude where it ends is within END_AMPLITUDE_MARGIN
#: of the loops' (core/deformable/decay.py). Measured: within 3e-4 on every draw below.
AMPLITUDE_RTOL = END_AMPLITUDE_MARGIN - 1.0


def _osc(belt_speed: float) -> Oscillator:
    return Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=belt_speed, u_s=2.0)


def _scale(osc: Oscillator, stop: HystereticStop) -> float:
    """The solver's length scale (core.deformable.state.Solve.scale)."""
    return max(osc.a, osc.b, osc.v, abs(stop.clearance), stop.limit_overlap)


def _swing(res, t_end: float, cycle: float, back: float = 0.0) -> tuple[float, float]:
    """Half the range of x and of x' over the cycle ending ``back`` before ``t_end``."""
    t = np.linspace(t_end - back - cycle, t_end - back, POINTS + 1)
    x, v = res.evaluate(t)
    return 0.5 * float(np.ptp(x)), 0.5 * float(np.ptp(v))


def _cycle(res) -> float:
    """The loops' cycle from the last stored reversals (two a cycle)."""
    rev = [tr.t for tr in res.transitions if tr.kind.value == "reversal"]
    return rev[-1] - rev[-3]


#: Loops on a soft stop (k_c0 = 166, beta_c = 6.68, beta_e = 180, D = 0.0486): followed
#: to t_end = 400, carried by the reduced oscillation to t_end = 1600. Both were "rest at
#: the stop, approached asymptotically"; the loops swing by 6.2e-7 and 1.5e-7 there, 7 and
#: 1.7 times the rest amplitude (9e-8), and 10 and 2.6 times the rest velocity.
SWINGING = (0.245, HystereticStop(0.36, 166.0, 61.8, limit_overlap=0.0486, beta_c=6.68,
                                  beta_e=180.0))


@pytest.mark.parametrize("t_end", [400.0, 1600.0])
def test_loops_still_swinging_at_t_end_are_an_oscillation_not_rest(t_end):
    belt_speed, stop = SWINGING
    osc = _osc(belt_speed)
    res = simulate(osc, stop, t_end, **PRESET)
    ref = simulate_hysteretic(osc, stop, t_end, **REFERENCE)
    rest_x, rest_v = rest_swing(PRESET["rtol"], PRESET["atol"], _scale(osc, stop))
    cycle = _cycle(ref)
    amp, vel = _swing(ref, t_end, cycle)
    assert amp > rest_x and vel > rest_v  # the motion is not at rest within the rule
    steady = res.steady
    assert steady.kind is SteadyKind.OSCILLATION, steady.describe()
    assert (steady.rest_amplitude, steady.rest_velocity) == pytest.approx((rest_x, rest_v))
    # the loops are followed, or modelled, to within 1e-3 of their amplitude here (measured
    # 1e-5); the label's 256 points per cycle add 7.5e-5
    assert steady.amplitude == pytest.approx(amp, rel=1e-3)
    assert steady.velocity_amplitude == pytest.approx(vel, rel=1e-3)
    # the reversals' cycle: the loops' at t_end = 400; at 1600 the one where the reduced
    # model took over (t ~ 100), which it keeps (the cycle depends on the amplitude: the
    # reference's at t_end is 5e-6 shorter)
    assert steady.period == pytest.approx(cycle, rel=1e-4)
    # The decay at t_end, against the reference's amplitude 20 cycles earlier: over them
    # the rate per cycle (1e-3 to 3e-4) changes by ~20 / k of itself (k ~ 1000 to 4000 the
    # cycles so far, loops dying like 1/k), and the label's sampling moves it by ~2e-3.
    earlier = _swing(ref, t_end, cycle, back=20.0 * cycle)[0]
    rate = 1.0 - (amp / earlier) ** (1.0 / 20.0)
    assert 1.0 - steady.decay_rate == pytest.approx(rate, rel=0.05)
    assert steady.halving_time == pytest.approx(cycle * math.log(2.0) / rate, rel=0.05)
    text = steady.describe()
    assert text.startswith("oscillation on the stop") and f"{steady.amplitude:.3g}" in text


def _draws(seed: int, n: int):
    """Random pressed stops under the paper's law: k_c0 1e2..1e6, k_e0 / k_c0 0.05..1,
    beta_c 1..1e3 and beta_e from it to 1e3, D 1e-3..1, x_bar 0.3..0.6 (< a = 0.6), belt
    speed 0.05..0.5, log-uniform where a range spans decades."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        k_c0 = 10.0 ** rng.uniform(2.0, 6.0)
        beta_c = 10.0 ** rng.uniform(0.0, 3.0)
        beta_e = min(beta_c * 10.0 ** rng.uniform(0.0, 3.0), 1e3)
        d = 10.0 ** rng.uniform(-3.0, 0.0)
        clearance = rng.uniform(0.3, 0.6)
        belt_speed = rng.uniform(0.05, 0.5)
        k_e0 = k_c0 * 10.0 ** rng.uniform(-1.3, 0.0)
        out.append((belt_speed, HystereticStop(clearance, k_c0, k_e0, limit_overlap=d,
                                               beta_c=beta_c, beta_e=beta_e)))
    return out


#: Seeded draws (the same every run) and their horizons: 16 of seed 7 to t_end = 400 and
#: 1600 alternately (4 rest, 3 by the rule and one approached; one oscillation; 9 others),
#: and 4 of seed 11 to 400 (2 rest by the rule, 2 oscillations). Left out: seed 7's draws
#: 12 and 13, and seed 11's 4 to 13, trains of contacts or loops that take 5 s to 25 s to
#: solve (or their reference), 0.1 s to 1 s the others.
CASES = ([(7, k, 400.0 if k % 2 == 0 else 1600.0) for k in range(16) if k not in (12, 13)]
         + [(11, k, 400.0) for k in (1, 2, 3, 14)])


@pytest.mark.slow
@pytest.mark.parametrize(("seed", "k", "t_end"), CASES)
def test_rest_on_a_pressed_stop_is_at_rest_and_an_oscillation_states_its_swing(
        seed, k, t_end):
    belt_speed, stop = _draws(seed, k + 1)[k]
    osc = _osc(belt_speed)
    res = simulate(osc, stop, t_end, **PRESET)
    steady = res.steady
    if not res.success or steady.kind not in (SteadyKind.REST, SteadyKind.OSCILLATION):
        return
    ref = simulate_hysteretic(osc, stop, t_end, **REFERENCE)
    rest_x, rest_v = rest_swing(PRESET["rtol"], PRESET["atol"], _scale(osc, stop))
    cycle = steady.period if steady.kind is SteadyKind.OSCILLATION else _cycle(ref)
    amp, vel = _swing(ref, t_end, cycle)
    if steady.kind is SteadyKind.REST:
        # Rest by the rule's thresholds on the candidate's own loops, or by a reduced
        # model whose amplitude is within END_AMPLITUDE_MARGIN of the loops'.
        assert amp <= END_AMPLITUDE_MARGIN * rest_x, (amp / rest_x, steady)
        assert vel <= END_AMPLITUDE_MARGIN * rest_v, (vel / rest_v, steady)
        return
    assert steady.amplitude == pytest.approx(amp, rel=AMPLITUDE_RTOL)
    assert steady.velocity_amplitude == pytest.approx(vel, rel=AMPLITUDE_RTOL)
    # not at rest by the reference either, to the same margin
    assert max(amp / rest_x, vel / rest_v) > 1.0 / END_AMPLITUDE_MARGIN
    assert 0.0 < steady.decay_rate < 1.0
