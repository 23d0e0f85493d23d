"""The explorer's figures, each built on the page's sources with what the updates need of it.

A builder takes the sources by name and returns a :class:`Built`: the layout the page
shows, the figures by key, and the models the updates change (spans, the rest axis, the
theory's renderers that a preview hides, the point labels, the map's colour mapper, the
legend below). :func:`set_axis_labels` writes the axes' labels in the page's units.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import panel as pn
from bokeh.layouts import column
from bokeh.models import (
    ColumnDataSource,
    DataRange1d,
    Grid,
    Label,
    LabelSet,
    LinearAxis,
    LinearColorMapper,
    Range1d,
    Span,
)
from bokeh.plotting import figure

from app.glyphs import add_glyph
from app.plots.columns import FORCE_TITLE, IMPULSES, force_quantity
from app.plots.labels import place_labels
from app.plots.legends import (
    band_entries,
    legend_html,
    legend_pane,
    swatch,
)
from app.plots.map_boundaries import LABEL_CORNERS
from app.plots.ranges import PHASE_X_PADDING
from app.plots.return_figure import build_return
from app.plots.style import (
    AXIS_LABEL_FONT,
    BAND_LEGEND_PX,
    ENERGY_COLORS,
    LABEL_FONT_PX,
    MAP_PALETTE,
    MAP_SIZE,
    MODE_COLORS,
    MODE_NAMES,
    PHASE_SIZE,
    PHASE_STYLE,
    PLOT_WIDTHS,
    REST_COLOR,
    SMALL_SIZE,
    TICK_LABEL_FONT,
    TIME_SIZE,
    TITLE_FONT,
    TOOLS,
)
from app.solve.solution import Solution
from app.state import Scales

#: Half height of the mode bands: far outside any data, kept out of the auto range.
BAND_EXTENT = 1e6
#: The theory's boundaries over the regime map: thin, dark, dashed (over any class colour).
BOUNDARY_STYLE = {"line_color": "#333333", "line_width": 1.5, "line_dash": "dashed"}

Sources = Mapping[str, ColumnDataSource]


@dataclass
class Built:
    """One plot as built: its ``layout``, its ``figures`` by key, and the models that the
    updates change."""

    layout: Any
    figures: dict[str, Any]
    spans: dict[str, Span] = field(default_factory=dict)
    legend: pn.pane.HTML | None = None
    #: Renderers of the theory, hidden while a preview (which has no theory) is drawn.
    theory: list[Any] = field(default_factory=list)
    point_labels: LabelSet | None = None
    rest_axis: LinearAxis | None = None
    map_mapper: LinearColorMapper | None = None
    #: The regime map's boundary labels by name.
    map_labels: dict[str, Label] = field(default_factory=dict)
    #: Lines the updates move (the return map's grazing line).
    slopes: dict[str, Any] = field(default_factory=dict)


def new_figure(title: str, size: tuple[int, int], **kw) -> Any:
    """A figure of the page's look: its fonts, tools and widths."""
    kw.setdefault("x_range", Range1d(0.0, 1.0))
    kw.setdefault("y_range", Range1d(0.0, 1.0))
    fig = figure(title=title, width=size[0], height=size[1], tools=TOOLS,
                 toolbar_location="right", output_backend="canvas",
                 sizing_mode="stretch_width", min_width=PLOT_WIDTHS[0],
                 max_width=PLOT_WIDTHS[1], **kw)
    fig.title.text_font_size = TITLE_FONT
    fig.toolbar.logo = None
    # Ticker, formatter and label policy: the shared ones (SharedModels.lighten).
    for axis in (*fig.xaxis, *fig.yaxis):
        axis.axis_label_text_font_size = AXIS_LABEL_FONT
        axis.major_label_text_font_size = TICK_LABEL_FONT
    return fig


def build_phase(s: Sources) -> Built:
    """The phase portrait: the motion by mode over the theory's references and points."""
    # Equal aspect: the browser fits the ranges to the frame it lays out
    # (``match_aspect``; ``aspect_scale`` is omega L [m/s] per 1e3 L [mm] in SI units, so
    # that x and x'/omega share one scale). The server does not know the frame's size, so
    # this figure's ranges are the one thing computed in the browser.
    # One padding for both: BokehJS pads after fitting the aspect, each axis by a
    # fraction of its own span, which keeps the ratio only if the fractions are equal.
    x_range = DataRange1d(range_padding=PHASE_X_PADDING, only_visible=True)
    y_range = DataRange1d(range_padding=PHASE_X_PADDING, only_visible=True)
    fig = new_figure("Phase portrait (x, x′)", PHASE_SIZE, x_axis_label="x",
                     y_axis_label="x′", x_range=x_range, y_range=y_range, match_aspect=True)
    ranged = [add_glyph(fig, "line", "x", "v", source=s[key], **PHASE_STYLE[key])
              for key in ("gamma0", "cycle", "removed")]
    theory = list(ranged)
    for name in MODE_NAMES.values():
        ranged.append(add_glyph(fig, "line", "x", "v", source=s[f"path_{name}"],
                                **PHASE_STYLE[name]))
    add_glyph(fig, "scatter", "x", "v", source=s["trans"], marker="marker", color="color",
              size=7, fill_alpha=0.6)
    theory.append(add_glyph(fig, "scatter", "x", "v", source=s["points"],
                            **PHASE_STYLE["points"]))
    ranged.append(theory[-1])
    # The stop, when near the motion (:func:`app.plots.ranges.stop_in_view`), is in the
    # ranges too.
    ranged.append(add_glyph(fig, "scatter", "x", "v", source=s["stop_pt"], size=0, alpha=0.0))
    # On a light backing: a label next to the stop line was crossed by it ("stick end"
    # of Fig. 5a, "limit" of Fig. 7c).
    labels = LabelSet(x="x", y="v", text="name", source=s["points"], x_offset="dx",
                      text_align="align", text_baseline="baseline", y_offset="dy",
                      text_font_size=f"{LABEL_FONT_PX}px",
                      background_fill_color="#ffffff", background_fill_alpha=0.8)
    fig.add_layout(labels)
    theory.append(labels)
    # Where a periodic steady state closes: drawn once, its repeats counted.
    add_glyph(fig, "scatter", "x", "v", source=s["repeat"], **PHASE_STYLE["repeat"])
    ranged.append(add_glyph(fig, "scatter", "x", "v", source=s["start"], **PHASE_STYLE["start"]))
    x_range.renderers = y_range.renderers = ranged
    # Underlay: the stick segment runs along the belt line and must stay visible.
    spans = {"stop": Span(location=0.0, dimension="height", line_color="#000000",
                          line_width=3, level="underlay"),
             "belt": Span(location=0.0, dimension="width", line_color="#2ca02c",
                          line_dash="dotted", line_width=2, level="underlay")}
    fig.add_layout(spans["stop"])
    fig.add_layout(spans["belt"])
    place_labels(fig, labels, spans["stop"])
    # The legend is HTML below the figure (one model, drawn by the browser's layout,
    # not a Bokeh legend with a stand-in renderer per entry).
    return Built(fig, {"phase": fig}, spans=spans, legend=legend_pane(), theory=theory,
                 point_labels=labels)


def build_time(s: Sources) -> Built:
    """The time histories x(t) and x'(t) on one time axis, over bands of the modes, and
    the bands' legend below them; the two figures and the legend are ``2 * TIME_SIZE``
    high together (the height the page keeps for the plot until it is built)."""
    size = (TIME_SIZE[0], TIME_SIZE[1] - BAND_LEGEND_PX // 2)
    fig_x = new_figure("Displacement x(t)", size, y_axis_label="x")
    fig_v = new_figure("Velocity x′(t)", size, x_axis_label="t", y_axis_label="x′",
                       x_range=fig_x.x_range)
    for fig, col in ((fig_x, "x"), (fig_v, "v")):
        add_glyph(fig, "quad", left="left", right="right", bottom=-BAND_EXTENT, top=BAND_EXTENT,
                  source=s["bands"], fill_color="color", line_color=None)
        add_glyph(fig, "line", "t", col, source=s["traj"], line_color="#222222", line_width=1.5)
    spans = {"stop_t": Span(location=0.0, dimension="width", line_color="#000000",
                            line_width=2, level="underlay"),
             "belt_t": Span(location=0.0, dimension="width", line_color="#2ca02c",
                            line_dash="dotted", line_width=2, level="underlay")}
    fig_x.add_layout(spans["stop_t"])
    fig_v.add_layout(spans["belt_t"])
    return Built(column(fig_x, fig_v, sizing_mode="stretch_width"),
                 {"time_x": fig_x, "time_v": fig_v}, spans=spans,
                 legend=legend_pane(legend_html(band_entries()), lines=1))


def build_force(s: Sources) -> Built:
    """Impulses or the contact force over time, and the force that holds the mass at rest
    on a rigid stop on an axis of its own."""
    fig = new_figure(FORCE_TITLE, SMALL_SIZE, x_axis_label="t", y_axis_label="impulse / force")
    add_glyph(fig, "segment", "t", 0.0, "t", "j", source=s["stems"], line_color=MODE_COLORS[2],
              line_width=1.5)
    add_glyph(fig, "scatter", "t", "j", source=s["stems"], size=5, color=MODE_COLORS[2])
    add_glyph(fig, "line", "t", "phi", source=s["force"], line_color=MODE_COLORS[2],
              line_width=1.5)
    # The force holding the mass on a rigid stop (a force, not an impulse): own axis.
    fig.extra_y_ranges = {"rest": Range1d(0.0, 1.0)}
    rest_axis = LinearAxis(y_range_name="rest", axis_label="force at rest",
                           axis_label_text_color=REST_COLOR, visible=False,
                           axis_label_text_font_size=AXIS_LABEL_FONT,
                           major_label_text_font_size=TICK_LABEL_FONT)
    fig.add_layout(rest_axis, "right")
    add_glyph(fig, "line", "t", "f", source=s["rest"], y_range_name="rest",
              line_color=REST_COLOR, line_width=2, line_dash="dashed")
    return Built(fig, {"force": fig}, rest_axis=rest_axis)


def build_loop(s: Sources) -> Built:
    """The hysteresis loop of a deformable stop between its two envelopes."""
    fig = new_figure("Hysteresis loop φ(overlap)", SMALL_SIZE,
                     x_axis_label="overlap x − x̄", y_axis_label="φ/k")
    items = []
    for name, label, style in (
        ("comp", "compression envelope", {"line_color": "#444444", "line_dash": "dashed"}),
        ("exp", "expansion envelope", {"line_color": "#888888", "line_dash": "dotdash"}),
        ("loop", "contact force", {"line_color": MODE_COLORS[2], "line_width": 2}),
    ):
        add_glyph(fig, "line", "d", "phi", source=s[name], **style)
        items.append((label, swatch("line", **style), ""))
    return Built(fig, {"loop": fig}, legend=legend_pane(legend_html(items)))


def build_friction(s: Sources) -> Built:
    """Coulomb's law (Fig. 1b) with the motion's operating points."""
    fig = new_figure("Friction law (Fig. 1b)", SMALL_SIZE,
                     x_axis_label="relative velocity uᵣ = v − x′",
                     y_axis_label="friction force / k")
    add_glyph(fig, "line", "u", "f", source=s["law"], line_color="#000000", line_width=2)
    add_glyph(fig, "scatter", "u", "f", source=s["ops"], color="color", size=6, alpha=0.5)
    return Built(fig, {"friction": fig})


def build_energy(s: Sources) -> Built:
    """The energy budget over time."""
    fig = new_figure("Energy", SMALL_SIZE, x_axis_label="t", y_axis_label="energy / k")
    items = []
    for name, color in ENERGY_COLORS.items():
        add_glyph(fig, "line", "t", name, source=s["energy"], line_color=color, line_width=1.5)
        items.append((name.replace("_", " "), swatch("line", line_color=color, line_width=1.5),
                      ""))
    return Built(fig, {"energy": fig}, legend=legend_pane(legend_html(items)))


def build_map(s: Sources) -> Built:
    """The regime map of the theory (an image of category codes) and the current point."""
    fig = new_figure("Regime map (tap to move there)", MAP_SIZE,
                     x_axis_label="belt speed v", y_axis_label="clearance x̄",
                     x_range=Range1d(0, 1), y_range=Range1d(0, 1))
    mapper = LinearColorMapper(palette=list(MAP_PALETTE), low=-0.5, high=len(MAP_PALETTE) - 0.5)
    add_glyph(fig, "image", image="image", x="x", y="y", dw="dw", dh="dh", source=s["map"],
              color_mapper=mapper)
    # The theory's boundaries (app.plots.map_boundaries), each named at its end by a label
    # of its own (placed where it stays in the frame: map_boundaries.LABEL_CORNERS).
    add_glyph(fig, "multi_line", "xs", "ys", source=s["bounds"], **BOUNDARY_STYLE)
    labels = {name: Label(x=0.0, y=0.0, text=name, visible=False, text_font_size="11px",
                          text_color=BOUNDARY_STYLE["line_color"],
                          background_fill_color="#ffffff", background_fill_alpha=0.7)
              for name in LABEL_CORNERS}
    for label in labels.values():
        fig.add_layout(label)
    # Overlay level: moving the marker repaints only the overlay canvas, not the image.
    add_glyph(fig, "scatter", "v", "x", source=s["here"], marker="circle_cross", size=14,
              fill_color="#ffffff", line_color="#000000", line_width=2, level="overlay")
    fig.center = [r for r in fig.center if not isinstance(r, Grid)]  # a map: no grid
    return Built(fig, {"map": fig}, map_mapper=mapper, map_labels=labels)


def build_return_plot(s: Sources) -> Built:
    """The return map of the impacts or stick onsets (:mod:`app.plots.return_figure`)."""
    parts = build_return(s, new_figure)
    return Built(parts["figure"], {"return": parts["figure"]}, legend=parts["legend"],
                 slopes={"grazing": parts["grazing"]})


#: The builder of each plot this package builds.
BUILDERS: Mapping[str, Callable[[Sources], Built]] = {
    "phase": build_phase, "time": build_time, "force": build_force, "loop": build_loop,
    "friction": build_friction, "energy": build_energy, "map": build_map,
    "return": build_return_plot,
}


def set_axis_labels(figs: Mapping[str, Any], rest_axis: LinearAxis | None, sol: Solution,
                    scales: Scales) -> None:
    """Label the axes of the built figures ``figs`` in the page's units."""
    length, velocity, time = scales.length_label, scales.velocity_label, scales.time_label
    si = " (mm)" if scales.si else ""
    labels: dict[str, tuple[Any, Any]] = {
        "phase": (length, velocity), "time_x": (None, length), "time_v": (time, velocity),
        "energy": (time, scales.energy_label), "friction": (None, scales.friction_label),
        "loop": ("overlap x − x̄" + si, scales.force_label),
        "map": ("belt speed v_dr (m/s)" if scales.si else "belt speed v", "clearance x̄" + si),
    }
    if "force" in figs:
        labels["force"] = ("program phase s" if sol.program is not None else time,
                           scales.impulse_label if force_quantity(sol) == IMPULSES
                           else scales.force_label)
        rest_axis.axis_label = f"force at rest: {scales.force_label}"
    for key, (x_label, y_label) in labels.items():
        fig = figs.get(key)
        if fig is None:
            continue
        if x_label is not None:
            fig.xaxis.axis_label = x_label
        if y_label is not None:
            fig.left[0].axis_label = y_label
    aspect = scales.velocity / scales.length  # x'/omega and x on one scale
    if "phase" in figs and figs["phase"].aspect_scale != aspect:
        figs["phase"].aspect_scale = aspect
