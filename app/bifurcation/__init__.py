"""Bifurcation diagrams and the simulated regime map (core.sweep in the page): public names.

- :mod:`app.bifurcation.spec`: a sweep as a value, checked, and the points it finds (pure);
- :mod:`app.bifurcation.theory_lines`: the closed-form theory drawn over a diagram;
- :mod:`app.bifurcation.sim_map`: the regime map from simulation against the theory's;
- :mod:`app.bifurcation.chunks`: a sweep computed chunk by chunk in the worker pool;
- :mod:`app.bifurcation.style`: the colours;
- :mod:`app.bifurcation.map_layers`, :mod:`app.bifurcation.view`: the page's card.

Examples
--------
>>> from app.state import scene_values
>>> spec = check_spec(scene_values("5a"), "belt_speed", 0.1, 0.2, 3, "impact_speed")
>>> spec.grid().tolist()
[0.1, 0.15000000000000002, 0.2]
"""

from app.bifurcation.chunks import CHUNK_SECONDS, FIRST_CHUNK, MAX_CHUNK, ChunkedSweep
from app.bifurcation.map_layers import MapLayers
from app.bifurcation.sim_map import (
    SIM_MAP_CELLS,
    SimMap,
    compare_map,
    map_cells,
    rgba,
    simulate_map_rows,
)
from app.bifurcation.spec import (
    CLOSED_FORM_T_END,
    DEFAULT_POINTS,
    DENSITY_BINS,
    DENSITY_SAMPLES,
    MAX_POINTS,
    PARAMETER_LABELS,
    PARAMETER_SI,
    PER_POINT,
    QUANTITY_LABELS,
    QUANTITY_SI,
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
    run_core,
    sweep_cost,
    sweep_inputs,
    sweep_points,
)
from app.bifurcation.style import (
    CURRENT_COLOR,
    DENSITY_PALETTE,
    DISAGREE_RGBA,
    FIGURE_HEIGHT,
    LABEL_COLORS,
    SIM_ALPHA,
    THEORY_COLOR,
)
from app.bifurcation.theory_lines import (
    THEORY_SAMPLES,
    named_values,
    quantity_levels,
    regime_changes,
    theory_lines,
)
from app.bifurcation.view import BifurcationView, legend_text, missing_note
from core import sweep as sweeps

__all__ = [
    "CHUNK_SECONDS", "CLOSED_FORM_T_END", "CURRENT_COLOR", "DEFAULT_POINTS", "DENSITY_BINS",
    "DENSITY_PALETTE", "DENSITY_SAMPLES", "DISAGREE_RGBA", "FIGURE_HEIGHT", "FIRST_CHUNK",
    "LABEL_COLORS", "MAX_CHUNK", "MAX_POINTS", "PARAMETER_LABELS", "PARAMETER_SI",
    "PER_POINT", "QUANTITY_LABELS", "QUANTITY_SI", "SIM_ALPHA", "SIM_MAP_CELLS",
    "THEORY_COLOR", "THEORY_SAMPLES", "UNITS_NOTE", "AxisUnits", "BifurcationView",
    "ChunkedSweep", "MapLayers", "Points", "SimMap", "SweepSpec", "applicable_parameters",
    "applicable_quantities", "axis_units", "check_spec", "closed_form", "compare_map",
    "default_quantity", "default_range", "density", "legend_text", "map_cells",
    "missing_note", "named_values", "parameter_name", "quantity_levels", "quantity_name",
    "regime_changes", "rgba", "run_core", "simulate_map_rows", "sweep_cost", "sweep_inputs",
    "sweep_points", "sweeps", "theory_lines",
]
