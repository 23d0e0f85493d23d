"""The deformable stop on its own: the rigid stop it stands for, and its force under a
prescribed overlap.

Neither needs the oscillator. :func:`equivalent_rigid` is the stop the closed forms of the
paper speak of (they are derived for a rigid stop, docs/physics.md, "The deformable stop";
paper Eq. 16); :func:`overlap_program` drives the contact law (Eqs. 9-13) through the
program of paper Fig. 2b (docs/contact-law.md, on the paper's reading of the law).

>>> from core import HystereticStop
>>> stop = HystereticStop(0.15, 1000.0, 500.0, limit_overlap=0.05, beta_c=5.0, beta_e=5.0)
>>> round(equivalent_rigid(stop).restitution, 4)
0.7071
>>> program = overlap_program(stop)
>>> float(program.overlap.max()) <= 0.75 * stop.limit_overlap
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.deformable.law import FIRST_LOADING, contact_force, reverse
from core.params import HystereticStop, RigidStop
from core.validation import check_integer, check_range

#: Periods of the overlap program of paper Fig. 2b.
PROGRAM_PERIODS = 4
#: Samples per period of the program.
PROGRAM_SAMPLES_PER_PERIOD = 200
#: Peak overlap of the program's first cycle, as a fraction of the limit overlap ``D``.
PROGRAM_PEAK = 0.75
#: Amplitude left at the end of the program (fraction of the first).
PROGRAM_DECAY = 0.25
#: Most periods, and samples per period, a program takes (a million samples at most).
MAX_PROGRAM_PERIODS, MAX_PROGRAM_SAMPLES_PER_PERIOD = 1000, 1000


@dataclass(frozen=True)
class OverlapProgram:
    """The stop driven by a prescribed overlap (paper Fig. 2b).

    Attributes
    ----------
    s : ndarray
        The program's phase [rad], ``2 pi`` per period.
    overlap : ndarray
        The overlap ``delta(s)`` (a length, as ``D``).
    force : ndarray
        The contact force ``phi`` over the spring stiffness ``k`` (a length), Eqs. 9-13.
    """

    s: np.ndarray
    overlap: np.ndarray
    force: np.ndarray


def equivalent_rigid(stop: RigidStop | HystereticStop | None) -> RigidStop | None:
    """The rigid stop the paper's theory speaks of: ``stop`` itself (``None`` for no stop),
    or for a deformable stop the rigid stop at its clearance with the equivalent
    restitution ``r_eq = sqrt(k_e0/k_c0)`` (paper Eq. 16), which a stiff stop with a sharp
    transition approaches (docs/physics.md, "The deformable stop")."""
    if isinstance(stop, HystereticStop):
        return RigidStop(clearance=stop.clearance, restitution=stop.equivalent_restitution)
    return stop


def overlap_program(stop: HystereticStop, *, periods: int = PROGRAM_PERIODS,
                    samples_per_period: int = PROGRAM_SAMPLES_PER_PERIOD,
                    peak: float = PROGRAM_PEAK, decay: float = PROGRAM_DECAY
                    ) -> OverlapProgram:
    """Contact force under the overlap program of paper Fig. 2b, from the stop's law.

    The overlap ``delta(s) = A(s) (1 - cos s) / 2`` rises from zero and returns to it each
    period while the amplitude ``A`` falls linearly from ``peak * D`` to ``decay`` of that
    over ``periods`` periods. A reversal (Eq. 13) is stored at each turn of the overlap
    rate, and a new contact starts on the compression envelope (Eq. 11).

    Parameters
    ----------
    stop : HystereticStop
    periods : int
        Periods of the program, in ``[1, MAX_PROGRAM_PERIODS]``.
    samples_per_period : int
        Samples per period, in ``[2, MAX_PROGRAM_SAMPLES_PER_PERIOD]``.
    peak : float
        First amplitude over the limit overlap ``D``, in ``(0, 1)`` (the force is unbounded
        at ``D``).
    decay : float
        Last amplitude over the first, in ``[0, 1]``.
    """
    if not isinstance(stop, HystereticStop):
        raise ValueError(f"stop must be a HystereticStop; got {stop!r}")
    periods = check_integer("periods", periods, 1, MAX_PROGRAM_PERIODS)
    samples_per_period = check_integer("samples_per_period", samples_per_period, 2,
                                       MAX_PROGRAM_SAMPLES_PER_PERIOD)
    peak = check_range("peak", peak, 0.0, 1.0, low_open=True, high_open=True)
    decay = check_range("decay", decay, 0.0, 1.0)
    n = periods * samples_per_period + 1
    s = np.linspace(0.0, 2.0 * math.pi * periods, n)
    amplitude = peak * stop.limit_overlap * (1.0 - (1.0 - decay) * s / s[-1])
    delta = amplitude * (1.0 - np.cos(s)) / 2.0
    force = np.zeros(n)
    branch = FIRST_LOADING
    for i in range(1, n):
        rising = delta[i] > delta[i - 1]
        if delta[i] <= 0.0:
            branch = FIRST_LOADING
        elif rising != branch.loading:
            branch = reverse(delta[i - 1], force[i - 1], branch)
        force[i] = float(contact_force(delta[i], branch, stop))
    return OverlapProgram(s=s, overlap=delta, force=force)
