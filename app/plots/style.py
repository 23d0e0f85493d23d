"""How the explorer's figures look: colours, sizes, fonts and glyph styles, one place for all."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from app.teach.glossary import PLAIN
from core import Mode, TransitionKind

#: Colours of the modes (slip / stick / contact); the UI tests look for these pixels.
MODE_COLORS: Mapping[int, str] = {
    int(Mode.SLIP): "#1f5fbf",
    int(Mode.STICK): "#e07b00",
    int(Mode.CONTACT): "#c8102e",
}
#: Names of the modes, for legends and the CSV.
MODE_NAMES: Mapping[int, str] = {int(Mode.SLIP): "slip", int(Mode.STICK): "stick",
                                 int(Mode.CONTACT): "contact"}
#: Light tints of the mode colours for the bands behind the time histories: apart also to
#: protanopes and deuteranopes (:data:`MIN_CLASS_DIFFERENCE`), light enough under the
#: black trajectory. Contact is a darker, greyer rose (a light pink beside the amber stick
#: read as one band to a protanope); no tint, darkened on the black curve's anti-aliased
#: edge, comes near the pinned runs' violet (app.compare).
BAND_COLORS: Mapping[int, str] = {
    int(Mode.SLIP): "#dbe6f6",
    int(Mode.STICK): "#fbe7cc",
    int(Mode.CONTACT): "#d3b8b8",
}
#: Marker and colour of each transition kind in the phase portrait.
TRANSITION_STYLE: Mapping[str, tuple[str, str]] = {
    TransitionKind.SLIP_STICK.value: ("triangle", "#e07b00"),
    TransitionKind.STICK_SLIP.value: ("inverted_triangle", "#7a4a00"),
    TransitionKind.SIGN_CHANGE.value: ("diamond", "#6a3d9a"),
    TransitionKind.IMPACT.value: ("circle", "#c8102e"),
    TransitionKind.STICK_IMPACT.value: ("square", "#c8102e"),
    TransitionKind.ACCUMULATION.value: ("star", "#000000"),
    TransitionKind.REST.value: ("square_pin", "#000000"),
    TransitionKind.CONTACT.value: ("circle", "#c8102e"),
    TransitionKind.SEPARATION.value: ("circle_x", "#c8102e"),
    TransitionKind.REVERSAL.value: ("cross", "#c8102e"),
    TransitionKind.FAILURE.value: ("x", "#000000"),
}
#: Legend labels of the transition kinds that differ from the kind's name (a mode is also
#: called "contact").
TRANSITION_LABELS: Mapping[str, str] = {
    TransitionKind.SIGN_CHANGE.value: "sign change",
    TransitionKind.CONTACT.value: "contact start",
}
#: Colours of the regime map's categories (cycled; the paper's scenes have 9 at most):
#: Paul Tol's "light" scheme (SRON, 2021), made for maps to be read by colour-blind
#: viewers, no two alike to them (:data:`MIN_CLASS_DIFFERENCE`; the blues, greens and
#: reds of the former palette read as one regime to a deuteranope).
MAP_PALETTE = (
    "#77aadd", "#eedd88", "#44bb99", "#ffaabb", "#99ddff", "#bbcc33", "#ee8866", "#aaaa00",
    "#dddddd",
)
#: Least CIEDE2000 difference between two classes of a palette to normal, protanope and
#: deuteranope vision (app.plots.colour_vision): patches that differ by 5 or more are
#: told apart at a glance; 7 leaves room for a screen's rendering.
MIN_CLASS_DIFFERENCE = 7.0
#: And a dichromat keeps this fraction of the least difference normal vision sees at
#: least: the palette does not rest on a red-green contrast.
CVD_KEPT_FRACTION = 0.75
#: Colour of the force that holds the mass on a rigid stop (and of its axis).
REST_COLOR = "#6a3d9a"
#: Colours of the energy terms.
ENERGY_COLORS: Mapping[str, str] = {
    "mechanical": "#000000", "belt_input": "#2ca02c", "friction_heat": "#1f5fbf",
    "stop_loss": "#c8102e", "stop_stored": "#9467bd",
}
#: Height [px] of the mode bands' legend below the time histories (a 20 px line and its
#: 4 px margin).
BAND_LEGEND_PX = 24
#: Heights of the figures [px]; their widths follow the page (:data:`PLOT_WIDTHS`). Each
#: time history's is its share of the plot's pane: a 230 px figure and half the legend.
PHASE_SIZE = (540, 500)
TIME_SIZE = (540, 230 + BAND_LEGEND_PX // 2)
SMALL_SIZE = (540, 300)
MAP_SIZE = (540, 380)
#: Narrowest and widest plot [px]: two columns side by side from ~1100 px of page, one
#: column (readable, legends not cut) on an 800 px window, no stretched plots beyond.
PLOT_WIDTHS = (360, 900)
#: Font sizes: axis labels and the theory's labels readable from the back of a room.
AXIS_LABEL_FONT, TICK_LABEL_FONT, TITLE_FONT = "13px", "12px", "14px"
#: Font size [px] of the theory points' labels on the page and in the presentation mode.
LABEL_FONT_PX, PRESENT_LABEL_FONT_PX = 12, 22
#: Styles of the phase portrait's glyphs (drawn and in its HTML legend).
PHASE_STYLE: Mapping[str, Mapping[str, Any]] = {
    "gamma0": {"line_color": "#777777", "line_dash": "dashed", "line_width": 1},
    "cycle": {"line_color": "#999999", "line_width": 1},
    "removed": {"line_color": "#555555", "line_dash": "dotted", "line_width": 1.5},
    **{name: {"line_color": MODE_COLORS[m], "line_width": 2} for m, name in MODE_NAMES.items()},
    "points": {"marker": "diamond", "size": 13, "fill_color": "#ffffff",
               "line_color": "#000000", "line_width": 2},
    "repeat": {"marker": "circle_dot", "size": 11, "fill_color": "#ffffff",
               "line_color": "#2ca02c", "line_width": 2},
    "start": {"marker": "circle", "size": 8, "fill_color": "#ffffff", "line_color": "#000000"},
}
#: Legend labels of the phase portrait's references, and what they are (tooltips).
PHASE_LABELS: Mapping[str, tuple[str, str]] = {
    "gamma0": ("Γ₀", "Γ₀ (Eq. 21): the disc about (a, 0) of radius v, touching "
               "the stick line x′ = v; a start inside it slips for ever (fast belt)"),
    "cycle": ("impactless cycle", "Γ_LC (Eqs. 23-24): the stick-slip cycle (or, for a "
              "fast belt, the slip circle) the motion settles on without the stop"),
    "points": ("theory (A.1-A.12)", "the steady-state points of the paper's appendix"),
    "repeat": ("cycle closes", "the periodic steady state is drawn once: from here it "
               "repeats; the label counts the repeats within the horizon"),
    "start": ("start", f"the initial state ({PLAIN['x0']}, {PLAIN['v0']}); click the "
              "portrait to move it"),
    "removed": ("stop removed", "Sec. 4.6: the pure slip circle about (a, 0) the mass "
                "would follow if the stop were removed while it rests on it"),
}
#: Tick labels are decimals down to this power of ten (Bokeh's default, -3, wrote the
#: hysteresis loop's overlaps as 5.000e-4, 1.000e-3, ...).
TICK_POWER_LIMIT_LOW = -5
#: Tools of every figure (SaveTool exports the PNG).
TOOLS = "pan,wheel_zoom,box_zoom,reset,save"
