"""The decay of a pressed mass's shrinking loops, read off their reversals: the amplitude
of each cycle, the decay law fitted to them and its check, the error of the cycle, and the
creep of the loops' centre (:mod:`core.deformable.oscillation` models the loops from it).

The decay law is the steadiest of three: geometric, ``A_k = A_0 q^k``; inverse,
``1/A_k = 1/A_0 + c k`` (the loss per loop of the exponential transition curves of paper
Eq. 13 grows like the amplitude cubed); towards a limit,
``A_k = A_inf + (A_0 - A_inf) q^k`` (loops that turn elastic). The centre creeps ``kappa``
times the amplitude lost, its rate growing like ``A^-p`` (:func:`creep_law`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from core.deformable.rest import DECAY_SPREAD, creep_left
from core.deformable.state import Solve

#: Amplitudes (one per cycle) the decay law is fitted to.
DECAY_FIT = 6

GEOMETRIC, INVERSE, LIMIT = 0, 1, 2
#: The true amplitude where a reduced oscillation ends is within this factor of the
#: model's: the fitted decay's per-cycle rates agree to DECAY_SPREAD (5 %), and the
#: amplitude's relative error stays below the rate's (it is ``n dc A`` for the inverse law,
#: ``<= dc / c``); twice that spread leaves a margin.
END_AMPLITUDE_MARGIN = 1.0 + 2.0 * DECAY_SPREAD
#: Largest growth ``p`` of the centre's creep rate, ``~ A^-p``, a reduced oscillation
#: accepts: the creep left, ``~ A^(1-p) / (1 - p)``, is then at most twice what the
#: measured rate gives over the amplitude left.
MAX_CREEP_POWER = 0.5


#: Reversals of a window of :data:`DECAY_FIT` cycles, and of the last two windows (which
#: share a reversal): what the decay, its check, the creep and the cycle's error read.
WINDOW = 2 * DECAY_FIT + 1
TWO_WINDOWS = 2 * WINDOW - 1


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
    spread, decay = min(_laws(a, pairs), key=lambda f: f[0])
    if spread > DECAY_SPREAD:
        return None
    if decay.law != INVERSE and not 0.0 < decay.rate < 1.0:
        return None
    return decay


def _laws(a: list[float], pairs: list[tuple[float, float]]) -> list[tuple[float, Decay]]:
    """Each decay law fitted to the shrinking amplitudes ``a`` (``pairs``: successive
    ones), with the spread of its per-cycle rates."""
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
    return fits


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


def creep_end(sv: Solve, reversal_x, s: int) -> float | None:
    """Where the centre of a settled pressed oscillation ends once its last amplitude
    is gone: the centre creeps ``kappa`` times the amplitude lost
    (:func:`creep_law`); ``None`` if it cannot be measured (then rest is
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
