"""The page's data sources: their columns, the models the figures share, how they are written.

An update replaces a source's ``.data`` in one assignment (the caller batches them with
``panel.io.hold``), and only when something changed, so that a change of the parameters
sends one message with only new numbers.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from bokeh.models import (
    AllIndices,
    AllLabels,
    BasicTicker,
    BasicTickFormatter,
    ColumnDataSource,
    GlyphRenderer,
    LinearAxis,
    LinearScale,
    Selection,
    UnionRenderers,
)

from app.plots.labels import POINT_COLUMNS
from app.plots.map_boundaries import BOUNDARY_COLUMNS
from app.plots.style import ENERGY_COLORS, MODE_NAMES, TICK_POWER_LIMIT_LOW


def _same(old: Any, new: Any) -> bool:
    if isinstance(old, np.ndarray) and isinstance(new, np.ndarray):
        return old.shape == new.shape and old.dtype == new.dtype and bool(
            np.array_equal(old, new, equal_nan=old.dtype.kind == "f"))
    return list(old) == list(new)


def assign(source: ColumnDataSource, cols: Mapping[str, Any]) -> bool:
    """Replace ``source.data`` in one assignment, unless nothing changed (then the browser
    has nothing to re-render). Returns whether it assigned."""
    old = source.data
    if old.keys() == cols.keys() and all(_same(old[k], cols[k]) for k in cols):
        return False
    source.data = dict(cols)
    return True


class SharedModels:
    """Models without state in the browser that every figure of a page can share: one
    ticker, tick formatter and label policy for all axes, one index filter for all
    renderers, one selection policy and one (empty) selection for all sources and one
    linear scale for all axes (each was one model per axis, renderer, source or figure:
    ~110 models of a page). BokehJS derives each frame's scales from a copy of the
    figure's scale (the shared model stays as sent); no figure has a selection tool, so
    the selection stays empty (a reset clears it to what it was)."""

    def __init__(self) -> None:
        self.scale = LinearScale()
        self.ticker = BasicTicker()
        self.formatter = BasicTickFormatter(power_limit_low=TICK_POWER_LIMIT_LOW)
        self.labels = AllLabels()
        self.filter = AllIndices()
        self.policy = UnionRenderers()
        self.selection = Selection()

    def source(self, data: Mapping[str, Any], **kw: Any) -> ColumnDataSource:
        """A data source with the shared selection policy and selection."""
        return ColumnDataSource(data=data, selection_policy=self.policy,
                                selected=self.selection, **kw)

    def lighten(self, fig: Any) -> None:
        """Give ``fig``'s axes and renderers the shared models, and let BokehJS derive
        the non-selection and muted glyphs ("auto": no selection tools, no muting
        legends) instead of receiving two more glyph models per renderer."""
        fig.x_scale = fig.y_scale = self.scale
        for axis in (*fig.left, *fig.right, *fig.above, *fig.below):
            if isinstance(axis, LinearAxis):
                axis.ticker = self.ticker
                axis.formatter = self.formatter
                axis.major_label_policy = self.labels
        for r in fig.renderers:
            if isinstance(r, GlyphRenderer):
                r.nonselection_glyph = "auto"
                r.muted_glyph = "auto"
                r.view.filter = self.filter


class Sources(dict):
    """The page's sources by name (:data:`EMPTY`), each made when first asked for: a page
    holds only those of the figures it builds (making one costs a new page ~0.6 ms)."""

    def __init__(self, shared: SharedModels) -> None:
        super().__init__()
        self.shared = shared

    def __missing__(self, name: str) -> ColumnDataSource:
        source = self[name] = self.shared.source(EMPTY[name])
        return source


class SourceData:
    """The current ``.data`` of each of the ``sources``, by name (made if need be)."""

    def __init__(self, sources: Mapping[str, ColumnDataSource]) -> None:
        self.sources = sources

    def __getitem__(self, name: str) -> Mapping[str, Any]:
        return self.sources[name].data


#: The sources of a page by name, with their columns (empty).
EMPTY: Mapping[str, Mapping[str, list]] = {
    "traj": {k: [] for k in ("t", "x", "v", "mode")},
    **{f"path_{name}": {"x": [], "v": []} for name in MODE_NAMES.values()},
    "repeat": {"x": [], "v": [], "text": []},
    "stop_pt": {"x": [], "v": []},
    "trans": {k: [] for k in ("x", "v", "t", "kind", "marker", "color")},
    "bands": {"left": [], "right": [], "color": []},
    "gamma0": {"x": [], "v": []},
    "removed": {"x": [], "v": []},
    "cycle": {"x": [], "v": []},
    "points": {k: [] for k in POINT_COLUMNS},
    "start": {"x": [], "v": []},
    "stems": {"t": [], "j": []},
    "force": {"t": [], "phi": []},
    "rest": {"t": [], "f": []},
    "loop": {"d": [], "phi": []},
    "comp": {"d": [], "phi": []},
    "exp": {"d": [], "phi": []},
    "law": {"u": [], "f": []},
    "ops": {"u": [], "f": [], "color": []},
    "energy": {"t": [], **{n: [] for n in ENERGY_COLORS}},
    "map": {"image": [], "x": [], "y": [], "dw": [], "dh": []},
    "here": {"v": [], "x": []},
    "bounds": {k: [] for k in BOUNDARY_COLUMNS},
    "ret_points": {"x": [], "y": [], "n": []},
    "ret_fixed": {"x": [], "y": []},
}
