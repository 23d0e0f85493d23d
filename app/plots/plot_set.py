"""The figures of one session, built when first shown and updated in place from each solution.

:class:`PlotSet` builds each figure when it is first shown, on ``ColumnDataSource`` objects
made with the set (a figure built later receives the current data); an update replaces each
source's ``.data`` in one assignment (the caller batches them with ``panel.io.hold``), so a
change of the parameters sends one message with only new numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import panel as pn
from bokeh.core.properties import validate
from bokeh.models import ColumnDataSource, LabelSet, LinearAxis, Span

from app.plots.columns import (
    band_columns,
    energy_columns,
    force_columns,
    friction_columns,
    loop_columns,
    phase_columns,
    phase_step,
    reference_columns,
    sample_bounds,
    trajectory_columns,
    transition_columns,
)
from app.plots.figures import BUILDERS, set_axis_labels
from app.plots.labels import applicable_points
from app.plots.legends import legend_html, phase_entries
from app.plots.map_boundaries import boundary_columns
from app.plots.ranges import RANGE_PADDING, data_bounds, set_range, stop_in_view
from app.plots.return_figure import draw_return
from app.plots.sources import SharedModels, SourceData, Sources, assign
from app.plots.style import ENERGY_COLORS, MAP_PALETTE, MODE_NAMES
from app.plots.window import RunWindow
from app.return_map import ReturnMap, return_map
from app.scenes import CUSTOM, PLOTS
from app.solve.regime_map import map_ranges
from app.solve.solution import Solution
from app.state import Scales

#: The plots this package builds (the mechanism is :mod:`app.animation`'s).
BUILT_HERE = tuple(p for p in PLOTS if p != "anim")
#: What the regime map's axes depend on besides the point: a change reframes the map.
MAP_FRAME_KEYS = ("scene", "stop_type", "mu_s", "mu_k", "u_s", "units")
#: The return map of no run.
NO_RETURN = ReturnMap("", np.zeros(0), 0, np.zeros(0))
#: Mode bands of no motion.
NO_BANDS = (np.zeros(0), np.zeros(0), np.zeros(0, np.int8))
#: The plots whose sources one column builder fills from the solution: source name ->
#: key of the builder's answer (``None``: all of it).
SIMPLE_FILLS: Mapping[str, tuple[Callable[..., Any], tuple[tuple[str, str | None], ...]]] = {
    "loop": (loop_columns, (("loop", "loop"), ("comp", "comp"), ("exp", "exp"))),
    "friction": (friction_columns, (("law", "law"), ("ops", "ops"))),
    "energy": (energy_columns, (("energy", None),)),
}


class PlotSet:
    """All figures of one session and their sources.

    Attributes
    ----------
    panes : dict
        Bokeh layout of each plot id of :data:`app.scenes.PLOTS` except ``'anim'`` (built
        by :mod:`app.animation`).
    sources : dict
        ``ColumnDataSource`` by name; ``sources['traj']`` also drives the animation.
    """

    def __init__(self) -> None:
        self.shared = SharedModels()
        self.sources: dict[str, ColumnDataSource] = Sources(self.shared)
        self.spans: dict[str, Span] = {}
        self.figures: dict[str, Any] = {}
        self.legends: dict[str, pn.pane.HTML] = {}
        self.panes: dict[str, Any] = {}
        self._theory_renderers: list[Any] = []
        self.rest_axis: LinearAxis | None = None
        self.point_labels: LabelSet | None = None
        self.map_mapper = None
        #: The regime map's boundary labels by name (:mod:`app.plots.map_boundaries`).
        self.map_labels: dict[str, Any] = {}
        #: Lines the updates move (the return map's grazing line).
        self.slopes: dict[str, Any] = {}
        #: The window of a long run the time histories show, and its overview.
        self.run_window = RunWindow(self._follow_window)
        self._last: Solution | None = None
        self._scales: Scales | None = None
        self._kinds_stop: str | None = None
        self._kinds_shown: set[str] = set()
        self._dirty: set[str] = set()
        self._map_shown: Mapping[str, Any] | None = None
        self._map_scales: Scales | None = None
        self._map_frame: tuple[float, float, float] | None = None
        self._map_frame_key: tuple | None = None
        self._bands = NO_BANDS
        #: Entries appended to the phase portrait's legend (pinned runs, :mod:`app.compare`).
        self.more_legend: Any = lambda: []
        #: Values the axes show besides the current run's (the pinned runs' extents,
        #: :mod:`app.compare`): ``(figure, "x" or "y") -> values``.
        self.more_extents: Any = lambda: {}

    # --- building ------------------------------------------------------------------------

    def build(self, name: str) -> Any:
        """The Bokeh layout of the plot ``name``, built on its first call.

        A figure is built when it is first shown: a new page holds only the figures its
        scene shows (each figure is some 20-40 models to build, send and render). The
        new figure is filled from the last solution by the next :meth:`refresh`.
        """
        if name not in self.panes:
            # Built with Bokeh's checks on, also under a caller's ``validate(False)``: they
            # turn values such as a title's text into models.
            with validate(True):
                built = BUILDERS[name](self.sources)
            for fig in built.figures.values():
                self.shared.lighten(fig)
            self.figures.update(built.figures)
            self.spans.update(built.spans)
            self._theory_renderers += built.theory
            if built.legend is not None:
                self.legends[name] = built.legend
            if built.point_labels is not None:
                self.point_labels = built.point_labels
            if built.rest_axis is not None:
                self.rest_axis = built.rest_axis
            if built.map_mapper is not None:
                self.map_mapper = built.map_mapper
            self.map_labels.update(built.map_labels)
            self.slopes.update(built.slopes)
            self.panes[name] = built.layout
            self._dirty.add(name)
        return self.panes[name]

    def view(self, name: str) -> pn.viewable.Viewable:
        """The plot ``name`` for the page (built on first call, :meth:`build`): its Bokeh
        layout, and below it its legend, if it has one."""
        body = pn.pane.Bokeh(self.build(name), sizing_mode="stretch_width")
        legend = self.legends.get(name)
        if legend is None:
            return body
        return pn.Column(body, legend, margin=0, sizing_mode="stretch_width")

    @property
    def built(self) -> frozenset[str]:
        """The plots built so far."""
        return frozenset(self.panes)

    @property
    def stale(self) -> frozenset[str]:
        """The plots not filled from the last solution yet (hidden when it came)."""
        return frozenset(self._dirty)

    @property
    def last(self) -> Solution | None:
        """The solution drawn last (by :meth:`update`)."""
        return self._last

    @property
    def bands(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The mode bands of the last motion drawn (:func:`app.sampling.mode_bands`)."""
        return self._bands

    # --- updating ------------------------------------------------------------------------

    def update(self, sol: Solution, scales: Scales, visible: tuple[str, ...],
               map_data: Mapping[str, Any] | None = None) -> None:
        """Assign the new columns of every visible plot (call under ``pn.io.hold``).

        Hidden plots are marked stale and filled by :meth:`refresh` when shown.
        """
        self._last, self._scales = sol, scales
        self.run_window.choose(sol)
        self._dirty = set(PLOTS)
        self.refresh(visible, map_data)

    def forget_transition_kinds(self) -> None:
        """List only the next solution's transition kinds in the legend (a new scene)."""
        self._kinds_stop = None

    def update_preview(self, sol: Solution, scales: Scales) -> None:
        """Cheap update while a slider is dragged: the motion, and the contact force of
        the same state; the theory's overlays (points, reference curves), which a preview
        does not compute, are hidden until the full solution arrives, so that nothing on
        the plots belongs to another state."""
        self._set_theory_visible(False)
        assign(self.sources["start"], {"x": [sol.x0 * scales.length],
                                       "v": [sol.v0 * scales.velocity]})
        self._draw_motion(sol, scales)
        self._fill_force(sol, scales, preview=True)
        self._set_spans(sol, scales)
        self._set_ranges({"phase", "time", "force"} & self.built, sol)

    def _draw_motion(self, sol: Solution, scales: Scales) -> None:
        """The phase path, the transitions it passes, and the time histories."""
        s = self.sources
        step = self._phase_step(sol, scales)
        traj = trajectory_columns(sol, scales, window=self.run_window.window)
        self._bands = traj.pop("bands", NO_BANDS)
        assign(s["traj"], traj)
        phase = phase_columns(sol, scales, step)
        for name in MODE_NAMES.values():
            assign(s[f"path_{name}"], phase[name])
        assign(s["repeat"], phase["repeat"])
        assign(s["trans"], transition_columns(sol, scales, phase["t_draw"]))

    def refresh_legend(self) -> None:
        """Write the phase portrait's legend again (its entries changed, not its data)."""
        if "phase" in self.legends:
            text = legend_html(phase_entries(SourceData(self.sources), self._kinds_shown)
                               + list(self.more_legend()))
            if self.legends["phase"].object != text:
                self.legends["phase"].object = text

    def _set_theory_visible(self, visible: bool) -> None:
        for r in self._theory_renderers:
            if r.visible != visible:
                r.visible = visible

    def _phase_step(self, sol: Solution, scales: Scales) -> tuple[float, float]:
        """Chord bound of the phase path (:func:`app.plots.columns.phase_step`) for a view
        that shows the motion and the reference curves (dimensionless)."""
        (x0, x1), (v0, v1) = sample_bounds(sol)
        for name in ("gamma0", "cycle"):
            ref = self.sources[name].data
            if len(ref["x"]):
                xr = np.asarray(ref["x"], float) / scales.length
                x0, x1 = min(x0, float(np.min(xr))), max(x1, float(np.max(xr)))
                vr = np.asarray(ref["v"], float) / scales.velocity
                vr = vr[np.isfinite(vr)]
                if len(vr):
                    v0, v1 = min(v0, float(vr.min())), max(v1, float(vr.max()))
        return phase_step((x0, x1), (v0, v1))

    def refresh(self, visible: tuple[str, ...], map_data: Mapping[str, Any] | None = None
                ) -> None:
        """Fill the stale sources of the ``visible`` plots from the last solution (building
        those not built yet)."""
        for name in visible:
            if name in BUILT_HERE:
                self.build(name)
        sol = self._last
        if sol is None:
            return
        scales = self._scales
        # Only built figures (and the mechanism, which reads the trajectory) are filled;
        # a plot built later is stale until the refresh after it (:meth:`build`).
        todo = self._dirty.intersection(visible).intersection({*self.panes, "anim"})
        if todo & {"phase", "time", "anim", "friction"}:
            self._fill_motion(sol, scales)
        if "time" in todo:
            assign(self.sources["bands"], band_columns(self._bands, scales))
            self._show_overview(sol, scales)
        if "force" in todo:
            self._fill_force(sol, scales)
        for name, (columns, targets) in SIMPLE_FILLS.items():
            if name in todo:
                cols = columns(sol, scales)
                for source, key in targets:
                    assign(self.sources[source], cols if key is None else cols[key])
        if "map" in todo and map_data is not None:
            self._set_map(sol, scales, map_data)
        if "return" in todo:
            self._fill_return(sol, scales)
        self._dirty -= todo - ({"map"} if map_data is None else set())
        self._set_spans(sol, scales)
        set_axis_labels(self.figures, self.rest_axis, sol, scales)
        self._set_ranges(todo, sol)

    def _fill_motion(self, sol: Solution, scales: Scales) -> None:
        """The motion, the theory's references and points, and the phase portrait's
        legend."""
        s = self.sources
        self._set_theory_visible(True)
        refs = reference_columns(sol, scales)
        for name in ("gamma0", "cycle", "removed"):
            assign(s[name], refs[name])
        assign(s["start"], {"x": [sol.x0 * scales.length], "v": [sol.v0 * scales.velocity]})
        self._draw_motion(sol, scales)
        assign(s["points"], applicable_points(refs["points"], s["path_stick"].data,
                                              s["trans"].data["kind"]))
        # Entries stay once shown (until the stop type changes): a legend that changes
        # size relayouts and repaints its figure once more after each release.
        stop_type = sol.values["stop_type"]
        if stop_type != self._kinds_stop:
            self._kinds_stop, self._kinds_shown = stop_type, set()
        self._kinds_shown.update(s["trans"].data["kind"])
        self.refresh_legend()
        self._dirty -= {"phase", "anim"}

    def _show_overview(self, sol: Solution, scales: Scales) -> None:
        """The whole run's overview below the time histories, for a long run."""
        traj = self.sources["traj"].data
        self.run_window.show_overview(
            self.panes["time"], self.figures["time_x"].x_range,
            self.sources["traj"], (0.0, sol.t_end * scales.time),
            data_bounds((traj["x"],), RANGE_PADDING))

    def _follow_window(self) -> None:
        """The brush moved the window: the histories, bands and time axes sampled for it
        again (the phase portrait and the other plots stay)."""
        sol, scales = self._last, self._scales
        if sol is None or "time" not in self.panes:
            return
        with pn.io.hold(), validate(False):
            traj = trajectory_columns(sol, scales, window=self.run_window.window)
            self._bands = traj.pop("bands", NO_BANDS)
            assign(self.sources["traj"], traj)
            assign(self.sources["bands"], band_columns(self._bands, scales))
            self._set_window_ranges(sol, scales, {"force", "energy"} & self.built)

    def _set_window_ranges(self, sol: Solution, scales: Scales, plots: set[str]) -> None:
        """The time axes of ``plots`` (force, energy) on the window, where it is one."""
        shown = self.run_window.shown(scales.time)
        if shown is None or sol.program is not None:
            return
        for name in plots:
            set_range(self.figures[name].x_range, (shown,), 0.0)

    def _fill_return(self, sol: Solution, scales: Scales) -> None:
        """The return map of the impacts, contacts or stick onsets."""
        rmap = (return_map(sol.result, sol.values["stop_type"], sol.t_end,
                           phase_step(*sample_bounds(sol)))
                if sol.result is not None else NO_RETURN)
        draw_return(self.figures["return"], self.sources, self.slopes["grazing"],
                    self.legends["return"], rmap, sol.values.get("restitution"), scales)

    def _fill_force(self, sol: Solution, scales: Scales, preview: bool = False) -> None:
        """The contact force; its rest axis comes and goes with the full solutions only
        (a drag does not lay the figure out again)."""
        cols = force_columns(sol, scales)
        assign(self.sources["stems"], cols["stems"])
        assign(self.sources["force"], cols["line"])
        assign(self.sources["rest"], cols["rest"])
        if self.rest_axis is not None and not preview:
            self.rest_axis.visible = bool(np.isfinite(cols["rest"]["f"]).any())

    def map_frame(self, values: Mapping[str, Any]) -> tuple[float, float, float]:
        """Axes ``(v_hi, x_lo, x_hi)`` of the regime map, stable for a scene: computed
        (:func:`app.solve.regime_map.map_ranges`) when what the map's axes depend on besides the
        point changes (scene, stop type, friction, units), kept when the point moves (a
        tap, a slider) or the start moves, and widened only to keep the point in view."""
        key = tuple(values.get(name) for name in MAP_FRAME_KEYS)
        if values.get("scene") == CUSTOM and self._map_frame_key is not None:
            # A parameter moved off the scene: the scene's frame stays.
            key = (self._map_frame_key[0], *key[1:])
        v, x = values["belt_speed"], values["clearance"]
        frame = self._map_frame
        if frame is None or key != self._map_frame_key:
            frame = map_ranges(values)
        elif not (0.0 <= v <= frame[0] and frame[1] <= x <= frame[2]):
            new = map_ranges(values)
            frame = (max(frame[0], new[0]), min(frame[1], new[1]), max(frame[2], new[2]))
        self._map_frame, self._map_frame_key = frame, key
        return frame

    def show_map(self, map_data: Mapping[str, Any]) -> None:
        """Draw the regime map of the last solution, computed after the rest of its update
        was sent (:meth:`app.explorer.Explorer._draw`); call under ``pn.io.hold``."""
        if self._last is not None and "map" in self.panes:
            self._set_map(self._last, self._scales, map_data)
            self._dirty.discard("map")

    def _set_ranges(self, plots: set[str] | frozenset[str], sol: Solution) -> None:
        """Axis ranges of the ``plots`` from the data just assigned (call in the same
        ``pn.io.hold``): computed on the server and sent with the data, so the browser
        paints each figure once, instead of computing ``DataRange1d`` bounds and echoing
        them back, which costs further messages and repaints."""
        d = SourceData(self.sources)
        f = self.figures
        plots = set(plots) & self.built
        more = self.more_extents() if plots & {"time", "force", "loop"} else {}
        stop = (stop_in_view(d["traj"]["x"], sol, self._scales.length)
                if plots & {"phase", "time"} else [])
        if "phase" in plots:  # ranges fitted in the browser (match_aspect); the stop:
            assign(self.sources["stop_pt"], {"x": stop, "v": [0.0] * len(stop)})
        if "time" in plots:
            traj = d["traj"]
            window = self.run_window.shown(self._scales.time)
            if window is None:
                set_range(f["time_x"].x_range, (traj["t"], more.get(("time_x", "x"), ())), 0.0)
            else:
                self.run_window.place(f["time_x"].x_range, window)
            set_range(f["time_x"].y_range, (traj["x"], stop, more.get(("time_x", "y"), ())),
                      RANGE_PADDING)
            set_range(f["time_v"].y_range, (traj["v"], more.get(("time_v", "y"), ())),
                      RANGE_PADDING)
        if "force" in plots:
            set_range(f["force"].x_range, (d["stems"]["t"], d["force"]["t"], d["rest"]["t"],
                                           more.get(("force", "x"), ())), RANGE_PADDING)
            set_range(f["force"].y_range, ((0.0,), d["stems"]["j"], d["force"]["phi"],
                                           more.get(("force", "y"), ())), RANGE_PADDING)
            set_range(f["force"].extra_y_ranges["rest"], ((0.0,), d["rest"]["f"]),
                      RANGE_PADDING)
        if "loop" in plots:
            set_range(f["loop"].x_range, (d["loop"]["d"], d["comp"]["d"], d["exp"]["d"],
                                          more.get(("loop", "x"), ())), RANGE_PADDING)
            set_range(f["loop"].y_range, (d["loop"]["phi"], more.get(("loop", "y"), ())),
                      RANGE_PADDING)
        if "friction" in plots:
            set_range(f["friction"].x_range, (d["law"]["u"], d["ops"]["u"]), RANGE_PADDING)
            set_range(f["friction"].y_range, (d["law"]["f"], d["ops"]["f"]), RANGE_PADDING)
        if "energy" in plots:
            energy = d["energy"]
            set_range(f["energy"].x_range, (energy["t"],), RANGE_PADDING)
            set_range(f["energy"].y_range, tuple(energy[n] for n in ENERGY_COLORS),
                      RANGE_PADDING)
        self._set_window_ranges(sol, self._scales, {"force", "energy"} & plots)

    def fit_ranges(self) -> None:
        """Fit the axes of the built, up-to-date figures again (what :attr:`more_extents`
        gives changed: a pin came or went); call under ``pn.io.hold``."""
        if self._last is not None:
            self._set_ranges(self.built - self._dirty, self._last)

    def _set_spans(self, sol: Solution, scales: Scales) -> None:
        has_stop = sol.stop is not None
        for name in ("stop", "stop_t"):
            if name in self.spans:
                span = self.spans[name]
                span.visible = has_stop
                span.location = sol.stop.clearance * scales.length if has_stop else 0.0
        for name in ("belt", "belt_t"):
            if name in self.spans:
                self.spans[name].location = sol.osc.v * scales.velocity

    def _set_map(self, sol: Solution, scales: Scales, data: Mapping[str, Any]) -> None:
        v_hi = data["v_hi"] * scales.velocity
        x_lo, x_hi = data["x_lo"] * scales.length, data["x_hi"] * scales.length
        if data is not self._map_shown or scales is not self._map_scales:  # cached maps
            self._map_shown, self._map_scales = data, scales
            codes = np.asarray(data["codes"]) % len(MAP_PALETTE)
            self.sources["map"].data = {"image": [codes.astype(np.float32)], "x": [0.0],
                                        "y": [x_lo], "dw": [v_hi], "dh": [x_hi - x_lo]}
            self._set_boundaries(boundary_columns(
                sol.values, (data["v_hi"], data["x_lo"], data["x_hi"]), scales.velocity,
                scales.length))
        fig = self.figures["map"]
        fig.x_range.update(start=0.0, end=v_hi)
        fig.y_range.update(start=x_lo, end=x_hi)
        # Without a stop the regime does not depend on the clearance: no clearance axis.
        has_stop = sol.values["stop_type"] != "none"
        if fig.yaxis[0].visible != has_stop:
            fig.yaxis[0].visible = has_stop
        clearance = sol.values["clearance"] * scales.length
        assign(self.sources["here"], {"v": [sol.osc.v * scales.velocity], "x": [clearance]})

    def _set_boundaries(self, cols: Mapping[str, list]) -> None:
        """Draw the regime map's boundary lines and name each at its end."""
        assign(self.sources["bounds"], cols)
        at = {text: i for i, text in enumerate(cols["text"])}
        for name, label in self.map_labels.items():
            i = at.get(name)
            if i is None:
                label.visible = False
                continue
            label.update(x=cols["lx"][i], y=cols["ly"][i], x_offset=cols["dx"][i],
                         y_offset=cols["dy"][i], text_align=cols["align"][i],
                         text_baseline=cols["baseline"][i], visible=True)
