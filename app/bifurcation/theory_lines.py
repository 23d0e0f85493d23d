"""The closed-form theory over a bifurcation diagram: named values, where the regime changes."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from app.bifurcation.spec import sweep_inputs
from app.solve.regime_map import regime_labels
from core import equivalent_rigid, theory

#: Values at which the closed-form regime is classified along the swept range.
THEORY_SAMPLES = 600


def theory_lines(values: Mapping[str, Any], parameter: str, lo: float, hi: float,
                 quantity: str) -> tuple[list[tuple[float, str]], list[tuple[float, str]]]:
    """Vertical lines (at parameter values) and horizontal ones (at quantity values) of
    the closed-form theory, each with its label (docs/physics.md).

    Named values: ``v*`` (Eq. 25) on a belt-speed axis; ``a``, ``b``, ``x*`` (Eq. 35) and
    the impactless ``x_max`` on a clearance axis; and a line where the regime that
    :func:`core.theory.classify` gives changes along the range, labelled with the new one.
    """
    vertical = named_values(values, parameter)
    # A regime change at a named value (the belt turns fast at v*) joins its label.
    near = 1.5 * (hi - lo) / THEORY_SAMPLES
    for x, text in regime_changes(values, parameter, lo, hi):
        named = [i for i, (y, _) in enumerate(vertical) if abs(y - x) <= near]
        if named:
            y, name = vertical[named[0]]
            vertical[named[0]] = (y, f"{name}: {text}")
        else:
            vertical.append((x, text))
    vertical = [(float(x), text) for x, text in vertical if lo <= x <= hi and math.isfinite(x)]
    return vertical, quantity_levels(values, parameter, quantity)


def named_values(values: Mapping[str, Any], parameter: str) -> list[tuple[float, str]]:
    """The theory's named values of ``parameter``: ``v*`` (Eq. 25) of the belt speed;
    ``a``, ``b``, ``x*`` (Eq. 35) and the impactless ``x_max`` of the clearance; none where
    the closed form has no value."""
    osc, stop, x0, v0, _, _ = sweep_inputs(values)
    try:
        if parameter == "belt_speed":
            return [(theory.critical_speed(osc, x0, v0), "v*")]
        if parameter == "clearance":
            rigid = equivalent_rigid(stop)
            r = rigid.restitution if rigid is not None else 1.0
            return [(osc.a, "a"), (osc.b, "b"), (theory.x_star(osc, r), "x*"),
                    (theory.x_max_impactless(osc, x0, v0), "x_max without stop")]
    except (ValueError, ZeroDivisionError, OverflowError):
        pass
    return []


def quantity_levels(values: Mapping[str, Any], parameter: str, quantity: str
                    ) -> list[tuple[float, str]]:
    """Horizontal lines of a diagram of ``quantity``: the displacements ``a``, ``b`` and
    the stop's for a displacement, the belt's speed for an impact speed; none that the
    swept ``parameter`` moves."""
    osc, stop, _, _, _, _ = sweep_inputs(values)
    levels: list[tuple[float, str]] = []
    if quantity in ("stick_x", "transition_x", "x_max"):
        if parameter not in ("mu_k", "u_s"):
            levels.append((osc.a, "a"))
        if parameter not in ("mu_s", "u_s"):
            levels.append((osc.b, "b"))
        if stop is not None and parameter != "clearance":
            levels.append((stop.clearance, "x_bar (stop)"))
    elif quantity in ("impact_speed", "rebound_speed") and parameter != "belt_speed":
        levels.append((osc.v, "v (belt)"))
    return levels


def regime_changes(values: Mapping[str, Any], parameter: str, lo: float, hi: float
                   ) -> list[tuple[float, str]]:
    """Where the closed-form regime changes along ``[lo, hi]`` (sampled at
    :data:`THEORY_SAMPLES` values), labelled with the regime that follows."""
    grid = np.linspace(lo, hi, THEORY_SAMPLES)
    v, x = values["belt_speed"], values["clearance"]
    if parameter == "belt_speed":
        words = regime_labels(values, grid, [x])[0]
    elif parameter == "clearance":
        words = regime_labels(values, [v], grid)[:, 0]
    else:
        words = np.array([regime_labels({**values, parameter: float(p)}, [v], [x])[0, 0]
                          for p in grid])
    change = np.flatnonzero(words[1:] != words[:-1])
    return [(0.5 * (grid[i] + grid[i + 1]), str(words[i + 1])) for i in change]

