"""The sweep card of a session: the bifurcation diagram, its controls, the map layers' boxes.

The view is built when the user first opens it (a new page holds none of its models). A
sweep runs in the solver's worker pool, one chunk of parameter values at a time
(:class:`app.bifurcation.chunks.ChunkedSweep`): each chunk's answer is drawn on the
session's event loop, and the next chunk is submitted only then, so a cancel (or a new
sweep) stops the work after the chunk that is running. A sweep of more than
:data:`DENSITY_SAMPLES` samples is drawn as a 2-D histogram (one image) instead of one
marker per sample. A sweep has a budget (:mod:`app.sweep_budget`): its card says it before
the sweep starts, and a sweep stopped at it keeps what it has and says so.

The theory is drawn on the diagram (:mod:`app.bifurcation.theory_lines`, docs/physics.md).
"""

from __future__ import annotations

import html
import math
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import panel as pn
from bokeh.events import Tap
from bokeh.models import ColumnDataSource, LabelSet, LinearColorMapper, Range1d, Span
from bokeh.plotting import figure

from app import sweep_budget as budget
from app.bifurcation.chunks import CHUNK_SECONDS, FIRST_CHUNK, ChunkedSweep
from app.bifurcation.map_layers import MapLayers
from app.bifurcation.spec import (
    DEFAULT_POINTS,
    DENSITY_SAMPLES,
    MAX_POINTS,
    PER_POINT,
    QUANTITY_LABELS,
    UNITS_NOTE,
    AxisUnits,
    Points,
    SweepSpec,
    applicable_parameters,
    applicable_quantities,
    axis_units,
    check_spec,
    closed_form,
    default_quantity,
    default_range,
    density,
    parameter_name,
    quantity_name,
    sweep_cost,
    sweep_points,
)
from app.bifurcation.style import (
    CURRENT_COLOR,
    DENSITY_PALETTE,
    FIGURE_HEIGHT,
    LABEL_COLORS,
    THEORY_COLOR,
)
from app.bifurcation.theory_lines import theory_lines
from app.state import DIMENSIONLESS, Scales
from app.widgets import on_click
from core import sweep as sweeps


class BifurcationView:
    """The sweep card of one session: the bifurcation diagram and its controls, and the
    check boxes of the regime map's simulated layers (:class:`MapLayers`, drawn on the
    explorer's map figure).

    Parameters
    ----------
    values : callable() -> Mapping
        The explorer's current solve values.
    on_pick : callable(parameter, value)
        Load a tapped parameter value into the explorer.
    map_figure : callable() -> figure or None
        The explorer's regime map figure, built if need be (``None`` if it cannot show).
    map_frame : callable() -> (v_hi, x_lo, x_hi)
        The regime map's axes.
    shared : app.plots.SharedModels, optional
        The page's shared ticker, scale, filter... (fewer models to send).
    scales : app.state.Scales, optional
        The page's units (:meth:`set_scales` changes them): the boxes, axes and tap are
        in them; the sweep itself runs on the core's dimensionless numbers.
    on_layers : callable(), optional
        Called when the map's simulated layers appear or go (the map's legend says which
        colours are on top).
    """

    def __init__(self, values: Callable[[], Mapping[str, Any]],
                 on_pick: Callable[[str, float], None],
                 map_figure: Callable[[], Any], map_frame: Callable[[], tuple],
                 shared: Any = None, scales: Scales = DIMENSIONLESS,
                 on_layers: Callable[[], None] | None = None) -> None:
        self._values, self.on_pick, self._shared = values, on_pick, shared
        self.scales = scales
        #: The regime map's simulated layers.
        self.layers = MapLayers(lambda: self._values(), map_figure, map_frame, shared,
                                on_layers)
        self.layers.scales = scales
        vals = values()
        params = applicable_parameters(vals)
        self.parameter = pn.widgets.Select(
            label="Swept parameter", options=self._parameter_options(params),
            value="belt_speed", width=200, css_classes=["fie-bif-parameter"])
        lo, hi = self._shown_range(default_range(vals, "belt_speed"), "belt_speed")
        self.lo = pn.widgets.FloatInput(label="from", value=_round(lo), width=110,
                                        css_classes=["fie-bif-lo"])
        self.hi = pn.widgets.FloatInput(label="to", value=_round(hi), width=110,
                                        css_classes=["fie-bif-hi"])
        self.points = pn.widgets.IntInput(label="points", start=2, value=min(
            DEFAULT_POINTS, max(budget.max_points(**sweep_cost(vals)), 2)),
                                          end=MAX_POINTS, width=110,
                                          css_classes=["fie-bif-points"])
        self.quantity = pn.widgets.Select(
            label="On the y axis", value=default_quantity(vals), width=260,
            options=self._quantity_options(applicable_quantities(vals)),
            css_classes=["fie-bif-quantity"])
        self.run = pn.widgets.Button(label="Sweep", color="primary", width=90,
                                     css_classes=["fie-bif-run"])
        self.stop = pn.widgets.Button(label="Cancel", width=90, disabled=True,
                                      css_classes=["fie-bif-cancel"])
        self.progress = pn.indicators.Progress(value=0, max=100, width=260, height=14,
                                               bar_color="primary",
                                               css_classes=["fie-bif-progress"])
        self.status = pn.pane.HTML("", sizing_mode="stretch_width",
                                   css_classes=["fie-bif-status"])
        #: The check boxes of the map's layers and what they say (:class:`MapLayers`).
        self.sim_layer, self.disagree_layer = self.layers.sim_layer, self.layers.disagree_layer
        self.map_status, self.map_job = self.layers.status, self.layers.job
        self.parameter.param.watch(self._on_parameter, "value")
        on_click(self.run, lambda e: self.start())
        on_click(self.stop, lambda e: self.cancel())
        self._build_figure()
        self.job = ChunkedSweep(self._work, self._on_chunk, self._failed, self._cut)
        self.spec: SweepSpec | None = None
        self.parts: list[Points] = []
        self.data = Points.join([])
        self._started = 0.0
        #: Wall time [s] of the last complete sweep, from its request to its last chunk.
        self.last_seconds: float | None = None
        self.layout = pn.Card(
            pn.Row(self.parameter, self.lo, self.hi, self.points, margin=0),
            pn.Row(self.quantity, self.run, self.stop, self.progress, margin=0),
            self.status, pn.pane.Bokeh(self.fig, sizing_mode="stretch_width"),
            pn.Row(self.sim_layer, self.disagree_layer, margin=0), self.map_status,
            title=self._title(),
            sizing_mode="stretch_width", collapsible=True, css_classes=["fie-bifurcation"],
            styles={"flex": "1 1 100%"}, margin=(4, 8))

    def _parameter_options(self, params: list[str]) -> dict[str, str]:
        return {parameter_name(p, self.scales): p for p in params}

    def _quantity_options(self, quantities: list[str]) -> dict[str, str]:
        return {quantity_name(q, self.scales): q for q in quantities}

    def _title(self) -> str:
        units = "SI units" if self.scales.si else UNITS_NOTE
        return f"Bifurcation diagram and regime map from simulation ({units})"

    def _units(self, spec: SweepSpec | None = None) -> AxisUnits:
        """The :class:`AxisUnits` of ``spec`` (default: the controls' parameter and
        quantity) in the page's units."""
        if spec is not None:
            return axis_units(spec.parameter, spec.quantity, self.scales)
        return axis_units(self.parameter.value, self.quantity.value, self.scales)

    def _shown_range(self, lo_hi: tuple[float, float], parameter: str) -> tuple[float, float]:
        """A dimensionless range of ``parameter`` as the boxes show it (rounded)."""
        factor = axis_units(parameter, "x_max", self.scales).parameter
        return _round(lo_hi[0] * factor), _round(lo_hi[1] * factor)

    def set_scales(self, scales: Scales) -> None:
        """Show the card in other units: the boxes' range is converted, the diagram, its
        theory lines and the map's simulated layers are drawn again (nothing is swept)."""
        if scales == self.scales:
            return
        old = axis_units(self.parameter.value, self.quantity.value, self.scales).parameter
        self.scales = scales
        new = self._units().parameter
        with pn.io.hold():
            if new != old:
                self.lo.value = _round(float(self.lo.value) / old * new)
                self.hi.value = _round(float(self.hi.value) / old * new)
            self.layout.title = self._title()
            self.parameter.options = self._parameter_options(list(self.parameter.values))
            self.quantity.options = self._quantity_options(list(self.quantity.values))
            spec = self.spec
            if spec is not None:
                self._draw_axes(spec)
                self._draw_theory(spec)
                self._draw_points(spec, self.data)
                self.current.location = float(spec.values[spec.parameter]) * \
                    self._units(spec).parameter
                if len(self.data.swept) == spec.n and self.stop.disabled:
                    # A finished sweep's status names the parameter in the new units.
                    self._set_status(self._finished_status(spec, self.data, spec.n),
                                     done=True)
            self.layers.scales = scales
            if self.layers.sim_map is not None and self.layers.renderers is not None:
                self.layers.show()

    def _build_figure(self) -> None:
        fig = figure(height=FIGURE_HEIGHT, sizing_mode="stretch_width",
                     tools="pan,wheel_zoom,box_zoom,reset,save", toolbar_location="right",
                     x_range=Range1d(0, 1), y_range=Range1d(0, 1),
                     title="Bifurcation diagram (tap a point to load its parameter value)",
                     output_backend="canvas")
        fig.toolbar.logo = None
        fig.title.text_font_size = "14px"
        for axis in (*fig.xaxis, *fig.yaxis):
            axis.axis_label_text_font_size = "13px"
            axis.major_label_text_font_size = "12px"
        self.source = ColumnDataSource({"x": [], "y": [], "color": []})
        self.image_source = ColumnDataSource({"image": [], "x": [], "y": [], "dw": [],
                                              "dh": []})
        self.vlines = ColumnDataSource({"x": [], "text": []})
        self.hlines = ColumnDataSource({"y": [], "text": []})
        self.mapper = LinearColorMapper(palette=list(DENSITY_PALETTE), nan_color=(0, 0, 0, 0))
        self.image = fig.image(image="image", x="x", y="y", dw="dw", dh="dh",
                               source=self.image_source, color_mapper=self.mapper)
        self.scatter = fig.scatter("x", "y", source=self.source, size=3, color="color",
                                   alpha=0.8, line_width=0)
        fig.vspan(x="x", source=self.vlines, line_color=THEORY_COLOR, line_dash="dashed",
                  line_width=1)
        fig.hspan(y="y", source=self.hlines, line_color=THEORY_COLOR, line_dash="dotted",
                  line_width=1)
        fig.add_layout(LabelSet(x="x", y=6, y_units="screen", text="text", source=self.vlines,
                                angle=math.pi / 2, x_offset=-3, text_font_size="11px",
                                text_color=THEORY_COLOR, text_baseline="bottom",
                                background_fill_color="#ffffff", background_fill_alpha=0.7))
        fig.add_layout(LabelSet(x=6, x_units="screen", y="y", text="text", source=self.hlines,
                                y_offset=2, text_font_size="11px", text_color=THEORY_COLOR,
                                background_fill_color="#ffffff", background_fill_alpha=0.7))
        self.current = Span(dimension="height", location=0.0, line_color=CURRENT_COLOR,
                            line_width=2, line_alpha=0.8)
        fig.add_layout(self.current)
        fig.on_event(Tap, self._on_tap)
        if self._shared is not None:
            self._shared.lighten(fig)
            for src in (self.source, self.image_source, self.vlines, self.hlines):
                src.selection_policy = self._shared.policy
        self.fig = fig

    # --- sweep -------------------------------------------------------------------------

    def _on_parameter(self, event) -> None:
        self.lo.value, self.hi.value = self._shown_range(
            default_range(self._values(), event.new), event.new)

    def start(self) -> None:
        """Sweep with the controls' settings (a running sweep is cancelled)."""
        values = self._values()
        factor = self._units().parameter
        try:
            spec = check_spec(values, self.parameter.value, float(self.lo.value) / factor,
                              float(self.hi.value) / factor, int(self.points.value),
                              self.quantity.value)
        except (ValueError, TypeError) as exc:
            self.job.cancel()
            note = (f" (the core's dimensionless values; the boxes show {factor:.4g} times"
                    " them)" if factor != 1.0 else "")
            self._set_status(html.escape(f"Not swept: {exc}{note}"), error=True)
            return
        self.spec, self.parts, self.data = spec, [], Points.join([])
        self._started = time.perf_counter()
        self.last_seconds = None
        with pn.io.hold():
            self.source.data = {"x": [], "y": [], "color": []}
            self.image_source.data = {"image": [], "x": [], "y": [], "dw": [], "dh": []}
            self._draw_axes(spec)
            self._draw_theory(spec)
            self.current.location = float(values[spec.parameter]) * self._units(spec).parameter
            self.progress.value = 0
            self.stop.disabled = False
            estimate = budget.estimate_s(spec.n, **sweep_cost(values))
            self._set_status(f"Sweeping {spec.n} values of "
                             f"{parameter_name(spec.parameter, self.scales)} "
                             f"({budget.budget_note(estimate)})…")
        kind = "closed" if closed_form(values) else "integrated"
        self.job.start(spec, spec.grid(), FIRST_CHUNK[kind], values, CHUNK_SECONDS[kind],
                       budget.SWEEP_BUDGET_S)

    def cancel(self) -> None:
        """Stop the running sweep; what was computed stays drawn."""
        if not self.job.running:
            return
        self.job.cancel()
        done = len(self.data.swept)
        self.stop.disabled = True
        total = self.spec.n if self.spec else 0
        self._set_status(f"Cancelled after {done} of {total} values.")

    def close(self) -> None:
        """The page closed: stop the sweep and the simulated map (a chunk in a solver
        process is stopped)."""
        self.job.cancel()
        self.layers.close()

    @property
    def sim_map(self):
        """The last simulated regime map (:attr:`MapLayers.sim_map`)."""
        return self.layers.sim_map

    @property
    def sim_layer_shown(self) -> bool:
        """Whether the simulated steady states cover the regime map now."""
        return self.layers.sim_layer_shown

    @staticmethod
    def _work(spec: SweepSpec, chunk: np.ndarray, cancelled: threading.Event) -> Points:
        return sweep_points(spec.values, spec.parameter, chunk, spec.quantity, cancelled)

    def _on_chunk(self, done: int, total: int, part: Points) -> None:
        spec = self.spec
        self.parts.append(part)
        self.data = data = Points.join(self.parts)
        with pn.io.hold():
            self._draw_points(spec, data)
            self.progress.value = int(round(100 * done / total))
            if done >= total:
                self.last_seconds = time.perf_counter() - self._started
                self.stop.disabled = True
                self._set_status(self._finished_status(spec, data, total), done=True)
            else:
                self._set_status(f"{done} of {total} values of "
                                 f"{parameter_name(spec.parameter, self.scales)}… (at most "
                                 f"{budget.SWEEP_BUDGET_S:g} s)")

    def _cut(self, done: int, total: int) -> None:
        """The sweep's budget ran out: what it has stays drawn, the card says so."""
        spec = self.spec
        self.last_seconds = time.perf_counter() - self._started
        self.stop.disabled = True
        reached = (f" ({parameter_name(spec.parameter, self.scales)} swept up to "
                   f"{float(self.data.swept.max()) * self._units(spec).parameter:.4g})"
                   if len(self.data.swept) else "")
        self._set_status(budget.cut_note(done, total) + reached, done=True)

    def _finished_status(self, spec: SweepSpec, data: Points, total: int) -> str:
        """What a complete sweep found, in the card's units."""
        counts = {k: int(np.sum(data.swept_label == k)) for k in sweeps.LABELS}
        found = ", ".join(f"{v} {k}" for k, v in counts.items() if v)
        return (f"{total} of {total} values of {parameter_name(spec.parameter, self.scales)} "
                f"in {self.last_seconds:.2f} s: {len(data.y)} samples "
                f"({'density image' if len(data.y) > DENSITY_SAMPLES else 'points'}); "
                f"steady states: {found}.{missing_note(data, spec)} {legend_text()}")

    def _draw_axes(self, spec: SweepSpec) -> None:
        units = self._units(spec)
        self.fig.x_range.update(start=spec.lo * units.parameter, end=spec.hi * units.parameter)
        self.fig.xaxis.axis_label = units.parameter_label
        self.fig.yaxis.axis_label = units.quantity_label

    def _draw_points(self, spec: SweepSpec, data: Points) -> None:
        units = self._units(spec)
        if units.parameter != 1.0 or units.quantity != 1.0:
            data = Points(data.x * units.parameter, data.y * units.quantity, data.label,
                          data.swept * units.parameter, data.swept_label)
        finite = np.isfinite(data.y)
        if finite.any():
            lo, hi = float(data.y[finite].min()), float(data.y[finite].max())
            pad = 0.06 * (hi - lo) if hi > lo else 0.5
            self.fig.y_range.update(start=lo - pad, end=hi + pad)
        if len(data.y) > DENSITY_SAMPLES:
            self.source.data = {"x": [], "y": [], "color": []}
            self.image_source.data = density(
                data, (spec.lo * units.parameter, spec.hi * units.parameter))
            self.mapper.update(low=0.0, high=float(np.nanmax(
                self.image_source.data["image"][0])) or 1.0)
        else:
            self.image_source.data = {"image": [], "x": [], "y": [], "dw": [], "dh": []}
            self.source.data = {"x": data.x, "y": data.y,
                                "color": [LABEL_COLORS.get(k, "#000000") for k in data.label]}

    def _draw_theory(self, spec: SweepSpec) -> None:
        try:
            vertical, horizontal = theory_lines(spec.values, spec.parameter, spec.lo,
                                                spec.hi, spec.quantity)
        except ValueError:
            vertical, horizontal = [], []
        units = self._units(spec)
        self.vlines.data = {"x": [x * units.parameter for x, _ in vertical],
                            "text": [t for _, t in vertical]}
        self.hlines.data = {"y": [y * units.quantity for y, _ in horizontal],
                            "text": [t for _, t in horizontal]}

    def _failed(self, exc: Exception) -> None:
        self.stop.disabled = True
        self._set_status(f"The sweep failed: {type(exc).__name__}: {exc}", error=True)

    def _set_status(self, text: str, *, error: bool = False, done: bool = False) -> None:
        cls = "fie-bif-error" if error else ("fie-bif-done" if done else "fie-bif-running")
        self.status.object = f"<div class='{cls}'>{text}</div>"

    def pick(self, x: float) -> float | None:
        """The swept value (the core's number) nearest the parameter value ``x`` as the
        diagram shows it (a tap, in the page's units), or None."""
        swept = self.data.swept
        if len(swept) == 0 or self.spec is None or x is None or not math.isfinite(x):
            return None
        x = x / self._units(self.spec).parameter
        return float(swept[int(np.argmin(np.abs(swept - x)))])

    def tap(self, x: float) -> None:
        """Load the swept value nearest the parameter value ``x`` as the diagram shows it
        (:meth:`pick`) into the explorer, and mark it."""
        value = self.pick(x)
        if value is None or self.spec is None:
            return
        self.current.location = value * self._units(self.spec).parameter
        self.on_pick(self.spec.parameter, value)

    def _on_tap(self, event: Tap) -> None:
        self.tap(event.x)

    def on_solution(self, values: Mapping[str, Any]) -> None:
        """The explorer solved new values: move the current value's line; a diagram of
        another scene (any value but the swept one changed) is swept again."""
        spec = self.spec
        if spec is not None:
            if spec.parameter in values:
                self.current.location = (float(values[spec.parameter])
                                         * self._units(spec).parameter)
            others = {k: v for k, v in values.items() if k != spec.parameter}
            if others != {k: v for k, v in spec.values.items() if k != spec.parameter}:
                self._refresh_options(values)
                self.start()
        if self.layers.wanted:
            self.layers.changed()

    def _refresh_options(self, values: Mapping[str, Any]) -> None:
        params = applicable_parameters(values)
        self.parameter.options = self._parameter_options(params)
        if self.parameter.value not in params:
            self.parameter.value = params[0]
        quantities = applicable_quantities(values)
        self.quantity.options = self._quantity_options(quantities)
        if self.quantity.value not in quantities:
            self.quantity.value = default_quantity(values)


def missing_note(data: Points, spec: SweepSpec) -> str:
    """A note when some or all points have no sample of the quantity: the samples are
    those of one steady period (e.g. no impact at rest)."""
    if spec.quantity in PER_POINT:
        missing = len(data.swept) - len(data.y)
    else:
        missing = len(data.swept) - len(np.unique(data.x))
    if missing <= 0:
        return ""
    name = QUANTITY_LABELS[spec.quantity]
    if not len(data.y):
        return (f" No point has a sample of '{name}': choose another quantity (steady "
                "x_max, the period).")
    return (f" {missing} of {len(data.swept)} values have no sample of '{name}': the samples "
            "are those of the steady motion (none at rest, none where nothing settled).")


def legend_text() -> str:
    """What the diagram's colours and lines mean (the status line of a finished sweep)."""
    # Swatches, not coloured words: the pale colours are not read as text on white.
    colours = ", ".join(
        f"<span style='white-space:nowrap'><i style='display:inline-block;width:10px;"
        f"height:10px;background:{c};margin-right:3px'></i>{k}</span>"
        for k, c in LABEL_COLORS.items())
    return (f"Colours: {colours}. <span style='color:{CURRENT_COLOR}'>Red line</span>: the "
            "explorer's value; dashed: the theory's boundaries (each labelled with the regime "
            "that follows it), dotted: a, b, the stop.")


def _round(x: float) -> float:
    """``x`` to 4 significant digits (a box the user reads)."""
    return float(f"{x:.4g}")
