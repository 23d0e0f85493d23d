"""The driver: check inputs once, then hand over to the method that fits the scene."""

from __future__ import annotations

import math

from core.params import HystereticStop, RigidStop
from core.result import Result
from core.rigid import solve_rigid
from core.solve_inputs import SolveInputs, solve_entry
from core.validation import check_choice, check_integer, check_options, check_range

#: Methods offered by :func:`simulate`.
METHODS = ("exact", "switch", "event")
#: Options each method uses; any other one given is refused.
METHOD_OPTIONS = {
    "exact": (),  # no stop or a rigid stop: closed form, nothing to tune
    "exact-hysteretic": ("rtol", "atol", "max_steps"),  # exact flight, integrated contact
    "switch": ("rtol", "atol", "eta", "max_steps", "time_budget"),
    "event": ("rtol", "atol", "max_steps", "time_budget"),
}
#: Upper bound of a numerical method's step limit.
MAX_STEPS = 1_000_000_000
#: Loosest ``rtol`` and ``atol`` taken: the event method at rtol 0.5 returned a "success"
#: whose energy balance was off by 0.15, seven times the motion's mechanical energy.
MAX_TOLERANCE = 1e-2


@solve_entry
def simulate(
    inputs: SolveInputs,
    *,
    method: str = "exact",
    rtol: float | None = None,
    atol: float | None = None,
    eta: float | None = None,
    max_steps: int | None = None,
    time_budget: float | None = None,
) -> Result:
    """Response of the friction(-impact) oscillator over ``[0, t_end]`` (dimensionless time).

    Parameters
    ----------
    osc : Oscillator
        Spring, friction and belt (paper Eqs. 1-6).
    stop : RigidStop, HystereticStop or None
        The obstacle (Eq. 8 or Eqs. 9-13); ``None``: none.
    t_end : float
        Horizon, ``> 0``.
    x0, v0 : float
        Initial displacement and velocity; ``x0 <= clearance``.
    n_samples : int
        Uniform samples in ``[0, t_end]``; the exact transition points are added. An
        integer (``2.7`` is refused, not rounded).
    transition_cap : int
        Transitions stored at most; all are counted in ``Result.transition_counts``.
    method : {"exact", "switch", "event"}
        ``exact``: closed form (rigid stop, no stop) or exact free flight with an
        integrated contact phase (deformable stop). ``switch``: the paper's switch model
        with Runge-Kutta-Fehlberg 4(5). ``event``: ``solve_ivp`` with event location.
    rtol, atol, eta : float, optional
        Tolerances of the numerical parts and the switch model's stick band. Only the
        options the method uses may be given (:func:`method_options`): ``exact`` with no
        stop or a rigid stop uses none, with a hysteretic stop ``rtol``, ``atol`` and
        ``max_steps``;
        ``event`` uses ``rtol`` and ``atol``; ``switch`` all three. Any other raises a
        ``TypeError`` that names it.
    t_eval : array, optional
        Sample at these times in ``[0, t_end]`` instead of ``n_samples`` uniform ones
        (every method).
    max_steps, time_budget : optional
        Work limits of the numerical methods (``switch``, ``event``): steps at most, and
        wall time in seconds; ``exact`` on a hysteretic stop takes ``max_steps``, counting
        the transitions it solves. A solve that reaches one returns the result up to that
        point (``t[-1]``) with ``Status.STEP_LIMIT`` or ``Status.TIME_BUDGET``. By default
        each method stops at its own step limit (:data:`core.switch.DEFAULT_MAX_STEPS`,
        :data:`core.event_method.DEFAULT_MAX_STEPS`,
        :data:`core.deformable.solver.DEFAULT_MAX_STEPS`), which it reaches within a few seconds
        whatever the horizon; there is no default time budget, so a default call gives the
        same result on any machine.

    Examples
    --------
    >>> from core import Oscillator, RigidStop, simulate
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> res = simulate(osc, RigidStop(clearance=0.3, restitution=1.0), t_end=50.0)
    >>> round(res.steady.period, 12) == round(2 * math.acos(1 - 0.3 / 0.2), 12)
    True
    """
    check_choice("method", method, METHODS)
    check_options(
        method, method_options(method, inputs.stop),
        {"rtol": rtol, "atol": atol, "eta": eta, "max_steps": max_steps,
         "time_budget": time_budget},
    )
    for name, value, high in (("rtol", rtol, MAX_TOLERANCE), ("atol", atol, MAX_TOLERANCE),
                              ("eta", eta, 1.0)):
        if value is not None:
            check_range(name, value, 0.0, high, low_open=True)
    limits: dict[str, float] = {}
    if max_steps is not None:
        limits["max_steps"] = check_integer("max_steps", max_steps, 1, MAX_STEPS)
    if time_budget is not None:
        limits["time_budget"] = check_range("time_budget", time_budget, 0.0, low_open=True)
    if method == "switch":
        from core.switch import solve_switch

        return solve_switch(inputs, **limits, **_given(rtol=rtol, atol=atol, eta=eta))
    if method == "event":
        from core.event_method import solve_event

        return solve_event(inputs, **limits, **_given(rtol=rtol, atol=atol))
    if isinstance(inputs.stop, HystereticStop):
        from core.deformable.solver import solve_hysteretic

        return solve_hysteretic(inputs, **limits, **_given(rtol=rtol, atol=atol))
    return solve_rigid(inputs)


def method_options(method: str, stop: RigidStop | HystereticStop | None) -> tuple[str, ...]:
    """Names of the options (``rtol``, ``atol``, ``eta``) that ``method`` uses for ``stop``.

    Examples
    --------
    >>> method_options("exact", None), method_options("event", None)
    ((), ('rtol', 'atol', 'max_steps', 'time_budget'))
    """
    if method == "exact" and isinstance(stop, HystereticStop):
        return METHOD_OPTIONS["exact-hysteretic"]
    return METHOD_OPTIONS[method]


def _given(**kwargs: float | None) -> dict[str, float]:
    """Only the options the caller set, so each method keeps its own defaults."""
    return {k: v for k, v in kwargs.items() if v is not None and math.isfinite(v)}
