"""Frozen, validated parameter values of the friction-impact oscillator.

The core works in the dimensionless form of docs/physics.md, "Dimensionless form" (paper
Eqs. 2-3): time ``t = omega*tau`` with ``omega = sqrt(k/m)``; lengths keep their unit.
``from_physical`` and ``to_physical`` convert from and to SI inputs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.validation import (
    MAX_BETA,
    MAX_MAGNITUDE,
    MAX_STOP_STIFFNESS,
    check_range,
    check_size,
)

#: Standard gravity, only used by helpers that speak of weight (m/s^2).
GRAVITY = 9.80665


@dataclass(frozen=True)
class Oscillator:
    """Mass-spring oscillator on a belt with Coulomb friction (paper Eqs. 1-6).

    Parameters
    ----------
    mu_s, mu_k : float
        Static and kinetic friction coefficients, ``0 <= mu_k <= mu_s``.
    belt_speed : float
        Dimensionless belt speed ``v = v_dr / omega`` (a length), ``>= 0``.
    u_s : float
        Static deflection ``F_N / k`` (a length), ``> 0``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1, u_s=1.0)
    >>> round(osc.a, 12), round(osc.b, 12)
    (0.2, 0.3)
    """

    mu_s: float
    mu_k: float
    belt_speed: float
    u_s: float = 1.0

    def __post_init__(self) -> None:
        mu_s = check_range("mu_s", self.mu_s, 0.0)
        mu_k = check_range("mu_k", self.mu_k, 0.0, mu_s)
        v = check_size("belt_speed", self.belt_speed, 0.0)
        u_s = check_size("u_s", self.u_s, 0.0, low_open=True)
        if mu_s * u_s > MAX_MAGNITUDE:
            raise ValueError(f"mu_s * u_s (the static friction limit b) must lie in "
                             f"[0, {MAX_MAGNITUDE:g}]; got {mu_s * u_s:g}")
        for name, value in (("mu_s", mu_s), ("mu_k", mu_k), ("belt_speed", v), ("u_s", u_s)):
            object.__setattr__(self, name, value)

    @property
    def a(self) -> float:
        """Kinetic friction force over ``k``: ``a = mu_k * u_s`` (a length)."""
        return self.mu_k * self.u_s

    @property
    def b(self) -> float:
        """Static friction limit over ``k``: ``b = mu_s * u_s`` (a length)."""
        return self.mu_s * self.u_s

    @property
    def v(self) -> float:
        """Dimensionless belt speed (a length)."""
        return self.belt_speed

    @classmethod
    def from_physical(
        cls,
        *,
        m: float,
        k: float,
        normal_force: float,
        mu_s: float,
        mu_k: float,
        belt_speed: float,
    ) -> Oscillator:
        """Build from SI values: mass ``m`` [kg], stiffness ``k`` [N/m], ``F_N`` [N],
        belt speed ``v_dr`` [m/s].

        >>> osc = Oscillator.from_physical(m=1.0, k=100.0, normal_force=50.0,
        ...                                mu_s=0.3, mu_k=0.2, belt_speed=0.5)
        >>> round(osc.u_s, 12), round(osc.belt_speed, 12)
        (0.5, 0.05)
        """
        m = check_range("m", m, 0.0, low_open=True)
        k = check_range("k", k, 0.0, low_open=True)
        normal_force = check_range("normal_force", normal_force, 0.0, low_open=True)
        belt_speed = check_range("belt_speed", belt_speed, 0.0)
        omega = math.sqrt(k / m)
        if not 0.0 < omega < math.inf:
            raise ValueError("k / m must give a finite, nonzero natural frequency "
                             f"sqrt(k / m); got k = {k:g} N/m, m = {m:g} kg")
        return cls(mu_s=mu_s, mu_k=mu_k, belt_speed=belt_speed / omega, u_s=normal_force / k)

    def to_physical(self, *, m: float, k: float) -> dict[str, float]:
        """SI values for a given mass [kg] and stiffness [N/m]: ``normal_force`` [N],
        ``belt_speed`` [m/s], ``omega`` [rad/s], plus the friction coefficients."""
        m = check_range("m", m, 0.0, low_open=True)
        k = check_range("k", k, 0.0, low_open=True)
        omega = math.sqrt(k / m)
        return {
            "m": m,
            "k": k,
            "omega": omega,
            "normal_force": self.u_s * k,
            "belt_speed": self.belt_speed * omega,
            "mu_s": self.mu_s,
            "mu_k": self.mu_k,
        }


@dataclass(frozen=True)
class RigidStop:
    """Rigid stop at ``x = clearance`` with Newton's restitution (paper Eq. 8).

    ``clearance`` is measured from the unstretched spring position in the belt's direction;
    it may be negative (the stop then pre-loads the spring).
    """

    clearance: float
    restitution: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "clearance", check_size("clearance", self.clearance))
        object.__setattr__(
            self, "restitution", check_range("restitution", self.restitution, 0.0, 1.0)
        )


#: Readings of the hysteretic contact law (:attr:`HystereticStop.law`).
CONTACT_LAWS = ("paper", "passive")


@dataclass(frozen=True)
class HystereticStop:
    """Deformable stop with the hysteretic contact law of docs/physics.md, "The deformable stop"
    (paper Eqs. 9-13).

    Parameters
    ----------
    clearance : float
        Position of the stop face (a length).
    k_c0, k_e0 : float
        Initial stiffness of the compression and expansion envelopes, relative to the
        spring stiffness ``k`` (``k_c0`` means ``k_c0/k``); ``0 < k_e0 <= k_c0 <= 1e12``.
    limit_overlap : float
        ``D = |U_c| > 0``: the envelopes' asymptote (a length).
    beta_c, beta_e : float
        Rates of approach to the compression / expansion envelope,
        ``0 < beta_c <= beta_e <= 1e6``.
    strength : float
        Compressive strength ``phi_u`` over ``k`` (a length); ``inf`` for none.
    law : str
        Reading of the transition curves (paper Eqs. 12-13, docs/contact-law.md): ``"paper"``
        (reproduces the paper's Fig. 2b; returns energy on some overlap programs) or
        ``"passive"`` (no closed overlap program returns energy).
    """

    clearance: float
    k_c0: float = 1000.0
    k_e0: float = 500.0
    limit_overlap: float = 0.05
    beta_c: float = 5.0
    beta_e: float = 5.0
    strength: float = math.inf
    law: str = "paper"

    def __post_init__(self) -> None:
        if self.law not in CONTACT_LAWS:
            raise ValueError(
                f"law must be one of {', '.join(map(repr, CONTACT_LAWS))}; got {self.law!r}"
            )
        object.__setattr__(self, "clearance", check_size("clearance", self.clearance))
        k_c0 = check_range("k_c0", self.k_c0, 0.0, MAX_STOP_STIFFNESS, low_open=True)
        object.__setattr__(self, "k_c0", k_c0)
        object.__setattr__(
            self, "k_e0", check_range("k_e0", self.k_e0, 0.0, k_c0, low_open=True)
        )
        object.__setattr__(
            self,
            "limit_overlap",
            check_size("limit_overlap", self.limit_overlap, 0.0, low_open=True),
        )
        beta_c = check_range("beta_c", self.beta_c, 0.0, MAX_BETA, low_open=True)
        object.__setattr__(self, "beta_c", beta_c)
        object.__setattr__(self, "beta_e", check_range("beta_e", self.beta_e, beta_c, MAX_BETA))
        object.__setattr__(
            self,
            "strength",
            check_range("strength", self.strength, 0.0, low_open=True, allow_inf=True),
        )

    @property
    def equivalent_restitution(self) -> float:
        """Restitution of the equivalent rigid stop, ``sqrt(k_e0/k_c0)`` (paper Eq. 16)."""
        return math.sqrt(self.k_e0 / self.k_c0)

    @classmethod
    def from_physical(
        cls,
        *,
        k: float,
        clearance: float,
        k_c0: float,
        k_e0: float,
        limit_overlap: float,
        beta_c: float = 5.0,
        beta_e: float = 5.0,
        strength: float = math.inf,
        law: str = "paper",
    ) -> HystereticStop:
        """Build from SI values: spring ``k`` [N/m], stiffnesses ``k_c0, k_e0`` [N/m],
        lengths [m], ``strength`` [N]."""
        k = check_range("k", k, 0.0, low_open=True)
        strength = check_range("strength", strength, 0.0, low_open=True, allow_inf=True)
        return cls(
            clearance=clearance,
            k_c0=check_range("k_c0", k_c0, 0.0, low_open=True) / k,
            k_e0=check_range("k_e0", k_e0, 0.0, low_open=True) / k,
            limit_overlap=limit_overlap,
            beta_c=beta_c,
            beta_e=beta_e,
            strength=strength / k if math.isfinite(strength) else math.inf,
            law=law,
        )
