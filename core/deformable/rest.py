"""Rest on the stop: the rule that declares the loops of a pressed mass at rest, the
swing within which they are, the state at rest (the equilibrium on the law's branch), and
the tolerances below which a pressed motion is rest or handed to a reduced model.

Loops of a mass pressed on the stop shrink without end (like ``1/k`` after ``k`` cycles
under the paper's law): rest is what a rule says. The rule (:func:`rest_rule`) reads the
last reversals of a contact: their swing must be within the rest amplitude
(:data:`REST_AMPLITUDE_PER_RTOL` ``rtol`` of the length scale) in the position and ten times
it in the velocity, and the centre's creep left by the horizon must not state more than the
tolerance of the reduced models (:func:`reduce_extent`). At rest the mass sits at the
equilibrium on the current branch, or where the shrinking loops' centre ends
(:func:`rest_at_stop`), and the work balance closes exactly.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from core.deformable.law import Branch, force_and_slope, phi_compression, phi_expansion
from core.deformable.state import REST, Solve, State
from core.result import Steady, SteadyKind, TransitionKind

#: Tolerance of the equilibrium on the stop (relative to the length scale): the rest force
#: then equals ``a - x`` to ~1e-15 relative, far inside the 1e-9 promised.
EQUILIBRIUM_XTOL = 1e-16


#: Relative tolerance of brentq's roots (its smallest allowed value).
ROOT_RTOL = 4.0 * np.finfo(float).eps


#: Extent of a pressed motion, as a multiple of ``rtol`` (times the length scale), below
#: which a reduced model takes over: its error in the state is at most that extent, half
#: the error the app states for each accuracy preset (``~100 rtol``, app/solve/presets.py).
REDUCE_PER_RTOL = 50.0
#: ... and at least this fraction of the length scale, a thousandth of a pixel of a plot
#: 1000 pixels high: below it the motion is rest to the eye whatever the preset.
PAGE_RESOLUTION = 1e-6


#: Largest relative spread of the fitted per-cycle rates for the decay to count as regular.
DECAY_SPREAD = 0.05
#: Band of a shrinking train of contacts (from the bottom of a flight to the peak of a
#: contact), as a multiple of ``rtol`` (times the length scale), below which the train is
#: advanced by its contact-to-contact map (:class:`Train`). Larger than
#: :data:`REDUCE_PER_RTOL`: the phase of a long train is not resolved step by step either
#: (a solve at ``rtol`` 1e-8 and one at 1e-11 differ by up to 5e-3 in the state after
#: hundreds of contacts, benchmarks/results/hysteretic_speed_2026-11-23.txt), while its
#: envelope is; the band bounds the position error whatever the phase.
TRAIN_PER_RTOL = 1e4
#: ... and at most a pixel of a plot 1000 pixels high (the draft preset).
TRAIN_MAX_BAND = 1e-3


#: Most reversals a solve follows, rather than hand the loops to a model whose time of rest
#: (the phase of hundreds of cycles) or end state (loops creeping on at rest) it cannot
#: state within the preset's error: ~20 us each on the 2-core machine (k_c0 = 100,
#: beta = 1000, D = 0.1), so ~40 ms at most. Followed, the rule for rest on the preset's
#: loops was within 2.2e-6 in time of the same rule on a solve at rtol 1e-11 (the model:
#: 0.017 to 0.026).
FOLLOW_REVERSALS = 2000


#: The velocity's swing of loops the rule for rest lets rest, over the rest amplitude
#: (the position's): the rest amplitude is 10 rtol of the scale, so this is the 100 rtol
#: the app states for each preset. Loops on a stiff stop swing in the velocity at
#: ``omega`` times the position (``omega`` ~ 100 to 1400 on the pressed stops of
#: benchmarks/hysteretic_speed.py): read on the position alone, the rule let them rest
#: with a velocity ``omega`` times the rest amplitude (the passive law's retracing loops,
#: k_c0 = 1e4, at draft: at rest with 1.5e-3, where they swing for ever).
REST_SPEED_PER_AMPLITUDE = 10.0


#: Overlap reversals of a sustained contact whose swing falls below this multiple of
#: ``rtol`` (times the length scale; ``atol`` at least) in the position, and below ten
#: times that in the velocity (:data:`REST_SPEED_PER_AMPLITUDE`),
#: are the limit of rest at the stop: the mass is pressed on the stop, and rest is
#: declared at the equilibrium. The rest state then differs from the motion by less than
#: ``10 rtol`` in the position and ``100 rtol`` in the velocity: a swing the integration
#: at that ``rtol`` does not resolve better (a run's error is measured, app/solve/presets.py).
REST_AMPLITUDE_PER_RTOL = 10.0


def rest_swing(rtol: float, atol: float, scale: float) -> tuple[float, float]:
    """The swing of the position and of the velocity within which loops on the stop are
    at rest, for a solve at ``rtol``, ``atol`` on the length ``scale``: the rest amplitude
    :data:`REST_AMPLITUDE_PER_RTOL` ``max(rtol scale, atol)`` and
    :data:`REST_SPEED_PER_AMPLITUDE` times it."""
    rest = REST_AMPLITUDE_PER_RTOL * max(rtol * scale, atol)
    return rest, REST_SPEED_PER_AMPLITUDE * rest


def rest_swing_of(osc, stop, rtol: float, atol: float) -> tuple[float, float]:
    """:func:`rest_swing` for the oscillator ``osc`` on the deformable ``stop``, on the
    solver's length scale ``max(a, b, v, |x_bar|, D)``."""
    scale = max(osc.a, osc.b, osc.v, abs(stop.clearance), stop.limit_overlap, 1e-300)
    return rest_swing(rtol, atol, scale)


def creep_left(ts, xs, t_end: float) -> float:
    """How far the centre of the last loops (reversal times ``ts``, positions ``xs``) would
    creep by ``t_end`` at its present rate per cycle. The paper's loops creep: on a soft
    stop (k_c0 = 100, beta = 1000, D = 0.01) loops of 3e-8 moved their centre by 7e-8 per
    cycle, 2.2e-5 in all after the swings had died out, and the rest declared there was off
    by 1.7e-5."""
    if len(xs) < 5:
        return 0.0
    ts, xs = ts[-5:], xs[-5:]
    # The midpoints of the first and last swings are three half cycles apart.
    creep = abs(xs[4] + xs[3] - xs[1] - xs[0]) / 3.0  # the centre's move in one cycle
    cycle = ts[4] - ts[2]
    return creep * max(t_end - ts[4], 0.0) / cycle if cycle > 0.0 else 0.0


def rest_swing_factor(cycle: float) -> float:
    """The factor on the position's swing of loops whose cycle is ``cycle`` that the rule
    for rest compares with the rest amplitude: their velocity swings by ``omega`` times
    the position's, and is allowed :data:`REST_SPEED_PER_AMPLITUDE` times the rest
    amplitude."""
    omega = 2.0 * math.pi / cycle if cycle > 0.0 else 0.0
    return max(1.0, omega / REST_SPEED_PER_AMPLITUDE)


def rest_rule(ts, xs, t_end: float, rest_amplitude: float,
              tolerance: float) -> tuple[str | None, float]:
    """What the reversals of one contact (times ``ts``, positions ``xs``, the last one just
    reached) say of rest: ``(None, 0)`` while the last four span more than
    ``rest_amplitude`` in the position, or their velocity (``omega`` times that) more than
    :data:`REST_SPEED_PER_AMPLITUDE` times it (:func:`rest_swing_factor`); then
    ``("rest", 0)`` if the centre's creep left by ``t_end`` (:func:`creep_left`) is within
    ``rest_amplitude`` too, else rest is a model of loops still creeping, with the stated
    error ``e``, the creep left plus the loops' swing: ``("model", e)``, or
    ``("follow", e)`` where ``e`` is above ``tolerance`` and the loops left to ``t_end``
    are few enough to follow (:data:`FOLLOW_REVERSALS`): they are, and the state there is
    the integration's."""
    if len(xs) < 4:
        return None, 0.0
    cycle = ts[-1] - ts[-3]
    if (max(xs[-4:]) - min(xs[-4:])) * rest_swing_factor(cycle) > rest_amplitude:
        return None, 0.0
    creep = creep_left(ts, xs, t_end)
    if creep <= rest_amplitude:
        return "rest", 0.0
    omega = 2.0 * math.pi / cycle if cycle > 0.0 else 1.0
    error = creep + rest_amplitude * min(max(1.0, omega), REST_SPEED_PER_AMPLITUDE)
    left = 2.0 * (t_end - ts[-1]) / cycle if cycle > 0.0 else math.inf
    if error > tolerance and left <= FOLLOW_REVERSALS:
        return "follow", error
    return "model", error


def reduce_extent(sv: Solve) -> float:
    """Extent of a pressed motion (and drift from a limit cycle) below which a reduced
    model takes over: :data:`REDUCE_PER_RTOL` ``rtol``, at least :data:`PAGE_RESOLUTION`
    (times the length scale)."""
    return max(REDUCE_PER_RTOL * sv.rtol, PAGE_RESOLUTION) * sv.scale()




def rest_amplitude(sv: Solve) -> float:
    """Amplitude of the overlap oscillation below which the mass rests on the stop."""
    return rest_swing(sv.rtol, sv.atol, sv.scale())[0]


def equilibrium(sv: Solve, branch: Branch, s: int) -> float | None:
    """Position on ``branch`` where the stop holds the mass against friction,
    ``x + phi(x - clearance) = s a`` (paper Eq. 14 with ``x' = x'' = 0``); ``None`` if
    friction pushes the mass away from the stop. The left side grows with ``x`` on every
    branch, so the root is unique."""
    xb, stop, sa = sv.xb, sv.stop, s * sv.a

    def excess(x: float) -> float:
        return x + force_and_slope(x - xb, branch, stop)[0] - sa

    x_hi = xb + sv.d_max
    if not (excess(xb) < 0.0 < excess(x_hi)):
        return None
    return brentq(excess, xb, x_hi, xtol=EQUILIBRIUM_XTOL * sv.scale(), rtol=ROOT_RTOL)


def held(sv: Solve, x: float, s: int) -> float:
    """``x``, or the equilibrium on the envelope (paper Eq. 11) that the law's state at
    rest there, ``(x - clearance, s a - x)``, lies beyond: the stop holds the mass only
    with a force between its envelopes. (Loops that end next to the compression
    envelope, k_c0 = 4000, k_e0 = 100, rtol 1e-5, left their centre 2e-7 short of it:
    the force at rest was clipped onto it, 0.4 % off ``a - x``.)"""
    d_lim, sa = sv.d_lim, s * sv.a
    d, c = x - sv.xb, sa - sv.xb
    for k, beyond in ((sv.stop.k_c0, sa - x > float(phi_compression(d, sv.stop))),
                      (sv.stop.k_e0, sa - x < float(phi_expansion(d, sv.stop)))):
        if beyond:
            # d + k D d / (D - d) = c: the smaller root of d^2 - (D (1 + k) + c) d + c D,
            # in the form without cancellation
            b = d_lim * (1.0 + k) + c
            return sv.xb + 2.0 * c * d_lim / (b + math.sqrt(b * b - 4.0 * c * d_lim))
    return x


def rest_at_stop(
    sv: Solve, st: State, branch: Branch, s: int, x_rest: float | None = None
) -> str:
    """The reversals have shrunk to nothing: the mass rests pressed on the stop, at the
    equilibrium on the current branch (the centre of the vanished oscillation).

    ``st`` is a reversal (``x' = 0``). Moving the state to the equilibrium, friction
    does ``s a (x_eq - x)`` and the mechanical energy changes by
    ``(x_eq^2 - x^2) / 2``; the difference is the work the vanished oscillation did on
    the stop (its energy, dissipated by the ever smaller loops), so the balance closes.
    The law's state at rest is the reversal point ``(delta_eq, phi_eq)``.
    """
    x_eq = equilibrium(sv, branch, s) if x_rest is None else held(sv, x_rest, s)
    if x_eq is not None:
        sa = s * sv.a
        wf, wb, ws = st.work
        dx = x_eq - st.x
        dm = 0.5 * (x_eq * x_eq - st.x * st.x - st.v * st.v)
        st.work = (wf + sa * dx, wb, ws + sa * dx - dm)
        st.x, st.v = x_eq, 0.0
        d_eq = x_eq - sv.xb
        phi_eq = force_and_slope(d_eq, branch, sv.stop)[0]
        if x_rest is not None:  # the law's state where the shrinking loops end
            phi_eq = sa - x_eq
        branch = Branch(False, d_eq, phi_eq)
        sv.new_branch(branch, d_eq, st.work[2])
    sv.record(TransitionKind.REST, st, 0.0)
    sv.add_row(REST, st.t, sv.t_end, (st.x,), s * sv.a, st.work)
    wf, wb, ws = st.work
    st.work = (wf, wb + s * sv.a * sv.vb * (sv.t_end - st.t), ws)
    phi = force_and_slope(st.x - sv.xb, branch, sv.stop)[0]
    sv.settle(Steady(SteadyKind.REST, x_max=st.x, impact_speed=0.0, t_reached=st.t,
                     period=math.nan), phi)
    st.t = sv.t_end
    return "rest"


def rest_in_place(sv: Solve, st: State, branch: Branch) -> None:
    """A start inside the stop that static friction holds on a still belt
    (``|x + phi| <= b``, ``v = 0``): the mass never moves, the stop holds ``phi``."""
    sv.contact_starts(st, 0.0)
    sv.new_branch(branch, st.x - sv.xb, st.work[2])
    sv.record(TransitionKind.REST, st, 0.0)
    sv.add_row(REST, st.t, sv.t_end, (st.x,), 0.0, st.work)
    sv.settle(Steady(SteadyKind.REST, x_max=st.x, impact_speed=0.0, t_reached=st.t,
                     period=math.nan), force_and_slope(st.x - sv.xb, branch, sv.stop)[0])
    st.t = sv.t_end


def train_band(sv: Solve) -> float:
    """Band below which a shrinking train is handed to :class:`Train`:
    :data:`TRAIN_PER_RTOL` ``rtol``, between :data:`PAGE_RESOLUTION` and
    :data:`TRAIN_MAX_BAND` (times the length scale)."""
    return min(max(TRAIN_PER_RTOL * sv.rtol, PAGE_RESOLUTION), TRAIN_MAX_BAND) * sv.scale()
