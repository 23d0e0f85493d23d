"""The plots of the page: one pane per plot, built when first shown, drawn from the state's
``solution`` (and a drag's draft from its ``preview``).

The served page is lazy: only the scene's first plots (:data:`FIRST_PLOTS`) are built with
the page; each other plot waits as an empty pane of about its height until the browser
reports it in view (``static/lazy_plots.js`` writes their names into a hidden box).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from typing import Any

import panel as pn
import param
from bokeh.core.properties import validate
from bokeh.events import Tap

from app.animation import ANIM_SIZE, Animation
from app.compare import Compare
from app.deferred import later
from app.map_legend import map_legend_html
from app.perf.browser_values import say_refused
from app.plot_choice import applicable_plots, visible_plots
from app.plots import MAP_SIZE, PHASE_SIZE, PLOT_WIDTHS, SMALL_SIZE, TIME_SIZE, PlotSet
from app.presentation import Presentation
from app.scenes import PLOT_TITLES, PLOTS, SCENES
from app.solve.regime_map import regime_map
from app.solve.runner import SolveRunner
from app.solve.solution import Solution
from app.state import SOLVE_PARAMS, VIEW_PARAMS, ExplorerState
from app.widgets import set_changed

log = logging.getLogger(__name__)

#: The plots a lazy page builds with the page, where a scene shows them (the first row of
#: a wide window); the others are built when the browser reports them in view.
FIRST_PLOTS = frozenset({"phase", "time"})
#: Height [px] of each plot's pane while it waits to be built: about the plot's own, so
#: that the page does not jump when it is drawn and only the plots in view are reported.
PANE_HEIGHTS = {"phase": PHASE_SIZE[1] + 60, "time": 2 * TIME_SIZE[1], "anim": ANIM_SIZE[1] + 90,
                "force": SMALL_SIZE[1], "loop": SMALL_SIZE[1], "friction": SMALL_SIZE[1],
                "energy": SMALL_SIZE[1] + 60, "map": MAP_SIZE[1] + 100,
                "return": SMALL_SIZE[1] + 60}
#: Delay [ms] before a drag's draft is drawn (a release arriving meanwhile cancels it).
PREVIEW_DELAY_MS = 15
#: The house stylesheet (panes render in shadow DOMs: each that uses its classes links it).
STYLESHEET = "assets/explorer.css"


class PlotsHost(pn.viewable.Viewer):
    """The plots of one page, watching its state.

    Parameters
    ----------
    commit : callable(dict)
        Commits a user's values (a tap on the phase portrait or the regime map).
    lazy : bool
        Build only :data:`FIRST_PLOTS` with the page (see the module's docstring).
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, commit: Callable[[Mapping[str, Any]], None], lazy: bool = False,
                 **params: Any) -> None:
        super().__init__(**params)
        self.commit, self._lazy = commit, lazy
        self.plots = PlotSet()
        self.anim = Animation(self.plots.sources["traj"], self.plots.shared)
        #: Pinned runs drawn as ghosts (the page pins through them).
        self.compare = Compare(self.plots, self._pins_changed, self._pin_failed)
        self.plots.more_legend = lambda: self.compare.legend_entries(self.state.values())
        self.plots.more_extents = self.compare.extents
        self.presentation = Presentation(self.state, self)
        #: Where a failed pin's solve is said (set by the page).
        self.on_pin_failed: Callable[[Exception], None] = lambda exc: None
        #: The waiting plots the browser has reported in view (built since).
        self._in_view: set[str] = set()
        #: Where the browser writes the names of waiting plots in view (a hidden box).
        self.in_view = pn.widgets.TextInput(value="", visible=False, margin=0,
                                            css_classes=["fie-in-view"])
        self.in_view.param.watch(self._reported_in_view, "value")
        self.map_legend = pn.pane.HTML("", sizing_mode="stretch_width",
                                       css_classes=["fie-map-legend"], stylesheets=[STYLESHEET])
        self._map_labels: list[str] | None = None
        self._map_covered = False
        #: Tells the page that a full solution arrived (its text counts them): the browser
        #: holds the figures' repaints after a slider's release until then
        #: (static/perf/release_hold.js). One small hidden model of its own.
        self.arrived = pn.pane.HTML("0", visible=False, margin=0,
                                    css_classes=["fie-solution-arrived"])
        self.plot_panes = {name: pn.Column(
            css_classes=["fie-plot", f"fie-plot-{name}"], name=PLOT_TITLES[name],
            margin=(4, 8), visible=False, sizing_mode="stretch_width",
            min_width=PLOT_WIDTHS[0], max_width=PLOT_WIDTHS[1],
            styles={"flex": f"1 1 {PLOT_WIDTHS[0] + 160}px"}) for name in PLOTS}
        self.plot_box = pn.FlexBox(*self.plot_panes.values(), sizing_mode="stretch_width",
                                   css_classes=["fie-plots"])
        self._previews = SolveRunner(lambda exc: None, preview=True)
        #: The drag's draft asked last (None: none is due), and whether one is on screen.
        self._draft: object | None = None
        self._draft_shown = False
        #: Whether the mechanism missed the run on screen (hidden by a presentation).
        self._anim_stale = False
        self.show_plots()
        st = self.state
        st.param.watch(self._state_changed, ["scene", "preview", "stale", *SOLVE_PARAMS,
                                             *VIEW_PARAMS])
        st.param.watch(self._presented, ["present", "slides"])
        # First of the solution's watchers (the readout and the others follow, in the same
        # message): the figures are what the page waits for.
        st.param.watch(self._draw, "solution")

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Column(self.arrived, self.in_view, self.plot_box,
                         sizing_mode="stretch_width", margin=0)

    # --- which plots -----------------------------------------------------------------------

    def applicable_plots(self) -> tuple[str, ...]:
        """The plots that can show the current state (:func:`app.plot_choice.applicable_plots`)."""
        return applicable_plots(self.state)

    def visible_plots(self) -> tuple[str, ...]:
        """The plots the current scene needs (:func:`app.plot_choice.visible_plots`)."""
        return visible_plots(self.state)

    def drawn_now(self) -> tuple[str, ...]:
        """The plots a new run is drawn in: those of :meth:`drawn` that a presentation's
        layout shows (the others are filled when it shows them, :meth:`_presented`)."""
        return self.drawn(self.presentation.shown(self.visible_plots()))

    def drawn(self, visible: tuple[str, ...]) -> tuple[str, ...]:
        """The plots of ``visible`` that are built and drawn: all of them, or on a lazy
        page those built already, the first ones and those the browser saw."""
        if not self._lazy:
            return visible
        return tuple(p for p in visible if p in FIRST_PLOTS or p in self._in_view
                     or self.plot_panes[p].objects)

    # --- building --------------------------------------------------------------------------

    def _reported_in_view(self, event: param.parameterized.Event) -> None:
        """The browser reports waiting plots in view: build and draw them."""
        self.build_in_view({n for n in str(event.new).split(",") if n in PLOTS})
        self.in_view.value = ""  # so that a later report of the same names is a change

    def build_in_view(self, names: set[str]) -> None:
        """Build and draw the waiting plots ``names`` (as if the browser saw them)."""
        names = set(names) - self._in_view
        if names:
            self._in_view |= names
            self._draw_new_plots()

    def _draw_new_plots(self) -> None:
        """Build the plots now due and fill them from the solution on screen; the plots
        drawn already are not sent again."""
        visible = self.visible_plots()
        new = [p for p in self.drawn(visible) if not self.plot_panes[p].objects]
        sol = self.state.solution
        if not new:
            return
        with pn.io.hold():
            self.show_plots()
            if sol is None:
                return
            with validate(False):
                self._draw_pins(sol)
            self._fill(sol, self.drawn(visible), "map" in new, "anim" in new)

    def _fill(self, sol: Solution, drawn: tuple[str, ...], map_due: bool,
              anim: bool) -> None:
        """Fill the plots ``drawn`` that missed the run on screen ``sol``: the regime map
        too with ``map_due`` (at once from its cache, or computed later), the animation
        with ``anim``."""
        map_data = (regime_map(sol.values, compute=False, frame=self.map_frame(sol))
                    if map_due else None)
        with validate(False):
            self.plots.refresh(drawn, map_data)
            if anim:
                self.anim.update(sol, self.state.scales())
                self._anim_stale = False
            if map_data is not None:
                self.show_map_legend(map_data["labels"])
        if map_due and map_data is None:
            later(lambda: self.draw_map(sol), 0)

    def _build_plot(self, name: str) -> pn.viewable.Viewable:
        """The body of the pane of plot ``name``, its figures built now (with their links
        to the animation and their tap handlers)."""
        if name == "anim":
            return self.anim.panel()
        layout = self.plots.build(name)
        figs = self.plots.figures
        if name == "phase":
            self.anim.attach_phase(figs["phase"])
            figs["phase"].on_event(Tap, self.phase_tapped)
            self.plots.shared.lighten(figs["phase"])  # the animation's marker too
        elif name == "time":
            self.anim.attach_time((figs["time_x"], figs["time_v"]))
        elif name == "map":
            figs["map"].on_event(Tap, self.map_tapped)
            return pn.Column(pn.pane.Bokeh(layout, sizing_mode="stretch_width"),
                             self.map_legend, margin=0, sizing_mode="stretch_width")
        return self.plots.view(name)

    def show_plots(self) -> None:
        """Show the panes of the visible plots (building those shown for the first time),
        hide the others; a new figure is filled by the next draw."""
        visible = self.visible_plots()
        shown = self.presentation.shown(visible)
        drawn = self.drawn(visible)
        for name, pane in self.plot_panes.items():
            if name in drawn and not pane.objects:
                pane.objects = [self._build_plot(name)]
            waiting = name in shown and not pane.objects
            # (An empty pane of the plot's height: a style that marked it stayed, in
            # BokehJS, on some of the plot's edge pixels once the plot was drawn.)
            set_changed(pane, visible=name in shown,
                        min_height=PANE_HEIGHTS[name] if waiting else None,
                        css_classes=["fie-plot", f"fie-plot-{name}",
                                     *(["fie-plot-pending"] if waiting else [])])
        self.compare.attach_all()
        self.presentation.restyle()

    def above_plots(self, pane: Any) -> None:
        """Put ``pane`` on the page above the plots (a full row of their box), once:
        panes used only on demand are added when first used."""
        if not any(obj is pane for obj in self.plot_box.objects):
            self.plot_box.objects = [pane, *self.plot_box.objects]

    # --- drawing ---------------------------------------------------------------------------

    def _draw(self, event: param.parameterized.Event) -> None:
        """Draw the full run on screen (the state's new ``solution``) in the visible plots
        (under the ``pn.io.hold`` of whoever set it)."""
        sol = event.new
        if sol is None:
            return
        self._draft, self._draft_shown = None, False
        scales = self.state.scales()
        # Figures shown for the first time are built with Bokeh's checks on (they also
        # turn values such as a title's text into models).
        with validate(True):
            self.show_plots()
        # The plots drawn are those built by now: showing them may have built more (a
        # presentation's layout builds its plots at once, and filled them from the run
        # before this one). The others wait, empty, until in view, or stale until a
        # presentation shows them.
        drawn = self.drawn_now()
        map_data = (regime_map(sol.values, compute=False, frame=self.map_frame(sol))
                    if "map" in drawn else None)
        self._draw_pins(sol)  # first: the axes fitted next show the ghosts too
        self.plots.update(sol, scales, drawn, map_data)
        self._anim_stale = "anim" not in drawn
        if not self._anim_stale:
            self.anim.update(sol, scales)
        if map_data is not None:
            self.show_map_legend(map_data["labels"])
        self.arrived.object = str(int(self.arrived.object) + 1)
        if "map" in drawn and map_data is None:
            # A new map (friction, stop or start changed): the rest of the picture is sent
            # first, the map (its computation and its 64 kB image) follows.
            later(lambda: self.draw_map(sol), 0)

    def _presented(self, *events: param.parameterized.Event) -> None:
        """A presentation's layout entered, changed or left: its panes, and the plots it
        shows filled from the run on screen where they missed it while hidden."""
        self.show_plots()
        sol = self.state.solution
        if sol is None:
            return
        drawn = self.drawn_now()
        stale = self.plots.stale.intersection(drawn)
        anim = "anim" in drawn and self._anim_stale
        if not stale and not anim:
            return
        with pn.io.hold():
            self._fill(sol, drawn, "map" in stale, anim)

    def _draw_pins(self, sol: Solution) -> None:
        if self.compare.pins:
            self.compare.draw(sol, self.state.scales())

    def _state_changed(self, *events: param.parameterized.Event) -> None:
        """A new value or a drag: a draft due is stale; a view's value (or a new scene's
        name) shows the run on screen again, a drag draws its draft, and a drag that ended
        without a new value the run again."""
        names = {e.name for e in events}
        self._draft = None
        if "scene" in names and self.state.scene in SCENES:
            self.plots.forget_transition_kinds()
        if names & set(SOLVE_PARAMS) or self.state.solution is None:
            return  # a new run follows
        ended = "preview" in names and self.state.preview is None and self._draft_shown
        if names & {"scene", *VIEW_PARAMS} or ended:
            self.redraw()
        elif "preview" in names and self.state.preview is not None:
            self._ask_draft(self.state.preview)

    def redraw(self) -> None:
        """Show the run on screen again, in every view (its ``solution`` event)."""
        with pn.io.hold(), validate(False):
            self.state.param.trigger("solution")

    def _ask_draft(self, values: Mapping[str, Any]) -> None:
        """A draft solve of the trajectory only, drawn unless a newer value came first."""
        draft = self._draft = object()

        def solved(sol: Solution) -> None:
            # Drawn a moment later: a release that arrives meanwhile (the drag's last value
            # and the release come together) replaces it, and its full solution is not held
            # up by sending and painting a draft that is already stale.
            if sol.result is not None:
                later(lambda: self._draw_draft(sol, draft), PREVIEW_DELAY_MS)

        self._previews.request(dict(values), solved)

    def _draw_draft(self, sol: Solution, draft: object) -> None:
        if draft is not self._draft:
            return
        self._draft_shown = True
        with pn.io.hold(), validate(False):
            self.plots.update_preview(sol, self.state.scales())

    def _pins_changed(self) -> None:
        """A pin came, went or was solved: its ghosts, the axes, the legend; the page's
        other views follow the state's ``pinned`` event."""
        sol = self.state.solution
        with pn.io.hold(), validate(False):
            if sol is not None:
                self.compare.draw(sol, self.state.scales())
                self.plots.fit_ranges()
                self.plots.refresh_legend()
            self.state.param.trigger("pinned")

    def _pin_failed(self, exc: Exception) -> None:
        self.on_pin_failed(exc)

    # --- the regime map --------------------------------------------------------------------

    def map_frame(self, sol: Solution) -> tuple[float, float, float]:
        """The regime map's axes, stable for a scene (:meth:`PlotSet.map_frame`)."""
        return self.plots.map_frame({**sol.values, "scene": self.state.scene,
                                     "units": self.state.units})

    def draw_map(self, sol: Solution) -> None:
        """Compute the regime map of ``sol`` and draw it, unless a newer solution came."""
        if sol is not self.state.solution:
            return
        try:
            data = regime_map(sol.values, frame=self.map_frame(sol))
        except Exception:  # noqa: BLE001 - a map that fails leaves the old one
            log.exception("regime map failed")
            return
        if "map" not in self.drawn(self.visible_plots()):
            return
        with pn.io.hold(), validate(False):
            self.plots.show_map(data)
            self.show_map_legend(data["labels"])

    def show_map_legend(self, labels: list[str] | None = None,
                        covered: bool | None = None) -> None:
        """The regime map's legend for ``labels`` (the last ones if ``None``), saying so
        when the simulated layer of the sweep card covers the theory's colours
        (``covered``; the last word if ``None``)."""
        if labels is not None:
            self._map_labels = labels
        if covered is not None:
            self._map_covered = covered
        if self._map_labels is not None:
            self.map_legend.object = map_legend_html(self._map_labels, self._map_covered)

    def map_figure(self) -> Any:
        """The regime map's figure, shown (with 'show all plots') if the scene hides it,
        or None where no map applies."""
        if "map" not in self.applicable_plots():
            return None
        if "map" not in self.visible_plots():
            self.commit({"show_all": True})
        if "map" not in self.plots.figures:  # a lazy page's map not yet in view
            self.build_in_view({"map"})
        return self.plots.figures.get("map")

    # --- taps and busy ---------------------------------------------------------------------

    def phase_tapped(self, event: Tap) -> None:
        """A tap on the phase portrait: the start there."""
        scales = self.state.scales()
        self._commit_tap(event, lambda x, y: {
            "x0": round(x / scales.length, 4), "v0": round(y / scales.velocity, 4)})

    def map_tapped(self, event: Tap) -> None:
        """A tap on the regime map: the belt speed and clearance there."""
        scales = self.state.scales()
        self._commit_tap(event, lambda x, y: {
            "belt_speed": max(0.0, round(x / scales.velocity, 4)),
            "clearance": round(y / scales.length, 4)})

    def _commit_tap(self, event: Tap, values: Callable[[float, float], dict[str, float]]) -> None:
        """Commit the ``values`` of a tap at ``(x, y)``; a tap no user can make (a script's:
        not numbers, or values outside the state's bounds) is refused in one quiet line."""
        if event.x is None or event.y is None:
            return
        try:
            tapped = values(float(event.x), float(event.y))
        except (TypeError, ValueError, OverflowError):
            tapped = {}
        bounds = {name: self.state.param[name].bounds for name in tapped}
        if not tapped or not all(low <= tapped[n] <= high for n, (low, high) in bounds.items()):
            say_refused(f"refused from the browser: tap at ({event.x!r:.30}, {event.y!r:.30})")
            return
        self.commit(tapped)

    def show_busy(self, busy: bool) -> None:
        """Mark the plots a running solve will replace (Panel's per-pane ``loading``)."""
        visible = self.visible_plots() if busy else ()
        with pn.io.hold():
            for name, pane in self.plot_panes.items():
                set_changed(pane, loading=name in visible)

    def close(self) -> None:
        self._previews.cancel()

