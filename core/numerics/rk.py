"""The Runge-Kutta-Fehlberg 4(5) pair for ``x' = v, v' = f(x, v)`` and its step-size control.

Fehlberg (1969), "Formula 2" of Table III: the paper's integrator (Andreaus & Casini,
§2.5; ``docs/physics.md``). The fourth-order solution is advanced (no local
extrapolation); the difference to the fifth-order one is the local error estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.validation import check_range

# --- Runge-Kutta-Fehlberg 4(5) coefficients ------------------------------------------------
A21 = 1.0 / 4.0
A31, A32 = 3.0 / 32.0, 9.0 / 32.0
A41, A42, A43 = 1932.0 / 2197.0, -7200.0 / 2197.0, 7296.0 / 2197.0
A51, A52, A53, A54 = 439.0 / 216.0, -8.0, 3680.0 / 513.0, -845.0 / 4104.0
A61, A62, A63, A64, A65 = -8.0 / 27.0, 2.0, -3544.0 / 2565.0, 1859.0 / 4104.0, -11.0 / 40.0
#: Fourth-order weights: the solution that is advanced (classic Fehlberg, no extrapolation).
B1, B3, B4, B5 = 25.0 / 216.0, 1408.0 / 2565.0, 2197.0 / 4104.0, -1.0 / 5.0
#: Fifth-order minus fourth-order weights: the local error estimate.
E1, E3, E4, E5, E6 = (
    16.0 / 135.0 - B1,
    6656.0 / 12825.0 - B3,
    28561.0 / 56430.0 - B4,
    -9.0 / 50.0 - B5,
    2.0 / 55.0,
)
#: Right-hand-side evaluations of one step (the first stage is reused from the last step).
STAGES_PER_STEP = 5

# --- step-size control -------------------------------------------------------------------
#: Safety factor of the step-size update ``h * SAFETY * err**(-1/5)``.
SAFETY = 0.9
#: Largest growth of the step between two steps.
FACTOR_MAX = 5.0
#: Largest shrink of the step after a rejection.
FACTOR_MIN = 0.2
#: Exponent of the update: the error estimate is ``O(h^5)`` for the fourth-order solution.
ERROR_EXPONENT = -1.0 / 5.0
#: A step below this many ulps of the current time means the integration cannot proceed.
MIN_STEP_ULPS = 64.0


def rkf45_step(f, x: float, v: float, a1: float, h: float) -> tuple[float, float, float, float]:
    """One Runge-Kutta-Fehlberg 4(5) step of ``x' = v, v' = f(x, v)``.

    Parameters
    ----------
    f : callable
        Acceleration ``f(x, v)``.
    x, v : float
        State at the start.
    a1 : float
        ``f(x, v)`` (the first stage, reused from the end of the previous step).
    h : float
        Step size.

    Returns
    -------
    x4, v4 : float
        Fourth-order solution at ``t + h``.
    ex, ev : float
        Error estimate (fifth- minus fourth-order solution).

    Examples
    --------
    >>> x4, v4, ex, ev = rkf45_step(lambda x, v: -x, 1.0, 0.0, -1.0, 0.1)
    >>> abs(x4 - math.cos(0.1)) < 1e-7, abs(ex) < 1e-7
    (True, True)
    """
    v2 = v + h * A21 * a1
    a2 = f(x + h * A21 * v, v2)
    v3 = v + h * (A31 * a1 + A32 * a2)
    a3 = f(x + h * (A31 * v + A32 * v2), v3)
    v4s = v + h * (A41 * a1 + A42 * a2 + A43 * a3)
    a4 = f(x + h * (A41 * v + A42 * v2 + A43 * v3), v4s)
    v5 = v + h * (A51 * a1 + A52 * a2 + A53 * a3 + A54 * a4)
    a5 = f(x + h * (A51 * v + A52 * v2 + A53 * v3 + A54 * v4s), v5)
    v6 = v + h * (A61 * a1 + A62 * a2 + A63 * a3 + A64 * a4 + A65 * a5)
    a6 = f(x + h * (A61 * v + A62 * v2 + A63 * v3 + A64 * v4s + A65 * v5), v6)
    x4 = x + h * (B1 * v + B3 * v3 + B4 * v4s + B5 * v5)
    v4 = v + h * (B1 * a1 + B3 * a3 + B4 * a4 + B5 * a5)
    ex = h * (E1 * v + E3 * v3 + E4 * v4s + E5 * v5 + E6 * v6)
    ev = h * (E1 * a1 + E3 * a3 + E4 * a4 + E5 * a5 + E6 * a6)
    return x4, v4, ex, ev


@dataclass(frozen=True)
class StepControl:
    """Error norm and step-size update of an embedded pair of order 4(5).

    The error of a step is the root mean square of the local error estimates of ``x`` and
    ``x'``, each scaled by ``atol + rtol * |value|`` (the larger of its ends); a step is
    accepted when it is at most 1.

    Examples
    --------
    >>> ctl = StepControl(rtol=1e-6, atol=1e-9)
    >>> ctl.error(0.0, 1.0, 1e-7, 0.0, 1.0, 0.0) <= 1.0
    True
    """

    rtol: float
    atol: float

    def __post_init__(self) -> None:
        check_range("rtol", self.rtol, 0.0, low_open=True)
        check_range("atol", self.atol, 0.0, low_open=True)

    def error(self, x: float, xn: float, ex: float, v: float, vn: float, ev: float) -> float:
        """Scaled error of a step from ``(x, v)`` to ``(xn, vn)`` with estimates ``ex, ev``."""
        sx = self.atol + self.rtol * max(abs(x), abs(xn))
        sv = self.atol + self.rtol * max(abs(v), abs(vn))
        return math.sqrt(0.5 * ((ex / sx) ** 2 + (ev / sv) ** 2))

    @staticmethod
    def grown(h: float, err: float) -> float:
        """The step after an accepted one of size ``h`` and scaled error ``err <= 1``."""
        if err == 0.0:
            return h * FACTOR_MAX
        return h * min(FACTOR_MAX, SAFETY * err**ERROR_EXPONENT)

    @staticmethod
    def shrunk(h: float, err: float) -> float:
        """The step to retry after a rejected one (``err > 1`` or not finite)."""
        shrink = SAFETY * err**ERROR_EXPONENT if math.isfinite(err) else FACTOR_MIN
        return h * max(FACTOR_MIN, shrink)

    @staticmethod
    def too_small(h: float, t: float) -> bool:
        """True when a step of size ``h`` at time ``t`` is lost in rounding."""
        return h <= MIN_STEP_ULPS * math.ulp(max(t, 1.0))
