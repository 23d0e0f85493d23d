"""How the sweep card and the simulated map look: colours of the steady states and lines."""

from __future__ import annotations

from collections.abc import Mapping

#: Steady-state labels' colours in the diagram and in the simulated map: from Paul Tol's
#: "muted" scheme (SRON, 2021), apart to protanopes and deuteranopes too
#: (:data:`app.plots.style.MIN_CLASS_DIFFERENCE`); cells that did not settle are grey.
LABEL_COLORS: Mapping[str, str] = {
    "periodic": "#117733", "grazing": "#ddcc77", "rest": "#882255", "equilibrium": "#aa4499",
    "pure_slip": "#cc6677", "contact_train": "#999933", "none": "#dddddd",
    "oscillation": "#88ccee",
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
