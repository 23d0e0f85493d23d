"""How the sweep card and the simulated map look: colours of the steady states and lines."""

from __future__ import annotations

from collections.abc import Mapping

#: Steady-state labels' colours in the diagram and in the simulated map.
LABEL_COLORS: Mapping[str, str] = {
    "periodic": "#1f5fbf", "grazing": "#e07b00", "rest": "#2ca02c", "equilibrium": "#6a3d9a",
    "pure_slip": "#c8102e", "contact_train": "#8c564b", "none": "#7f7f7f",
    "oscillation": "#17becf",
}
#: Colour and opacity of the cells where simulation and theory disagree.
DISAGREE_RGBA = (200, 16, 46, 220)
#: Opacity of the simulated map over the theory's (0-255).
SIM_ALPHA = 235
#: Colours of the density image, light to dark (counts on a log scale).
DENSITY_PALETTE = ("#ffffff", "#d4e1f2", "#a6c3e6", "#6a9bd1", "#3a72b8", "#1f4f8f",
                   "#0b2c57", "#000000")
#: Colour of the theory's lines and of the current value's line.
THEORY_COLOR, CURRENT_COLOR = "#555555", "#c8102e"
#: Height [px] of the diagram.
FIGURE_HEIGHT = 440
