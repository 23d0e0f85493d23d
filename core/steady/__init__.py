"""What the motion settles to, for every method and label: its steady state and its cycle.

One home, one concept a module (docs/physics.md, "Steady states"):

* :mod:`~core.steady.rest`: the one rule for rest at the stop (:func:`pressed_on_stop`,
  :func:`rest_force`, :func:`comes_to_rest`);
* :mod:`~core.steady.fixed_point`: the one detector of a periodic steady state, a fixed
  point of the friction-impact map (Eq. 20, :class:`FixedPointDetector`);
* :mod:`~core.steady.tail`: the steady state read off a method's last transitions
  (:func:`steady_from_transitions`);
* :mod:`~core.steady.train` and :mod:`~core.steady.pressed`: the labels a deformable
  stop's law decides (:func:`train_steady`) and those of a mass pressed on the stop
  (:func:`pressed_steady`);
* :mod:`~core.steady.cycle`: the cycle a steady motion repeats (:func:`steady_cycle`), the
  horizon tiled with it (:func:`fold_times`) and its transitions
  (:func:`cycle_transitions`).
"""

from core.steady.cycle import (
    TILE_SNAP,
    TURN,
    SteadyCycle,
    cycle_transitions,
    first_cycle_end,
    fold_times,
    settled_time,
    steady_cycle,
)
from core.steady.fixed_point import (
    FIXED_POINT_LOOKBACK,
    FIXED_POINT_RTOL,
    PERIOD_ULPS,
    Cycle,
    FixedPointDetector,
)
from core.steady.pressed import (
    SWING_POINTS,
    SWING_SPAN_CHANGE,
    SWING_SPAN_CYCLES,
    SWING_STEADY,
    SWING_WINDOW,
    SwingProbe,
    pressed_steady,
)
from core.steady.rest import REST_SPEED, comes_to_rest, pressed_on_stop, rest_force
from core.steady.tail import (
    STEADY_WINDOW,
    method_rtol,
    steady_from_transitions,
)
from core.steady.train import (
    TRAIN_CONTACTS,
    TRAIN_CYCLE,
    impacts_lose,
    train_contacts,
    train_loses,
    train_steady,
)

__all__ = [
    "FIXED_POINT_LOOKBACK",
    "FIXED_POINT_RTOL",
    "PERIOD_ULPS",
    "REST_SPEED",
    "STEADY_WINDOW",
    "SWING_POINTS",
    "SWING_SPAN_CHANGE",
    "SWING_SPAN_CYCLES",
    "SWING_STEADY",
    "SWING_WINDOW",
    "TILE_SNAP",
    "TRAIN_CONTACTS",
    "TRAIN_CYCLE",
    "TURN",
    "Cycle",
    "FixedPointDetector",
    "SteadyCycle",
    "SwingProbe",
    "comes_to_rest",
    "cycle_transitions",
    "first_cycle_end",
    "fold_times",
    "impacts_lose",
    "method_rtol",
    "pressed_on_stop",
    "pressed_steady",
    "rest_force",
    "settled_time",
    "steady_cycle",
    "steady_from_transitions",
    "train_contacts",
    "train_loses",
    "train_steady",
]
