"""Which plots a state shows: those that apply to its stop, of those its scene needs (or all
of them, with 'show all plots')."""

from __future__ import annotations

from typing import Any

from app.scenes import HYSTERETIC_PLOTS, IMPACTLESS_PLOTS, PLOT_TITLES, PLOTS, RIGID_PLOTS, SCENES


def applicable_plots(state: Any) -> tuple[str, ...]:
    """The plots that can show ``state`` (no contact force without a stop).

    >>> from app.state import ExplorerState
    >>> applicable_plots(ExplorerState(stop_type="none"))
    ('phase', 'time', 'anim', 'friction', 'energy', 'map', 'return')
    """
    if state.program and state.stop_type == "hysteretic":
        return ("loop", "force")
    left_out = {"none": {"force", "loop"}, "rigid": {"loop"}}.get(state.stop_type, set())
    return tuple(p for p in PLOTS if p not in left_out)


def visible_plots(state: Any) -> tuple[str, ...]:
    """The plots ``state``'s scene needs (or all that apply, with 'show all plots')."""
    applicable = applicable_plots(state)
    if state.program and state.stop_type == "hysteretic":
        return applicable
    by_stop = {"none": IMPACTLESS_PLOTS, "rigid": RIGID_PLOTS,
               "hysteretic": HYSTERETIC_PLOTS}[state.stop_type]
    scene = SCENES.get(state.scene)
    wanted = PLOTS if state.show_all else (scene.plots if scene is not None else by_stop)
    return tuple(p for p in applicable if p in wanted)


def show_all_label(visible: tuple[str, ...], applicable: tuple[str, ...]) -> str:
    """The label of the 'show all plots' box, naming the plots it would add.

    >>> show_all_label(("phase", "time"), ("phase", "time", "friction", "energy"))
    'show all plots (+ friction law, energy)'
    """
    hidden = [PLOT_TITLES[p].lower() for p in applicable if p not in visible]
    return "show all plots" + (f" (+ {', '.join(hidden)})" if hidden else "")
