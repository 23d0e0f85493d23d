"""The rules a user's value meets before it reaches the state: the constraints between
values (mu_k <= mu_s, k_e0 <= k_c0, beta_c <= beta_e), the reasons a typed value is refused,
and what a commit changes.

Pure functions of the state's values (tested without a browser); the controls
(:mod:`app.controls`) apply them. Refusals speak the core's words (:mod:`core.validation`:
the parameter, the allowed range, the value).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, NamedTuple

from app.control_specs import CONSTRAINTS, SI_STATE_NAME
from app.scenes import CUSTOM
from app.state import (
    HORIZON_CHOICES,
    SOLVE_PARAMS,
    SOLVER_CHOICES,
    ExplorerState,
    core_inputs,
    si_bound_error,
    si_units,
)
from app.widgets import bounds_reason

#: Solve values whose change keeps the scene (its title and caption): how the motion is
#: solved and how long it is watched (:data:`~app.state.SOLVER_CHOICES`,
#: :data:`~app.state.HORIZON_CHOICES`).
SCENE_KEEPERS = SOLVER_CHOICES + HORIZON_CHOICES


class Note(NamedTuple):
    """``low`` followed ``high`` down: from ``was`` to ``now``."""

    low: str
    was: float
    now: float
    high: str


def constrained(values: dict[str, Any]) -> dict[str, Any]:
    """Apply the constraints (:data:`~app.control_specs.CONSTRAINTS`) in place: the lower
    of each pair follows the higher down.

    >>> constrained({"mu_k": 0.4, "mu_s": 0.3})
    {'mu_k': 0.3, 'mu_s': 0.3}
    """
    for low, high in CONSTRAINTS:
        if low in values and high in values and values[low] > values[high]:
            values[low] = values[high]
    return values


def commit_changes(state: ExplorerState, changes: Mapping[str, Any]
                   ) -> tuple[dict[str, Any], list[Note]]:
    """What a user's final value(s) ``changes`` set in ``state`` (only real changes), and
    the values the constraints moved.

    Solve values go through the constraints and drop the overlap program off a
    deformable stop; a real change of one (other than the method or accuracy,
    :data:`SCENE_KEEPERS`) makes the scene 'custom'.
    """
    new = {k: v for k, v in changes.items() if k not in SOLVE_PARAMS}
    solve_changes = {k: v for k, v in changes.items() if k in SOLVE_PARAMS}
    notes: list[Note] = []
    if solve_changes:
        diff, notes = _solve_changes(state, solve_changes)
        new.update(diff)
        if "scene" not in changes and any(k not in SCENE_KEEPERS for k in diff):
            new["scene"] = CUSTOM
    return {k: v for k, v in new.items() if getattr(state, k) != v}, notes


def _solve_changes(state: ExplorerState, changes: Mapping[str, Any]
                   ) -> tuple[dict[str, Any], list[Note]]:
    """The solve values ``changes`` make differ from ``state``'s, through the constraints,
    and the values the constraints moved."""
    wanted = {**state.values(), **changes}
    if wanted["stop_type"] != "hysteretic":  # the program drives a deformable stop
        wanted["program"] = False
    merged = constrained(dict(wanted))
    notes = [Note(low, wanted[low], merged[low], high) for low, high in CONSTRAINTS
             if merged[low] != wanted[low]]
    return {k: v for k, v in merged.items() if v != getattr(state, k)}, notes


def core_reason(values: Mapping[str, Any]) -> str | None:
    """The core's message for solve values it refuses, or None."""
    try:
        core_inputs(values)
    except ValueError as exc:
        return str(exc)
    return None


def refusal(state: ExplorerState, name: str, value: float,
            bounds: tuple[float, float]) -> str | None:
    """Why a typed ``value`` of ``name`` (its box allowing ``bounds``) is refused, or None.

    The page's limits (a horizon the page can draw, a slider that can be drawn) come first,
    then what the core's validation refuses of the whole set (a stop behind the start).
    """
    higher = dict(CONSTRAINTS).get(name)
    if higher is not None:  # the lower of a pair may not pass the higher
        reason = bounds_reason(name, value, (bounds[0], getattr(state, higher)))
        if reason:
            return f"{reason} (it may not exceed {higher})"
    reason = bounds_reason(name, value, bounds)
    if reason is None and name in SOLVE_PARAMS:
        reason = core_reason(constrained({**state.values(), name: value}))
        if reason == core_reason(state.values()):  # not this value's doing
            reason = None
    return reason


def refusal_si(state: ExplorerState, key: str, value: float, label: str,
               low: float) -> str | None:
    """Why a typed SI ``value`` of ``key`` (a key of :meth:`ExplorerState.physical`; its box
    named ``label``, its lower bound ``low``) is refused, or None: first the state's bounds
    in SI with the current m, k and L, then the conversion's own checks."""
    name = SI_STATE_NAME[key]
    units = (state.mass, state.stiffness, state.length_unit)
    factor = si_units(*units)[name][2]
    message = si_bound_error(name, value / factor, *units)
    if message:
        return message
    higher = dict(CONSTRAINTS).get(name)
    if higher is not None:  # the lower of a pair (k_e0 <= k_c0), as in refusal
        top = getattr(state, higher) * factor
        if value > top and not math.isclose(value, top, rel_tol=1e-12):
            return (f"{bounds_reason(label, value, (low, top))} (it may not exceed "
                    f"{higher})")
    try:
        state.from_physical(**{key: value})
    except ValueError as exc:
        return str(exc)
    return None


def differs(values: Mapping[str, Any], scene: Mapping[str, Any]) -> bool:
    """Whether solve values differ from a scene's: numbers beyond 1e-11 relative (an SI
    address holds 12 digits), anything else at all; the method and accuracy are not the
    scene's, nor is the horizon (:data:`SCENE_KEEPERS`).

    >>> from app.state import scene_values
    >>> v = scene_values("7c")
    >>> differs({**v, "belt_speed": v["belt_speed"] * (1 + 1e-13)}, v)
    False
    >>> differs({**v, "restitution": 1.0}, v), differs({**v, "stop_type": "none"}, v)
    (True, True)
    """
    for name in SOLVE_PARAMS:
        if name in SCENE_KEEPERS:
            continue
        a, b = values[name], scene[name]
        if isinstance(a, float) and isinstance(b, float | int) and not isinstance(b, bool):
            if not math.isclose(a, b, rel_tol=1e-11):
                return True
        elif a != b:
            return True
    return False
