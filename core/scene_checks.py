"""Type checks of a scene at the boundary of the core: an oscillator, a stop and a start.

They name the type received, as :mod:`core.validation` names the value; they live apart
from it because they know the parameter classes, which :mod:`core.params` builds on those
value checks.
"""

from __future__ import annotations

from core.params import HystereticStop, Oscillator, RigidStop
from core.validation import check_finite, check_start


def check_oscillator(osc: object) -> None:
    """``osc`` must be an :class:`~core.params.Oscillator`."""
    if not isinstance(osc, Oscillator):
        raise TypeError(f"osc must be an Oscillator; got {type(osc).__name__}")


def check_stop(stop: object) -> None:
    """``stop`` must be None, a :class:`~core.params.RigidStop` or a
    :class:`~core.params.HystereticStop`."""
    if stop is not None and not isinstance(stop, (RigidStop, HystereticStop)):
        raise TypeError(
            f"stop must be None, a RigidStop or a HystereticStop; got {type(stop).__name__}"
        )


def check_rigid_stop(stop: object, x0: float) -> None:
    """For the closed forms: ``stop`` must be None or a RigidStop ahead of ``x0``."""
    if stop is None:
        return
    if not isinstance(stop, RigidStop):
        raise TypeError(
            "stop must be a RigidStop or None; the closed forms hold for a rigid stop only "
            f"(got {type(stop).__name__}; for a hysteretic stop use "
            "RigidStop(stop.clearance, stop.equivalent_restitution) as its rigid equivalent)"
        )
    check_start(x0, stop.clearance)


def check_state(osc: object, x0: float, v0: float) -> tuple[float, float]:
    """``osc`` must be an :class:`~core.params.Oscillator`; returns the initial state as
    finite floats."""
    check_oscillator(osc)
    return check_finite("x0", x0), check_finite("v0", v0)
