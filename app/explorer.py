"""The explorer's page for one session: its components, each watching one
:class:`~app.state.ExplorerState`, laid out.

Data flow: a slider's release (or a typed value, a tap, a choice) is committed by the
controls (:mod:`app.controls`) into the state in one batch; the solving
(:mod:`app.solving`) watches the solve values and sets the state's ``solution`` when the
solver answers, under one ``pn.io.hold``; the views watch it: the plots
(:mod:`app.plots_host`), the readout (:mod:`app.readout`), the notices, the studies. A drag
sets the state's ``preview`` (a draft of the trajectory is drawn); the address follows the
state (:mod:`app.permalink`). No component calls another's private method; what is stale
is a parameter event of the state (``stale``, ``preview``, ``solution``).
"""

from __future__ import annotations

from typing import Any

import panel as pn
import param

from app.compare_menu import CompareMenu
from app.control_specs import SHOWN_LATER, SLIDERS, WIDGET_WIDTH  # noqa: F401 - the page's
from app.controls import Controls
from app.export import Downloads
from app.lessons.mount import LessonsMount
from app.notices import Notices
from app.page_style import MAIN_COLUMN_CSS
from app.permalink import URL_DELAY_MS, Permalink  # noqa: F401 - the page's timing
from app.plots_host import FIRST_PLOTS, PlotsHost  # noqa: F401 - the page's lazy plots
from app.readout import READOUT_SPARE_LINES, Readout  # noqa: F401 - the readout's room
from app.solving import Solving
from app.state import ExplorerState
from app.studies import Studies
from app.teach.view import Teach


class Explorer(pn.viewable.Viewer):
    """The whole page for one session.

    Parameters
    ----------
    state : ExplorerState, optional
        Start from this state instead of the default scene.
    lazy_plots : bool
        Build only the scene's first plots with the page; each other plot waits as an empty
        pane until the browser reports it in view (static/lazy_plots.js). The served page
        is lazy; without a browser (tests, exports) every plot of the scene is built at once.
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, state: ExplorerState | None = None, lazy_plots: bool = False,
                 **params: Any) -> None:
        super().__init__(state=state or ExplorerState(), **params)
        st = self.state
        self.notices = Notices(state=st)
        self.solving = Solving(self.notices, state=st)
        self.host = PlotsHost(lambda values: self.controls.commit(values), lazy_plots,
                              state=st)
        self.host.on_pin_failed = self.solving.failed
        self.controls = Controls(self.notices, state=st)
        self.readout_view = Readout(self.host.compare, state=st)
        self.menu = CompareMenu(self.host.compare, self.host.presentation, self.notices,
                                state=st)
        self.permalink = Permalink(self.notices, self.menu, state=st)
        self.studies = Studies(self.host, self.controls.commit, self.notices, state=st)
        self.downloads = Downloads(st, WIDGET_WIDTH)
        # The scene's story and the model card, built when first opened.
        self.teach = Teach(st)
        self.solving.param.watch(lambda event: self.host.show_busy(event.new), "busy")
        self.lessons = LessonsMount(self.permalink)
        self.host.presentation.lesson = self.lessons  # the strip steps the open lesson
        self.solving.solve()

    # --- layout ----------------------------------------------------------------------------

    def sidebar(self) -> list[Any]:
        """The controls, top to bottom."""
        return [self.menu.present, *self.controls.sidebar(), self.studies.measure,
                self.studies.open_sweeps, self.controls.show_all, self.downloads.trajectory,
                self.downloads.transitions, self.menu.button, self.lessons.button]

    def main(self) -> list[Any]:
        """The notices, the lesson (if one is open), the caption, the readout and the
        plots."""
        host, readout = self.host, self.readout_view
        # A step that asks a question hides what would give its answer away.
        self.lessons.hide_while_asking(readout.caption, readout.readout, host.plot_box)
        # While presenting the strip names the scene: no caption, no story buttons.
        host.presentation.hide_while_presenting(readout.caption, *self.teach.buttons)
        return [self.notices, *self.lessons.panels, readout.caption, *self.teach.buttons,
                readout.readout, host.arrived, host.in_view, host.plot_box]

    def main_panel(self) -> pn.Column:
        """The main area (:meth:`main`) in one column; the story and the model card open
        in it below their buttons."""
        column = pn.Column(*self.main(), sizing_mode="stretch_width", margin=0,
                           stylesheets=[MAIN_COLUMN_CSS])
        self.teach.attach(column)
        return column

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Row(pn.Column(*self.sidebar(), width=WIDGET_WIDTH + 30), self.main_panel())

    # --- the page's address and life -------------------------------------------------------

    def sync_url(self, location: Any = None) -> None:
        """Load the page from its address, open the lesson step it names, and keep the
        address in step (:meth:`app.permalink.Permalink.sync_url`)."""
        self.permalink.sync_url(location, then=self.lessons.open_address)

    @property
    def location(self) -> Any:
        """The page's address (:meth:`sync_url`), or None."""
        return self.permalink.location

    def close(self) -> None:
        """The page closed: stop its measurement, sweeps and solves, freeing their solver
        processes (called by the server when it discards the session)."""
        self.studies.close()
        self.solving.cancel()
        self.host.close()

    # --- the parts tests and benchmarks read -----------------------------------------------

    @property
    def solution(self) -> Any:
        """The full run on screen (the state's ``solution``)."""
        return self.state.solution

    @property
    def error(self) -> str | None:
        """The last message of the alert."""
        return self.notices.error

    def __getattr__(self, name: str) -> Any:
        # The components' public parts by their names on the page: ``ex.sliders``,
        # ``ex.plots``, ``ex.alert``, ``ex.measure``, ...
        if not name.startswith("_"):
            for part in PARTS.get(name, ()):
                component = self.__dict__.get(part)
                if component is not None and hasattr(component, name):
                    return getattr(component, name)
        raise AttributeError(name)


#: Where each public part of the page lives: its name -> the component holding it.
PARTS: dict[str, tuple[str, ...]] = {
    **{name: ("controls",) for name in (
        "sliders", "scene_select", "stop_type", "units", "accuracy", "method", "program",
        "show_all", "contact_law", "hysteretic_box", "si_box", "si_start", "commit",
        "commit_si", "reset")},
    **{name: ("host",) for name in (
        "plots", "anim", "plot_panes", "plot_box", "map_legend", "arrived", "in_view",
        "compare", "presentation", "visible_plots", "applicable_plots", "redraw",
        "draw_map", "map_tapped", "phase_tapped")},
    **{name: ("notices",) for name in ("alert", "retry")},
    **{name: ("readout_view",) for name in ("caption", "readout")},
    **{name: ("studies",) for name in ("measure", "open_sweeps", "trade", "sweeps",
                                       "measure_trade", "sweep", "trade_runner")},
    **{name: ("permalink",) for name in ("apply_query", "query", "write_url")},
}
