"""The reduced oscillation on the stop: the loops of a mass pressed on a deformable stop
(``x_bar < a``) advanced by a model of their decay once they are small and regular.

When the belt presses the mass on the stop, the response ends in a train of ever smaller
contacts or in an oscillation on the stop whose loops shrink (paper Fig. 11). Step by step,
its cost grows with the number of loops, not with what changes: thousands of loops whose
amplitude is far below what a plot can show. Once the motion about the equilibrium is that
small and its decay is regular, it is advanced by a reduced model instead::

    x(t) = x_c + kappa C(A(t)) + e (l(A(t)) - 1) + A(t) cos(phase0 + 2 pi (t - t_s) / T)

with the cycle ``T`` measured over the last cycles and the amplitude ``A`` following the
decay law fitted to the last amplitudes (one per cycle), the steadiest of

* geometric, ``A_k = A_0 q^k`` (loops of a law that is linear at small amplitude);
* inverse, ``1/A_k = 1/A_0 + c k`` (the loss per loop of the exponential transition curves
  of paper Eq. 13 grows like the amplitude cubed, so the amplitude falls like ``1/k``);
* towards a limit, ``A_k = A_inf + (A_0 - A_inf) q^k`` (loops that become elastic below an
  amplitude: overlaps under ``D / beta`` never leave the compression envelope, Eq. 13).

Loops of the passive law that retrace one curve inside its band neither shrink nor creep:
they are an exactly conservative oscillation, and their last cycle is repeated
(:func:`repeat_retracing`).

The centre creeps as the loops shrink (the loops of Eq. 13 do not close: each ends at a
slightly different force): ``kappa`` is the creep per amplitude lost over the last cycles
(``kappa ~ 7`` on the slow scene of Fig. 11's kind), and its rate grows like ``A^-p`` as the
loops shrink (``p`` measured against the cycles before, below 1/2), so the creep is
``C(A) = A_0^p (A_0^(1-p) - A^(1-p)) / (1 - p)``. The last swing's midpoint ``x_c`` lags the
centre by ``e``, half the loss of a half cycle, which vanishes with the loss per cycle
(``l``: ``A / A_0``, ``(A / A_0)^2`` or ``(A - A_inf) / (A_0 - A_inf)`` for the three laws).

Error: while it runs, the model stays within ``2 A_0`` plus the creep's error (the band,
which must be below what the page shows, the train's band); where it ends, its error in the
position is at most ``2 spread A(t_1)`` plus ``A(t_1)`` times the phase's error (the model
keeps the phase with the window's mean cycle, whose error is bounded by
:func:`period_error`), and at most ``2 (1 + 2 spread) A(t_1)`` whatever the phase, plus the
creep's error (its rate off by 100 % and by its change over the cycles before), the
velocity's ``2 pi / T`` times the oscillating part; at rest the rest amplitude plus the
creep's error.
The solver reports both (``reduced_band``, ``reduced_error``); the model takes over once the
latter is within the tolerance, or the band is (the position then within it throughout, the
velocity up to ``2 pi / T`` times it). The time of rest is the reversal where the rule for
rest (:func:`rest_rule`) holds on the model's reversals; its phase is the model's weak
point, so loops whose rest is near (:data:`FOLLOW_REVERSALS`) are followed to it instead.
A rest farther away is modelled, and the solver states a bound of its time's error
(``rest_time_error``, :func:`rest_time_error`).
"""


from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from core.deformable.decay import (
    DECAY_FIT,
    END_AMPLITUDE_MARGIN,
    GEOMETRIC,
    INVERSE,
    LIMIT,
    WINDOW,
    Decay,
    creep_law,
    cycle_amplitudes,
    decay_holds,
    fit_decay,
    period_error,
)
from core.deformable.law import Branch, stored_energy
from core.deformable.rest import (
    FOLLOW_REVERSALS,
    reduce_extent,
    rest_amplitude,
    rest_at_stop,
    rest_swing_factor,
    train_band,
)
from core.deformable.state import OSC, Solve, State
from core.result import TransitionKind

#: A failed reduced oscillation is tried again after this fraction of the cycles its
#: contact has had (:func:`_try_again_later`): loops that die like ``1/k`` are then ~11 %
#: smaller, and a model that could take over is late by at most that many cycles. (After
#: every window instead, a soft stop's loops, k_c0 = 100, beta = 1000, D = 0.1, tried 279
#: times to t_end = 1e4, an eighth of the solve.)
RETRY_FRACTION = 0.125


class Oscillation(NamedTuple):
    """The reduced model's motion from its start ``t_s`` (row data of the solver)."""

    x_c: float  # centre at the start
    amp0: float  # amplitude at the start
    period: float  # cycle
    phase0: float  # phase at the start
    decay: Decay
    kappa: float = 0.0  # creep of the centre per amplitude lost, at the start
    creep_power: float = 0.0  # the creep rate grows like A^-p as the amplitude A falls
    kappa_change: float = 0.0  # change of kappa from the cycles before
    offset: float = 0.0  # x_c less the centre: the last swing's midpoint lags the decay
    dissipation: float = math.nan  # what the stop dissipates until rest (nan: omega^2 A0^2/2)
    period_error: float = math.inf  # bound of the cycle's error, averaged over those left

    @property
    def error_bound(self) -> float:
        """Bound of the model's error in the position while it runs (see the module's
        docstring): the band it starts in and the centre's whole creep."""
        return 2.0 * self.amp0 + self.creep_error(0.0)

    def creep_error(self, amp) -> float:
        """Bound of the error of the centre's creep once the amplitude is ``amp``: the
        creep's rate off by 100 % and by its change over the cycles before."""
        return (abs(self.kappa) + abs(self.kappa_change)) * abs(float(self.creep(amp)))

    def creep(self, amp):
        """Amplitude lost, weighted by the creep rate ``(A_0 / A)^p``, from ``A_0`` to
        ``amp``: ``A_0^p (A_0^(1-p) - amp^(1-p)) / (1 - p)``."""
        q = 1.0 - self.creep_power
        return self.amp0**self.creep_power * (self.amp0**q - np.asarray(amp) ** q) / q

    def end_error(self, tau: float, rest_amplitude: float | None = None,
                  velocity: bool = True) -> float:
        """Bound of the model's error in the state ``tau`` after the start, where it ends
        (the horizon, or rest when ``rest_amplitude`` is given).

        The model's amplitude there is ``A(tau)``, the true one within
        :data:`END_AMPLITUDE_MARGIN` ``M`` of it (the fitted per-cycle rates agree to
        :data:`DECAY_SPREAD`). The model keeps the phase with its cycle ``T``; the true
        phase is off by at most ``dphi = 2 pi tau period_error / T`` (see
        :func:`period_error`), so the positions about the centres differ by at most
        ``(M - 1) A + A dphi``, and by ``2 M A`` whatever the phase; the velocities by up
        to ``2 pi / T`` times that. The centres differ by at most the creep of the
        amplitude lost (its rate off by 100 %). At rest the model's amplitude is below half
        the rest amplitude, the true one within ``M`` of it, and the velocity's within
        ``2 pi / T`` times that (``velocity=False``: the position's error alone).
        """
        amp = float(self.decay.amplitude(self.amp0, tau / self.period))
        creep = self.creep_error(amp)
        omega = 2.0 * math.pi / self.period
        if rest_amplitude is not None:
            # Rest at the centre: the true loops left are within M A of it, their
            # velocity within omega M A of zero (A below half the rest amplitude).
            return END_AMPLITUDE_MARGIN * amp * (max(1.0, omega) if velocity else 1.0) + creep
        dphi = omega * tau / self.period * self.period_error
        phase = min(END_AMPLITUDE_MARGIN - 1.0 + dphi, 2.0 * END_AMPLITUDE_MARGIN)
        return phase * amp * max(1.0, omega) + creep

    def centre(self, amp) -> float:
        """Centre of the oscillation once its amplitude is ``amp``."""
        return (self.x_c + self.kappa * self.creep(amp)
                + self.offset * (self._lag(amp) - 1.0))

    def _lag(self, amp):
        """The midpoint's lag behind the centre, relative to the start's, once the
        amplitude is ``amp``: it is half the loss of a half cycle, ``~ dA/dn``, which is
        ``~ A`` (geometric), ``~ A^2`` (inverse) or ``~ A - A_inf`` (limit)."""
        u = np.asarray(amp, dtype=float)
        if self.decay.law == GEOMETRIC:
            return u / self.amp0
        if self.decay.law == INVERSE:
            return (u / self.amp0) ** 2
        return (u - self.decay.limit) / (self.amp0 - self.decay.limit)

    def _dlag(self, amp):
        """``d lag / dA``."""
        u = np.asarray(amp, dtype=float)
        if self.decay.law == GEOMETRIC:
            return np.full_like(u, 1.0 / self.amp0)
        if self.decay.law == INVERSE:
            return 2.0 * u / self.amp0**2
        return np.full_like(u, 1.0 / (self.amp0 - self.decay.limit))

    def state(self, tau):
        """Position and velocity ``tau`` after the start (arrays or floats)."""
        n = np.asarray(tau, dtype=float) / self.period
        amp = self.decay.amplitude(self.amp0, n)
        damp = self.decay.slope(self.amp0, n) / self.period
        w = 2.0 * math.pi / self.period
        ph = self.phase0 + w * np.asarray(tau, dtype=float)
        c, s = np.cos(ph), np.sin(ph)
        rate = (self.kappa * (self.amp0 / np.maximum(amp, 1e-300)) ** self.creep_power
                - self.offset * self._dlag(amp))
        return (self.centre(amp) + amp * c, damp * (c - rate) - amp * w * s, amp)

    def acceleration(self, tau):
        """``x''`` ``tau`` after the start: the linear restoring force of the model's cycle
        about its centre, ``-omega^2 (x - x_c(A))`` (the decay's and the creep's rates are
        of the order of the amplitude's change per cycle, not counted)."""
        x, _, amp = self.state(tau)
        w = 2.0 * math.pi / self.period
        return -w * w * (x - self.centre(amp))

    def energy(self, amp) -> float:
        """Energy of the oscillation at amplitude ``amp``: the linear oscillator's of this
        cycle, or :attr:`dissipation` times ``(amp / A_0)^2`` when that is known."""
        if not math.isnan(self.dissipation):
            return self.dissipation * (np.asarray(amp) / self.amp0) ** 2
        w = 2.0 * math.pi / self.period
        return 0.5 * w * w * amp * amp


def reduce_oscillation(sv: Solve, st: State, branch: Branch, reversal_x, s: int):
    """Hand a small pressed oscillation to a reduced model (this module's),
    or return ``None`` while it is too large or its decay not yet regular.

    One cycle is two reversals; its amplitude is a quarter of its two swings. Loops that
    retrace one curve (the passive law inside its band) repeat their last cycle
    (:func:`repeat_retracing`). Loops that tend to a limit amplitude (they turn elastic)
    repeat their last cycle once the amplitude left and the phase lost by the horizon
    (:func:`retrace_error`) are within the tolerance. Loops that die out follow the fitted
    decay until the rest amplitude.
    """
    if not (sv.use_reduced and sv.pressed() and s > 0) or len(reversal_x) < WINDOW:
        return None
    ts, xs, ns = zip(*reversal_x[-WINDOW:], strict=True)
    tol = reduce_extent(sv)
    if sv.stop.law == "passive":
        return repeat_retracing(sv, st, ts, xs, ns)
    amps = cycle_amplitudes(xs)
    decay = fit_decay(amps)
    if decay is None:
        return None
    period = (ts[-1] - ts[0]) / DECAY_FIT  # the window's mean cycle: the model keeps phase
    if decay.law == LIMIT and decay.limit * rest_swing_factor(period) > 0.5 * rest_amplitude(sv):
        # The loops near their limit: the last cycle is repeated once the amplitude left
        # and the phase the repeated cycle loses by the horizon are within the tolerance.
        omega = 2.0 * math.pi / period
        error = (2.0 * (amps[-1] - decay.limit) * max(1.0, omega)
                 + retrace_error(sv, st, ts, xs))
        if error > tol:
            return None
        return _repeat_last_cycle(sv, st, ts, ns, error)
    if 2.0 * amps[-1] > train_band(sv) or 2.0 * math.pi / period * amps[-1] >= sv.vb:
        return None
    return _decaying(sv, st, branch, reversal_x, s, decay, period, tol)


def _decaying(sv: Solve, st: State, branch: Branch, reversal_x, s: int, decay: Decay,
              period: float, tol: float):
    """The reduced model of loops that die out (:func:`reduce_oscillation`), tried on the
    window's cycles with the fitted ``decay``: ``None`` while its bounds are above the
    tolerance ``tol`` or its decay does not hold (tried again later)."""
    xs = [x for _, x, _ in reversal_x[-WINDOW:]]
    swings = np.abs(np.diff(xs))
    x_c = 0.5 * (xs[-1] + xs[-2])
    # Without its creep first (cheap): most reversals end here while the loops are large.
    plain = Oscillation(x_c, 0.5 * swings[-1], period, 0.0, decay)
    tau_end, rests = oscillation_end(sv, st, plain)
    if rests and tau_end <= 0.5 * period * FOLLOW_REVERSALS:
        # Rest is near: the loops are followed to it, the rule's time then the integration's
        # (the model's cycle, the window's mean, shortens by ~1e-3 as the loops shrink: its
        # reversals drift by up to 0.03 by rest). Until well past it, no more tries.
        sv.defer_reduction(st.t + 2.0 * tau_end)
        return None
    # The cycle's error counts only where the model ends moving (at the horizon).
    cycle_error = math.inf if rests else period_error(reversal_x)
    plain = plain._replace(period_error=cycle_error)
    rest_amp = rest_amplitude(sv) if rests else None
    # At rest the velocity of the loops left (within ten times the rest amplitude, by the
    # rule) is the solver's rest, as when the loops are followed to it; it is stated, not a
    # reason to wait.
    if plain.end_error(tau_end, rest_amp, velocity=not rests) > tol and plain.error_bound > tol:
        return None
    # The checks below are pure: the cheaper and more often failing ones first (loops
    # whose creep grows too fast fail creep_law at every try on soft stops).
    creep = creep_law(reversal_x)
    if creep is None:
        # Its growth changes over many cycles (these tries were 40 % of loops followed to
        # the horizon on a soft stop, k_c0 = 100, beta = 1000, D = 0.01).
        return _try_again_later(sv, st, period, len(reversal_x))
    offset = x_c - 0.25 * (xs[-3] + 2.0 * xs[-2] + xs[-1])
    model = Oscillation(x_c, 0.5 * swings[-1], period, 0.0 if st.x >= x_c else math.pi,
                        decay, *creep, offset, period_error=cycle_error)
    # While it runs the model moves in a band below what the page can show (the same
    # band as a reduced train's); where it ends, the state's error is within the
    # tolerance, or else its whole band is (the position's error then is, throughout).
    if (model.error_bound > train_band(sv)
            or model.end_error(tau_end, rest_amp, velocity=not rests) > tol
            and model.error_bound > tol):
        # The full model's bounds shrink with the loops (these tries were 45 % of Fig. 11's
        # solve to t_end = 1000, 2,900 of them failing here).
        return _try_again_later(sv, st, period, len(reversal_x))
    amp_end = float(decay.amplitude(plain.amp0, tau_end / period))
    if not decay_holds(reversal_x, decay, plain.amp0, amp_end):
        return None
    if rests:
        sv.bound(rest_time=rest_time_error(model, tau_end, period_error(reversal_x)))
    return oscillate(sv, st, branch, s, model)


def _try_again_later(sv: Solve, st: State, period: float, reversals: int) -> None:
    """No reduced oscillation now; the next try once the window of cycles it reads has
    renewed (``WINDOW`` cycles), not at the next fourth reversal, and once the loops have
    run on by :data:`RETRY_FRACTION` of the contact's cycles: what failed (the creep's fit,
    the model's bounds) changes only as the loops shrink, and after ``k`` cycles they
    shrink like ``1/k``."""
    sv.defer_reduction(st.t + max(WINDOW, RETRY_FRACTION * 0.5 * reversals) * period)


def rest_time_error(model: Oscillation, tau_rest: float, cycle_error: float) -> float:
    """Bound of the error of a reduced oscillation's time of rest, ``tau_rest`` after its
    start.

    The model keeps its cycle ``T``, off by at most ``cycle_error`` (:func:`period_error`)
    over the ``n = tau_rest / T`` cycles left: its reversals drift by ``n cycle_error``. The
    true amplitude where the model's falls to the rest rule's is within
    :data:`END_AMPLITUDE_MARGIN` ``M`` of it, so the true loops reach it within
    ``(M - 1) A / |dA/dn|`` cycles of the model's (the decay's slope there); and the rule
    holds at a reversal, half a cycle apart. (Loops followed to rest need none of this:
    within :data:`FOLLOW_REVERSALS` they are not modelled.)"""
    period = model.period
    n = tau_rest / period
    amp = float(model.decay.amplitude(model.amp0, n))
    slope = abs(float(model.decay.slope(model.amp0, n)))
    count = (END_AMPLITUDE_MARGIN - 1.0) * amp / slope if slope > 0.0 else math.inf
    return n * cycle_error + (count + 0.5) * period


def retraces_one_curve(sv: Solve, ns) -> bool:
    """Whether the loops of the window (the transition counts ``ns`` of its reversals)
    retrace one curve of the passive law: reversals alone (friction's sign is fixed) and
    every branch since the window's first reversal on the curve of one anchor
    (:class:`~core.deformable.law.Branch`), which loading and unloading follow alike."""
    if any(n1 - n0 != 1 for n0, n1 in zip(ns[:-1], ns[1:], strict=True)):
        return False
    branches = sv.contact.branches[-len(ns):]
    anchor = branches[-1].anchor
    return anchor is not None and all(b.anchor == anchor for b in branches)


def repeat_retracing(sv: Solve, st: State, ts, xs, ns) -> str | None:
    """Repeat the last cycle of loops that retrace one curve of the passive law
    (:func:`retraces_one_curve`), with the error of :func:`retrace_error` stated.

    Such loops are an exactly conservative motion, ``x'' = s a - x - phi(x - x_bar)`` with
    one ``phi``: from the switch the true motion repeats its cycle. The repeated cycle errs
    by its integration's error: once in the state (the drift of the reversals) and once
    per cycle in its duration (the phase). Following the loops does no better: every
    cycle's error adds up, and the integration's amplitude walks with the cycle.

    Measured against every loop followed at rtol 1e-11 from the same switch, on the eight
    cells of the grid of benchmarks/hysteretic_speed.py whose passive loops retrace
    (benchmarks/results/2026-11-26-passive-reduce.txt), at rtol 1e-8: at t_end = 1e4 the
    repeated cycle was off by 7.6e-7 to 2.4e-5 of the scale, 2.1 to 67 times below the
    stated error, where each loop followed at rtol 1e-8 was off by 4e-3 to 2.3e-2 (the
    five cells with k_c0 = 100); at t_end = 100, 1.1e-8 to 2e-7 (stated 1.0e-7 to 6.9e-6;
    followed, 1.7e-7 to 1.5e-5). So the loops are handed over as soon as they retrace,
    whatever the horizon, and the error is stated even where it is above the tolerance
    (no solve at that tolerance keeps the phase of a neutral oscillation over 1e4 cycles).

    Not stated: the amplitude the loops before left, which the integration set to its
    tolerance, sets the cycle. Against a tight solve from ``t = 0`` the state at
    t_end = 1e4 was off by up to 3.2e-3 of the scale (each loop followed: 7.2e-3), as the
    readout's note on the timing errors of many loops says.
    """
    if not retraces_one_curve(sv, ns):
        return None
    return _repeat_last_cycle(sv, st, ts, ns, retrace_error(sv, st, ts, xs, periodic=True))


def _repeat_last_cycle(sv: Solve, st: State, ts, ns, error: float):
    """Hand the loops to the periodic steady state from their last cycle (two reversals
    before the last), a ``reduced`` transition with ``error`` stated; ``None`` if the
    cycle does not close."""
    sv.periodic(ts[-3], ns[-3], st)
    if sv.steady is None:
        return None
    sv.record(TransitionKind.REDUCED, st, 0.0)
    sv.bound(error=error)
    return "periodic"


def retrace_error(sv: Solve, st: State, ts, xs, periodic: bool = False) -> float:
    """Error at the horizon of repeating the last cycle of loops that retrace their curve
    (reversal times ``ts``, positions ``xs``, two per cycle): the reversals' drift per cycle
    summed over the ``N`` cycles left, plus the phase. The loops still shrink a little (the
    period changes by ~4e-8 per cycle, measured on k_c0 = 100, beta = 1000, D = 0.1), so
    the repeated cycle's time is off by ``dP N + dP' N^2 / 2`` after ``N`` cycles, ``dP``
    the spread of the window's periods and ``dP'`` their change per cycle, and the state by
    that times the oscillation's speed ``omega A`` (position) or acceleration
    ``omega^2 A`` (velocity); the drift moves the velocity by ``omega`` times as much.
    The reversals' times jitter by ~3e-7 at rtol 1e-8, so the window's spread samples
    the tiled period's error rather than bounding it: the phase term is doubled (measured
    against every loop followed at the same tolerance, on five cells of
    benchmarks/hysteretic_speed.py's grid with the passive law: the undoubled bound fell
    short by up to 2.1 times).

    ``periodic``: the loops retrace one curve (:func:`retraces_one_curve`), so their true
    cycle does not change; the change of the window's periods is the integration's, which
    their spread already samples, and the ``dP' N^2 / 2`` term is left out: with it the
    bound at t_end = 1e4 was 1,000 to 55,000 times the error on the cells of
    :func:`repeat_retracing`, without it 2.1 to 67 times."""
    period = ts[-1] - ts[-3]
    cycles = (sv.t_end - st.t) / period
    drift = max(abs(xs[k] - xs[k - 2]) for k in range(2, len(xs)))
    periods = np.subtract(ts[2:], ts[:-2])
    # At least the integration's own error of a cycle's duration: loops of the passive law
    # that retrace exactly (their tops on the anchor, Solve.retraced_top) repeat their
    # cycle to the bit, and a spread of zero stated no error at all (draft, k_c0 = 1e4).
    spread = max(float(periods.max() - periods.min()), sv.rtol * period)
    trend = 0.0 if periodic else abs(float(periods[-1] - periods[0])) / max(len(periods) - 1, 1)
    omega = 2.0 * math.pi / period
    rate = omega * max(1.0, omega) * 0.5 * abs(xs[-1] - xs[-2])
    # The reversals' drift moves the positions; the velocities follow at omega times it.
    return (drift * cycles * max(1.0, omega)
            + 2.0 * rate * (spread * cycles + trend * 0.5 * cycles * cycles))


def oscillation_end(sv: Solve, st: State, model: Oscillation) -> tuple[float, bool]:
    """How long the reduced oscillation runs from ``st`` (to the reversal where the rule for
    rest, :func:`rest_rule`, holds on the model's reversals, or to the horizon), and
    whether it ends at rest.

    The rule reads the last four reversals: their range is the first of their three
    swings, so it holds two to three reversals after the amplitude falls below half the
    rest amplitude. (The model rested at that first reversal: two reversals before the
    rule on every loop followed, 0.017 to 0.026 in time on three cells of
    benchmarks/hysteretic_speed.py.)"""
    # The rule bounds the velocity's swing too (rest_swing_factor).
    rest = rest_amplitude(sv) / rest_swing_factor(model.period)
    cycles = model.decay.cycles_to(model.amp0, 0.5 * rest)
    if not st.t + cycles * model.period < sv.t_end:
        return sv.t_end - st.t, False
    first = math.ceil(2.0 * max(cycles, 0.5))  # the first reversal with A below rest / 2
    ks = np.arange(max(first - 6, 0), first + 8)
    xs = model.state(0.5 * model.period * ks)[0]
    spans = np.ptp(np.lib.stride_tricks.sliding_window_view(xs, 4), axis=1)
    held = np.nonzero(spans <= rest)[0]
    k = int(ks[held[0] + 3]) if len(held) else first + 2
    tau_rest = 0.5 * model.period * k  # at a reversal
    if st.t + tau_rest < sv.t_end:
        return tau_rest, True
    return sv.t_end - st.t, False


def oscillate(sv: Solve, st: State, branch: Branch, s: int, model: Oscillation) -> str:
    """Advance a small pressed oscillation by its reduced model until its amplitude is
    below the rest amplitude, then rest at the equilibrium.

    Energy: friction and belt work follow the model's motion; the stop takes the rest
    of the balance, and its loss grows by the oscillator's energy ``omega^2 A^2 / 2``
    as the amplitude decays (or, when it ends at rest, by what the loss is there, in
    proportion to ``A^2``), so ``stop_loss`` never falls.
    """
    sv.record(TransitionKind.REDUCED, st, st.v)
    tau, rests = oscillation_end(sv, st, model)
    t1 = st.t + tau if rests else sv.t_end
    x_s, m_s, t_s = st.x, 0.5 * (st.x * st.x + st.v * st.v), st.t
    loss_s = st.work[2] - stored_energy(st.x - sv.xb, branch.phi_r, sv.stop)
    sa = s * sv.a
    if rests:
        # The loss at rest (where the centre has crept to, on the law's state there) less
        # the loss now: the model dissipates exactly that, so the loss never falls at rest.
        x_eq = float(model.centre(0.0))
        at_rest = (st.work[2] + sa * (x_eq - x_s) - 0.5 * x_eq * x_eq + m_s
                   - stored_energy(x_eq - sv.xb, sa - x_eq, sv.stop))
        model = model._replace(dissipation=max(at_rest - loss_s, 0.0))
    sv.add_row(OSC, st.t, t1, (model, x_s, m_s, loss_s), sa, st.work)
    x1, v1, _ = (float(q) for q in model.state(t1 - st.t))
    wf, wb, ws = st.work
    dwf = sa * (x1 - x_s)
    dm = 0.5 * (x1 * x1 + v1 * v1) - m_s
    st.work = (wf + dwf, wb + sa * sv.vb * (t1 - st.t), ws + dwf - dm)
    st.t, st.x, st.v = t1, x1, v1
    sv.bound(error=model.end_error(t1 - t_s, None if not rests else rest_amplitude(sv)),
             band=model.error_bound)
    if not rests:
        return "horizon"
    return rest_at_stop(sv, st, branch, s, x_rest=model.centre(0.0))


