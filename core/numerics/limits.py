"""Work limits of a numerical solve: a step count and an optional wall-clock budget.

A solve that reaches a limit stops there and returns its result up to that time with
:attr:`~core.result.Status.STEP_LIMIT` or :attr:`~core.result.Status.TIME_BUDGET`; it never
loops without end nor raises. Each method declares its own default step limit, sized to
its cost per step (:data:`core.switch.DEFAULT_MAX_STEPS`,
:data:`core.event_method.DEFAULT_MAX_STEPS`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from core.result import Status
from core.validation import check_integer, check_range

#: Default limit on the events (transitions and restarts of the integration) of one solve.
MAX_EVENTS = 1_000_000
#: Upper bound of a count option (only so that its error message can state a range); a
#: :class:`WorkLimit` made without a step count allows this many, i.e. no step limit.
COUNT_MAX = 10**15


@dataclass
class WorkLimit:
    """The step count and the deadline of one solve.

    Parameters
    ----------
    max_steps : int
        Steps allowed (``>= 1``); default :data:`COUNT_MAX` (no step limit).
    time_budget : float or None
        Wall-clock seconds allowed (``> 0``); ``None``: no budget.

    Examples
    --------
    >>> limit = WorkLimit(max_steps=2)
    >>> limit.reached(1), limit.reached(2)
    (None, <Status.STEP_LIMIT: 'step_limit'>)
    """

    max_steps: int = COUNT_MAX
    time_budget: float | None = None
    deadline: float = field(init=False, default=math.inf)

    def __post_init__(self) -> None:
        self.max_steps = check_integer("max_steps", self.max_steps, 1, COUNT_MAX)
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
