"""The friction–impact map as a return map: the state at each impact (or stick onset)
against the one before (docs/physics.md, "Zeno and grazing sums" and "Steady states").

Each point is ``(s_n, s_{n+1})`` for successive events of one kind: the approach speeds of
the impacts on a rigid stop, the approach speeds of the contacts with a deformable stop,
and, where nothing strikes a stop, the positions where the block starts to stick. Two
pictures of the theory read off it directly: a grazing sequence, whose approach speeds
fall as ``w_h = r^h w_0``, lies on the straight line ``s_{n+1} = r s_n`` (straight in log
scale too), and a periodic steady state (a fixed point of the map ``P^j``, paper Eq. 20)
returns to the same points, on the identity line when one event closes each period.

The points come from the run's stored transitions (:attr:`core.Result.transitions`, the
first ones of a long run; :attr:`ReturnMap.total` counts all of them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core import Result, SteadyKind, TransitionKind, steady_cycle

#: Events whose approach speed the map follows, per stop type (an impact from stick
#: is an impact too: it starts the sequence of Fig. 7c).
SPEED_EVENTS = {
    "rigid": (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT),
    "hysteretic": (TransitionKind.CONTACT,),
}
#: Where no stop is struck: the stick onsets, by their position.
STICK_EVENTS = (TransitionKind.SLIP_STICK,)


@dataclass(frozen=True)
class ReturnMap:
    """Successive values ``values[n]`` of one event's state, and what they are.

    Attributes
    ----------
    quantity : str
        ``"impact speed"``, ``"contact speed"``, ``"stick position"`` or ``""`` (no events).
    values : np.ndarray
        The state at each stored event, in time order (speeds as magnitudes).
    total : int
        Events of those kinds in the whole run (more than ``len(values)`` past the
        result's cap of stored transitions).
    fixed : np.ndarray
        The values at the events of one period of a periodic steady state (the map's
        fixed point, or the ``j`` points of a fixed point of ``P^j``); empty otherwise.
    """

    quantity: str
    values: np.ndarray
    total: int
    fixed: np.ndarray

    @property
    def pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """The points ``(s_n, s_{n+1})``."""
        return self.values[:-1], self.values[1:]


def _events(result: Result, kinds: tuple[TransitionKind, ...]):
    return [tr for tr in result.transitions if tr.kind in kinds]


def return_map(result: Result, stop_type: str, t_end: float,
               step: tuple[float, float] = (1e-6, 1e-6)) -> ReturnMap:
    """The return map of ``result`` (a run of ``t_end`` with a stop of ``stop_type``:
    ``"none"``, ``"rigid"`` or ``"hysteretic"``); ``step`` is the chord bound within which
    a steady cycle counts as closed (:func:`core.steady_cycle`).

    Impacts (or contacts) where the stop is struck, else the stick onsets.

    >>> from core import Oscillator, RigidStop, simulate
    >>> res = simulate(Oscillator(0.3, 0.2, 0.5), RigidStop(0.3, 0.5), t_end=40.0)
    >>> m = return_map(res, "rigid", 40.0)
    >>> m.quantity, len(m.values) == m.total
    ('impact speed', True)
    """
    kinds = SPEED_EVENTS.get(stop_type, ())
    events = _events(result, kinds)
    quantity = {"rigid": "impact speed", "hysteretic": "contact speed"}.get(stop_type, "")
    if not events:
        kinds, quantity = STICK_EVENTS, "stick position"
        events = _events(result, kinds)
    if not events:
        return ReturnMap("", np.zeros(0), 0, np.zeros(0))
    counts = result.transition_counts
    total = sum(int(counts.get(k.value, 0)) for k in kinds)
    times = np.array([tr.t for tr in events])
    values = (np.array([tr.x for tr in events]) if quantity == "stick position"
              else np.abs(np.array([tr.v for tr in events])))
    return ReturnMap(quantity, values, max(total, len(values)),
                     _fixed(result, t_end, step, times, values))


def _fixed(result: Result, t_end: float, step: tuple[float, float], times: np.ndarray,
           values: np.ndarray) -> np.ndarray:
    """The values at the events of one period of a periodic steady state, or none."""
    if result.steady.kind is not SteadyKind.PERIODIC:
        return np.zeros(0)
    cycle = steady_cycle(result, t_end, step)
    if cycle is None or not math.isfinite(cycle[1]):
        return np.zeros(0)
    t0, period = cycle
    # Half-open, with a little room: the event at t0 opens the cycle, its repeat at
    # t0 + period belongs to the next one.
    pad = 1e-9 * max(1.0, period)
    sel = (times >= t0 - pad) & (times < t0 + period - pad)
    return values[sel]
