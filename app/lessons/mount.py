"""Where the lessons join the page: a button in the sidebar, and above the plots the lesson
player (:mod:`app.lessons.player`), built only when the address names a lesson
(``?lesson=NAME&step=K``, or ``?lesson=`` for the list). The button opens the page's own
address with ``lesson=`` added. A page opened without a lesson carries the button and its
script, nothing else.
"""

from __future__ import annotations

import json
import urllib.parse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import panel as pn

from app.lessons.driver import LESSON_KEY, LESSON_KEYS, STEP_KEY, PageDriver
from app.lessons.stepper import LessonPosition
from app.state import URL_KEYS

__all__ = ["LESSON_KEYS", "LESSONS_DIR", "ExplorerPage", "LessonsMount"]

#: The folder of the shipped lessons (this package's own).
LESSONS_DIR = Path(__file__).resolve().parent
#: The browser opens the list of lessons: the page's address with an empty ``lesson=``.
OPEN_LIST_JS = f"""
const url = new URL(window.location.href);
url.searchParams.set('{LESSON_KEY}', '');
url.searchParams.delete('{STEP_KEY}');
window.location.assign(url.toString());
"""
#: Width [px] of the sidebar's button.
BUTTON_WIDTH = 290


class ExplorerPage:
    """The explorer as a :class:`~app.lessons.driver.PageDriver`: its own reading of a
    permalink (:meth:`app.permalink.Permalink.apply_query`), and its state written as one
    in dimensionless numbers whatever the units shown (what a step's guess is read in)."""

    def __init__(self, permalink: Any) -> None:
        self.permalink = permalink

    def apply_query(self, query: str) -> Sequence[str]:
        return self.permalink.apply_query(query)

    @property
    def query(self) -> str:
        """The state's values under their permalink keys (the core's dimensionless
        numbers)."""
        state = self.permalink.state
        pairs = {}
        for name, key in URL_KEYS.items():
            value = state.param[name].serialize(getattr(state, name))
            pairs[key] = value if isinstance(value, str) else json.dumps(value)
        return urllib.parse.urlencode(pairs)


class LessonsMount:
    """The lessons' place in the explorer's page (``explorer.lessons``).

    Parameters
    ----------
    permalink : app.permalink.Permalink
        The page's address, through which the lessons drive it (:class:`ExplorerPage`).
    folder : Path
        Where the lessons are read from.

    The step shown is :attr:`position` (none while no lesson is open), stepped by
    :meth:`step`: the presentation strip's stepper (:mod:`app.lessons.stepper`).
    """

    def __init__(self, permalink: Any, folder: Path = LESSONS_DIR) -> None:
        self.driver: PageDriver = ExplorerPage(permalink)
        self.folder = folder
        #: What the page hides while a step asks its question (:meth:`hide_while_asking`).
        self.hidden: list[Any] = []
        # (No tooltip: a description is one model more on every page.)
        self.button = pn.widgets.Button(label="Lessons: the paper step by step",
                                        width=BUTTON_WIDTH, css_classes=["fie-open-lessons"])
        # The lessons open on the page's own address with ``lesson=`` added (the page keeps
        # its state in its address): the page that comes loads the mathematics' typesetter,
        # which a page without a lesson does not (app.perf.resources).
        self.button.js_on_click(code=OPEN_LIST_JS)
        self.location: Any = None
        #: The player (app.lessons.player.LessonPlayer), built when first needed.
        self.player: Any = None
        #: The step the player shows (it alone writes it).
        self.position = LessonPosition()
        self._state = permalink.state
        # While presenting the strip steps the lesson, and the player's box makes way.
        self._state.param.watch(self._presenting, "present")

    @property
    def panels(self) -> list[Any]:
        """What the page shows above its plots: the player, if a lesson is open (the
        address is read before the page is laid out; the button opens a new page)."""
        return [] if self.player is None else [self.player.layout]

    def _player(self) -> Any:
        if self.player is None:
            from app.lessons.player import LessonPlayer  # only a page that opens one
            self.player = LessonPlayer(self.driver, self.folder, self.location, self.hidden,
                                       self.position)
            self.player.present(bool(self._state.present))
        return self.player

    def _presenting(self, event: Any) -> None:
        if self.player is not None:
            self.player.present(bool(event.new))

    def step(self, delta: int) -> None:
        """Step the open lesson by ``delta`` steps (its player's stepping); no lesson open,
        nothing."""
        if self.player is not None:
            self.player.step(delta)

    def hide_while_asking(self, *panes: Any) -> None:
        """Hide ``panes`` while a step asks its question (the page's panes that would give
        the answer away: the plots, the scene's caption, the readout)."""
        self.hidden[:] = panes
        if self.player is not None:
            self.player.hide_while_asking()

    def open_address(self, location: Any) -> None:
        """Open the lesson step the address ``location`` names, if any (the page has read
        the rest of it)."""
        self.location = location
        if location is None:
            return
        pairs = urllib.parse.parse_qsl(location.search.removeprefix("?"),
                                       keep_blank_values=True)
        if any(key == LESSON_KEY for key, _ in pairs):
            # A state beside the step (a copied address) is what the student left on
            # screen: the page keeps it.
            state_keys = set(URL_KEYS) | set(URL_KEYS.values())
            keep_state = any(key in state_keys for key, _ in pairs)
            self._player().open_address(pairs, apply_state=not keep_state)
