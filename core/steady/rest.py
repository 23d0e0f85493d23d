"""The one rule for rest at the stop: whether a mass at rest there stays pressed on it.

At the stop ``x = x_bar`` with ``x' = 0`` the mass moves backwards relative to a moving
belt, so kinetic friction ``+a`` acts and the net force without the stop is ``a - x_bar``.
The mass stays pressed on the stop iff that force does not pull it away, ``a >= x_bar``.
The same inequality decides whether the rebounds of an impact sequence come back to the
stop ever faster (accumulation, ``x_bar < a``) or not (grazing; docs/physics.md).
"""

from __future__ import annotations

import math

from core.params import Oscillator

#: An impact whose bounce would rise less than this fraction of the stop's length scale
#: off the stop (height ``w^2 / (2 |a - x_bar|)``) cannot be told from rest: one ulp of
#: ``x`` at a turning point next to the stop already gives a speed of that order. The
#: threshold on the speed is ``REST_SPEED * sqrt(|a - x_bar| * L)``; 1e-7 is the square
#: root of ~500 ulps of position.
REST_SPEED = 1e-7


def pressed_on_stop(osc: Oscillator, clearance: float) -> bool:
    """True when a mass at rest at the stop stays pressed on it: ``a >= x_bar``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> pressed_on_stop(osc, 0.1), pressed_on_stop(osc, 0.3)
    (True, False)
    """
    return osc.a >= clearance


def rest_force(osc: Oscillator, clearance: float) -> float:
    """Contact force over ``k`` (a length) of the mass resting on the stop.

    On a moving belt kinetic friction presses it: ``a - x_bar``. On a still belt static
    friction is indeterminate and the least force it allows, ``max(-x_bar - b, 0)``, is
    reported. Zero when the mass is not pressed.

    Examples
    --------
    >>> round(rest_force(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5), 0.05), 12)
    0.15
    """
    if osc.v > 0.0:
        return max(osc.a - clearance, 0.0)
    return max(-clearance - osc.b, 0.0)


def comes_to_rest(osc: Oscillator, clearance: float, speed: float) -> bool:
    """True when an impact at ``speed`` leaves the mass at rest at the stop to the
    resolution of the numbers: it is pressed on the stop and the bounce it starts would
    rise less than ``REST_SPEED**2`` of the stop's length scale (see :data:`REST_SPEED`).

    Examples
    --------
    >>> osc = Oscillator(mu_s=1.0, mu_k=1.0, belt_speed=0.0)
    >>> comes_to_rest(osc, 0.0, 1e-20), comes_to_rest(osc, 0.0, 1e-3)
    (True, False)
    """
    if not pressed_on_stop(osc, clearance):
        return False
    if speed == 0.0:
        return True
    d = abs(osc.a - clearance)
    scale = max(abs(clearance), d)
    return speed <= REST_SPEED * math.sqrt(d * scale)
