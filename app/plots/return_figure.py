"""The return-map figure: the state at each impact (or stick onset) against the one before
(:mod:`app.return_map`), with the identity line, the line ``s_{n+1} = r s_n`` of a grazing
sequence, and the fixed point of a periodic steady state.

Speeds are drawn on log axes, where the ``r^h`` decay of grazing is a straight line
parallel to the identity (``log s_{n+1} = log s_n + log r``) and ten decades fit one frame;
positions (the stick onsets, of either sign) on linear axes. Where the run has no impacts
and no stick onsets the title says so.

A log axis labels its ticks in one format, ``3.5e−02``, whose labels are all of one size:
BokehJS's own labels a span of two decades or more in powers of ten with superscripts
(taller) and a narrower one in plain numbers, as wide as their digits, and an axis that
changed size on a release made BokehJS lay the figure out again (20-35 ms in Chromium,
scene 7c) and, its frame 4 px smaller or larger, the page, every figure repainted.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from bokeh.models import (
    BasicTicker,
    BasicTickFormatter,
    ColumnDataSource,
    CustomJSTickFormatter,
    LinearScale,
    LogScale,
    LogTicker,
    Range1d,
    Slope,
)

from app.glyphs import add_glyph
from app.plots.legends import legend_html, legend_pane, swatch
from app.plots.sources import assign
from app.plots.style import MODE_COLORS, SMALL_SIZE
from app.return_map import ReturnMap
from app.state import Scales

#: Title of the figure with nothing to show.
NO_EVENTS = "Return map: no impacts or stick onsets in this run"
#: What the events of each quantity are called (a long run stores the first ones).
EVENT_NAMES = {"impact speed": "impacts", "contact speed": "contacts",
               "stick position": "stick onsets"}
#: Styles of the identity line, the grazing line, the points and the fixed point.
IDENTITY_STYLE = {"line_color": "#888888", "line_dash": "dashed", "line_width": 1.5}
GRAZING_STYLE = {"line_color": MODE_COLORS[2], "line_dash": "dotted", "line_width": 2}
POINT_STYLE = {"color": "#1f3a93", "size": 7, "alpha": 0.7}
# (Hollow: the points it marks show through.)
FIXED_STYLE = {"size": 16, "fill_color": "#ffffff", "fill_alpha": 0.0,
               "line_color": "#d62728", "line_width": 2.5}
#: Factor around the points' span on a log axis (half a decade of room in all: 10^0.25
#: each side), and the fraction of a linear span.
LOG_PAD = 10.0 ** 0.25
LINEAR_PAD = 0.1
#: A log axis's tick label: two digits and a signed exponent of two (the minus sign of
#: the width of the plus; the digits of one width in the page's fonts), for any tick.
LOG_TICK_CODE = """
if (!(tick > 0)) return "";
let e = Math.floor(Math.log10(tick));
let m = (tick / 10 ** e).toFixed(1);
if (m === "10.0") { e += 1; m = "1.0"; }
return m + "e" + (e < 0 ? "\u2212" : "+") + String(Math.abs(e)).padStart(2, "0");
"""


def return_columns(rmap: ReturnMap, unit: float) -> dict[str, dict[str, np.ndarray]]:
    """The sources of the figure: ``points`` ``(s_n, s_{n+1})`` and ``fixed`` (each
    fixed point of ``P^j`` with its successor), in shown units (``unit`` per
    dimensionless unit of the quantity).

    >>> m = ReturnMap("impact speed", np.array([1.0, 0.5, 0.25]), 3, np.zeros(0))
    >>> return_columns(m, 2.0)["points"]["y"].tolist()
    [1.0, 0.5]
    """
    s_n, s_next = rmap.pairs
    fixed = rmap.fixed
    return {"points": {"x": s_n * unit, "y": s_next * unit, "n": np.arange(len(s_n))},
            "fixed": {"x": fixed * unit, "y": np.roll(fixed, -1) * unit}}


def build_return(sources: Mapping[str, ColumnDataSource], new_figure: Any) -> dict[str, Any]:
    """The figure (made by ``new_figure(title, size, **kw)``), its lines and its legend."""
    fig = new_figure("Return map", SMALL_SIZE, x_axis_label="s_n", y_axis_label="s_n+1",
                     x_range=Range1d(0.0, 1.0), y_range=Range1d(0.0, 1.0))
    identity = Slope(gradient=1.0, y_intercept=0.0, **IDENTITY_STYLE)
    grazing = Slope(gradient=1.0, y_intercept=0.0, visible=False, **GRAZING_STYLE)
    fig.add_layout(identity)
    fig.add_layout(grazing)
    add_glyph(fig, "scatter", "x", "y", source=sources["ret_points"], **POINT_STYLE)
    add_glyph(fig, "scatter", "x", "y", source=sources["ret_fixed"], level="overlay",
              marker="diamond", **FIXED_STYLE)
    return {"figure": fig, "grazing": grazing, "legend": legend_pane()}


def legend_entries(rmap: ReturnMap, restitution: float | None) -> str:
    """The legend's HTML for what the figure shows of ``rmap``."""
    if not rmap.quantity:
        return ""
    items = [(f"{rmap.quantity} n+1 vs n", swatch("circle", **POINT_STYLE), ""),
             ("identity s_n+1 = s_n", swatch("line", **IDENTITY_STYLE),
              "a point on it repeats itself: one event per period")]
    if restitution is not None:
        items.append((f"grazing s_n+1 = r s_n (r = {restitution:g})",
                      swatch("line", **GRAZING_STYLE),
                      "impact speeds falling as r^h (docs/physics.md, Zeno and grazing sums)"))
    if len(rmap.fixed):
        items.append(("periodic steady state (fixed point)", swatch("diamond", **FIXED_STYLE),
                      "the points one period of the steady state visits"))
    return legend_html(items)


def title(rmap: ReturnMap) -> str:
    """The figure's title: what is drawn and how many points, or that nothing is."""
    if not rmap.quantity:
        return NO_EVENTS
    n = max(len(rmap.values) - 1, 0)
    events = EVENT_NAMES.get(rmap.quantity, "events")
    kept = ("" if rmap.total == len(rmap.values)
            else f", from the first {len(rmap.values)} of {rmap.total} {events}")
    return f"Return map: {rmap.quantity} n+1 vs n ({n} points{kept})"


def set_axes(fig: Any, log: bool, x_values: np.ndarray, y_values: np.ndarray) -> None:
    """Log or linear axes for the figure, fitted to the values."""
    scale_type = LogScale if log else LinearScale
    if not isinstance(fig.x_scale, scale_type):
        fig.x_scale, fig.y_scale = scale_type(), scale_type()
        for axis in (*fig.xaxis, *fig.yaxis):
            axis.ticker = LogTicker() if log else BasicTicker()
            axis.formatter = (CustomJSTickFormatter(code=LOG_TICK_CODE) if log
                              else BasicTickFormatter())
    values = np.concatenate((x_values, y_values))
    values = values[np.isfinite(values) & ((values > 0) if log else True)]
    if len(values) == 0:
        lo, hi = (0.1, 1.0) if log else (0.0, 1.0)
    elif log:
        lo, hi = float(values.min()) / LOG_PAD, float(values.max()) * LOG_PAD
    else:
        lo, hi = float(values.min()), float(values.max())
        pad = LINEAR_PAD * (hi - lo) if hi > lo else 0.5 * max(abs(lo), 1.0)
        lo, hi = lo - pad, hi + pad
    # One frame for both axes: the identity line is the diagonal.
    for rng in (fig.x_range, fig.y_range):
        if (rng.start, rng.end) != (lo, hi):
            rng.update(start=lo, end=hi, reset_start=lo, reset_end=hi)


def draw_return(fig: Any, sources: Mapping[str, ColumnDataSource], grazing: Slope,
                legend: Any, rmap: ReturnMap, restitution: float | None,
                scales: Scales) -> None:
    """Draw ``rmap`` in the figure: its points and fixed point, the title, the grazing
    line ``s_n+1 = r s_n`` of a stop of ``restitution`` 0 < r < 1, the axes, the
    ``legend`` (an HTML pane)."""
    speed = rmap.quantity in ("impact speed", "contact speed")
    # The other quantity is a position (the stick onsets): a length.
    cols = return_columns(rmap, scales.velocity if speed else scales.length)
    assign(sources["ret_points"], cols["points"])
    assign(sources["ret_fixed"], cols["fixed"])
    if fig.title.text != title(rmap):
        fig.title.text = title(rmap)
    r = restitution
    show_r = rmap.quantity == "impact speed" and r is not None and 0.0 < r < 1.0
    grazing.update(visible=show_r, gradient=float(r) if show_r else 1.0)
    label = (f"{rmap.quantity} ({scales.velocity_label})" if speed
             else f"{rmap.quantity}{' (mm)' if scales.si else ''}" if rmap.quantity
             else "state")
    fig.xaxis.axis_label, fig.yaxis.axis_label = f"{label}: n", f"{label}: n+1"
    set_axes(fig, speed, cols["points"]["x"], cols["points"]["y"])
    text = legend_entries(rmap, float(r) if show_r else None)
    if legend.object != text:
        legend.object = text
