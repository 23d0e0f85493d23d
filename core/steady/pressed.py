"""What a mass pressed on a deformable stop settles to when no fixed point is found.

Rest where its swing at the horizon (:class:`SwingProbe`) is within what the rule for rest
lets rest, else an oscillation on the stop with that swing and its decay, a train of
contacts, or loops that keep their size (docs/contact-law.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from core.result import Steady, SteadyKind, Transition, TransitionKind

#: Relative change per cycle of the amplitude of an oscillation on the stop below which it
#: is steady rather than dying out: an amplitude shrinking that slowly keeps 99 % of itself
#: for 1e4 cycles, more than any horizon offers (t_end <= 1e4, periods ~1), and solves at
#: rtol 1e-8 to 1e-11 leave retracing loops drifting by ~4e-9 per cycle. (The passive law's
#: loops are labelled by the law, :func:`pressed_steady`'s ``lossless``: with their curve
#: kept over reversals they drift by the integration's ~1e-8 per cycle at rtol 1e-8.)
SWING_STEADY = 1e-6
#: Swings (two a cycle) whose change the label of an oscillation on the stop is read from:
#: four cycles, three ratios of successive cycles.
SWING_WINDOW = 8
#: Points per cycle on which the swing at the horizon is measured: the half range of
#: samples of a sine misses its amplitude by at most ``1 - cos(pi / 256) = 7.5e-5`` of it.
SWING_POINTS = 256
#: Cycles an oscillation must have run past its last stored reversals for its decay to be
#: read from the amplitude there and at the horizon (a reduced model carried it on) rather
#: than from those reversals: the amplitudes then differ by far more than their sampling.
SWING_SPAN_CYCLES = 8
#: ... over enough cycles for the amplitude to change by this fraction: its sampling
#: (:data:`SWING_POINTS`) then moves the rate read by ~2e-3 of itself.
SWING_SPAN_CHANGE = 0.1


@dataclass(frozen=True)
class SwingProbe:
    """How far a motion on the stop swings at the horizon, against the rule for rest.

    ``evaluate(t) -> (x, x')`` is the solution; ``rest_amplitude`` and ``rest_velocity``
    the rule's thresholds on the swing of the position and of the velocity (the solver's
    :func:`core.deformable.rest.rest_swing`: 10 and 100 ``rtol`` of the length scale,
    docs/contact-law.md)."""

    evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    t_end: float
    rest_amplitude: float
    rest_velocity: float

    def swing(self, t1: float, cycle: float) -> tuple[float, float]:
        """Half the range of ``x`` and of ``x'`` over the cycle that ends at ``t1``."""
        t = np.linspace(max(t1 - cycle, 0.0), t1, SWING_POINTS + 1)
        x, v = self.evaluate(t)
        return 0.5 * float(np.ptp(x)), 0.5 * float(np.ptp(v))

    def at_rest(self, amplitude: float, velocity: float) -> bool:
        return amplitude <= self.rest_amplitude and velocity <= self.rest_velocity


def _oscillation(probe: SwingProbe, reversals: list[Transition], ratio: float,
                 x_max: float) -> Steady | None:
    """The oscillation on the stop that the reversals end on, as it is at the horizon, or
    ``None`` if its swing there is within what the rule for rest lets rest.

    Its decay is the ratio of successive cycles' amplitudes: the reversals' ``ratio``
    where they reach the horizon, else (a reduced model carried the loops on) read from
    the amplitude of their last cycle and the one at the horizon, over the cycles between."""
    cycle = reversals[-1].t - reversals[-3].t
    if not cycle > 0.0:
        return None
    amp, vel = probe.swing(probe.t_end, cycle)
    if probe.at_rest(amp, vel):
        return None
    cycles = (probe.t_end - reversals[-1].t) / cycle
    if cycles >= SWING_SPAN_CYCLES:
        # Back from the horizon by as many cycles as shrink it by SWING_SPAN_CHANGE at the
        # reversals' rate (the rate at the horizon, not averaged over the model's run: on
        # loops dying like 1/k, from a switch at t ~ 100 to t_end = 1600 that average was
        # 1.6 times the rate at the end), all the cycles since them at most.
        back = cycles if not ratio < 1.0 else min(
            cycles, max(SWING_SPAN_CYCLES, SWING_SPAN_CHANGE / (1.0 - ratio)))
        then = probe.swing(probe.t_end - back * cycle, cycle)[0]
        ratio = (amp / then) ** (1.0 / back) if then > 0.0 else ratio
    return Steady(SteadyKind.OSCILLATION, period=cycle, transitions_per_period=2,
                  sequence=("reversal", "reversal"), x_max=x_max, decay_rate=ratio,
                  amplitude=amp, velocity_amplitude=vel,
                  rest_amplitude=probe.rest_amplitude, rest_velocity=probe.rest_velocity)


def pressed_steady(tail: list[Transition], lossless: bool = False,
                   probe: SwingProbe | None = None) -> Steady:
    """Steady state of a mass the belt presses on the stop (``x_bar < a``), read off the
    latest transitions when no fixed point was found.

    No slip circle misses or grazes the stop then (the circles about ``(a, 0)`` all cross
    it), so neither pure slip nor grazing can be the limit: the motion ends at rest on the
    stop, or goes on as a train of contacts, or as an oscillation on the stop. A train is
    labelled with the measured ratio of successive approach speeds; a sustained oscillation
    whose swings shrink is rest approached, with the measured ratio of successive swings
    (over whole cycles), and one whose swings keep their size (:data:`SWING_STEADY` per
    cycle) is periodic.

    ``probe``: the solution at the horizon. Shrinking loops are rest only where their
    swing there is within what the rule for rest lets rest; else they are an oscillation
    on the stop, with that swing and its decay (:class:`SwingProbe`). Without it they are
    rest approached.

    ``lossless``: the contact law dissipates nothing on loops made of overlap reversals
    alone (the passive law retraces its curve there, docs/contact-law.md). Such loops are
    periodic whatever their measured change, which is then the numbers' drift.
    """
    train = _contact_train(tail)
    if train is not None:
        return train
    reversals = [tr for tr in tail if tr.kind is TransitionKind.REVERSAL]
    loops = _loops(tail, reversals, lossless, probe)
    if loops is not None:
        return loops
    if tail and tail[-1].kind is TransitionKind.REDUCED:
        swinging = None
        if probe is not None and len(reversals) >= 3:
            swinging = _oscillation(probe, reversals, math.nan, max(tr.x for tr in tail))
        if swinging is not None:
            return swinging
        return Steady(SteadyKind.REST, x_max=tail[-1].x, impact_speed=0.0)
    return Steady(SteadyKind.NONE)


def _contact_train(tail: list[Transition]) -> Steady | None:
    """A train of contacts the tail ends on (a separation among its last four
    transitions), labelled with the median ratio of successive approach speeds."""
    speeds = [tr.v for tr in tail if tr.kind is TransitionKind.CONTACT]
    if len(speeds) < 2 or not any(tr.kind is TransitionKind.SEPARATION for tr in tail[-4:]):
        return None
    ratio = float(np.median(np.array(speeds[1:]) / np.array(speeds[:-1])))
    return Steady(
        SteadyKind.CONTACT_TRAIN,
        impact_speed=speeds[-1],
        decay_rate=ratio,
        x_max=max(tr.x for tr in tail),
    )


def _loops(tail: list[Transition], reversals: list[Transition], lossless: bool,
           probe: SwingProbe | None) -> Steady | None:
    """Loops on the stop the reversals end on: rest approached (or an oscillation still
    swinging at the horizon) when their amplitude shrinks, periodic when it keeps its
    size (or the law retraces them), ``None`` for fewer than two cycles or a growth."""
    xs = [tr.x for tr in reversals]
    swings = np.abs(np.diff(xs))
    n = min(SWING_WINDOW, len(swings) - len(swings) % 2)
    if n < 4 or not np.all(swings[-n:] > 0.0):
        return None
    # One amplitude a cycle, from its two swings: the paper's loops creep, so their
    # swings alternate in size, and a ratio of single swings read growth every other
    # reversal (k_c0 = 1e4, beta = 1000, D = 1e-3: +0.65 % while the loops die like 1/k).
    amps = swings[-n:][0::2] + swings[-n:][1::2]
    ratio = float(np.median(amps[1:] / amps[:-1]))
    retrace = lossless and all(tr.kind is TransitionKind.REVERSAL for tr in tail[-n - 1:])
    if ratio < 1.0 - SWING_STEADY and not retrace:
        swinging = None if probe is None else _oscillation(probe, reversals, ratio, max(xs))
        if swinging is not None:
            return swinging
        return Steady(SteadyKind.REST, x_max=max(xs), impact_speed=0.0,
                      decay_rate=math.sqrt(ratio))
    if ratio <= 1.0 + SWING_STEADY or retrace:
        # Loops that keep their size: a sustained oscillation on the stop, one cycle
        # every two reversals.
        last = reversals[-5:]
        return Steady(SteadyKind.PERIODIC, period=0.5 * (last[-1].t - last[0].t),
                      transitions_per_period=2, sequence=("reversal", "reversal"),
                      x_max=max(xs), t_reached=last[0].t)
    return None
