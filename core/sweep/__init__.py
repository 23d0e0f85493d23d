"""Parameter sweeps: the steady state at many parameter points (bifurcation diagrams, maps).

:func:`sweep` varies one parameter, :func:`sweep_grid` two; both return a
:class:`SweepResult` with, per point, the steady-state label, period, transitions per
period, ``x_max``, impact speed, the simulated regime label and the Poincaré samples (the
transitions of one steady period, paper Eq. 20; docs/sweeps.md).

With no stop or a rigid stop and ``method="exact"`` the points advance together through
the closed-form segments (:mod:`core.sweep.closed_form`); any point that needs more is
solved by :func:`core.simulate` and flagged in ``SweepResult.fallback``. A deformable stop
or a numerical method solves each point with :func:`core.simulate`;
:mod:`core.sweep.distributed` spreads such sweeps over a Dask cluster.

>>> import numpy as np
>>> from core import Oscillator, RigidStop
>>> from core.sweep import sweep
>>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
>>> res = sweep(osc, RigidStop(0.25, 1.0), "belt_speed", np.linspace(0.05, 0.5, 4),
...             quantity="impact_speed", t_end=200.0)
>>> res.labels.tolist()
['periodic', 'periodic', 'periodic', 'periodic']
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop
from core.simulate import METHODS
from core.sweep.lanes import PARAMETERS, Lanes, make_lanes
from core.sweep.result import KINDS, LABELS, QUANTITIES, LaneRecords, SweepResult, check_quantity
from core.validation import check_horizon, check_size

__all__ = [
    "KINDS",
    "LABELS",
    "PARAMETERS",
    "QUANTITIES",
    "GridPlan",
    "SweepResult",
    "plan_grid",
    "solve_block",
    "sweep",
    "sweep_grid",
]

#: Lanes advanced together: large enough that numpy's per-call cost is spread over many
#: points, small enough that a block's history arrays stay in the cache.
BLOCK = 8192


def vectorised(stop, method: str) -> bool:
    """True when the closed-form stepper covers the scene (no stop or a rigid stop)."""
    return method == "exact" and not isinstance(stop, HystereticStop)


def solve_block(lanes: Lanes, t_end: float, x0: float, v0: float, method: str) -> LaneRecords:
    """Steady state of a block of lanes: vectorised where exact, else one by one."""
    from core.sweep import scalar

    if not vectorised(lanes.stop, method):
        return scalar.solve_lanes(lanes, t_end, x0, v0, method)
    from core.sweep import closed_form

    parts = []
    for start in range(0, len(lanes), BLOCK):
        block = lanes.take(slice(start, start + BLOCK))
        rec = closed_form.solve_lanes(block, t_end, x0, v0)
        redo = np.flatnonzero(rec.fallback)
        if len(redo):
            rec = _replace(rec, redo, scalar.solve_lanes(block.take(redo), t_end, x0, v0, method))
        parts.append(rec)
    return LaneRecords.concat(parts)


def _replace(rec: LaneRecords, idx: np.ndarray, sub: LaneRecords) -> LaneRecords:
    """``rec`` with the lanes ``idx`` taken from ``sub`` (in order)."""
    n = len(rec.label)
    pieces, start = [], 0
    for k, i in enumerate(idx.tolist()):
        if i > start:
            pieces.append(rec.take(start, i))
        pieces.append(sub.take(k, k + 1))
        start = i + 1
    if start < n:
        pieces.append(rec.take(start, n))
    return LaneRecords.concat(pieces)


@dataclass(frozen=True)
class GridPlan:
    """A checked sweep over one or two parameters: its lanes and options
    (:func:`plan_grid`)."""

    lanes: Lanes
    axes: dict[str, np.ndarray]
    quantity: str
    t_end: float
    method: str
    x0: float
    v0: float

    def solve(self) -> LaneRecords:
        """Solve every lane here (:func:`solve_block`)."""
        return solve_block(self.lanes, self.t_end, self.x0, self.v0, self.method)

    def finish(self, rec: LaneRecords) -> SweepResult:
        """The :class:`SweepResult` of the solved lanes ``rec`` (in the lanes' order)."""
        return rec.finish(tuple(self.axes), self.axes, self.quantity, self.t_end, self.method)


def plan_grid(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None,
    axes: dict,
    *,
    quantity: str | None = None,
    t_end: float = 200.0,
    method: str = "exact",
    x0: float = 0.0,
    v0: float = 0.0,
) -> GridPlan:
    """Check a sweep's scene and options once and lay out its lanes; the options are the
    keywords of :func:`sweep`, :func:`sweep_grid` and
    :func:`core.sweep.distributed.sweep_distributed`.

    Parameters
    ----------
    osc, stop
        The base scene; every parameter but the swept ones keeps its value.
    axes : dict
        ``{name: values}`` for one or two names of :data:`PARAMETERS`: ``belt_speed``,
        ``clearance``, ``restitution``, ``mu_s``, ``mu_k``, ``u_s`` (each value is checked
        against its range).
    quantity : str, optional
        Default Poincaré quantity of :meth:`SweepResult.samples`, one of
        :data:`QUANTITIES`; unless given, the impact speed with a stop, the stick onset
        without.
    t_end : float
        Horizon of each simulation (dimensionless time); a steady state not reached by
        then is labelled ``'none'``.
    method : {"exact", "switch", "event"}
        As :func:`core.simulate`; only ``exact`` without a deformable stop is vectorised.
    x0, v0 : float
        Initial state of every point.
    """
    if not quantity:  # impact speed with a stop, the stick onset without
        quantity = "stick_x" if stop is None else "impact_speed"
    quantity = check_quantity(quantity, isinstance(stop, HystereticStop))
    t_end = check_horizon(t_end)
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    x0, v0 = check_size("x0", x0), check_size("v0", v0)
    if not 1 <= len(axes) <= 2:
        raise ValueError(f"a sweep varies one or two parameters; got {len(axes)}")
    lanes = make_lanes(osc, stop, dict(axes), x0)
    values = {k: np.asarray(v, float) for k, v in axes.items()}
    return GridPlan(lanes, values, quantity, t_end, method, x0, v0)


def takes_plan_options(fn):
    """Show ``fn(..., **options)`` with :func:`plan_grid`'s keyword options in its signature
    (``help``, ``inspect``), as if it listed them itself; the options are checked by
    :func:`plan_grid`, which ``fn`` calls."""
    own = [p for p in inspect.signature(fn).parameters.values() if p.kind is not p.VAR_KEYWORD]
    options = [
        p for p in inspect.signature(plan_grid).parameters.values() if p.kind is p.KEYWORD_ONLY
    ]
    fn.__signature__ = inspect.signature(fn).replace(parameters=own + options)
    return fn


@takes_plan_options
def sweep(
    osc: Oscillator, stop: RigidStop | HystereticStop | None, parameter: str, values, **options
) -> SweepResult:
    """Steady state of the scene ``(osc, stop)`` at each value of one parameter.

    Parameters
    ----------
    osc, stop
        The base scene; every parameter but ``parameter`` keeps its value.
    parameter : str
        One of :data:`PARAMETERS`: ``belt_speed``, ``clearance``, ``restitution``,
        ``mu_s``, ``mu_k``, ``u_s``.
    values : 1-D array
        The parameter's values (each is checked against its range).
    **options
        ``quantity``, ``t_end`` (default 200), ``method`` (default ``"exact"``), ``x0``,
        ``v0``: see :func:`plan_grid`.
    """
    return sweep_grid(osc, stop, {parameter: values}, **options)


@takes_plan_options
def sweep_grid(
    osc: Oscillator, stop: RigidStop | HystereticStop | None, axes: dict, **options
) -> SweepResult:
    """Steady state over the grid of one or two parameters, ``axes = {name: values}``.

    The result's per-point arrays are in row-major order over ``axes`` (the last parameter
    varies fastest); ``result.labels`` and ``result.regime_labels`` have the grid's shape.
    ``options`` are those of :func:`sweep` (:func:`plan_grid`).
    """
    plan = plan_grid(osc, stop, axes, **options)
    return plan.finish(plan.solve())
