"""Stateless solver library for the friction-impact oscillator of Andreaus & Casini (2002).

>>> from core import Oscillator, RigidStop, simulate
>>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1, u_s=1.0)
>>> res = simulate(osc, stop=RigidStop(clearance=0.25, restitution=0.7), t_end=100.0)
>>> res.steady.kind.value   # a < clearance < x* = a + v sqrt(1 - r^2): case c
'grazing'

``core`` imports neither panel, bokeh nor param; ``app`` is built on top of it.
"""

# Each public name is re-exported explicitly (``import X as X``, PEP 484), so a reader
# and a type checker see where it lives; ``app`` imports from here only.
from core import sweep as sweep
from core import theory as theory
from core.deformable.law import FIRST_LOADING as FIRST_LOADING
from core.deformable.law import contact_force as contact_force
from core.deformable.law import phi_compression as phi_compression
from core.deformable.law import phi_expansion as phi_expansion
from core.deformable.law import reverse as reverse
from core.deformable.rest import rest_swing_of as rest_swing_of
from core.deformable.solver import effective_restitutions as effective_restitutions
from core.params import HystereticStop as HystereticStop
from core.params import Oscillator as Oscillator
from core.params import RigidStop as RigidStop
from core.result import STATS_KEYS as STATS_KEYS
from core.result import DenseSolution as DenseSolution
from core.result import Energy as Energy
from core.result import Mode as Mode
from core.result import Result as Result
from core.result import Status as Status
from core.result import Steady as Steady
from core.result import SteadyKind as SteadyKind
from core.result import Transition as Transition
from core.result import TransitionKind as TransitionKind
from core.simulate import MAX_STEPS as MAX_STEPS
from core.simulate import METHODS as METHODS
from core.simulate import method_options as method_options
from core.simulate import simulate as simulate
from core.steady import SteadyCycle as SteadyCycle
from core.steady import first_cycle_end as first_cycle_end
from core.steady import pressed_on_stop as pressed_on_stop
from core.steady import rest_force as rest_force
from core.steady import steady_cycle as steady_cycle
from core.stop_response import OverlapProgram as OverlapProgram
from core.stop_response import equivalent_rigid as equivalent_rigid
from core.stop_response import overlap_program as overlap_program
from core.switch_model import ETA_MAX_REL as ETA_MAX_REL
from core.switch_model import eta_bounds as eta_bounds
from core.validation import check_range as check_range
from core.validation import check_start as check_start

__all__ = [
    "ETA_MAX_REL",
    "FIRST_LOADING",
    "MAX_STEPS",
    "METHODS",
    "STATS_KEYS",
    "DenseSolution",
    "Energy",
    "HystereticStop",
    "Mode",
    "Oscillator",
    "OverlapProgram",
    "Result",
    "RigidStop",
    "Status",
    "Steady",
    "SteadyCycle",
    "SteadyKind",
    "Transition",
    "TransitionKind",
    "check_range",
    "check_start",
    "contact_force",
    "effective_restitutions",
    "equivalent_rigid",
    "eta_bounds",
    "first_cycle_end",
    "method_options",
    "overlap_program",
    "phi_compression",
    "phi_expansion",
    "pressed_on_stop",
    "rest_swing_of",
    "rest_force",
    "reverse",
    "simulate",
    "steady_cycle",
    "sweep",
    "theory",
]
