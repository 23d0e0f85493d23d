"""The explorer view: widgets, plots, readout and their wiring, one instance per session.

Data flow: a slider's ``value`` (while dragging) runs a cheap preview solve that redraws
the trajectory only; its ``value_throttled`` (on release, or a typed entry) commits the value
to :class:`~app.state.ExplorerState`, whose watcher runs the full solve and updates every
visible plot, the animation and the readout under one ``pn.io.hold`` (one message). Any
failure of a solve shows its message in an alert and keeps the last good picture.
"""

from __future__ import annotations

import html
import json
import logging
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import panel as pn
import param
from bokeh.core.properties import validate
from bokeh.events import Tap
from panel.io.location import Location
from panel.io.state import set_curdoc

from app import links, presentation
from app.animation import ANIM_SIZE, Animation
from app.compare import URL_KEY as PINS_KEY
from app.compare import Compare, CompareMenu
from app.export import file_name, trajectory_csv, transitions_csv
from app.perf.browser_values import say_refused
from app.plots import MAP_PALETTE, MAP_SIZE, PHASE_SIZE, PLOT_WIDTHS, SMALL_SIZE, TIME_SIZE, PlotSet
from app.readout import readout_html
from app.scenes import (
    CUSTOM,
    DEFAULT_SCENE,
    HYSTERETIC_PLOTS,
    IMPACTLESS_PLOTS,
    PLOT_TITLES,
    PLOTS,
    RIGID_PLOTS,
    SCENES,
)
from app.solve_process import Abandoned
from app.solver import (
    ACCURACY,
    MAX_SOLVE_BUDGET_S,
    Solution,
    SolveRunner,
    SolveTooSlow,
    cut_short,
    regime_map,
    retry_budget,
)
from app.state import (
    ACCURACIES,
    CONTACT_LAWS,
    METHODS,
    SI_NAMES,
    SOLVE_PARAMS,
    SOLVER_CHOICES,
    STOP_TYPES,
    UNITS,
    URL_KEYS,
    URL_SI_PARAMS,
    VIEW_PARAMS,
    ExplorerState,
    core_inputs,
    scene_values,
    si_bound_error,
    si_range,
    si_units,
)
from app.teach.glossary import tooltip as glossary_tooltip  # teach
from app.teach.view import Teach  # teach
from app.trade import MEASURE_BUDGET_S, MeasureRefused, TradeRunner, trade_html
from app.widgets import (
    Checkbox,
    RadioButtonGroup,
    Select,
    ShownLater,
    TypedSlider,
    bounds_reason,
    format_number,
    set_changed,
)
from core import Status

log = logging.getLogger(__name__)

#: Slider label and step of each numeric state parameter.
SLIDERS: Mapping[str, tuple[str, float]] = {
    "belt_speed": ("belt speed v", 0.001),
    "clearance": ("clearance x_bar", 0.001),
    "restitution": ("restitution r", 0.01),
    "mu_s": ("static friction mu_s", 0.005),
    "mu_k": ("kinetic friction mu_k", 0.005),
    "u_s": ("static deflection u_s = F_N/k", 0.01),
    "k_c0": ("compression stiffness k_c0/k", 1.0),
    "k_e0": ("expansion stiffness k_e0/k", 1.0),
    "limit_overlap": ("limit overlap D", 0.0005),
    "beta_c": ("beta_c (towards compression)", 0.5),
    "beta_e": ("beta_e (towards expansion)", 0.5),
    "x0": ("initial displacement x0", 0.005),
    "v0": ("initial velocity x'0", 0.005),
    "t_end": ("horizon t_end", 1.0),
    "mass": ("mass m (kg)", 0.01),
    "stiffness": ("stiffness k (N/m)", 1.0),
}
#: What each symbol means (the box's tooltip; the allowed range is added to it).
TOOLTIPS: Mapping[str, str] = {
    "belt_speed": "Belt speed v = v_dr / omega (a length in these units).",
    "clearance": "Stop position x_bar, measured from the unstretched spring.",
    "restitution": "Newton's coefficient r: rebound speed over impact speed.",
    "mu_s": "Static friction coefficient; b = mu_s u_s is the stick limit.",
    "mu_k": "Kinetic friction coefficient (at most mu_s); a = mu_k u_s is the slip centre.",
    "u_s": "Static deflection u_s = F_N / k: the spring stretch the normal force makes.",
    "k_c0": "Slope of the compression envelope at zero overlap, over k (Eq. 11).",
    "k_e0": "Slope of the expansion envelope at zero overlap, over k (at most k_c0; "
            "Eq. 11).",
    "limit_overlap": "Limit overlap D: both envelopes grow without bound as the overlap "
                     "nears D, so the stop cannot be pushed past it (Eq. 11).",
    "beta_c": "How fast a reloading curve approaches the compression envelope, per D "
              "(at most beta_e; Eq. 13).",
    "beta_e": "How fast an unloading curve approaches the expansion envelope, per D (Eq. 13).",
    "x0": "Initial displacement of the mass.",
    "v0": "Initial velocity of the mass.",
    "t_end": "Length of the simulated run (dimensionless time t = omega tau).",
    "mass": "Mass m of the oscillator.",
    "stiffness": "Stiffness k of the spring.",
    "normal_force": "Normal force F_N pressing the mass on the belt.",
    "belt_speed_si": "Belt speed v_dr.",
    "v0_si": "Initial velocity of the mass.",
    "t_end_si": "Length of the simulated run in seconds.",
    "k_c0_si": "Slope of the compression envelope at zero overlap (Eq. 11).",
    "k_e0_si": "Slope of the expansion envelope at zero overlap (at most k_c0; Eq. 11).",
}
# teach: each symbol's tooltip links to the glossary (app.teach.glossary)
TOOLTIPS = {name: glossary_tooltip(name, text) for name, text in TOOLTIPS.items()}
#: What each reading of the contact law means (the selector's tooltip; docs/contact-law.md).
CONTACT_LAW_TIPS: Mapping[str, str] = {
    "paper": "the paper's reading of Eqs. 12-13, which reproduces Fig. 2b; each reversal "
             "restarts the exponential from the reversal point. Not passive: some closed "
             "overlap programs give back more energy than they took",
    "passive": "the same envelopes and exponential, but loading inside the band retraces "
               "the unloading curve (elastic inside the band, loss on the envelope): no "
               "closed overlap program returns energy",
}
#: What each method models (the method selector's tooltip).
METHOD_TIPS: Mapping[str, str] = {
    "auto": "exact where it applies",
    "exact": "closed-form slip arcs and stick segments, Newton impacts; a deformable stop's "
             "contact integrated",
    "event": "solve_ivp on the non-smooth model, stopping at each stick, slip and contact "
             "event",
    "switch": "the paper's switch model: a stick band of width eta, integrated by RKF 4(5)",
}
#: SI widgets derived from the state through ExplorerState.physical / from_physical:
#: name -> (label, step, key of ExplorerState.physical()).
SI_SLIDERS: Mapping[str, tuple[str, float, str]] = {
    "normal_force": ("normal force F_N (N)", 0.1, "normal_force"),
    "belt_speed_si": ("belt speed v_dr (m/s)", 0.001, "belt_speed"),
    "v0_si": ("initial velocity x'0 (m/s)", 0.001, "v0"),
    "t_end_si": ("horizon t_end (s)", 0.01, "t_end"),
    "k_c0_si": ("compression stiffness k_c0 (N/m)", 1.0, "k_c0"),
    "k_e0_si": ("expansion stiffness k_e0 (N/m)", 1.0, "k_e0"),
}
#: The state value each SI value converts to (its bounds, in SI, are the SI box's).
SI_STATE_NAME: Mapping[str, str] = {si: name for name, (si, _) in SI_NAMES.items()}
#: SI sliders that stand for a dimensionless one in SI mode, and the factor that converts
#: its slider range, a power of an SI value: x'0 [m/s] = omega x'0, t_end [s] =
#: t_end / omega, k_c0 [N/m] = k (k_c0 / k).
SI_TWINS: Mapping[str, tuple[str, str, int]] = {
    "v0_si": ("v0", "omega", 1), "t_end_si": ("t_end", "omega", -1),
    "k_c0_si": ("k_c0", "k", 1), "k_e0_si": ("k_e0", "k", 1),
}
#: Sliders of a length: their label gains "(m)" in SI mode.
LENGTH_SLIDERS = ("clearance", "limit_overlap", "x0")
#: Sliders in groups that join the page when first shown (:class:`~app.widgets.ShownLater`):
#: the deformable stop's, the SI set's and the SI twins of the start and horizon. A new
#: page makes their widgets only then.
HYSTERETIC_SLIDERS = ("k_c0", "k_c0_si", "k_e0", "k_e0_si", "limit_overlap", "beta_c", "beta_e")
SI_BOX_SLIDERS = ("mass", "stiffness", "normal_force", "belt_speed_si")
SI_START_SLIDERS = ("v0_si", "t_end_si")
SHOWN_LATER = frozenset(HYSTERETIC_SLIDERS + SI_BOX_SLIDERS + SI_START_SLIDERS)
#: Constraints kept by the widgets: the first may not exceed the second.
CONSTRAINTS = (("mu_k", "mu_s"), ("k_e0", "k_c0"), ("beta_c", "beta_e"))
#: Smallest mu_s the slider allows (a zero-width mu_k slider cannot be drawn).
MU_S_MIN = 0.005
#: Width of the sidebar widgets [px].
WIDGET_WIDTH = 290
#: The label of the button that measures the speed/accuracy trade (app.trade).
MEASURE_LABEL = "Measure the trade (a few seconds)"
#: The house stylesheet (served by ``--static-dirs assets=static``); panes render in shadow
#: DOMs, so each pane that uses the house classes links it itself.
STYLESHEET = "assets/explorer.css"
#: Soft range of the SI sliders, as multiples of their current value.
SI_SOFT_SPAN = 3.0
#: Delay [ms] of the URL rewrite after the last change of the state.
URL_DELAY_MS = 400
#: Delay [ms] before a drag's preview is drawn (a release arriving meanwhile cancels it).
PREVIEW_DELAY_MS = 15
#: Height [px] of one line of the readout (``explorer.css``) and the room kept below it.
READOUT_ROW_PX, READOUT_PAD_PX = 20, 8
#: Lines the readout reserves beyond its rows (one long row that wraps at the page's width).
READOUT_SPARE_LINES = 1


#: Query keys the page reads besides the state's (:data:`URL_KEYS`, by key or by name): the
#: pinned runs, the presentation mode and slide format, and the switch of the browser-side
#: paint shortcuts (static/perf/).
OTHER_URL_KEYS = frozenset({PINS_KEY, presentation.URL_KEY, presentation.SLIDES_KEY,
                            "paint_shortcuts"})


class Explorer(pn.viewable.Viewer):
    """The whole page for one session.

    Parameters
    ----------
    state : ExplorerState, optional
        Start from this state instead of the default scene.
    lazy_plots : bool
        Build only the scene's first plots (:data:`FIRST_PLOTS`) with the page; each other
        plot waits as an empty pane until the browser reports it in view
        (static/lazy_plots.js). The served page is lazy; without a browser (tests, exports)
        every plot of the scene is built at once.
    """

    def __init__(self, state: ExplorerState | None = None, lazy_plots: bool = False,
                 **params: Any) -> None:
        super().__init__(**params)
        self.state = state or ExplorerState()
        self._lazy = lazy_plots
        #: The waiting plots the browser has reported in view (built since).
        self._in_view: set[str] = set()
        #: Where the browser writes the names of waiting plots in view (a hidden box).
        self.in_view = pn.widgets.TextInput(value="", visible=False, margin=0,
                                            css_classes=["fie-in-view"])
        self.in_view.param.watch(self._on_in_view, "value")
        self.solution: Solution | None = None
        self.error: str | None = None
        self._syncing = False
        self._url_timer: _Deferred | None = None
        #: The page's address (:meth:`sync_url`), or None.
        self.location: Location | None = None
        #: The alert of the address's refused values and the values the page opened with:
        #: it stays while the solution drawn is of those values.
        self._link_alert: tuple[str, dict[str, Any]] | None = None
        #: Counts the commits: a preview solved before the latest commit is not drawn.
        self._commits = 0
        #: Full solves and drag previews, in the worker pool (the latest request wins).
        self._solves = SolveRunner(self._solve_failed, self._show_busy)
        #: The budget [s] that the solve on screen overran (None: it did not).
        self._ran_out: float | None = None
        #: "Retry with more time": built, and put below the alert, the first time a solve
        #: runs out of time (a new page carries no model for it).
        self.retry: pn.widgets.Button | None = None
        #: The main area's column (:meth:`main_panel`).
        self._main: pn.Column | None = None
        self._previews = SolveRunner(lambda exc: None, preview=True)
        self.plots = PlotSet()
        self.anim = Animation(self.plots.sources["traj"], self.plots.shared)
        self._build_widgets()
        # An HTML pane whose text is always escaped (a Markdown alert rendered the HTML of a
        # URL's value: a shared link could run script in the page).
        self.alert = pn.pane.HTML("", visible=False, sizing_mode="stretch_width",
                                  css_classes=["fie-alert"], stylesheets=[STYLESHEET])
        self.caption = pn.pane.HTML("", sizing_mode="stretch_width",
                                    css_classes=["fie-caption"], stylesheets=[STYLESHEET])
        # teach: the scene's story and the model card, built when first opened (app.teach)
        self.teach = Teach(self.state)
        # Sized to its content, its rows wrapped, never cut; the space it reserves grows
        # with its rows within a scene and is set again only by a new scene: a readout
        # that grew or shrank on a release made BokehJS lay out every figure again (about
        # 60 ms before the new picture showed).
        self.readout = pn.pane.HTML("", sizing_mode="stretch_width",
                                    css_classes=["fie-readout-pane"], stylesheets=[STYLESHEET])
        self._readout_scene: str | None = None
        self.map_legend = pn.pane.HTML("", sizing_mode="stretch_width",
                                       css_classes=["fie-map-legend"],
                                       stylesheets=[STYLESHEET])
        self.download = pn.widgets.FileDownload(
            callback=self._csv, filename="trajectory.csv", label="Download trajectory (CSV)",
            color="default", width=WIDGET_WIDTH, css_classes=["fie-download"],
        )
        self.download_transitions = pn.widgets.FileDownload(
            callback=self._transitions_csv, filename="transitions.csv",
            label="Download transitions (CSV)", color="default", width=WIDGET_WIDTH,
            css_classes=["fie-download-transitions"],
        )
        self.measure = pn.widgets.Button(
            label=MEASURE_LABEL, width=WIDGET_WIDTH, css_classes=["fie-measure"],
            description="Solve this run again with every method and preset: wall time now, "
                        "error against a reference solution, steady state found (at most "
                        f"{MEASURE_BUDGET_S:g} s).")
        self.measure.on_click(self._measure)
        #: The measurement of the trade, in the solver processes (one at a time).
        self._trade = TradeRunner(self._measured, self._measure_failed)
        #: The message of the last refused measurement (hidden when the measurement ends).
        self._measure_refusal: str | None = None
        #: The sweep card (app.bifurcation), built when first opened.
        self.sweeps: Any = None
        #: The regime labels the map legend names (the last map drawn).
        self._map_labels: list[str] | None = None
        self.open_sweeps = pn.widgets.Button(
            label="Bifurcation diagram (sweep)", width=WIDGET_WIDTH,
            css_classes=["fie-open-sweeps"])
        self.open_sweeps.on_click(self._open_sweeps)
        self._plot_box: pn.FlexBox | None = None
        # Put on the page by its first measurement (above the plots): a new page holds
        # none of its models.
        self.trade = pn.pane.HTML("", visible=False, sizing_mode="stretch_width",
                                  css_classes=["fie-trade-pane"], stylesheets=[STYLESHEET],
                                  styles={"flex": "1 1 100%"})
        #: The solve values the trade table describes.
        self._trade_values: Mapping[str, Any] | None = None
        self.plot_panes = self._build_plot_panes()
        #: Tells the page that a full solution arrived (its text counts them): the browser
        #: holds the figures' repaints after a slider's release until then
        #: (static/perf/release_hold.js). One small hidden model of its own.
        self.arrived = pn.pane.HTML("0", visible=False, margin=0,
                                    css_classes=["fie-solution-arrived"])
        self._arrivals = 0
        #: Pinned runs drawn as ghosts, and the menu that pins, compares and presents.
        self.compare = Compare(self.plots, self._pins_changed, self._solve_failed)
        self.plots.more_legend = lambda: self.compare.legend_entries(self.state.values())
        self.plots.more_extents = self.compare.extents
        self.menu = CompareMenu(self)
        self._show_plots(self.visible_plots())
        self.state.param.watch(self._on_state, ["scene", *SOLVE_PARAMS, *VIEW_PARAMS])
        self.state.param.watch(self._on_scene_label, ["scene"])
        self._sync_widgets()
        self._update()

    # --- building ------------------------------------------------------------------------

    def _build_widgets(self) -> None:
        st = self.state
        self.sliders: dict[str, TypedSlider] = {}
        for name, (label, step) in SLIDERS.items():
            p = st.param[name]
            bounds = p.bounds
            soft = p.softbounds or bounds
            if name == "mu_s":
                bounds, soft = (MU_S_MIN, bounds[1]), (MU_S_MIN, soft[1])
            on_commit = (
                (lambda v, k={"mass": "m", "stiffness": "k"}[name]: self._commit_si({k: v}))
                if name in ("mass", "stiffness") else (lambda v, n=name: self._commit({n: v}))
            )
            self.sliders[name] = TypedSlider(
                label, getattr(st, name), step, soft, bounds,
                on_drag=lambda v, n=name: self._preview(n, v), on_commit=on_commit,
                on_release=self._release_arrived, width=WIDGET_WIDTH,
                css_class=f"fie-w-{name}", name=name, tooltip=TOOLTIPS[name],
                validate=lambda v, n=name: self._refusal(n, v), lazy=name in SHOWN_LATER,
            )
        phys = st.physical()
        factors = si_units(st.mass, st.stiffness)
        for name, (label, step, key) in SI_SLIDERS.items():
            value = phys[key]
            param = SI_STATE_NAME[key]
            # The state's bounds in SI (moved with m and k by _sync_widgets).
            bounds = tuple(b * factors[param][2] for b in st.param[param].bounds)
            soft = (0.0, max(SI_SOFT_SPAN * value, step))
            if name in SI_TWINS:
                twin, factor, power = SI_TWINS[name]
                scale = phys[factor] ** power
                soft = tuple(scale * b for b in st.param[twin].softbounds)
            self.sliders[name] = TypedSlider(
                label, value, step, soft, bounds,
                on_drag=lambda v, k=key: self._preview_si(k, v),
                on_commit=lambda v, k=key: self._commit_si({k: v}),
                on_release=self._release_arrived, width=WIDGET_WIDTH,
                css_class=f"fie-w-{name}", name=label.split(" (")[0], tooltip=TOOLTIPS[name],
                validate=lambda v, n=name, k=key: self._refusal_si(n, k, v),
                lazy=name in SHOWN_LATER,
            )
        self.scene_select = Select(
            label="Scene (paper figure)", value=st.scene, width=WIDGET_WIDTH,
            options={**{SCENES[k].title: k for k in SCENES}, "custom": CUSTOM},
            css_classes=["fie-scene"],
        )
        self.scene_select.param.watch(self._on_scene_select, "value")
        self.stop_type = RadioButtonGroup(
            label="Stop", options=list(STOP_TYPES), value=st.stop_type, width=WIDGET_WIDTH,
            color="default", css_classes=["fie-stop-type"])
        self.units = RadioButtonGroup(
            label="Units", options=list(UNITS), value=st.units, width=WIDGET_WIDTH)
        self.accuracy = RadioButtonGroup(
            label="Accuracy", options=list(ACCURACIES), value=st.accuracy, width=WIDGET_WIDTH,
            description=_accuracy_tip(), css_classes=["fie-accuracy"])
        self.method = Select(
            label="Method", options=list(METHODS), value=st.method, width=WIDGET_WIDTH,
            description="; ".join(f"{k}: {v}" for k, v in METHOD_TIPS.items()) + ".",
            css_classes=["fie-method"])
        self.program = Checkbox(
            label="overlap program (Fig. 2b): the stop alone", value=st.program,
            css_classes=["fie-program"])
        self.reset = pn.widgets.Button(
            label=_reset_label(st.scene), width=WIDGET_WIDTH, css_classes=["fie-reset"],
            description="Put back every value of the figure last loaded.")
        self.reset.on_click(self._reset)
        #: The paper's figure the reset button returns to (the last scene loaded).
        self.figure = st.scene if st.scene in SCENES else DEFAULT_FIGURE
        self.show_all = Checkbox(label="show all plots", value=st.show_all)
        # First in the deformable stop's group, and like it in the page once first shown.
        self.contact_law = Select(
            label="Contact law", options=list(CONTACT_LAWS), value=st.contact_law,
            width=WIDGET_WIDTH, css_classes=["fie-contact-law"],
            description="; ".join(f"{k}: {v}" for k, v in CONTACT_LAW_TIPS.items())
                        + ".")
        for widget, pname in ((self.stop_type, "stop_type"), (self.units, "units"),
                              (self.accuracy, "accuracy"), (self.method, "method"),
                              (self.show_all, "show_all"), (self.program, "program"),
                              (self.contact_law, "contact_law")):
            widget.param.watch(lambda e, n=pname: self._commit({n: e.new}), "value")
        # Groups shown only in some states join the page when first shown (their sliders'
        # widgets are made then).
        self.hysteretic_box = ShownLater(
            self.contact_law, *(self.sliders[n] for n in HYSTERETIC_SLIDERS))
        self.si_box = ShownLater(*(self.sliders[n] for n in SI_BOX_SLIDERS))
        #: The SI twins outside those groups, each in a column of its own.
        self.si_start = {n: ShownLater(self.sliders[n]) for n in SI_START_SLIDERS}

    def _build_plot_panes(self) -> dict[str, pn.viewable.Viewable]:
        """An empty, hidden pane per plot; :meth:`_show_plots` builds a plot into its pane
        the first time it is shown."""
        panes: dict[str, pn.viewable.Viewable] = {}
        for name in PLOTS:
            # Responsive grid: each plot grows from its narrowest width to its widest, and
            # the row wraps when two do not fit (app.plots.PLOT_WIDTHS).
            panes[name] = pn.Column(css_classes=["fie-plot", f"fie-plot-{name}"],
                                    name=PLOT_TITLES[name], margin=(4, 8), visible=False,
                                    sizing_mode="stretch_width", min_width=PLOT_WIDTHS[0],
                                    max_width=PLOT_WIDTHS[1], styles=_pane_styles())
        return panes

    def _drawn(self, visible: tuple[str, ...]) -> tuple[str, ...]:
        """The plots of ``visible`` that are built and drawn: all of them, or on a lazy
        page those built already, the first ones and those the browser saw."""
        if not self._lazy:
            return visible
        return tuple(p for p in visible if p in FIRST_PLOTS or p in self._in_view
                     or self.plot_panes[p].objects)

    def _on_in_view(self, event: param.parameterized.Event) -> None:
        """The browser reports waiting plots in view: build and draw them."""
        names = {n for n in str(event.new).split(",") if n in PLOTS} - self._in_view
        if not names:
            return
        self._in_view |= names
        self._draw_new_plots()
        self.in_view.value = ""  # so that a later report of the same names is a change

    def _draw_new_plots(self) -> None:
        """Build the plots now due (:meth:`_drawn`) and fill them from the solution on
        screen; the plots drawn already are not sent again."""
        visible = self.visible_plots()
        new = [p for p in self._drawn(visible) if not self.plot_panes[p].objects]
        if not new:
            return
        sol = self.solution
        map_data = None
        with pn.io.hold():
            self._show_plots(visible)
            if sol is None:
                return
            scales = self.state.scales()
            if "map" in new:
                map_data = regime_map(sol.values, compute=False, frame=self._map_frame(sol))
            with validate(False):
                if self.compare.pins:
                    self.compare.draw(sol, scales)
                self.plots.refresh(self._drawn(visible), map_data)
                if "anim" in new:
                    self.anim.update(sol, scales)
                if map_data is not None:
                    self._show_map_legend(map_data["labels"])
        if "map" in new and map_data is None:
            self._later(lambda: self._draw_map(sol), 0)

    def _build_plot(self, name: str) -> pn.viewable.Viewable:
        """The body of the pane of plot ``name``, its figures built now (with their links
        to the animation and their tap handlers)."""
        if name == "anim":
            return self.anim.panel()
        layout = self.plots.build(name)
        figs = self.plots.figures
        if name == "phase":
            self.anim.attach_phase(figs["phase"])
            figs["phase"].on_event(Tap, self._on_phase_tap)
            self.plots.shared.lighten(figs["phase"])  # the animation's marker too
        elif name == "time":
            self.anim.attach_time((figs["time_x"], figs["time_v"]))
        elif name == "map":
            figs["map"].on_event(Tap, self._on_map_tap)
            return pn.Column(pn.pane.Bokeh(layout, sizing_mode="stretch_width"),
                             self.map_legend, margin=0, sizing_mode="stretch_width")
        return self.plots.view(name)

    def _show_plots(self, visible: tuple[str, ...]) -> None:
        """Show the panes of ``visible`` (building those shown for the first time), hide
        the others (call under ``pn.io.hold``; a new figure is filled by the next
        :meth:`PlotSet.refresh`)."""
        shown = self.menu.presentation.shown(visible)
        drawn = self._drawn(visible)
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
        self.menu.presentation.restyle()

    # --- views ---------------------------------------------------------------------------

    def sidebar(self) -> list[Any]:
        """The controls, top to bottom."""
        w = {name: slider.layout for name, slider in self.sliders.items()
             if name not in SHOWN_LATER}
        return [
            self.scene_select, self.reset,
            pn.pane.HTML("<b>Stop</b>", margin=(8, 10, 0, 10)), self.stop_type, self.program,
            w["clearance"], w["restitution"], self.hysteretic_box,
            pn.pane.HTML("<b>Belt and friction</b>", margin=(8, 10, 0, 10)),
            w["belt_speed"], w["mu_s"], w["mu_k"], w["u_s"],
            pn.pane.HTML("<b>Units</b>", margin=(8, 10, 0, 10)), self.units, self.si_box,
            pn.pane.HTML("<b>Start and horizon</b> (or click the phase portrait)",
                         margin=(8, 10, 0, 10)),
            w["x0"], w["v0"], self.si_start["v0_si"], w["t_end"], self.si_start["t_end_si"],
            pn.pane.HTML("<b>Solver</b>", margin=(8, 10, 0, 10)), self.accuracy, self.method,
            self.measure, self.open_sweeps, self.show_all, self.download,
            self.download_transitions, self.menu.button,
        ]

    def main(self) -> list[Any]:
        """The alert, the caption, the readout and the plots."""
        self._plot_box = pn.FlexBox(*self.plot_panes.values(), sizing_mode="stretch_width",
                                    css_classes=["fie-plots"])
        return [self.alert, self.caption, *self.teach.buttons, self.readout, self.arrived,
                self.in_view, self._plot_box]  # teach: *self.teach.buttons

    def main_panel(self) -> pn.Column:
        """The main area (:meth:`main`) in one column, which later notices join."""
        self._main = pn.Column(*self.main(), sizing_mode="stretch_width", margin=0)
        self.teach.attach(self._main)  # teach: the texts open below their buttons
        return self._main

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Row(pn.Column(*self.sidebar(), width=WIDGET_WIDTH + 30), self.main_panel())

    # --- URL -----------------------------------------------------------------------------

    def sync_url(self, location: Location | None = None) -> None:
        """Keep the state in the page's query string (permalinks), that of ``location``
        (default: the session's, :func:`app.links.session_location`).

        A URL naming only a scene loads that scene; parameters given beside it override the
        scene's values. The page reads the address's text itself (:mod:`app.links`): no
        value can fail in Panel's parser. The URL is rewritten :data:`URL_DELAY_MS` after
        the last change, so that its round trip (the browser echoes the new address) does
        not delay the repaint of a slider release.
        """
        self.location = loc = location if location is not None else links.session_location()
        if loc is None:
            return
        texts, repeated = links.once(links.query_pairs(loc.search))
        scene = texts.get("scene")
        if scene in SCENES and scene != self.state.scene:
            self.state.load_scene(scene)
        errors, unknown = self._apply_query(texts, repeated)
        errors += self.menu.apply_query(texts)
        if errors or unknown:
            self._url_error(errors, unknown)
        self.state.param.watch(self._url_changed, list(URL_KEYS))
        pn.state.onload(self._write_url)

    def _apply_query(self, texts: Mapping[str, str],
                     repeated: Mapping[str, Sequence[str]]) -> tuple[list[str], list[str]]:
        """Set the state from the URL's parameters (their text, :mod:`app.links`) in one
        batch; return the messages of the values refused and the unknown keys.

        A parameter is read under its permalink key (``tend``) or its own name (``t_end``);
        a key that is neither, nor one of :data:`OTHER_URL_KEYS`, is reported, and so is
        a key given more than once. With ``units=SI`` the values of
        :data:`URL_SI_PARAMS` are SI values (m/s, s, N/m), as the page writes them,
        converted with the address's ``m`` and ``k``."""
        names = {**{name: name for name in URL_KEYS},
                 **{key: name for name, key in URL_KEYS.items()}}
        values, given, unknown, errors, unparsed = {}, {}, [], [], {}
        for key, texts_of_key in repeated.items():
            if key in names or key in OTHER_URL_KEYS:
                errors.append(links.repeated_message(key, names.get(key), texts_of_key))
            else:
                unknown.append(key)
        for key, text in texts.items():
            name = names.get(key)
            if name is None:
                if key not in OTHER_URL_KEYS:
                    unknown.append(key)
                continue
            given[name] = text
            try:
                values[name] = links.parse_value(self.state.param[name], text)
            except ValueError:
                unparsed[name] = text
        # Each value is checked on its own, so that one bad value does not drop the others.
        good, bad = {}, {}
        for name, value in values.items():
            try:
                ExplorerState(**{name: value})
            except Exception:  # noqa: BLE001 - any rejected value: say which
                bad[name] = value
            else:
                good[name] = value
        si = good.get("units", self.state.units) == "SI"
        errors.extend(self._unparsed_messages(unparsed, good, si))
        if si:
            errors.extend(self._si_from_url(good, bad))
        good = {name: value for name, value in good.items()
                if value != getattr(self.state, name)}
        # A scene's values changed by the address are no longer that scene: its title and
        # caption would describe another motion (the reset button still returns to it).
        scene = good.get("scene", self.state.scene)
        if scene in SCENES and _differs({**self.state.values(), **good}, scene_values(
                scene, accuracy=self.state.accuracy, method=self.state.method)):
            good["scene"] = CUSTOM
        try:
            self.state.param.update(**good)
        except Exception:  # noqa: BLE001 - a combination the state refuses
            bad.update(good)
        errors = [links.refused_message(name, self.state.param[name], given[name])
                  for name in bad if name in given] + errors
        return errors, unknown

    def _unparsed_messages(self, unparsed: Mapping[str, str], good: Mapping[str, Any],
                           si: bool) -> list[str]:
        """The messages of an address's values that are no value at all (``tend=true``):
        in an SI address those of :data:`URL_SI_PARAMS` with their SI range (they are read
        in m/s, s, N/m), not the state's dimensionless one."""
        mass = good.get("mass", self.state.mass)
        stiffness = good.get("stiffness", self.state.stiffness)
        return [f"{URL_KEYS[name]}: {si_units(mass, stiffness)[name][0]} must be a number "
                f"in {si_range(name, mass, stiffness)}; got {links.shown(text)}"
                if si and name in URL_SI_PARAMS
                else links.refused_message(name, self.state.param[name], text)
                for name, text in unparsed.items()]

    def _si_from_url(self, good: dict[str, Any], bad: dict[str, Any]) -> list[str]:
        """Turn the SI values of an SI address (:data:`URL_SI_PARAMS` in ``good`` and
        ``bad``) into the state's, in place; return the messages of those out of range.

        A value is checked only after conversion (its bounds depend on ``m`` and ``k``)."""
        mass, stiffness = good.get("mass", self.state.mass), good.get("stiffness",
                                                                      self.state.stiffness)
        factors, errors = si_units(mass, stiffness), []
        for name in URL_SI_PARAMS:
            raw = good.pop(name, bad.get(name))
            if raw is None:
                continue
            bad.pop(name, None)
            value = raw / factors[name][2]
            message = si_bound_error(name, value, mass, stiffness)
            if message:
                errors.append(f"{URL_KEYS[name]}: {message}")
            elif not math.isclose(value, getattr(self.state, name), rel_tol=1e-11):
                # Within 1e-11 the address is the state's own, written with 12 digits.
                good[name] = value
        return errors

    def _url_changed(self, *events: param.parameterized.Event) -> None:
        """Rewrite the URL once the state has been still for :data:`URL_DELAY_MS`."""
        if self._url_timer is not None:
            self._url_timer.cancel()
        self._url_timer = self._later(self._write_url, URL_DELAY_MS)

    def _later(self, fn: Callable[[], None], delay_ms: float) -> _Deferred:
        """Run ``fn`` after ``delay_ms`` on the session's event loop (at once without a
        server session, e.g. in tests)."""
        call = _Deferred(fn)
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:
            call()
        else:
            def run() -> None:
                with set_curdoc(doc):
                    call()
            doc.add_timeout_callback(run, delay_ms)
        return call

    def _write_url(self, *events: param.parameterized.Event) -> None:
        self._url_timer = None
        loc = self.location if self.location is not None else pn.state.location
        if loc is None:
            return
        query = {}
        si = (si_units(self.state.mass, self.state.stiffness) if self.state.units == "SI"
              else {})
        for name, key in URL_KEYS.items():
            value = getattr(self.state, name)
            if name in URL_SI_PARAMS and si:
                # In SI the address says what the boxes say (12 digits: no rounding tail).
                value = float(f"{value * si[name][2]:.12g}")
            value = self.state.param[name].serialize(value)
            query[key] = value if isinstance(value, str) else json.dumps(value)
        current = dict(links.query_pairs(loc.search))
        query.update(self.menu.query(current))
        # Written as text (app.links): the keys the page does not read stay as they came.
        loc.search = links.merged_search(loc.search, query)

    def _url_error(self, errors: Sequence[str], unknown: Sequence[str] = ()) -> None:
        """Say which of the URL's values were rejected (``errors``: each names its key,
        what it allows and what came), and which keys the page does not know."""
        parts = list(errors)
        if unknown:
            parts.append(links.unknown_message(unknown, URL_KEYS.values()))
        self._show_error("Some URL parameters could not be applied: " + "; ".join(parts))
        self._link_alert = (self.alert.object, self.state.values())

    # --- events --------------------------------------------------------------------------

    def _constrained(self, values: dict[str, Any]) -> dict[str, Any]:
        """Apply the widgets' constraints (mu_k <= mu_s, k_e0 <= k_c0, beta_c <= beta_e)."""
        for low, high in CONSTRAINTS:
            if low in values and high in values and values[low] > values[high]:
                values[low] = values[high]
        return values

    def _commit(self, changes: Mapping[str, Any]) -> None:
        """A user's final value(s): into the state in one batch (one solve).

        Solve parameters go through the constraints; a real change of one (other than the
        method or accuracy, :data:`~app.state.SOLVER_CHOICES`) makes the scene 'custom'.
        Releasing a slider where the drag started redraws the last full solution
        over the previews.
        """
        if self._syncing:
            return
        self._commits += 1
        new = {k: v for k, v in changes.items() if k not in SOLVE_PARAMS}
        solve_changes = {k: v for k, v in changes.items() if k in SOLVE_PARAMS}
        notes = []
        if solve_changes:
            wanted = {**self.state.values(), **solve_changes}
            if wanted["stop_type"] != "hysteretic":  # the program drives a deformable stop
                wanted["program"] = False
            merged = self._constrained(dict(wanted))
            notes = [(low, wanted[low], merged[low], high) for low, high in CONSTRAINTS
                     if merged[low] != wanted[low]]
            diff = {k: v for k, v in merged.items() if v != getattr(self.state, k)}
            new.update(diff)
            if "scene" not in changes and any(k not in SOLVER_CHOICES for k in diff):
                new["scene"] = CUSTOM
        changed = {k: v for k, v in new.items() if getattr(self.state, k) != v}
        for slider in self.sliders.values():  # a note is about the last change only
            if slider.noting and not slider.invalid:
                slider.note("")
        if changed:
            self.state.param.update(**changed)
        elif self.solution is not None:
            self._draw(self.solution)
        for low, was, now, high in notes:
            self._coupled_note(low, was, now, high)

    def _coupled_note(self, low: str, was: float, now: float, high: str) -> None:
        """Say that ``low`` followed ``high`` down, next to the box the user sees."""
        si = self.state.units == "SI"
        twin_of = {twin: name for name, (twin, _, _) in SI_TWINS.items()}
        shown = twin_of.get(low, low) if si else low
        slider = self.sliders[shown]
        scale = slider.value / now if shown != low and now else 1.0
        slider.note(f"{slider.name} lowered from {format_number(was * scale)} to "
                    f"{format_number(now * scale)} to stay ≤ {high}")

    def _refusal(self, name: str, value: float) -> str | None:
        """Why a typed ``value`` of ``name`` is refused, or None.

        The page's limits (the state's bounds: a horizon the page can draw, a slider that
        can be drawn) come first, then what the core's validation refuses of the whole set
        (a stop behind the start); both in the core's words (:mod:`core.validation`: the
        parameter, the allowed range, the value).
        """
        st = self.state
        higher = dict(CONSTRAINTS).get(name)
        if higher is not None:  # the lower of a pair may not pass the higher
            reason = bounds_reason(name, value, (self.sliders[name].bounds[0],
                                                 getattr(st, higher)))
            if reason:
                return f"{reason} (it may not exceed {higher})"
        reason = bounds_reason(name, value, self.sliders[name].bounds)
        if reason is None and name in SOLVE_PARAMS:
            reason = _core_reason(self._constrained({**st.values(), name: value}))
            if reason == _core_reason(st.values()):  # not this value's doing
                reason = None
        return reason

    def _refusal_si(self, name: str, key: str, value: float) -> str | None:
        """Why a typed SI ``value`` is refused (see :meth:`_refusal`), or None: first the
        state's bounds in SI with the current m and k, then the conversion's own checks."""
        st = self.state
        param = SI_STATE_NAME[key]
        factor = si_units(st.mass, st.stiffness)[param][2]
        message = si_bound_error(param, value / factor, st.mass, st.stiffness)
        if message:
            return message
        higher = dict(CONSTRAINTS).get(param)
        if higher is not None:  # the lower of a pair (k_e0 <= k_c0), as in _refusal
            top = getattr(st, higher) * factor
            if value > top and not math.isclose(value, top, rel_tol=1e-12):
                low = self.sliders[name].bounds[0]
                return (f"{bounds_reason(self.sliders[name].name, value, (low, top))} (it "
                        f"may not exceed {higher})")
        try:
            self.state.from_physical(**{key: value})
        except ValueError as exc:
            return str(exc)
        return None

    def _reset(self, event: Any = None) -> None:
        """Every value of the figure last loaded, whatever was typed or refused since."""
        for slider in self.sliders.values():
            slider.clear()
        if self.state.scene == self.figure and self.state.values() == scene_values(
                self.figure, accuracy=self.state.accuracy, method=self.state.method):
            self._sync_widgets()
            return
        self._commits += 1
        self.state.load_scene(self.figure)

    def _commit_si(self, si: Mapping[str, float]) -> None:
        """A user's final SI value(s): converted, then committed as the state's values
        (through the same constraints)."""
        if self._syncing:
            return
        try:
            values = self.state.from_physical(**si)
        except ValueError as exc:
            self._commits += 1
            self._show_error(str(exc))
            return
        self._commit(values)

    def _release_arrived(self) -> None:
        """A slider's release has arrived and will be committed: a preview whose drawing is
        still pending is stale (it would delay the release's full picture on the server,
        and its message the browser's work on it)."""
        self._commits += 1

    def _preview(self, name: str, value: float) -> None:
        """While dragging: a draft solve of the trajectory only."""
        if self._syncing or name not in SOLVE_PARAMS:
            return
        self._preview_values({name: value})

    def _preview_si(self, key: str, value: float) -> None:
        if self._syncing:
            return
        try:
            values = self.state.from_physical(**{key: value})
        except ValueError:
            return
        self._preview_values({k: v for k, v in values.items() if k in SOLVE_PARAMS})

    def _preview_values(self, changes: Mapping[str, Any]) -> None:
        values = self._constrained({**self.state.values(), **changes})
        if values.get("program"):
            return
        if values == self.state.values() and self.solution is not None:
            # Back at the committed value: its release sends no new value, so show the full
            # picture now rather than leave a draft on screen.
            self._draw(self.solution)
            return
        commits = self._commits

        def solved(sol: Solution) -> None:
            # Drawn a moment later: a release that arrives meanwhile (the drag's last value
            # and the release come together) replaces it, and its full solution is not held
            # up by sending and painting a preview that is already stale.
            if sol.result is not None:
                self._later(lambda: self._draw_preview(sol, commits), PREVIEW_DELAY_MS)

        self._previews.request(values, solved)

    def _draw_preview(self, sol: Solution, commits: int) -> None:
        if commits != self._commits:
            return
        with pn.io.hold(), validate(False):
            self.plots.update_preview(sol, self.state.scales())

    def _on_phase_tap(self, event: Tap) -> None:
        self._commit_tap(event, lambda x, y: {
            "x0": round(x, 4), "v0": round(y / self.state.scales().velocity, 4)})

    def _on_map_tap(self, event: Tap) -> None:
        self._commit_tap(event, lambda x, y: {
            "belt_speed": max(0.0, round(x / self.state.scales().velocity, 4)),
            "clearance": round(y, 4)})

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
        self._commit(tapped)

    def _on_scene_select(self, event: param.parameterized.Event) -> None:
        if self._syncing or event.new == CUSTOM or event.new not in SCENES:
            return
        self.state.load_scene(event.new)

    def _on_scene_label(self, event: param.parameterized.Event) -> None:
        self._set_syncing(lambda: setattr(self.scene_select, "value", event.new))
        if event.new in SCENES:
            self.figure = event.new
            set_changed(self.reset, label=_reset_label(event.new))

    def _on_state(self, *events: param.parameterized.Event) -> None:
        self._commits += 1
        self._sync_widgets()
        names = {e.name for e in events}
        if "scene" in names and self.state.scene in SCENES:
            self.plots.forget_transition_kinds()
        if names & set(SOLVE_PARAMS):
            self._update()
        elif self.solution is not None:
            self._draw(self.solution)

    # --- state -> widgets ----------------------------------------------------------------

    def _set_syncing(self, fn) -> None:
        self._syncing = True
        try:
            fn()
        finally:
            self._syncing = False

    def _sync_widgets(self) -> None:
        """Show the state in the widgets (after a scene, a URL, a tap or a clamp)."""
        self._set_syncing(self._sync_widgets_now)

    def _sync_widgets_now(self) -> None:
        st = self.state
        bounded = {low: getattr(st, high) for low, high in CONSTRAINTS}
        for name, w in self.sliders.items():
            if name in SI_SLIDERS or w.moved_on_from(getattr(st, name)):
                continue
            if name in bounded:  # the lower slider of a constraint ends at the higher value
                top = bounded[name]
                w.set(getattr(st, name), hard_end=top,
                      soft_end=min(st.param[name].softbounds[1], top))
            elif w.value != getattr(st, name):
                w.set(getattr(st, name))
        try:
            phys = st.physical()
        except ValueError:
            phys = None
        if phys is not None:
            twin_of = {twin: name for name, (twin, _, _) in SI_TWINS.items()}
            si_bounded = {twin_of[low]: phys[high] for low, high in CONSTRAINTS
                          if low in twin_of and high in twin_of}
            factors = si_units(st.mass, st.stiffness)
            for name, (_, step, key) in SI_SLIDERS.items():
                w, value = self.sliders[name], phys[key]
                param = SI_STATE_NAME[key]
                low, high = (b * factors[param][2] for b in st.param[param].bounds)
                # Set once per sync: a tooltip that changes is a model sent to the page.
                if name in si_bounded:  # as above, in SI
                    top = si_bounded[name]
                    w.set_bounds((low, top))
                    w.set(value, soft_end=top)
                    continue
                w.set_bounds((low, high))
                if not math.isclose(w.value, value, rel_tol=1e-12, abs_tol=1e-15):
                    grow = 1.0 if name in SI_TWINS else SI_SOFT_SPAN
                    w.set(value, soft_end=max(w.end, grow * value, step))
        for widget, value in ((self.stop_type, st.stop_type), (self.units, st.units),
                              (self.accuracy, st.accuracy), (self.method, st.method),
                              (self.show_all, st.show_all), (self.scene_select, st.scene),
                              (self.program, st.program), (self.contact_law, st.contact_law)):
            set_changed(widget, value=value)
        si = st.units == "SI"
        self.si_box.show(si)
        for name, (twin, _, _) in SI_TWINS.items():
            self.sliders[name].visible = si
            self.sliders[twin].visible = not si
        for box in self.si_start.values():
            box.show(si)
        self.sliders["u_s"].visible = not si
        self.sliders["belt_speed"].visible = not si
        has_stop = st.stop_type != "none"
        self.sliders["clearance"].visible = has_stop
        self.sliders["restitution"].visible = st.stop_type == "rigid"
        self.hysteretic_box.show(st.stop_type == "hysteretic")
        set_changed(self.program, visible=st.stop_type == "hysteretic")
        for name in LENGTH_SLIDERS:
            self.sliders[name].set_label(SLIDERS[name][0] + (" (m)" if si else ""))

    # --- solving and drawing -------------------------------------------------------------

    def applicable_plots(self) -> tuple[str, ...]:
        """The plots that can show the current state (no contact force without a stop)."""
        st = self.state
        if st.program and st.stop_type == "hysteretic":
            return ("loop", "force")
        left_out = {"none": {"force", "loop"}, "rigid": {"loop"}}.get(st.stop_type, set())
        return tuple(p for p in PLOTS if p not in left_out)

    def visible_plots(self) -> tuple[str, ...]:
        """The plots the current scene needs (or all that apply, with 'show all plots')."""
        st = self.state
        applicable = self.applicable_plots()
        if st.program and st.stop_type == "hysteretic":
            return applicable
        by_stop = {"none": IMPACTLESS_PLOTS, "rigid": RIGID_PLOTS,
                   "hysteretic": HYSTERETIC_PLOTS}[st.stop_type]
        scene = SCENES.get(st.scene)
        wanted = PLOTS if st.show_all else (scene.plots if scene is not None else by_stop)
        return tuple(p for p in applicable if p in wanted)

    def _update(self) -> None:
        """Full solve of the state, then redraw (:meth:`_solved`); on failure show why and
        keep the picture. The solve runs in the worker pool, not on the event loop."""
        self._show_retry(None)
        self._solves.request(self.state.values(), self._solved)

    def _retry_solve(self, event: Any = None) -> None:
        """Solve the state on screen again with :func:`~app.solver.retry_budget` of the
        budget that ran out; the picture stays until the answer comes."""
        budget = retry_budget(self._ran_out or MAX_SOLVE_BUDGET_S)
        if self.retry is not None:
            self.retry.param.update(disabled=True, label=f"Solving (up to {budget:g} s)…")
        self._solves.request(self.state.values(), self._solved, budget=budget)

    def _show_retry(self, ran_out: float | None) -> None:
        """Offer to solve again with more time after ``ran_out`` seconds were not enough
        (hide the offer with None, or when the budget cannot grow)."""
        self._ran_out = ran_out
        offer = ran_out is not None and ran_out < MAX_SOLVE_BUDGET_S
        if self.retry is None:
            if not offer:
                return
            self.retry = pn.widgets.Button(
                label="Retry with more time", color="primary", css_classes=["fie-retry"],
                visible=False, margin=(0, 10, 8, 10))
            self.retry.on_click(self._retry_solve)
            if self._main is not None:
                at = next(i for i, obj in enumerate(self._main.objects) if obj is self.alert)
                self._main.insert(at + 1, self.retry)
        if offer:
            self.retry.param.update(
                visible=True, disabled=False, label="Retry with more time",
                description=f"Solve this run again with up to {retry_budget(ran_out):g} s "
                            "(the plots stay until it is done).")
        else:
            set_changed(self.retry, visible=False)

    def _solved(self, sol: Solution) -> None:
        self.solution = sol
        self.error = None
        try:
            self._draw(sol)
        except Exception as exc:  # noqa: BLE001 - a drawing fault must not go unsaid
            log.error("drawing failed", exc_info=exc)
            self._show_error(f"The picture could not be drawn: {type(exc).__name__}: {exc}")
        if self.sweeps is not None:
            self.sweeps.on_solution(sol.values)

    # --- sweeps (app.bifurcation) ----------------------------------------------------------

    def _open_sweeps(self, event: Any = None) -> None:
        """Build the sweep card on first use (a new page holds none of its models), put it
        above the plots and sweep the current scene."""
        if self.sweeps is None:
            from app.bifurcation import BifurcationView

            self.sweeps = BifurcationView(
                values=self.state.values, on_pick=lambda name, v: self._commit({name: v}),
                map_figure=self._sweep_map_figure,
                map_frame=lambda: self._map_frame(self.solution), shared=self.plots.shared,
                scales=self.state.scales(), on_layers=self._show_map_legend)
            self._above_plots(self.sweeps.layout)
            self.sweeps.start()
        else:
            self.sweeps.layout.collapsed = False

    def _above_plots(self, pane: Any) -> None:
        """Put ``pane`` on the page above the plots (a full row of their box), once:
        panes used only on demand are added when first used."""
        box = self._plot_box
        if box is not None and not any(obj is pane for obj in box.objects):
            box.objects = [pane, *box.objects]

    def _sweep_map_figure(self) -> Any:
        """The regime map's figure, shown (with 'show all plots') if the scene hides it."""
        if "map" not in self.applicable_plots():
            return None
        if "map" not in self.visible_plots():
            self._commit({"show_all": True})
        if "map" not in self.plots.figures:  # a lazy page's map not yet in view
            self._in_view.add("map")
            self._draw_new_plots()
        return self.plots.figures.get("map")

    def _solve_failed(self, exc: Exception) -> None:
        if isinstance(exc, ValueError):
            self._show_error(str(exc))
        elif isinstance(exc, SolveTooSlow):
            more = ("" if exc.budget is None or exc.budget < MAX_SOLVE_BUDGET_S else
                    f" Even {exc.budget:g} s were not enough.")
            self._show_error(f"The solve was too slow: {exc}{more}", lead="Not solved in time:",
                             tail="The plots still show the previous run.")
            self._show_retry(exc.budget)
        else:
            log.error("solve failed", exc_info=exc)
            self._show_error(f"The solver failed: {type(exc).__name__}: {exc}")

    def _show_busy(self, busy: bool) -> None:
        """Mark the plots a running solve will replace (Panel's per-pane ``loading``)."""
        visible = self.visible_plots() if busy else ()
        with pn.io.hold():
            for name, pane in self.plot_panes.items():
                set_changed(pane, loading=name in visible)

    def _draw(self, sol: Solution) -> None:
        st = self.state
        scales = st.scales()
        visible = self.visible_plots()
        drawn = self._drawn(visible)  # the others wait, empty, until in view
        map_data = (regime_map(sol.values, compute=False, frame=self._map_frame(sol))
                    if "map" in drawn else None)
        # The values come from the solver and the plot code, valid by construction: Bokeh's
        # check of each of the ~100 properties set here is skipped (server time on the
        # critical path of every release).
        with pn.io.hold():
            # Figures shown for the first time are built with the checks on (they also
            # turn values such as a title's text into models).
            self._show_plots(visible)
            with validate(False):
                if self.compare.pins:  # first: the axes fitted next show the ghosts too
                    self.compare.draw(sol, scales)
                self.plots.update(sol, scales, drawn, map_data)
                if "anim" in drawn:
                    self.anim.update(sol, scales)
                readout = readout_html(sol, scales) + self.compare.table(sol, scales)
                self.readout.object = readout
                self._reserve_readout(readout.count("<tr>"))
                self.caption.object = self._caption_html()
                if map_data is not None:
                    self._show_map_legend(map_data["labels"])
                if self.sweeps is not None:
                    self.sweeps.set_scales(scales)
                set_changed(self.show_all, name=_show_all_label(visible, self.applicable_plots()))
                if self._link_alert != (self.alert.object, dict(sol.values)):
                    set_changed(self.alert, visible=False)
                self._trade_follows(sol)
                self._arrivals += 1  # last: the page's figures hold their paints until it
                self.arrived.object = str(self._arrivals)
        if cut_short(sol):
            self._say_cut_short(sol)
        else:
            self._show_retry(None)
        if "map" in drawn and map_data is None:
            # A new map (friction, stop or start changed): the rest of the picture is sent
            # first, the map (its computation and its 64 kB image) follows.
            self._later(lambda: self._draw_map(sol), 0)

    def _trade_follows(self, sol: Solution) -> None:
        """A new run on screen: the trade table of another run goes, and a measurement of
        another run stops (its table would not be shown)."""
        if self.trade.visible and self._trade_values != sol.values:
            set_changed(self.trade, visible=False)
        if self._trade.running and self._trade.values != dict(sol.values):
            self._trade.cancel()

    def _say_cut_short(self, sol: Solution) -> None:
        """Say that the core stopped ``sol`` before its horizon, and offer more time."""
        res, scales = sol.result, self.state.scales()
        unit = " s" if scales.si else ""
        why = (f"its time budget of {sol.budget:g} s ran out" if res.status is Status.TIME_BUDGET
               else "it reached its limit on integration steps")
        more = ("" if sol.budget < MAX_SOLVE_BUDGET_S else
                " More time cannot be given: a shorter horizon t_end or a looser accuracy "
                "answers sooner.")
        self._show_error(
            f"the {sol.method} method stopped at t = {float(res.t[-1]) * scales.time:.4g}"
            f"{unit} of t_end = {sol.t_end * scales.time:.4g}{unit}: {why}.{more}",
            lead="Solved only in part:", tail="The plots show the run up to there.")
        self._show_retry(sol.budget)

    def _measure(self, event: Any = None) -> None:
        """Measure the speed/accuracy trade of the run on screen, in the solver processes
        (:class:`app.trade.TradeRunner`); a click while one runs is refused."""
        values = dict(self.state.values())
        if values.get("program"):
            return
        try:
            self._trade.start(values)
        except MeasureRefused as exc:
            self._show_error(str(exc), lead="Not measured:", tail="")
            self._measure_refusal = self.error
            return
        self.measure.disabled = True
        self.measure.label = f"Measuring… (at most {MEASURE_BUDGET_S:g} s)"

    def _measure_ended(self) -> None:
        self.measure.disabled = False
        self.measure.label = MEASURE_LABEL
        if self.alert.visible and self.error == self._measure_refusal:
            self.alert.visible = False  # "already running": no longer so

    def _measured(self, values: Mapping[str, Any], rows: list) -> None:
        self._measure_ended()
        if values != dict(self.state.values()):
            return  # the run changed meanwhile
        self._trade_values = values
        self.trade.object = (
            "<div class='fie-title'>Speed and accuracy, measured for this run</div>"
            + trade_html(rows))
        self.trade.visible = True
        self._above_plots(self.trade)

    def _measure_failed(self, exc: Exception) -> None:
        self._measure_ended()
        if not isinstance(exc, Abandoned):  # cancelled: the run changed or the page closed
            self._show_error(f"{type(exc).__name__}: {exc}", lead="The measurement failed:",
                             tail="")

    def close(self) -> None:
        """The page closed: stop its measurement, sweeps and solves, freeing their solver
        processes (called by the server when it discards the session)."""
        self._trade.cancel()
        if self.sweeps is not None:
            self.sweeps.close()
        self._solves.cancel()
        self._previews.cancel()

    def _reserve_readout(self, rows: int) -> None:
        """Keep room for ``rows`` rows (and a wrapped line) below the caption: more rows
        grow the room; a new scene sets it afresh."""
        height = (rows + READOUT_SPARE_LINES) * READOUT_ROW_PX + READOUT_PAD_PX
        scene = self.state.scene
        if scene != self._readout_scene and scene != CUSTOM:
            self._readout_scene = scene
        elif self.readout.min_height is not None and height <= self.readout.min_height:
            return
        set_changed(self.readout, min_height=height)

    def _map_frame(self, sol: Solution) -> tuple[float, float, float]:
        """The regime map's axes, stable for a scene (:meth:`PlotSet.map_frame`)."""
        return self.plots.map_frame({**sol.values, "scene": self.state.scene,
                                     "units": self.state.units})

    def _draw_map(self, sol: Solution) -> None:
        """Compute the regime map of ``sol`` and draw it, unless a newer solution came."""
        if sol is not self.solution:
            return
        try:
            data = regime_map(sol.values, frame=self._map_frame(sol))
        except Exception:  # noqa: BLE001 - a map that fails leaves the old one
            log.exception("regime map failed")
            return
        if "map" not in self._drawn(self.visible_plots()):
            return
        with pn.io.hold(), validate(False):
            self.plots.show_map(data)
            self._show_map_legend(data["labels"])

    def _show_map_legend(self, labels: list[str] | None = None) -> None:
        """The regime map's legend for ``labels`` (the last ones if ``None``), saying so
        when the simulated layer of the sweep card covers the theory's colours."""
        if labels is not None:
            self._map_labels = labels
        if self._map_labels is None:
            return
        covered = self.sweeps is not None and self.sweeps.sim_layer_shown
        self.map_legend.object = _map_legend(self._map_labels, covered)

    def _caption_html(self) -> str:
        scene = SCENES.get(self.state.scene)
        if scene is None:
            return ("<div class='fie-title'>Custom parameters</div><div>Pick a scene to "
                    "return to one of the paper's figures.</div>")
        return (f"<div class='fie-title'>{html.escape(scene.title)}</div>"
                f"<div class='fie-look'>{html.escape(scene.caption)}</div>")

    def _show_error(self, message: str, lead: str = "Input not applied:",
                    tail: str = "The plots still show the last valid parameters.") -> None:
        """Show ``message`` as text (it may echo a URL's or a user's value), after ``lead``
        and before ``tail``."""
        self.error = message
        with pn.io.hold():
            self.alert.object = (
                f"<div class='fie-alert-box' role='alert'><b>{html.escape(lead)}</b> "
                f"{html.escape(message)}<br>{html.escape(tail)}</div>")
            self.alert.visible = True

    def _pins_changed(self) -> None:
        """A pin came, went or was solved: its ghosts, the table, the legend, the URL."""
        sol = self.solution
        if sol is not None:
            scales = self.state.scales()
            with pn.io.hold(), validate(False):
                self.compare.draw(sol, scales)
                self.plots.fit_ranges()
                self.plots.refresh_legend()
                readout = readout_html(sol, scales) + self.compare.table(sol, scales)
                self.readout.object = readout
                self._reserve_readout(readout.count("<tr>"))
        self.menu.refresh()
        self._url_changed()

    def _csv(self):
        """The trajectory file; its name (set before the transfer) names the run."""
        if self.solution is None:
            return None
        self.download.filename = self._file_name("trajectory")
        return trajectory_csv(self.solution, self.state.scales())

    def _transitions_csv(self):
        """One row per transition (impacts with speeds before and after, impulses)."""
        if self.solution is None:
            return None
        self.download_transitions.filename = self._file_name("transitions")
        return transitions_csv(self.solution, self.state.scales())

    def _file_name(self, what: str) -> str:
        scene = self.figure if self.state.scene == CUSTOM else self.state.scene
        scene = scene if self.state.scene != CUSTOM else f"custom-from-{scene}"
        return file_name(self.solution.values, scene, what, self.state.scales())


#: The figure the reset button returns to when the page opens on custom values.
DEFAULT_FIGURE = DEFAULT_SCENE
#: The plots a lazy page builds with the page, where a scene shows them (the first row of
#: a wide window); the others are built when the browser reports them in view.
FIRST_PLOTS = frozenset({"phase", "time"})
#: Height [px] of each plot's pane while it waits to be built: about the plot's own, so
#: that the page does not jump when it is drawn and only the plots in view are reported.
PANE_HEIGHTS = {"phase": PHASE_SIZE[1] + 60, "time": 2 * TIME_SIZE[1], "anim": ANIM_SIZE[1] + 90,
                "force": SMALL_SIZE[1], "loop": SMALL_SIZE[1], "friction": SMALL_SIZE[1],
                "energy": SMALL_SIZE[1] + 60, "map": MAP_SIZE[1] + 100}


def _pane_styles() -> dict[str, str]:
    """Inline styles of a plot's pane: its share of the grid's row."""
    return {"flex": f"1 1 {PLOT_WIDTHS[0] + 160}px"}


def _reset_label(scene: str) -> str:
    """The reset button's label, naming the figure it returns to.

    >>> _reset_label("7c")
    'Reset to Fig. 7c'
    """
    return f"Reset to Fig. {scene}" if scene in SCENES else f"Reset to Fig. {DEFAULT_FIGURE}"


def _accuracy_tip() -> str:
    """The accuracy presets in one tooltip, from :data:`app.solver.ACCURACY`."""
    parts = [f"{name}: rtol {ACCURACY[name]['rtol']:g}, switch band eta "
             f"{ACCURACY[name]['eta']:g}, {ACCURACY[name]['n_samples']} samples"
             for name in ACCURACIES]
    return ("; ".join(parts) + ". The exact method on no stop or a rigid stop is closed form "
            "at every preset: only the smoothness of the curves changes. No preset promises "
            "an error: a full run that integrates has its error measured (the Solve row).")


def _core_reason(values: Mapping[str, Any]) -> str | None:
    """The core's message for solve values it refuses, or None."""
    try:
        core_inputs(values)
    except ValueError as exc:
        return str(exc)
    return None


def _differs(values: Mapping[str, Any], scene: Mapping[str, Any]) -> bool:
    """Whether solve values differ from a scene's: numbers beyond 1e-11 relative (an SI
    address holds 12 digits), anything else at all; the method and accuracy are not the
    scene's (:data:`~app.state.SOLVER_CHOICES`).

    >>> from app.state import scene_values
    >>> v = scene_values("7c")
    >>> _differs({**v, "belt_speed": v["belt_speed"] * (1 + 1e-13)}, v)
    False
    >>> _differs({**v, "restitution": 1.0}, v), _differs({**v, "stop_type": "none"}, v)
    (True, True)
    """
    for name in SOLVE_PARAMS:
        if name in SOLVER_CHOICES:
            continue
        a, b = values[name], scene[name]
        if isinstance(a, float) and isinstance(b, float | int) and not isinstance(b, bool):
            if not math.isclose(a, b, rel_tol=1e-11):
                return True
        elif a != b:
            return True
    return False


def _show_all_label(visible: tuple[str, ...], applicable: tuple[str, ...]) -> str:
    """The label of the 'show all plots' box, naming the plots it would add.

    >>> _show_all_label(("phase", "time"), ("phase", "time", "friction", "energy"))
    'show all plots (+ friction law, energy)'
    """
    hidden = [PLOT_TITLES[p].lower() for p in applicable if p not in visible]
    return "show all plots" + (f" (+ {', '.join(hidden)})" if hidden else "")


class _Deferred:
    """A call that can be cancelled before it runs."""

    def __init__(self, fn: Callable[[], None]) -> None:
        self._fn: Callable[[], None] | None = fn

    def cancel(self) -> None:
        self._fn = None

    def __call__(self) -> None:
        fn, self._fn = self._fn, None
        if fn is not None:
            fn()


#: What the words of the regime map's legend mean (shown under it, for the words used).
MAP_TERMS = {
    "slow": "slow / fast belt: v below / above the critical speed v* (Eq. 25)",
    "no impact": "no impact: the motion stays short of the stop",
    "elastic": "elastic / inelastic / plastic: restitution r = 1 / 0 < r < 1 / r = 0",
    "case": "case a / b / c: where the stick phase meets the stop (Sec. 4.2-4.4, Eq. 35)",
    "grazing": "grazing: impacts fade towards a slip circle touching the stop",
    "rest": "rest: the impacts accumulate and the mass stays pressed on the stop",
}


def _map_legend(labels: list[str], covered: bool = False) -> str:
    """Colour swatches naming the regimes of the map, and what their words mean; with
    ``covered``, first that the simulated layer hides them."""
    items = "".join(
        f"<span class='fie-swatch'><i style='background:{MAP_PALETTE[i % len(MAP_PALETTE)]}'>"
        f"</i>{html.escape(label)}</span>"
        for i, label in enumerate(labels)
    )
    words = " ".join(labels)
    terms = [text for word, text in MAP_TERMS.items()
             if word in words or (word == "slow" and "fast" in words)
             or (word == "elastic" and ("inelastic" in words or "plastic" in words))]
    notes = "".join(f"<div class='fie-look'>{html.escape(t)}</div>" for t in terms)
    head = ("<div class='fie-look fie-map-covered'>The simulated steady states cover the "
            "map (their colours are in the sweep card); the theory's regimes below show "
            "where that layer is off.</div>" if covered else "")
    return f"<div class='fie-legend'>{head}{items}{notes}</div>"
