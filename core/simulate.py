"""The driver: check inputs once, then hand over to the method that fits the scene."""

from __future__ import annotations

import math

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop
from core.result import Result
from core.rigid import simulate_rigid
from core.validation import (
    check_choice,
    check_integer,
    check_options,
    check_oscillator,
    check_range,
    check_start,
    check_stop,
    check_times,
)

#: Methods offered by :func:`simulate`.
METHODS = ("exact", "switch", "event")
#: Options each method uses; any other one given is refused.
METHOD_OPTIONS = {
    "exact": (),  # no stop or a rigid stop: closed form, nothing to tune
    "exact-hysteretic": ("rtol", "atol"),  # exact flight, integrated contact phase
    "switch": ("rtol", "atol", "eta"),
    "event": ("rtol", "atol"),
}
#: Bounds of the sampling density and the transition store.
MAX_SAMPLES = 10_000_000
MAX_TRANSITION_CAP = 10_000_000


def simulate(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None = None,
    t_end: float = 100.0,
    x0: float = 0.0,
    v0: float = 0.0,
    *,
    n_samples: int = 2000,
    transition_cap: int = 10_000,
    method: str = "exact",
    rtol: float | None = None,
    atol: float | None = None,
    eta: float | None = None,
    t_eval: np.ndarray | None = None,
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
        stop or a rigid stop uses none, with a hysteretic stop ``rtol`` and ``atol``;
        ``event`` uses ``rtol`` and ``atol``; ``switch`` all three. Any other raises a
        ``TypeError`` that names it.
    t_eval : array, optional
        Sample at these times in ``[0, t_end]`` instead of ``n_samples`` uniform ones.

    Examples
    --------
    >>> from core import Oscillator, RigidStop, simulate
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    >>> res = simulate(osc, RigidStop(clearance=0.3, restitution=1.0), t_end=50.0)
    >>> round(res.steady.period, 12) == round(2 * math.acos(1 - 0.3 / 0.2), 12)
    True
    """
    check_oscillator(osc)
    check_stop(stop)
    t_end = check_range("t_end", t_end, 0.0, low_open=True)
    x0 = check_range("x0", x0)
    v0 = check_range("v0", v0)
    if stop is not None:
        soft = isinstance(stop, HystereticStop)
        check_start(x0, stop.clearance, stop.limit_overlap if soft else None)
    n_samples = check_integer("n_samples", n_samples, 2, MAX_SAMPLES)
    transition_cap = check_integer("transition_cap", transition_cap, 0, MAX_TRANSITION_CAP)
    check_choice("method", method, METHODS)
    check_options(method, method_options(method, stop), {"rtol": rtol, "atol": atol, "eta": eta})
    for name, value in (("rtol", rtol), ("atol", atol), ("eta", eta)):
        if value is not None:
            check_range(name, value, 0.0, 1.0, low_open=True)
    if t_eval is not None:
        t_eval = check_times("t_eval", t_eval, t_end)
    # t_eval reaches only the exact rigid solver for now; the numerical and hysteretic
    # solvers take it once their functions accept it.

    if method == "switch":
        from core.switch import simulate_switch

        return simulate_switch(
            osc, stop, t_end, x0, v0, n_samples=n_samples, transition_cap=transition_cap,
            **_given(rtol=rtol, atol=atol, eta=eta),
        )
    if method == "event":
        from core.event_method import simulate_event

        return simulate_event(
            osc, stop, t_end, x0, v0, n_samples=n_samples, transition_cap=transition_cap,
            **_given(rtol=rtol, atol=atol),
        )
    if isinstance(stop, HystereticStop):
        from core.hysteretic import simulate_hysteretic

        return simulate_hysteretic(
            osc, stop, t_end, x0, v0, n_samples=n_samples, transition_cap=transition_cap,
            **_given(rtol=rtol, atol=atol),
        )
    return simulate_rigid(
        osc, stop, t_end, x0, v0, n_samples=n_samples, transition_cap=transition_cap,
        t_eval=t_eval,
    )


def method_options(method: str, stop: RigidStop | HystereticStop | None) -> tuple[str, ...]:
    """Names of the options (``rtol``, ``atol``, ``eta``) that ``method`` uses for ``stop``.

    Examples
    --------
    >>> method_options("exact", None), method_options("event", None)
    ((), ('rtol', 'atol'))
    """
    if method == "exact" and isinstance(stop, HystereticStop):
        return METHOD_OPTIONS["exact-hysteretic"]
    return METHOD_OPTIONS[method]


def _given(**kwargs: float | None) -> dict[str, float]:
    """Only the options the caller set, so each method keeps its own defaults."""
    return {k: v for k, v in kwargs.items() if v is not None and math.isfinite(v)}
