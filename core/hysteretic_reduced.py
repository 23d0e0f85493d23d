"""Reduced models of a mass pressed on a deformable stop (``x_bar < a``).

When the belt presses the mass on the stop, the response ends in a train of ever smaller
contacts or in an oscillation on the stop whose loops shrink (paper Fig. 11). Step by step,
its cost grows with the number of loops, not with what changes: thousands of loops whose
amplitude is far below what a plot can show. Once the motion about the equilibrium is that
small and its decay is regular, it is advanced by a reduced model instead::

    x(t) = x_c + kappa (A_0 - A(t)) + A(t) cos(phase0 + 2 pi (t - t_s) / T)

with the cycle ``T`` measured over the last cycles and the amplitude ``A`` following the
decay law fitted to the last amplitudes (one per cycle), the steadiest of

* geometric, ``A_k = A_0 q^k`` (loops of a law that is linear at small amplitude);
* inverse, ``1/A_k = 1/A_0 + c k`` (the loss per loop of the exponential transition curves
  of paper Eq. 13 grows like the amplitude cubed, so the amplitude falls like ``1/k``);
* towards a limit, ``A_k = A_inf + (A_0 - A_inf) q^k`` (loops that become elastic below an
  amplitude: overlaps under ``D / beta`` never leave the compression envelope, Eq. 13).

The centre creeps as the loops shrink (the loops of Eq. 13 do not close: each ends at a
slightly different force), in proportion to the amplitude lost, ``kappa`` measured over the
same cycles (``kappa ~ 7`` on the slow scene of Fig. 11's kind: the centre moves seven times
the amplitude it loses). The model's error in the state is bounded by
``(2 + |kappa|) A_0`` (the band it starts in, and the centre's creep if ``kappa`` were off by
100 %); the solver reports it. The time of rest is when ``A`` falls below the rest amplitude.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

#: Amplitudes (one per cycle) the decay law is fitted to.
DECAY_FIT = 6
#: Largest relative spread of the fitted per-cycle rates for the decay to count as regular.
DECAY_SPREAD = 0.05

GEOMETRIC, INVERSE, LIMIT = 0, 1, 2


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
    kappa: float = 0.0  # creep of the centre per amplitude lost

    @property
    def error_bound(self) -> float:
        """Bound of the model's error in the position (see the module's docstring)."""
        return (2.0 + abs(self.kappa)) * self.amp0

    def centre(self, amp) -> float:
        """Centre of the oscillation once its amplitude is ``amp``."""
        return self.x_c + self.kappa * (self.amp0 - amp)

    def state(self, tau):
        """Position and velocity ``tau`` after the start (arrays or floats)."""
        n = np.asarray(tau, dtype=float) / self.period
        amp = self.decay.amplitude(self.amp0, n)
        damp = self.decay.slope(self.amp0, n) / self.period
        w = 2.0 * math.pi / self.period
        ph = self.phase0 + w * np.asarray(tau, dtype=float)
        c, s = np.cos(ph), np.sin(ph)
        return (self.centre(amp) + amp * c, damp * (c - self.kappa) - amp * w * s, amp)

    def energy(self, amp) -> float:
        """Energy of the linear oscillator of this cycle at amplitude ``amp``."""
        w = 2.0 * math.pi / self.period
        return 0.5 * w * w * amp * amp
