"""What a lesson needs of the page: a permalink query in, the page's refusals out.

A lesson drives the page only through its permalinks (:class:`PageDriver`): a step's state
is a query the page reads as it reads its own address, refusing what it cannot take with
its own messages. :func:`step_query` makes a step's query whole, so that a step's state
does not depend on what the student did before it.

Examples
--------
>>> from app.lessons.format import Step
>>> query = step_query(Step("t", "scene=7c&r=0.5", "text", plots=("energy",)))
>>> query.startswith("scene=7c&r=0.5&"), "xbar=0.24" in query, "all=true" in query
(True, True, True)
"""

from __future__ import annotations

import json
import urllib.parse
from collections.abc import Sequence
from typing import Protocol

from app.lessons.format import Step
from app.scenes import SCENES
from app.state import (
    SOLVER_CHOICES,
    URL_KEYS,
    URL_SI_PARAMS,
    VIEW_PARAMS,
    ExplorerState,
    scene_values,
)

#: The address's keys of a lesson: its name and the step shown (1-based).
LESSON_KEY, STEP_KEY = "lesson", "step"
LESSON_KEYS = (LESSON_KEY, STEP_KEY)
#: State values a scene does not set (loading a scene keeps them): a step that does not give
#: them gets their defaults.
KEPT_BY_SCENES = (*SOLVER_CHOICES, *VIEW_PARAMS)


class PageDriver(Protocol):
    """The page as a lesson drives it."""

    def apply_query(self, query: str) -> Sequence[str]:
        """Load the state of permalink ``query`` (``scene=7c&r=0.3``, as the page reads its
        address) and return the page's messages for what it refused (empty: all taken)."""

    @property
    def query(self) -> str:
        """The page's state as a permalink query (what its address carries)."""


def _given(pairs: Sequence[tuple[str, str]]) -> set[str]:
    """The state values a query gives (under their key or their own name)."""
    names = {**{name: name for name in URL_KEYS}, **{k: n for n, k in URL_KEYS.items()}}
    return {names[key] for key, _ in pairs if key in names}


def step_query(step: Step) -> str:
    """The query that loads ``step``'s state whatever the page showed before: the step's
    own keys, then every other value of its scene (the page loads a scene only when its
    label differs, and a value changed without the label would stay), the defaults of the
    values a scene keeps (:data:`KEPT_BY_SCENES`), and ``all=true`` if the step is about a
    plot its scene does not show. In a step in SI units the values read in SI
    (:data:`~app.state.URL_SI_PARAMS`) are left to the scene."""
    pairs = urllib.parse.parse_qsl(step.state, keep_blank_values=True)
    given = _given(pairs)
    scene = SCENES.get(dict(pairs).get("scene", ""))
    si = dict(pairs).get(URL_KEYS["units"], dict(pairs).get("units")) == "SI"
    values = {name: ExplorerState.param[name].default for name in KEPT_BY_SCENES}
    if scene is not None:
        values.update((name, value) for name, value in scene_values(scene.key).items()
                      if name not in KEPT_BY_SCENES and not (si and name in URL_SI_PARAMS))
        values["show_all"] = any(p not in scene.plots for p in step.plots)
    extra = []
    for name, value in values.items():
        if name not in given:
            text = ExplorerState.param[name].serialize(value)
            extra.append((URL_KEYS[name], text if isinstance(text, str) else json.dumps(text)))
    return "&".join(filter(None, [step.state, urllib.parse.urlencode(extra)]))


def with_lesson(search: str, name: str | None, step: int = 1) -> str:
    """The address ``search`` showing step ``step`` of lesson ``name`` (``""``: the list of
    lessons, ``None``: no lesson); its other keys stay as they came.

    >>> with_lesson("?scene=5a&lesson=x&step=2", "paper", 3)
    '?scene=5a&lesson=paper&step=3'
    >>> with_lesson("?scene=5a&lesson=paper&step=3", "")
    '?scene=5a&lesson='
    >>> with_lesson("?scene=5a&lesson=paper&step=3", None)
    '?scene=5a'
    """
    pairs = [(k, v) for k, v in urllib.parse.parse_qsl(search.removeprefix("?"),
                                                        keep_blank_values=True)
             if k not in LESSON_KEYS]
    if name is not None:
        pairs += [(LESSON_KEY, name), (STEP_KEY, str(step))] if name else [(LESSON_KEY, "")]
    return "?" + urllib.parse.urlencode(pairs) if pairs else ""


def step_link(name: str, step: int) -> str:
    """The permalink of a step (relative to the page).

    >>> step_link("paper", 4)
    '?lesson=paper&step=4'
    """
    return "?" + urllib.parse.urlencode({LESSON_KEY: name, STEP_KEY: step})
