"""The paper's closed forms for the state on screen (:mod:`core.theory`), gathered once per
solve for the readout and the plots' overlays."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from core import equivalent_rigid, theory


@dataclass(frozen=True)
class Theory:
    """Closed-form references for the current parameters (:mod:`core.theory`)."""

    regime: Any
    critical_speed: float
    fast: bool
    gamma0_radius: float
    limit_cycle: Any
    x_max_impactless: float
    x_star: float
    points: Mapping[str, tuple[float, float]]
    restitution: float  # r of the stop, or r_eq = sqrt(k_e0/k_c0) (Eq. 16)


def theory_for(osc, stop, x0: float, v0: float) -> Theory | None:
    """Closed-form references, or ``None`` if the theory does not cover the inputs; a
    deformable stop is read as its equivalent rigid stop (:func:`core.equivalent_rigid`,
    paper Eq. 16).

    >>> from core import Oscillator, RigidStop
    >>> theory_for(Oscillator(0.3, 0.2, 0.1), RigidStop(0.25, 0.7), 0.0, 0.0).regime.case
    'c'
    """
    rigid = equivalent_rigid(stop)
    r = rigid.restitution if rigid is not None else 1.0
    try:
        return Theory(
            regime=theory.classify(osc, rigid, x0, v0),
            critical_speed=theory.critical_speed(osc, x0, v0),
            fast=theory.is_fast_belt(osc, x0, v0),
            gamma0_radius=theory.gamma0_radius(osc),
            limit_cycle=theory.impactless_limit_cycle(osc) if osc.v > 0 else None,
            x_max_impactless=theory.x_max_impactless(osc, x0, v0),
            x_star=theory.x_star(osc, r),
            points=MappingProxyType(theory.steady_points(osc, rigid)),
            restitution=r,
        )
    except (ValueError, ZeroDivisionError, OverflowError):
        return None
