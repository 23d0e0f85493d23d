"""Reduced models of a mass pressed on a deformable stop (``x_bar < a``).

This module is longer than the project's ~500 lines because it holds both reduced models
(the contact train and the oscillation on the stop) with the tests that let them take over.

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
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from core.deformable.law import FIRST_LOADING, Branch, stored_energy
from core.deformable.state import _OSC, _TRAIN, _State
from core.result import TransitionKind

if TYPE_CHECKING:
    from core.deformable.solver import _Solver

#: Amplitudes (one per cycle) the decay law is fitted to.
DECAY_FIT = 6
#: Largest relative spread of the fitted per-cycle rates for the decay to count as regular.
DECAY_SPREAD = 0.05

GEOMETRIC, INVERSE, LIMIT = 0, 1, 2
#: Extent of a pressed motion, as a multiple of ``rtol`` (times the length scale), below
#: which a reduced model takes over: its error in the state is at most that extent, half
#: the error the app states for each accuracy preset (``~100 rtol``, app/solver.py).
REDUCE_PER_RTOL = 50.0
#: ... and at least this fraction of the length scale, a thousandth of a pixel of a plot
#: 1000 pixels high: below it the motion is rest to the eye whatever the preset.
PAGE_RESOLUTION = 1e-6
#: The true amplitude where a reduced oscillation ends is within this factor of the
#: model's: the fitted decay's per-cycle rates agree to DECAY_SPREAD (5 %), and the
#: amplitude's relative error stays below the rate's (it is ``n dc A`` for the inverse law,
#: ``<= dc / c``); twice that spread leaves a margin.
END_AMPLITUDE_MARGIN = 1.0 + 2.0 * DECAY_SPREAD
#: Largest growth ``p`` of the centre's creep rate, ``~ A^-p``, a reduced oscillation
#: accepts: the creep left, ``~ A^(1-p) / (1 - p)``, is then at most twice what the
#: measured rate gives over the amplitude left.
MAX_CREEP_POWER = 0.5
#: Most reversals a solve follows, rather than hand the loops to a model whose time of rest
#: (the phase of hundreds of cycles) or end state (loops creeping on at rest) it cannot
#: state within the preset's error: ~20 us each on the 2-core machine (k_c0 = 100,
#: beta = 1000, D = 0.1), so ~40 ms at most. Followed, the rule for rest on the preset's
#: loops was within 2.2e-6 in time of the same rule on a solve at rtol 1e-11 (the model:
#: 0.017 to 0.026).
FOLLOW_REVERSALS = 2000


#: Reversals of a window of :data:`DECAY_FIT` cycles, and of the last two windows (which
#: share a reversal): what the decay, its check, the creep and the cycle's error read.
WINDOW = 2 * DECAY_FIT + 1
TWO_WINDOWS = 2 * WINDOW - 1
#: A failed reduced oscillation is tried again after this fraction of the cycles its
#: contact has had (:func:`_try_again_later`): loops that die like ``1/k`` are then ~11 %
#: smaller, and a model that could take over is late by at most that many cycles. (After
#: every window instead, a soft stop's loops, k_c0 = 100, beta = 1000, D = 0.1, tried 279
#: times to t_end = 1e4, an eighth of the solve.)
RETRY_FRACTION = 0.125


def cycle_amplitudes(xs) -> np.ndarray:
    """Amplitude of each cycle of the reversal positions ``xs`` (two reversals a cycle):
    a quarter of its two swings."""
    swings = np.abs(np.diff(np.asarray(xs, dtype=float)))
    return 0.25 * (swings[0::2] + swings[1::2])


def _two_windows(reversal_x) -> tuple[np.ndarray, np.ndarray] | None:
    """Times and positions of the reversals of the last two windows of cycles (``None``
    with fewer)."""
    if len(reversal_x) < TWO_WINDOWS:
        return None
    tail = reversal_x[-TWO_WINDOWS:]
    return np.array([t for t, _, _ in tail]), np.array([x for _, x, _ in tail])


class Decay(NamedTuple):
    """A fitted decay law of the amplitude per cycle (see the module's docstring)."""

    law: int
    rate: float  # q (GEOMETRIC, LIMIT) or c (INVERSE)
    limit: float  # A_inf (LIMIT), else 0

    def amplitude(self, amp0: float, n):
        """Amplitude after ``n`` cycles (array or float) from ``amp0``."""
        n = np.asarray(n, dtype=float)
        if self.law == GEOMETRIC:
            return amp0 * self.rate**n
        if self.law == INVERSE:
            return amp0 / (1.0 + self.rate * amp0 * n)
        return self.limit + (amp0 - self.limit) * self.rate**n

    def slope(self, amp0: float, n):
        """``dA/dn`` after ``n`` cycles."""
        n = np.asarray(n, dtype=float)
        if self.law == GEOMETRIC:
            return amp0 * self.rate**n * math.log(self.rate)
        if self.law == INVERSE:
            return -self.rate * amp0 * amp0 / (1.0 + self.rate * amp0 * n) ** 2
        return (amp0 - self.limit) * self.rate**n * math.log(self.rate)

    def cycles_to(self, amp0: float, target: float) -> float:
        """Cycles until the amplitude falls to ``target``; ``inf`` if it never does."""
        if amp0 <= target:
            return 0.0
        if self.law == GEOMETRIC:
            return math.log(target / amp0) / math.log(self.rate)
        if self.law == INVERSE:
            return (1.0 / target - 1.0 / amp0) / self.rate
        if self.limit >= target:
            return math.inf
        return math.log((target - self.limit) / (amp0 - self.limit)) / math.log(self.rate)


def _spread(values: list[float]) -> float:
    """Relative standard deviation (plain floats: six values, numpy's overhead would
    dominate; the fit runs once per contact or reversal)."""
    n = len(values)
    mean = sum(values) / n
    if mean == 0.0:
        return math.inf
    return math.sqrt(sum((v - mean) ** 2 for v in values) / n) / abs(mean)


def fit_decay(amplitudes) -> Decay | None:
    """The steadiest decay law of the last :data:`DECAY_FIT` amplitudes (one per cycle),
    or ``None`` if they do not shrink or no law fits within :data:`DECAY_SPREAD`.

    Examples
    --------
    >>> fit_decay([1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125]).law == GEOMETRIC
    True
    """
    a = [float(v) for v in amplitudes][-DECAY_FIT:]
    if len(a) < DECAY_FIT or a[-1] <= 0.0:
        return None
    pairs = list(zip(a[:-1], a[1:], strict=True))
    if any(q >= p for p, q in pairs):
        return None
    ratio = [q / p for p, q in pairs]
    inverse = [1.0 / q - 1.0 / p for p, q in pairs]
    steps = [q - p for p, q in pairs]
    to_limit = [q / p for p, q in zip(steps[:-1], steps[1:], strict=True)]
    # Spreads of the decrements (1 - ratio), not of the ratios: ratios near 1 always look
    # steady relative to their mean.
    fits = [(_spread([1.0 - r for r in ratio]), Decay(GEOMETRIC, 0.5 * sum(ratio[-2:]), 0.0)),
            (_spread(inverse), Decay(INVERSE, 0.5 * sum(inverse[-2:]), 0.0))]
    q = 0.5 * sum(to_limit[-2:])
    if 0.0 < q < 1.0:
        limit = a[-1] + steps[-1] * q / (1.0 - q)
        if limit > 0.0:
            fits.append((_spread([1.0 - r for r in to_limit]), Decay(LIMIT, q, limit)))
    spread, decay = min(fits, key=lambda f: f[0])
    if spread > DECAY_SPREAD:
        return None
    if decay.law != INVERSE and not 0.0 < decay.rate < 1.0:
        return None
    return decay


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


def reduce_oscillation(sv: _Solver, st: _State, branch: Branch, reversal_x, s: int):
    """Hand a small pressed oscillation to a reduced model (:mod:`core.deformable.reduced`),
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
    period = ts[-1] - ts[-3]
    tol = reduce_extent(sv)
    if sv.stop.law == "passive":
        return repeat_retracing(sv, st, ts, xs, ns)
    swings = np.abs(np.diff(xs))
    amps = cycle_amplitudes(xs)
    decay = fit_decay(amps)
    if decay is None:
        return None
    period = (ts[-1] - ts[0]) / DECAY_FIT  # the window's mean cycle: the model keeps phase
    omega = 2.0 * math.pi / period
    if decay.law == LIMIT and decay.limit * rest_swing_factor(period) > 0.5 * sv.rest_amplitude():
        # The loops near their limit: the last cycle is repeated once the amplitude left
        # and the phase the repeated cycle loses by the horizon are within the tolerance.
        error = (2.0 * (amps[-1] - decay.limit) * max(1.0, omega)
                 + retrace_error(sv, st, ts, xs))
        if error > tol:
            return None
        return _repeat_last_cycle(sv, st, ts, ns, error)
    if 2.0 * amps[-1] > train_band(sv) or 2.0 * math.pi / period * amps[-1] >= sv.vb:
        return None
    x_c = 0.5 * (xs[-1] + xs[-2])
    # Without its creep first (cheap): most reversals end here while the loops are large.
    plain = Oscillation(x_c, 0.5 * swings[-1], period, 0.0, decay)
    tau_end, rests = oscillation_end(sv, st, plain)
    if rests and tau_end <= 0.5 * period * FOLLOW_REVERSALS:
        # Rest is near: the loops are followed to it, the rule's time then the integration's
        # (the model's cycle, the window's mean, shortens by ~1e-3 as the loops shrink: its
        # reversals drift by up to 0.03 by rest). Until well past it, no more tries.
        sv.reduce_after = st.t + 2.0 * tau_end
        return None
    # The cycle's error counts only where the model ends moving (at the horizon).
    cycle_error = math.inf if rests else period_error(reversal_x)
    plain = plain._replace(period_error=cycle_error)
    rest_amp = sv.rest_amplitude() if rests else None
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
        sv.rest_time_error = max(sv.rest_time_error, rest_time_error(
            model, tau_end, period_error(reversal_x)))
    return oscillate(sv, st, branch, s, model)


def _try_again_later(sv: _Solver, st: _State, period: float, reversals: int) -> None:
    """No reduced oscillation now; the next try once the window of cycles it reads has
    renewed (``WINDOW`` cycles), not at the next fourth reversal, and once the loops have
    run on by :data:`RETRY_FRACTION` of the contact's cycles: what failed (the creep's fit,
    the model's bounds) changes only as the loops shrink, and after ``k`` cycles they
    shrink like ``1/k``."""
    sv.reduce_after = st.t + max(WINDOW, RETRY_FRACTION * 0.5 * reversals) * period


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


def retraces_one_curve(sv: _Solver, ns) -> bool:
    """Whether the loops of the window (the transition counts ``ns`` of its reversals)
    retrace one curve of the passive law: reversals alone (friction's sign is fixed) and
    every branch since the window's first reversal on the curve of one anchor
    (:class:`~core.deformable.law.Branch`), which loading and unloading follow alike."""
    if any(n1 - n0 != 1 for n0, n1 in zip(ns[:-1], ns[1:], strict=True)):
        return False
    branches = sv.contact.branches[-len(ns):]
    anchor = branches[-1].anchor
    return anchor is not None and all(b.anchor == anchor for b in branches)


def repeat_retracing(sv: _Solver, st: _State, ts, xs, ns) -> str | None:
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


def _repeat_last_cycle(sv: _Solver, st: _State, ts, ns, error: float):
    """Hand the loops to the periodic steady state from their last cycle (two reversals
    before the last), a ``reduced`` transition with ``error`` stated; ``None`` if the
    cycle does not close."""
    sv.periodic(ts[-3], ns[-3], st)
    if sv.steady is None:
        return None
    sv.record(TransitionKind.REDUCED, st, 0.0)
    sv.reduced_error = max(sv.reduced_error, error)
    return "periodic"


def decay_holds(reversal_x, decay: Decay, amp0: float, amp_end: float) -> bool:
    """Whether the loops can decay from ``amp0`` to ``amp_end`` by ``decay``: the
    :data:`DECAY_FIT` cycles before the last ones decay by the same law at nearly the same
    rate (within twice :data:`DECAY_SPREAD`), and, should the rate keep falling by as much
    per window of cycles, the decay still reaches ``amp_end`` (the rate's sum over all the
    windows to come is finite). Loops that turn elastic fit a geometric decay within the
    spread while the decrement per cycle keeps falling: on stiff stops (k_c0 = 23,000 and
    58,000, beta ~ 400-460) the model rested where every loop followed goes on at a limit
    amplitude, its velocity up to 1.7e-4 of the scale."""
    windows = _two_windows(reversal_x)
    if windows is None:
        return False
    before = fit_decay(cycle_amplitudes(windows[1][:WINDOW]))
    if before is None or before.law != decay.law:
        return False
    if decay.law == LIMIT:
        return (abs(before.rate - decay.rate) <= 2.0 * DECAY_SPREAD * (1.0 - decay.rate)
                and abs(before.limit - decay.limit) <= 2.0 * DECAY_SPREAD * decay.limit)
    # The rate per cycle: 1 - q (geometric: log A falls by ~ that per cycle) or c
    # (inverse: 1/A grows by c per cycle).
    rate, rate_before = ((decay.rate, before.rate) if decay.law == INVERSE
                         else (1.0 - decay.rate, 1.0 - before.rate))
    if abs(rate_before - rate) > 2.0 * DECAY_SPREAD * rate:
        return False
    fall = (rate_before - rate) / rate_before  # relative fall of the rate per window
    if fall <= 0.0:
        return True
    reachable = DECAY_FIT * rate / fall  # the rate summed over every window to come
    needed = (1.0 / amp_end - 1.0 / amp0 if decay.law == INVERSE
              else math.log(amp0 / amp_end))
    return needed <= reachable


def period_error(reversal_x) -> float:
    """Bound of the error of the model's cycle (the mean of the last :data:`DECAY_FIT`
    cycles), averaged over the cycles left; ``inf`` without two windows of cycles or a
    shrinking amplitude.

    The cycle depends on the amplitude (the loops' mean stiffness does): ``T(A) = T_inf +
    dev(A)`` with ``dev`` shrinking as the loops do (like ``A^2``, measured on
    k_c0 = 100, beta = 10, D = 0.01). The cycles left lie between ``T_inf`` and the
    window's, so their mean is off by at most ``|dev|`` at the window, plus the window's
    own noise. ``dev`` is bounded from the change of the mean cycle between the last two
    windows, ``dT``, taken as linear in the amplitude (slower to vanish than ``A^2``, so
    larger): ``|dev| <= (|dT| + 2 (s_1 + s_2)) / (1 - A_2 / A_1)``, ``s`` the windows'
    standard errors and ``A`` their amplitudes. On that scene, switching at t = 156 to
    1039, this bound on the time of the last reversal by t = 1e4 was 2.9 to 4.2 times the
    error against every loop followed at rtol 1e-10."""
    windows = _two_windows(reversal_x)
    if windows is None:
        return math.inf
    ts, xs = windows
    n = WINDOW
    cycles = ts[2:] - ts[:-2]  # one per reversal: consecutive ones share a half cycle
    swings = np.abs(np.diff(xs))
    old, new = cycles[: n - 1], cycles[-(n - 1):]
    a_old, a_new = swings[: n - 1].mean(), swings[-(n - 1):].mean()
    if not a_new < a_old:
        return math.inf
    half = math.sqrt(0.5 * (n - 1))  # independent cycles in a window
    s_old, s_new = old.std() / half, new.std() / half
    dev = (abs(new.mean() - old.mean()) + 2.0 * (s_old + s_new)) / (1.0 - a_new / a_old)
    return float(dev + 2.0 * s_new)


def retrace_error(sv: _Solver, st: _State, ts, xs, periodic: bool = False) -> float:
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
    # that retrace exactly (their tops on the anchor, _Solver.retraced_top) repeat their
    # cycle to the bit, and a spread of zero stated no error at all (draft, k_c0 = 1e4).
    spread = max(float(periods.max() - periods.min()), sv.rtol * period)
    trend = 0.0 if periodic else abs(float(periods[-1] - periods[0])) / max(len(periods) - 1, 1)
    omega = 2.0 * math.pi / period
    rate = omega * max(1.0, omega) * 0.5 * abs(xs[-1] - xs[-2])
    # The reversals' drift moves the positions; the velocities follow at omega times it.
    return (drift * cycles * max(1.0, omega)
            + 2.0 * rate * (spread * cycles + trend * 0.5 * cycles * cycles))


def oscillation_end(sv: _Solver, st: _State, model: Oscillation) -> tuple[float, bool]:
    """How long the reduced oscillation runs from ``st`` (to the reversal where the rule for
    rest, :func:`rest_rule`, holds on the model's reversals, or to the horizon), and
    whether it ends at rest.

    The rule reads the last four reversals: their range is the first of their three
    swings, so it holds two to three reversals after the amplitude falls below half the
    rest amplitude. (The model rested at that first reversal: two reversals before the
    rule on every loop followed, 0.017 to 0.026 in time on three cells of
    benchmarks/hysteretic_speed.py.)"""
    # The rule bounds the velocity's swing too (rest_swing_factor).
    rest = sv.rest_amplitude() / rest_swing_factor(model.period)
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
#: at that ``rtol`` does not resolve better (a run's error is measured, app/solver.py).
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


def _window_creep(xs) -> tuple[float, float]:
    """Creep of the centre per amplitude lost over the cycles of the reversals ``xs``, and
    their mean amplitude."""
    xa = np.asarray(xs)
    amps = cycle_amplitudes(xa)
    centres = 0.25 * (xa[0:-2:2] + 2.0 * xa[1:-1:2] + xa[2::2])
    return float((centres[-1] - centres[0]) / (amps[0] - amps[-1])), float(amps.mean())


def creep_law(reversal_x) -> tuple[float, float, float] | None:
    """``(kappa, p, dk)``: the centre's creep per amplitude lost over the last cycles, how
    it grows as the loops shrink, ``kappa ~ A^-p``, and its change ``dk`` from the
    :data:`DECAY_FIT` cycles before (``p = 0`` if it does not grow); ``None`` without
    those cycles, or if the creep grows so fast (``p >=`` :data:`MAX_CREEP_POWER`) that
    where it ends cannot be told from a few cycles."""
    windows = _two_windows(reversal_x)
    if windows is None:
        return None
    xs = windows[1]
    kappa, amp = _window_creep(xs[-WINDOW:])
    kappa0, amp0 = _window_creep(xs[:WINDOW])
    if kappa * kappa0 <= 0.0 or not amp0 > amp or abs(kappa) <= abs(kappa0):
        return kappa, 0.0, kappa - kappa0
    power = math.log(kappa / kappa0) / math.log(amp0 / amp)
    if power >= MAX_CREEP_POWER:
        return None
    return kappa, power, kappa - kappa0


def reduce_extent(sv: _Solver) -> float:
    """Extent of a pressed motion (and drift from a limit cycle) below which a reduced
    model takes over: :data:`REDUCE_PER_RTOL` ``rtol``, at least :data:`PAGE_RESOLUTION`
    (times the length scale)."""
    return max(REDUCE_PER_RTOL * sv.rtol, PAGE_RESOLUTION) * sv.scale()


def creep_end(sv: _Solver, reversal_x, s: int) -> float | None:
    """Where the centre of a settled pressed oscillation ends once its last amplitude
    is gone: the centre creeps ``kappa`` times the amplitude lost
    (:mod:`core.deformable.reduced`); ``None`` if it cannot be measured (then rest is
    at the equilibrium on the current branch)."""
    if not (sv.pressed() and s > 0) or len(reversal_x) < WINDOW:
        return None
    xa = np.array([x for _, x, _ in reversal_x[-WINDOW:]])
    amps = cycle_amplitudes(xa)
    if not np.all(np.diff(amps) < 0.0):
        return None
    kappa, _ = _window_creep(xa)
    shift = kappa * 0.5 * abs(float(xa[-1] - xa[-2]))
    # No farther than the creep's present rate takes the centre by the horizon: loops that
    # barely shrink while their centre creeps give a kappa of thousands (k_c0 = 100,
    # beta = 1000, D = 0.01 at t = 99.5: -2171, a rest 7.5e-6 off where the creep left
    # was 8.6e-8).
    tail = reversal_x[-5:]
    most = creep_left([t for t, _, _ in tail], [x for _, x, _ in tail], sv.t_end)
    return 0.5 * (xa[-1] + xa[-2]) + math.copysign(min(abs(shift), most), shift)


def oscillate(sv: _Solver, st: _State, branch: Branch, s: int, model: Oscillation) -> str:
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
    if not sv.contact.kind or sv.timeline[-1][1] != 1:
        sv.timeline.append((st.t, 1, len(sv.contact.kind)))
    sa = s * sv.a
    if rests:
        # The loss at rest (where the centre has crept to, on the law's state there) less
        # the loss now: the model dissipates exactly that, so the loss never falls at rest.
        x_eq = float(model.centre(0.0))
        at_rest = (st.work[2] + sa * (x_eq - x_s) - 0.5 * x_eq * x_eq + m_s
                   - stored_energy(x_eq - sv.xb, sa - x_eq, sv.stop))
        model = model._replace(dissipation=max(at_rest - loss_s, 0.0))
    sv.contact.add(_OSC, st.t, t1, (model, x_s, m_s, loss_s), sa, st.work)
    x1, v1, _ = (float(q) for q in model.state(t1 - st.t))
    wf, wb, ws = st.work
    dwf = sa * (x1 - x_s)
    dm = 0.5 * (x1 * x1 + v1 * v1) - m_s
    st.work = (wf + dwf, wb + sa * sv.vb * (t1 - st.t), ws + dwf - dm)
    st.t, st.x, st.v = t1, x1, v1
    sv.reduced_band = max(sv.reduced_band, model.error_bound)
    sv.reduced_error = max(sv.reduced_error, model.end_error(
        t1 - t_s, None if not rests else sv.rest_amplitude()))
    if not rests:
        return "horizon"
    return sv.rest_at_stop(st, branch, s, x_rest=model.centre(0.0))


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
#: Contacts the loss law of a train is fitted to (a train that nears its elastic limit
#: changes its approach speed by 1e-4 per contact: six contacts do not tell the law).
TRAIN_FIT = 32
#: Contacts laid out per block while the model is advanced to the horizon.
TRAIN_BLOCK = 65_536
#: Most contacts the model lays out (memory: three float arrays of this length).
TRAIN_MAX_CONTACTS = 20_000_000


def contact_at(start: np.ndarray, w: np.ndarray, dur: np.ndarray, tau):
    """Where times ``tau`` after the switch fall in a train laid out as contacts starting at
    ``start[k]`` with approach speed ``w[k]``, lasting ``dur[k]`` and leaving at
    ``w[k + 1]``: ``(tau, s, dur, w_in, w_out, inside)``, ``s`` the time since the contact's
    start and ``inside`` whether it is still on (else in the flight after it)."""
    tau = np.atleast_1d(np.asarray(tau, dtype=float))
    k = np.clip(np.searchsorted(start, tau, side="right") - 1, 0, len(start) - 1)
    s = tau - start[k]
    return tau, s, dur[k], w[k], w[k + 1], s < dur[k]


def _hermite_overlap(d, w_in, w_out, th):
    """Overlap of a contact of duration ``d`` drawn as the cubic Hermite curve from the face
    at speed ``w_in`` back to it at ``-w_out``, at the fraction ``th`` of its duration."""
    return d * (w_in * (th - 2.0 * th * th + th**3) - w_out * (th**3 - th * th))


class Train(NamedTuple):
    """A train of contacts of a pressed mass advanced by its contact-to-contact map.

    Contact ``k`` (``k = 0`` at the switch) starts ``start[k]`` after the switch with the
    approach speed ``w[k]`` (the fitted loss law, :class:`TrainDecay`) and lasts
    ``dur[k]`` (linear in ``w``, fitted over the same contacts). It ends with the
    separation speed ``w[k + 1]``: the flight between two contacts is a slip circle about
    ``(a, 0)`` through the stop, so it returns at the speed it left with, and lasts
    ``2 atan(w[k + 1] / (a - x_bar))`` exactly (paper Eqs. 3-6). Inside a contact the
    overlap is the cubic Hermite curve through its ends. The position error is bounded by
    the band of the train at the switch (both motions stay in it), the velocity error by
    twice the approach speed (the phase of a long train, not resolved step by step either).
    """

    a: float
    xb: float
    start: np.ndarray
    w: np.ndarray  # one more than start: the last separation speed
    dur: np.ndarray
    band: float
    t_last: float  # end of the model after the switch (the horizon, or rest)
    settled: bool  # the train ends at rest on the stop

    @property
    def amp0(self) -> float:
        return float(self.w[0])

    @property
    def error_bound(self) -> float:
        return self.band

    def state(self, tau):
        """Position, velocity and the train's speed ``tau`` after the switch: the
        approach speed of the contact under way, in a flight the one it returns at
        (the stop is unloaded there: a contact's loss counts from its separation)."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        th = np.where(inside, s / np.where(d > 0.0, d, 1.0), 0.0)
        delta = _hermite_overlap(d, w_in, w_out, th)
        v_c = w_in * (3.0 * th * th - 4.0 * th + 1.0) - w_out * (3.0 * th * th - 2.0 * th)
        sig = np.where(inside, 0.0, s - d)
        gap = self.xb - self.a
        x_f = self.a + gap * np.cos(sig) - w_out * np.sin(sig)
        v_f = -gap * np.sin(sig) - w_out * np.cos(sig)
        x = np.where(inside, self.xb + delta, x_f)
        v = np.where(inside, v_c, v_f)
        return x, v, np.where(inside, w_in, w_out)

    def peak(self, tau):
        """Peak overlap of the contact under way ``tau`` after the switch (0 in a flight):
        the cubic's, where its velocity ``v_c`` of :meth:`state` vanishes (the smaller root
        of ``3 (w_in - w_out) th^2 - (4 w_in - 2 w_out) th + w_in``, in the stable form)."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        b = 4.0 * w_in - 2.0 * w_out
        th = 2.0 * w_in / (b + np.sqrt(np.maximum(b * b - 12.0 * (w_in - w_out) * w_in, 0.0)))
        delta = _hermite_overlap(d, w_in, w_out, th)
        return np.where(inside, delta, 0.0)

    def energy(self, w) -> float:
        """Energy of the train above its touching limit at approach speed ``w``: the
        flight's ``((x - a)^2 + x'^2) / 2`` less its value at ``w = 0``."""
        return 0.5 * np.asarray(w, dtype=float) ** 2


def train_band(sv: _Solver) -> float:
    """Band below which a shrinking train is handed to :class:`Train`:
    :data:`TRAIN_PER_RTOL` ``rtol``, between :data:`PAGE_RESOLUTION` and
    :data:`TRAIN_MAX_BAND` (times the length scale)."""
    return min(max(TRAIN_PER_RTOL * sv.rtol, PAGE_RESOLUTION), TRAIN_MAX_BAND) * sv.scale()


class TrainDecay(NamedTuple):
    """Loss of approach speed per contact of a shrinking train, ``w_k - w_{k+1} = c (w_k -
    w_inf)^n``, advanced in closed form as ``dw/dk = -c (w - w_inf)^n``.

    It covers the geometric decay (``n = 1``), the ``1/k`` decay of contacts that lose
    energy like the cube of their size (``n = 2``, ``w_inf = 0``) and trains whose contacts
    turn elastic as their overlap falls below ``D / beta`` (Eq. 13): their loss vanishes
    as ``w`` nears a limit ``w_inf > 0``, with a large ``n`` (slow algebraic approach).
    """

    c: float
    n: float
    limit: float

    def speed(self, w0: float, k):
        """Approach speed ``k`` contacts after one at ``w0``."""
        k = np.asarray(k, dtype=float)
        u0 = w0 - self.limit
        if abs(self.n - 1.0) < 1e-6:
            return self.limit + u0 * (1.0 - self.c) ** k
        base = u0 ** (1.0 - self.n) + (self.n - 1.0) * self.c * k
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            u = np.where(base > 0.0, np.abs(base) ** (1.0 / (1.0 - self.n)), 0.0)
        return self.limit + u


def _fit_losses(w, loss, limits):
    """Least-squares ``n`` and ``log c`` of ``log loss = log c + n log(w - w_inf)`` for each
    limit ``w_inf``, and the largest relative miss of the fitted losses."""
    u = np.maximum(w[None, :-1] - limits[:, None], 1e-300)
    x, y = np.log(u), np.log(loss)[None, :]
    xm, ym = x.mean(axis=1, keepdims=True), y.mean(axis=1, keepdims=True)
    n = ((x - xm) * (y - ym)).sum(axis=1) / ((x - xm) ** 2).sum(axis=1)
    logc = ym[:, 0] - n * xm[:, 0]
    with np.errstate(over="ignore"):
        miss = np.abs(np.expm1(logc[:, None] + n[:, None] * x - y)).max(axis=1)
    return n, logc, miss


def fit_train_decay(ws) -> TrainDecay | None:
    """The loss law of :class:`TrainDecay` fitted to consecutive approach speeds ``ws``
    (least squares on ``log(w_k - w_{k+1})`` against ``log(w_k - w_inf)`` for a grid of
    ``w_inf``), or ``None`` if they do not shrink or the best fit misses a loss by more
    than :data:`DECAY_SPREAD`.

    Examples
    --------
    >>> law = fit_train_decay(0.9 ** np.arange(32))  # geometric: loses 10 % per contact
    >>> round(law.n, 6), law.limit, round(law.c, 6)
    (1.0, 0.0, 0.1)
    """
    w = np.asarray(ws, dtype=float)
    loss = w[:-1] - w[1:]
    if len(w) < 8 or np.any(loss <= 0.0):
        return None
    limits = np.concatenate(([0.0], w[-1] * (1.0 - np.geomspace(1e-6, 1.0, 48)[:-1])))
    n, logc, miss = _fit_losses(w, loss, limits)
    best = int(np.argmin(miss))
    # A finer grid between the neighbours of the best limit (the coarse one is 34 % apart
    # in w - w_inf).
    lo, hi = limits[max(best - 1, 0)], limits[min(best + 1, len(limits) - 1)]
    limits = np.linspace(min(lo, hi), max(lo, hi), 49)
    n, logc, miss = _fit_losses(w, loss, limits)
    best = int(np.argmin(miss))
    if miss[best] > DECAY_SPREAD or not 0.5 <= n[best] <= 200.0:
        return None
    return TrainDecay(float(np.exp(logc[best])), float(n[best]), float(limits[best]))


def fit_train(sv: _Solver, train: list) -> Train | None:
    """The reduced model of a shrinking train from its last :data:`TRAIN_FIT` contacts,
    or ``None`` while the train is too wide, could stick in flight, or is not regular
    (another transition than one reversal per contact, a loss law that does not fit).

    ``train`` holds ``(t, approach speed, peak x, transitions so far)`` of the contacts;
    the last entry is the contact just started.
    """
    if not (sv.use_reduced and sv.pressed()) or len(train) < TRAIN_FIT + 1:
        return None
    gap = sv.a - sv.xb
    w_now = train[-1][1]
    band = train[-2][2] - (sv.a - math.hypot(gap, w_now))
    if not band <= train_band(sv) or w_now >= sv.vb:
        return None
    window = train[-(TRAIN_FIT + 1):]
    if any(n1 - n0 != 3 for (_, _, _, n0), (_, _, _, n1) in zip(window[:-1], window[1:],
                                                                   strict=True)):
        return None
    w_arr = np.array([w for _, w, _, _ in window])
    decay = fit_train_decay(w_arr)
    if decay is None:
        return None
    times = np.array([t for t, _, _, _ in window])
    durs = np.diff(times) - 2.0 * np.arctan(w_arr[1:] / gap)
    if np.any(durs <= 0.0):
        return None
    slope, icpt = np.polyfit(w_arr[:-1], durs, 1)
    return _lay_out(sv, decay, w_now, float(slope), float(icpt), band, train[-1][0])


def _lay_out(sv, decay: TrainDecay, w0: float, slope: float, icpt: float, band: float,
             t_s: float) -> Train | None:
    """Contacts from the switch to the horizon, or up to the first whose band is below the
    rest amplitude (the train has settled on the stop: the model ends at its start)."""
    gap = sv.a - sv.xb
    rest = sv.rest_amplitude()
    horizon = sv.t_end - t_s
    starts, speeds, durs = [], [], []
    t_next, k0 = 0.0, 0
    while True:
        w = decay.speed(w0, np.arange(k0, k0 + TRAIN_BLOCK + 1, dtype=float))
        d = icpt + slope * w[:-1]
        if np.any(d <= 0.0) or k0 > TRAIN_MAX_CONTACTS:
            return None
        step = d + 2.0 * np.arctan(w[1:] / gap)
        ends = t_next + np.cumsum(step)
        begins = np.concatenate(([t_next], ends[:-1]))
        n, settled, done = TRAIN_BLOCK, False, False
        # Band of a contact and its flight: the flight's depth below the stop and the
        # Hermite overlap's peak (about d w / 3).
        # Settled once the band is within the rest error, and the approach speed within
        # half of it, as loops on the stop rest (a swing of four reversals, twice their
        # amplitude, within the rest amplitude: their speed within half the rest error).
        band_k = np.hypot(gap, w[:-1]) - gap + 0.5 * d * w[:-1]
        small = np.nonzero(np.maximum(band_k, 2.0 * w[:-1]) <= rest)[0]
        if len(small):
            n, settled, done = int(small[0]), True, True
        over = np.nonzero(ends > horizon)[0]
        if len(over) and int(over[0]) + 1 <= n:
            n, settled, done = int(over[0]) + 1, False, True
        starts.append(begins[:n])
        speeds.append(w[:n])
        durs.append(d[:n])
        if done:
            speeds.append(w[n:n + 1])
            t_last = float(begins[n]) if settled else horizon
            break
        t_next, k0 = float(ends[-1]), k0 + TRAIN_BLOCK
    start = np.concatenate(starts)
    if len(start) == 0:  # settled at the switch
        start, dur = np.zeros(1), np.zeros(1)
    else:
        dur = np.concatenate(durs)
    w_all = np.concatenate(speeds)
    if len(w_all) < len(start) + 1:
        w_all = np.append(w_all, w_all[-1])
    return Train(sv.a, sv.xb, start, w_all, dur, band, t_last, settled)


def record_last_restitution(sv: _Solver, w: np.ndarray) -> None:
    """The restitution of the last contact a train's model lays out (rebound over approach
    speed, ``w[-1] / w[-2]``): the run's last contact, which ``info`` reports."""
    if len(w) >= 2 and w[-2] > 0.0:
        sv.restitution.append(float(w[-1] / w[-2]))


def advance_train(sv: _Solver, st: _State, model: Train) -> str:
    """Advance a shrinking train by its reduced model from the start of a contact
    (``st``) to the horizon, or to rest at the equilibrium on the compression envelope
    once its band is below the rest amplitude.

    Energy: friction and belt work follow the model's motion (slip towards the stop
    throughout, ``x' < v``); the stop takes the rest of the balance and its loss grows by
    the train's energy ``w^2 / 2`` as the approach speed ``w`` falls, so ``stop_loss``
    never falls.
    """
    sv.record(TransitionKind.REDUCED, st, st.v)
    t1 = min(st.t + model.t_last, sv.t_end)
    x_s, m_s, loss_s = st.x, 0.5 * (st.x * st.x + st.v * st.v), st.work[2]
    sv.new_branch(FIRST_LOADING, 0.0, st.work[2])
    if not sv.contact.kind or sv.timeline[-1][1] != 1:
        sv.timeline.append((st.t, 1, len(sv.contact.kind)))
    sv.contact.add(_TRAIN, st.t, t1, (model, x_s, m_s, loss_s), sv.a, st.work)
    x1, v1, _ = (float(q[0]) for q in model.state(t1 - st.t))
    wf, wb, ws = st.work
    dwf = sv.a * (x1 - x_s)
    dm = 0.5 * (x1 * x1 + v1 * v1) - m_s
    st.work = (wf + dwf, wb + sv.a * sv.vb * (t1 - st.t), ws + dwf - dm)
    st.t, st.x, st.v = t1, x1, v1
    laid_out = len(model.start) - 1
    sv.n_contacts += laid_out
    for kind in (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION):
        sv.log.count(kind, laid_out)  # counted, not stored (the map logs its last ones)
    record_last_restitution(sv, model.w)
    sv.reduced_band = max(sv.reduced_band, model.error_bound)
    sv.reduced_error = max(sv.reduced_error, model.error_bound)
    if not model.settled or t1 >= sv.t_end:
        # At the horizon the phase of the contacts is not kept: both speeds lie within the
        # approach speed of the train, so the velocity may be off by twice it.
        sv.reduced_error = max(sv.reduced_error, 2.0 * float(model.w[0]))
        return "horizon"
    st.x = sv.xb
    return sv.rest_at_stop(st, FIRST_LOADING, 1)
