"""Work limits of a numerical solve: a step count and an optional wall-clock budget.

A solve that reaches a limit stops there and returns its result up to that time with
:attr:`~core.result.Status.STEP_LIMIT` or :attr:`~core.result.Status.TIME_BUDGET`; it never
loops without end nor raises.
"""

from __future__ import annotations

import math
import numbers
import time
from dataclasses import dataclass, field

from core.result import Status
from core.validation import check_range

#: Default limit on the steps of one solve (accepted and rejected): far above what a solve
#: to ``t_end = 1e4`` at ``rtol = 1e-10`` needs, and a bound of a few tens of seconds on a
#: scene the method cannot resolve.
MAX_STEPS = 2_000_000
#: Default limit on the events (transitions and restarts of the integration) of one solve.
MAX_EVENTS = 1_000_000


def check_count(name: str, value, low: int = 1) -> int:
    """``value`` as an ``int`` if it is a whole number ``>= low``, else a ``ValueError``.

    >>> check_count("max_steps", 10)
    10
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a whole number; got {type(value).__name__}")
    if not (math.isfinite(value) and float(value).is_integer()):
        raise ValueError(f"{name} must be a whole number >= {low}; got {value!r}")
    return int(check_range(name, int(value), low))


@dataclass
class WorkLimit:
    """The step count and the deadline of one solve.

    Parameters
    ----------
    max_steps : int
        Steps allowed (``>= 1``).
    time_budget : float or None
        Wall-clock seconds allowed (``> 0``); ``None``: no budget.

    Examples
    --------
    >>> limit = WorkLimit(max_steps=2)
    >>> limit.reached(1), limit.reached(2)
    (None, <Status.STEP_LIMIT: 'step_limit'>)
    """

    max_steps: int = MAX_STEPS
    time_budget: float | None = None
    deadline: float = field(init=False, default=math.inf)

    def __post_init__(self) -> None:
        self.max_steps = check_count("max_steps", self.max_steps)
        if self.time_budget is not None:
            self.time_budget = check_range(
                "time_budget", self.time_budget, 0.0, low_open=True, allow_inf=True
            )
            self.deadline = time.perf_counter() + self.time_budget

    def reached(self, steps: int) -> Status | None:
        """The status to stop with after ``steps`` steps, or ``None`` to go on."""
        if steps >= self.max_steps:
            return Status.STEP_LIMIT
        if self.deadline < math.inf and time.perf_counter() > self.deadline:
            return Status.TIME_BUDGET
        return None
