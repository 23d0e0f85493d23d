"""The explorer's Bokeh figures: this package's public names, gathered from its modules.

- :mod:`app.plots.style`: colours, sizes, fonts and glyph styles;
- :mod:`app.plots.columns`: pure functions from a solution to the columns of a source;
- :mod:`app.plots.labels`: the theory points and the browser's placement of their labels;
- :mod:`app.plots.legends`: the HTML legends below the figures;
- :mod:`app.plots.sources`: the sources, the models the figures share, writing a source;
- :mod:`app.plots.ranges`: axis ranges computed on the server;
- :mod:`app.plots.figures`: building each figure;
- :mod:`app.plots.map_boundaries`: the theory's boundaries over the regime map;
- :mod:`app.plots.colour_vision`: how far apart the palettes' colours look, colour-blind too;
- :mod:`app.plots.plot_set`: :class:`PlotSet`, the figures of one session, updated in place.

A figure is built when first shown:

>>> plots = PlotSet()
>>> sorted(plots.built), type(plots.build("phase")).__name__, sorted(plots.built)
([], 'figure', ['phase'])
"""

from app.plots.columns import (
    CHORD_PX,
    CIRCLE_VERTICES,
    CONTACT_FORCE,
    DRAWING_CACHE,
    EMPTY_SPAN,
    FORCE_TITLE,
    HISTORY_COLUMNS,
    IMPULSES,
    MAX_LOOP_POINTS,
    MAX_MARKERS,
    MAX_OPERATING_POINTS,
    MAX_POINTS,
    PHASE_FRAME_MAX,
    PROGRAM_FORCE,
    band_columns,
    energy_columns,
    force_columns,
    force_quantity,
    friction_columns,
    loop_columns,
    phase_columns,
    phase_step,
    reference_columns,
    removed_circle,
    sample_bounds,
    trajectory_columns,
    transition_columns,
)
from app.plots.figures import BAND_EXTENT, Built
from app.plots.labels import PAPER_NAMES, PAPER_STICK_CONTACT, PLACE_LABELS_JS, theory_points
from app.plots.legends import LEGEND_LINES, legend_html, legend_pane, phase_entries, swatch
from app.plots.plot_set import BUILT_HERE, MAP_FRAME_KEYS, PlotSet
from app.plots.ranges import (
    PHASE_X_PADDING,
    RANGE_PADDING,
    STOP_VIEW_REACH,
    data_bounds,
    set_range,
    stop_in_view,
)
from app.plots.sources import SharedModels, assign
from app.plots.style import (
    AXIS_LABEL_FONT,
    BAND_COLORS,
    ENERGY_COLORS,
    LABEL_FONT_PX,
    MAP_PALETTE,
    MAP_SIZE,
    MODE_COLORS,
    MODE_NAMES,
    PHASE_LABELS,
    PHASE_SIZE,
    PHASE_STYLE,
    PLOT_WIDTHS,
    PRESENT_LABEL_FONT_PX,
    REST_COLOR,
    SMALL_SIZE,
    TICK_LABEL_FONT,
    TICK_POWER_LIMIT_LOW,
    TIME_SIZE,
    TITLE_FONT,
    TOOLS,
    TRANSITION_LABELS,
    TRANSITION_STYLE,
)

__all__ = [
    "AXIS_LABEL_FONT", "BAND_COLORS", "BAND_EXTENT", "BUILT_HERE", "Built", "CHORD_PX",
    "CIRCLE_VERTICES", "CONTACT_FORCE", "EMPTY_SPAN", "ENERGY_COLORS", "FORCE_TITLE",
    "HISTORY_COLUMNS", "IMPULSES", "LABEL_FONT_PX", "LEGEND_LINES", "MAP_FRAME_KEYS",
    "MAP_PALETTE", "MAP_SIZE", "MAX_LOOP_POINTS", "MAX_MARKERS", "MAX_OPERATING_POINTS",
    "MAX_POINTS", "MODE_COLORS", "MODE_NAMES", "PAPER_NAMES", "PAPER_STICK_CONTACT",
    "PHASE_FRAME_MAX", "PHASE_LABELS", "PHASE_SIZE", "PHASE_STYLE", "PHASE_X_PADDING",
    "PLACE_LABELS_JS", "PLOT_WIDTHS", "PRESENT_LABEL_FONT_PX", "PROGRAM_FORCE", "PlotSet",
    "RANGE_PADDING", "REST_COLOR", "SMALL_SIZE", "STOP_VIEW_REACH", "SharedModels",
    "TICK_LABEL_FONT", "TICK_POWER_LIMIT_LOW", "TIME_SIZE", "TITLE_FONT", "TOOLS",
    "TRANSITION_LABELS", "TRANSITION_STYLE", "DRAWING_CACHE",
    "assign", "band_columns", "data_bounds", "energy_columns", "force_columns",
    "force_quantity", "friction_columns", "legend_html", "legend_pane", "loop_columns",
    "phase_columns", "phase_entries", "phase_step", "reference_columns", "removed_circle",
    "sample_bounds", "set_range", "stop_in_view", "swatch", "theory_points",
    "trajectory_columns", "transition_columns",
]
