"""Stateless solver library for the friction-impact oscillator of Andreaus & Casini (2002).

>>> from core import Oscillator, RigidStop, simulate
>>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1, u_s=1.0)
>>> res = simulate(osc, stop=RigidStop(clearance=0.25, restitution=0.7), t_end=100.0)
>>> res.steady.kind.value   # a < clearance < x* = a + v sqrt(1 - r^2): case c
'grazing'

``core`` imports neither panel, bokeh nor param; ``app`` is built on top of it.
"""

from core import theory
from core.hysteresis import FIRST_LOADING, contact_force, phi_compression, phi_expansion, reverse
from core.hysteretic import effective_restitutions
from core.params import HystereticStop, Oscillator, RigidStop
from core.result import (
    STATS_KEYS,
    DenseSolution,
    Energy,
    Mode,
    Result,
    Status,
    Steady,
    SteadyKind,
    Transition,
    TransitionKind,
)
from core.simulate import METHODS, method_options, simulate
from core.steady import pressed_on_stop, rest_force
from core.validation import check_range

__all__ = [
    "FIRST_LOADING",
    "METHODS",
    "STATS_KEYS",
    "DenseSolution",
    "Energy",
    "HystereticStop",
    "Mode",
    "Oscillator",
    "Result",
    "RigidStop",
    "Status",
    "Steady",
    "SteadyKind",
    "Transition",
    "TransitionKind",
    "check_range",
    "contact_force",
    "effective_restitutions",
    "method_options",
    "phi_compression",
    "phi_expansion",
    "pressed_on_stop",
    "rest_force",
    "reverse",
    "simulate",
    "theory",
]
