"""The Bokeh figures of the explorer, created per session and updated in place.

:class:`PlotSet` builds each figure when it is first shown, on ``ColumnDataSource`` objects made
with the set (a figure built later receives the current data); an update
replaces each source's ``.data`` in one assignment (the caller batches them with
``panel.io.hold``), so a change of the parameters sends one message with only new numbers.
Arrays are float32 and sampled for the screen from the exact motion (:mod:`app.sampling`).
The ``*_columns`` functions are pure: they turn a :class:`~app.solve.solution.Solution` into the
columns of one source and are tested without a browser.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import panel as pn
from bokeh.core.properties import validate
from bokeh.layouts import column
from bokeh.models import (
    AllIndices,
    AllLabels,
    BasicTicker,
    BasicTickFormatter,
    ColumnDataSource,
    CustomJS,
    DataRange1d,
    GlyphRenderer,
    Grid,
    Label,
    LabelSet,
    LinearAxis,
    LinearColorMapper,
    LinearScale,
    Range1d,
    Selection,
    Span,
    UnionRenderers,
)
from bokeh.plotting import figure

from app import sampling
from app.glyphs import add_glyph
from app.scenes import CUSTOM, PLOTS
from app.solve.regime_map import map_ranges
from app.solve.solution import Solution
from app.state import DIMENSIONLESS, Scales
from core import Mode, TransitionKind, phi_compression, phi_expansion

#: Colours of the modes (slip / stick / contact); the UI tests look for these pixels.
MODE_COLORS: Mapping[int, str] = {
    int(Mode.SLIP): "#1f5fbf",
    int(Mode.STICK): "#e07b00",
    int(Mode.CONTACT): "#c8102e",
}
#: Names of the modes, for legends and the CSV.
MODE_NAMES: Mapping[int, str] = {int(Mode.SLIP): "slip", int(Mode.STICK): "stick",
                                 int(Mode.CONTACT): "contact"}
#: Light tints of the mode colours for the bands behind the time histories.
BAND_COLORS: Mapping[int, str] = {
    int(Mode.SLIP): "#dbe6f6",
    int(Mode.STICK): "#fbe7cc",
    int(Mode.CONTACT): "#f6d2d8",
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
#: Colours of the regime map's categories (cycled); no two alike (a lavender and a grey
#: read as one regime in the legend of Fig. 7c's map).
MAP_PALETTE = (
    "#c6dbef", "#fdd0a2", "#c7e9c0", "#dadaeb", "#fcbba1", "#ffffb3", "#9ecae1", "#fdae6b",
    "#a1d99b", "#bcbddc", "#fc9272", "#e5d8bd",
)
#: Colour of the force that holds the mass on a rigid stop (and of its axis).
REST_COLOR = "#6a3d9a"
#: Colours of the energy terms.
ENERGY_COLORS: Mapping[str, str] = {
    "mechanical": "#000000", "belt_input": "#2ca02c", "friction_heat": "#1f5fbf",
    "stop_loss": "#c8102e", "stop_stored": "#9467bd",
}
#: Points of the full trajectory sent to the browser (a few per pixel of a plot's width).
MAX_POINTS = 1600
#: Points of the hysteresis loop sent at most (of many contacts, the latest loops).
MAX_LOOP_POINTS = 4 * MAX_POINTS
#: Transition markers drawn at most (the latest ones).
MAX_MARKERS = 400
#: Operating points drawn on the friction law.
MAX_OPERATING_POINTS = 500
#: A theory point's label is anchored by its corner next to the point (``align`` and
#: ``baseline`` of its source), that corner this far from the point's centre [px]:
#: sideways, clear of the marker's half width (``PHASE_STYLE["points"]``: a 13 px diamond
#: is 4.3 px wide each side, plus half its line) by a fifth of the font, and up or down by
#: a quarter of the font (clear of the stick line under a label above it). The page's font
#: (12 px) gives ``dx``, ``dy``: where a label is drawn until the browser places it on the
#: frame it lays out (:data:`PLACE_LABELS_JS`, which uses the same offsets for the font it
#: draws, presentation fonts included).
LABEL_FONT_PX, PRESENT_LABEL_FONT_PX = 12, 22


def label_offsets(font_px: float, line_width: float) -> tuple[int, int]:
    """Sideways and vertical distance [px] of a label's corner from its point's centre.

    >>> label_offsets(LABEL_FONT_PX, 2)
    (8, 3)
    """
    half_width = PHASE_STYLE["points"]["size"] / 2 / 1.5 + line_width / 2
    return round(half_width + 0.2 * font_px), round(0.25 * font_px)


#: The paper's names of the theory's points, after its transitions (Sec. 2): slip->stick
#: (SlSt), stick->slip (StSl), slip->contact (SlC), contact->slip (CSl), stick->contact
#: (StC, a stick segment that ends at the stop); ``lim`` is the point the impacts tend to.
PAPER_NAMES: Mapping[str, str] = {
    "P_stick_start": "P_SlSt", "P_stick_end": "P_StSl", "P_impact_in": "P_SlC",
    "P_impact_out": "P_CSl", "P_limit": "P_lim",
}
#: A stick segment's end on the stop is the stick->contact point.
PAPER_STICK_CONTACT = "P_StC"
#: Points whose velocities differ by less than this fraction of the largest are on one
#: level (their labels, 10 px high, would share a line in a 500 px high portrait).
LABEL_LEVEL_FRACTION = 0.03
#: Vertices of the reference circles (Gamma_0, limit cycle).
CIRCLE_VERTICES = 181
#: Samples of the hysteresis envelopes.
ENVELOPE_SAMPLES = 120
#: Half height of the mode bands: far outside any data, kept out of the auto range.
BAND_EXTENT = 1e6
#: Fraction of the data span added to an axis range (half each side), and more for the
#: phase portrait's displacement (room for the theory points' labels).
RANGE_PADDING = 0.1
PHASE_X_PADDING = 0.15
#: A stop the motion does not reach is still shown (phase portrait, x(t)) when it lies
#: within this fraction of the motion's displacement span beyond it; a farther stop would
#: squeeze the motion into a corner (the readout then says the stop lies beyond x_max).
STOP_VIEW_REACH = 0.5
#: Relative span below which data are a single value (the axis then spans one unit).
EMPTY_SPAN = 1e-12
#: Heights of the figures [px]; their widths follow the page (:data:`PLOT_WIDTHS`).
PHASE_SIZE = (540, 500)
TIME_SIZE = (540, 230)
SMALL_SIZE = (540, 300)
MAP_SIZE = (540, 380)
#: Narrowest and widest plot [px]: two columns side by side from ~1100 px of page, one
#: column (readable, legends not cut) on an 800 px window, no stretched plots beyond.
PLOT_WIDTHS = (360, 900)
#: Font sizes: axis labels and the theory's labels readable from the back of a room.
AXIS_LABEL_FONT, TICK_LABEL_FONT, TITLE_FONT = "13px", "12px", "14px"
#: What the regime map's axes depend on besides the point: a change reframes the map.
MAP_FRAME_KEYS = ("scene", "stop_type", "mu_s", "mu_k", "u_s", "units")
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
#: Offsets [px] of the theory points' labels on the page (:func:`label_offsets`): sideways,
#: and up (above the point) or down (below it).
LABEL_GAP_PX, LABEL_ABOVE_PX = label_offsets(LABEL_FONT_PX, PHASE_STYLE["points"]["line_width"])
LABEL_BELOW_PX = -LABEL_ABOVE_PX
#: Vertical offsets [px] of the label of a point on the x axis (the limit point): clear of
#: a marker of the same size on the axis (the start point (0, 0), contact markers by the
#: stop) by the usual offset.
LABEL_AXIS_PX = round(LABEL_ABOVE_PX + (PHASE_STYLE["points"]["size"]
                                        + PHASE_STYLE["points"]["line_width"]) / 2)
#: The browser's placement of the theory points' labels (the body of a ``CustomJS``): the
#: server does not know the frame's pixel size (the figures follow the page and the
#: ranges fit the aspect in the browser), so it cannot tell which labels would leave the
#: frame, run into each other or onto a marker.
PLACE_LABELS_JS = Path(__file__).resolve().parent.parent / "static" / "point_labels.js"
#: Legend labels of the phase portrait's references, and what they are (tooltips).
PHASE_LABELS: Mapping[str, tuple[str, str]] = {
    "gamma0": ("Gamma_0", "Gamma_0 (Eq. 21): the disc about (a, 0) of radius v, touching "
               "the stick line x' = v; a start inside it slips for ever (fast belt)"),
    "cycle": ("impactless cycle", "Gamma_LC (Eqs. 23-24): the stick-slip cycle (or, for a "
              "fast belt, the slip circle) the motion settles on without the stop"),
    "points": ("theory (A.1-A.12)", "the steady-state points of the paper's appendix"),
    "repeat": ("cycle closes", "the periodic steady state is drawn once: from here it "
               "repeats; the label counts the repeats within the horizon"),
    "start": ("start", "the initial state (x0, x'0); click the portrait to move it"),
    "removed": ("stop removed", "Sec. 4.6: the pure slip circle about (a, 0) the mass "
                "would follow if the stop were removed while it rests on it"),
}
#: Tick labels are decimals down to this power of ten (Bokeh's default, -3, wrote the
#: hysteresis loop's overlaps as 5.000e-4, 1.000e-3, ...).
TICK_POWER_LIMIT_LOW = -5
#: The plots this module builds (the mechanism is :mod:`app.animation`'s).
BUILT_HERE = tuple(p for p in PLOTS if p != "anim")
#: Tools of every figure (SaveTool exports the PNG).
TOOLS = "pan,wheel_zoom,box_zoom,reset,save"


def _f32(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float32)


def _same(old: Any, new: Any) -> bool:
    if isinstance(old, np.ndarray) and isinstance(new, np.ndarray):
        return old.shape == new.shape and old.dtype == new.dtype and bool(
            np.array_equal(old, new, equal_nan=old.dtype.kind == "f"))
    return list(old) == list(new)


def _assign(source: ColumnDataSource, cols: Mapping[str, Any]) -> bool:
    """Replace ``source.data`` in one assignment, unless nothing changed (then the browser
    has nothing to re-render). Returns whether it assigned."""
    old = source.data
    if old.keys() == cols.keys() and all(_same(old[k], cols[k]) for k in cols):
        return False
    source.data = dict(cols)
    return True


#: The largest frame of the phase portrait [px] (the widest plot, and its height): the
#: chord bound is set for it, so a wider window does not show chords.
PHASE_FRAME_MAX = (PLOT_WIDTHS[1] - 80, PHASE_SIZE[1] - 80)
#: Longest chord of the phase path on the largest frame [px]: below what the eye tells from
#: a curve (a 2 px chord of a 100 px radius arc deviates from it by 0.005 px).
CHORD_PX = 2.0
#: Pixel columns the time histories are reduced to (a wide screen's plot, the largest).
HISTORY_COLUMNS = 1600


def _drawing(sol: Solution):
    """The solution as a function of time (:func:`app.sampling.evaluator`), cached on
    the solution (one evaluator serves the phase portrait and the time histories)."""
    res = sol.result
    cache = _DRAWING_CACHE
    key = id(sol)
    hit = cache.get(key)
    if hit is not None and hit[0] is sol:
        return hit[1]
    value = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0, sol.method)
    cache.clear()  # one solution at a time: the last drawn
    cache[key] = (sol, value)
    return value


_DRAWING_CACHE: dict[int, tuple[Solution, Any]] = {}


def phase_step(x_bounds: tuple[float, float], v_bounds: tuple[float, float]
               ) -> tuple[float, float]:
    """Longest chord along each axis [data units] for :data:`CHORD_PX` on the largest
    frame, for equal-aspect ranges that hold both bounds (dimensionless ``v``)."""
    (x0, x1), (v0, v1) = x_bounds, v_bounds
    per_px = max((x1 - x0) / PHASE_FRAME_MAX[0], (v1 - v0) / PHASE_FRAME_MAX[1], EMPTY_SPAN)
    return CHORD_PX * per_px, CHORD_PX * per_px


def trajectory_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                       columns: int = HISTORY_COLUMNS) -> dict[str, np.ndarray]:
    """Columns of the trajectory source (time histories and the animation): ``t``
    (shown units, also read by the animation), ``x``, ``v`` and
    ``mode``, reduced to the first, last, lowest and highest sample of each of
    ``columns`` pixel columns from samples of the exact motion
    (:func:`app.sampling.history`); ``bands`` holds the mode bands."""
    res = sol.result
    if res is None:
        return {**{k: _f32([]) for k in ("t", "x", "v")},
                "mode": np.zeros(0, np.int8)}
    evaluate, exact = _drawing(sol)
    step = phase_step(*_sample_bounds(sol))
    h = sampling.history(res, evaluate, sol.t_end, exact, columns, step)
    return {"t": _f32(h.t * scales.time), "x": _f32(h.x),
            "v": _f32(h.v * scales.velocity), "mode": np.asarray(h.mode, dtype=np.int8),
            "bands": h.bands}


def _sample_bounds(sol: Solution) -> tuple[tuple[float, float], tuple[float, float]]:
    res = sol.result
    x, v = np.asarray(res.x, float), np.asarray(res.v, float)
    if len(x) == 0:
        return (0.0, 1.0), (0.0, 1.0)
    return (float(x.min()), float(x.max())), (float(v.min()), float(v.max()))


def phase_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                  step: tuple[float, float] | None = None) -> dict[str, Any]:
    """The phase portrait's path up to the end of the first steady cycle
    (:func:`app.sampling.draw_horizon`): per mode name the columns ``x``, ``v`` of its
    pieces (NaN between pieces), each piece sampled so that no chord is longer than
    ``step`` (default :func:`phase_step` of the samples' bounds); ``t_draw`` the time
    drawn to, and ``repeat`` the state where a steady cycle closes (drawn once) with the
    number of its repeats within the horizon."""
    res = sol.result
    empty = {"x": _f32([]), "v": _f32([])}
    out: dict[str, Any] = {name: dict(empty) for name in MODE_NAMES.values()}
    out["t_draw"], out["repeat"] = 0.0, {"x": _f32([]), "v": _f32([]), "text": []}
    if res is None or len(res.t) == 0:
        return out
    if step is None:
        step = phase_step(*_sample_bounds(sol))
    evaluate, exact = _drawing(sol)
    t_draw = sampling.draw_horizon(res, sol.t_end, step)
    # Without the closed form, evaluating costs (a deformable stop's contacts: ~3 ms per
    # thousand points): the result's own samples are taken as they are.
    path = sampling.phase_path(res, evaluate, t_draw, step, known=not exact)
    x, v, mode = path.x, path.v * scales.velocity, path.mode
    # Consecutive pieces meet at their transition's state, so each mode's runs are drawn
    # as they are, one NaN after each run to break the line.
    for m, name in MODE_NAMES.items():
        sel = mode == m
        keep = sel | np.r_[False, sel[:-1]]
        out[name] = {"x": _f32(np.where(sel, x, np.nan)[keep]),
                     "v": _f32(np.where(sel, v, np.nan)[keep])}
    out["t_draw"] = t_draw
    steady = res.steady
    if t_draw < sol.t_end and math.isfinite(steady.period) and steady.period > 0 and (
            steady.kind.value == "periodic"):
        repeats = int((sol.t_end - t_draw) // steady.period)
        xr, vr = evaluate(np.array([t_draw]))
        out["repeat"] = {"x": _f32(xr), "v": _f32(vr * scales.velocity),
                         "text": [f"repeats {repeats}x"]}
    return out


def transition_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                       t_draw: float = math.inf) -> dict[str, list]:
    """Markers of the transitions the phase portrait draws (up to ``t_draw``; the later
    ones repeat them)."""
    res = sol.result
    trs = [tr for tr in res.transitions if tr.t <= t_draw] if res is not None else []
    trs = trs[-MAX_MARKERS:]
    styles = [TRANSITION_STYLE.get(tr.kind.value, ("circle", "#000000")) for tr in trs]
    return {
        "x": _f32([tr.x for tr in trs]),
        "v": _f32([tr.v * scales.velocity for tr in trs]),
        "t": _f32([tr.t * scales.time for tr in trs]),
        "kind": [tr.kind.value for tr in trs],
        "marker": [s[0] for s in styles],
        "color": [s[1] for s in styles],
    }


def band_columns(bands, scales: Scales = DIMENSIONLESS) -> dict[str, Any]:
    """Mode bands behind the time histories: ``left``, ``right``, ``color``, from
    :func:`app.sampling.mode_bands` (a stick interval narrower than a pixel column covers
    the column)."""
    left, right, mode = bands
    return {
        "left": _f32(np.asarray(left) * scales.time),
        "right": _f32(np.asarray(right) * scales.time),
        "color": [BAND_COLORS[int(m)] for m in mode],
    }


def reference_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """The thin references of the phase portrait: Gamma_0, the impactless limit cycle (or
    the pure slip circle of a fast belt), and the theory's steady-state points."""
    empty = {"x": _f32([]), "v": _f32([])}
    th = sol.theory
    if th is None:
        return {"gamma0": empty, "cycle": empty, "removed": empty,
                "points": _theory_points({}, math.inf, scales)}
    a, v = sol.osc.a, sol.osc.v
    phi = np.linspace(0.0, 2.0 * math.pi, CIRCLE_VERTICES)
    gamma0 = {"x": _f32(a + th.gamma0_radius * np.cos(phi)),
              "v": _f32(th.gamma0_radius * np.sin(phi) * scales.velocity)}
    if th.fast or th.limit_cycle is None:
        radius = th.critical_speed
        cycle = {"x": _f32(a + radius * np.cos(phi)),
                 "v": _f32(radius * np.sin(phi) * scales.velocity)}
    else:
        lc = th.limit_cycle
        cx = lc.centre[0] + lc.radius * np.cos(phi)
        cv = lc.radius * np.sin(phi)
        # The slip arc is the part of the circle below the stick line x' = v.
        arc = cv <= v * (1 + 1e-12)
        cv = np.where(arc, cv, np.nan)
        start = int(np.argmax(~arc)) if (~arc).any() else len(phi)
        order = np.r_[start:len(phi), 0:start]  # begin the arc inside the cut
        cx, cv = cx[order], cv[order]
        cx = np.r_[cx, np.nan, lc.stick_start[0], lc.stick_end[0]]
        cv = np.r_[cv, np.nan, v, v]
        cycle = {"x": _f32(cx), "v": _f32(cv * scales.velocity)}
    stop = sol.stop.clearance if sol.stop is not None else math.inf
    return {"gamma0": gamma0, "cycle": cycle, "removed": removed_circle(sol, scales),
            "points": _theory_points(th.points, stop, scales, a)}


def _applicable_points(points: Mapping[str, list], sources: Mapping[str, Any]
                       ) -> dict[str, list]:
    """The theory's points that the drawn motion can have: no stick points when it never
    sticks (a pure slip orbit), no impact points when it never reaches the stop."""
    sticks = len(sources["path_stick"].data["x"]) > 0
    impacts = any(k in ("impact", "stick->impact") for k in sources["trans"].data["kind"])
    keep = [i for i, name in enumerate(points["name"])
            if (sticks or "stick" not in name) and (impacts or "impact" not in name)]
    return {k: [col[i] for i in keep] for k, col in points.items()}


def removed_circle(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, np.ndarray]:
    """The pure slip circle the mass would follow if the stop were removed once it rests
    pressed on it (paper Sec. 4.6, dotted in Figs. 6b and 7d): centre ``(a, 0)`` through
    the rest point ``(x_bar, 0)``. Empty unless the motion ends at rest on a rigid stop
    short of ``a`` on a moving belt."""
    res, stop = sol.result, sol.stop
    a = sol.osc.a
    if (res is None or stop is None or sol.values["stop_type"] != "rigid"
            or res.steady.kind.value != "rest" or sol.osc.v <= 0 or stop.clearance >= a):
        return {"x": _f32([]), "v": _f32([])}
    radius = a - stop.clearance
    phi = np.linspace(0.0, 2.0 * math.pi, CIRCLE_VERTICES)
    return {"x": _f32(a + radius * np.cos(phi)),
            "v": _f32(radius * np.sin(phi) * scales.velocity)}


def _theory_points(named: Mapping[str, tuple[float, float]], stop: float,
                   scales: Scales, centre: float = math.nan) -> dict:
    """The theory's points with their labels; points that coincide (a stick segment that
    ends at the stop: its end is the impact point) are one marker with a joint label, not
    labels printed over each other.

    Each label is anchored by its corner next to the point (``align``, ``baseline``), that
    corner off the point by ``dx``, ``dy`` [px] (:func:`label_offsets`). That corner is
    also the one the browser tries first (``side``, "<align> <baseline>") when it places
    the labels on the frame it lays out (:data:`PLACE_LABELS_JS`: another one where this
    one would leave the frame or touch a label, a marker or the stop). The preferred side
    is away from the curves through the point:

    - points on the stick line are labelled above it, written rightwards;
    - points on the stop are labelled left of it (the stop is the motion's right edge: the
      label stays in view), on the side of the slip arc through the point that faces away
      from it: the arc about ``(centre, 0)`` leaves the stop leftwards towards the x axis
      when the stop lies short of the centre and away from it beyond, so the label goes
      above a point of the upper half beyond the centre (``P_CSl`` of Fig. 5a: towards the
      axis, inside the orbit) and below one short of it; a label goes below its point too
      when a label on the same level, to its left, is written towards it (the stick line's
      two ends: their labels ran into each other when the stick is short);
    - the limit point on the x axis (``P_lim``) is labelled above it on the side away from
      the circle's centre: the circle about ``(centre, 0)`` through it lies on the other
      side (Fig. 6b: the label left of the stop, off the pure slip circle beyond it; Fig.
      7c: right of the stop, off the grazing circle short of it).

    >>> p = _theory_points({"P_stick_end": (0.25, 0.07), "P_impact_in": (0.25, 0.07 + 1e-15),
    ...                     "P_stick_start": (0.1, 0.07)}, 0.25, DIMENSIONLESS, 0.2)
    >>> p["name"], p["align"], p["baseline"], p["dy"]
    (['stick end = impact in', 'stick start'], ['right', 'left'], ['top', 'bottom'], [-3, 3])
    >>> p = _theory_points({"P_limit": (0.24, 0.0)}, 0.24, DIMENSIONLESS, 0.2)
    >>> p["align"], p["dx"], p["baseline"], p["side"]
    (['left'], [8], ['bottom'], ['left bottom'])
    """
    merged: list[tuple[float, float, list[str]]] = []
    keys: list[list[str]] = []
    for key, (x, v) in named.items():
        label = key.removeprefix("P_").replace("_", " ")
        for (mx, mv, labels), same in zip(merged, keys, strict=True):
            if math.isclose(x, mx, rel_tol=1e-9, abs_tol=1e-12) and math.isclose(
                    v, mv, rel_tol=1e-9, abs_tol=1e-12):
                labels.append(label)
                same.append(key)
                break
        else:
            merged.append((x, v, [label]))
            keys.append([key])
    on_stop = [m[0] >= stop - 1e-9 * max(1.0, abs(stop)) for m in merged]
    level = LABEL_LEVEL_FRACTION * max((abs(m[1]) for m in merged), default=0.0)
    facing = [s and any(not other_s and o[0] < m[0] and abs(o[1] - m[1]) <= level
                        for o, other_s in zip(merged, on_stop, strict=True))
              for m, s in zip(merged, on_stop, strict=True)]
    tiny = 1e-9 * max(1.0, abs(stop) if math.isfinite(stop) else 1.0)
    rightwards, above, axis = [], [], []
    for (x, v, _), s, f in zip(merged, on_stop, facing, strict=True):
        axis.append(s and abs(v) <= tiny)
        if not s:  # on the stick line: the slip arc leaves its end down to the right
            rightwards.append(not x > centre)
            above.append(not x > centre)
        elif axis[-1]:
            rightwards.append(x > centre + tiny)
            above.append(True)
        else:
            rightwards.append(False)
            above.append(not f and v * (x - centre) <= 0.0)
    side = [1 if r else -1 for r in rightwards]
    up = [1 if a else -1 for a in above]
    dy = [u * (LABEL_AXIS_PX if a else LABEL_ABOVE_PX) for u, a in zip(up, axis, strict=True)]
    align = ["left" if r else "right" for r in rightwards]
    baseline = ["bottom" if a else "top" for a in above]
    return {"x": [m[0] for m in merged], "v": [m[1] * scales.velocity for m in merged],
            "name": [" = ".join(m[2]) for m in merged],
            "paper": [_paper_name(k) for k in keys], "align": align, "baseline": baseline,
            "dx": [d * LABEL_GAP_PX for d in side], "dy": dy,
            "side": [f"{a} {b}" for a, b in zip(align, baseline, strict=True)]}


@cache
def _place_labels_code() -> str:
    return PLACE_LABELS_JS.read_text(encoding="utf-8")


def _paper_name(keys: list[str]) -> str:
    """The paper's name of a point that is each of ``keys`` (:data:`PAPER_NAMES`).

    >>> _paper_name(["P_stick_end", "P_impact_in"]), _paper_name(["P_impact_out"])
    ('P_StC', 'P_CSl')
    """
    if {"P_stick_end", "P_impact_in"} <= set(keys):
        return PAPER_STICK_CONTACT
    return " = ".join(PAPER_NAMES.get(k, k) for k in keys)


#: The contact-force plot's title.
FORCE_TITLE = "Contact force"
#: What the contact-force plot's left axis shows, by run (:func:`force_quantity`).
IMPULSES, CONTACT_FORCE, PROGRAM_FORCE = ("impulses", "contact force",
                                          "contact force over the program phase")


def force_quantity(sol: Solution) -> str:
    """What the contact-force plot draws of ``sol`` on its left axis: a rigid stop's
    impulses (:data:`IMPULSES`), the overlap program's force over its phase
    (:data:`PROGRAM_FORCE`), otherwise the contact force over time (:data:`CONTACT_FORCE`).
    Runs of different quantities are not drawn on one axis.

    >>> from app.state import scene_values
    >>> from app.solve.pool import solve
    >>> force_quantity(solve(scene_values("7c"))), force_quantity(solve(scene_values("10")))
    ('impulses', 'contact force')
    """
    if sol.program is not None:
        return PROGRAM_FORCE
    return IMPULSES if sol.values["stop_type"] == "rigid" else CONTACT_FORCE


def force_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Contact force: rigid impulses as stems (``t``, ``j``) and, once the mass rests on a
    rigid stop, the force that holds it there (``rest``: ``k (a - x_bar)``, docs/physics.md,
    "Rest at the stop"; on an axis of its own); deformable ``phi(t)``."""
    res, prog = sol.result, sol.program
    stems = {"t": _f32([]), "j": _f32([])}
    line = {"t": _f32([]), "phi": _f32([])}
    rest = {"t": _f32([]), "f": _f32([])}
    if prog is not None:
        line = {"t": _f32(prog.s), "phi": _f32(prog.force * scales.force)}
    elif res is not None and sol.values["stop_type"] == "rigid":
        # Every stored impact (the core stores the first ``transition_cap``).
        imp = np.asarray(res.impulses).reshape(-1, 2)
        stems = {"t": _f32(imp[:, 0] * scales.time), "j": _f32(imp[:, 1] * scales.impulse)}
        pressed = np.asarray(res.mode) == int(Mode.CONTACT)
        if pressed.any():
            idx = _columns(res, (np.asarray(res.contact_force),))
            f = np.where(pressed[idx], np.asarray(res.contact_force)[idx], np.nan)
            rest = {"t": _f32(res.t[idx] * scales.time), "f": _f32(f * scales.force)}
    elif res is not None and sol.values["stop_type"] == "hysteretic":
        t, phi = _thinned(res, (np.asarray(res.contact_force),))
        line = {"t": _f32(t * scales.time), "phi": _f32(phi * scales.force)}
    return {"stems": stems, "line": line, "rest": rest}


def _columns(res, series: tuple[np.ndarray, ...]) -> np.ndarray:
    """Indices of the result's samples that draw ``series`` over time as every sample
    would, on :data:`HISTORY_COLUMNS` pixel columns (:func:`app.sampling.m4`)."""
    t = np.asarray(res.t, float)
    if len(t) == 0:
        return np.zeros(0, np.int64)
    return sampling.m4(t, series, float(t[0]), float(t[-1]), HISTORY_COLUMNS)


def _thinned(res, series: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """``t`` and ``series`` at the samples that draw them, on one axis, as every sample
    would: reduced per pixel column (:func:`_columns`), then thinned
    (:func:`app.sampling.thin`)."""
    idx = _columns(res, series)
    t = np.asarray(res.t, float)[idx]
    ys = tuple(np.asarray(y, float)[idx] for y in series)
    tol = sampling.thin_tolerance(*ys)
    keep = sampling.thin(t, ys, (tol,) * len(ys))
    return (t[keep], *(y[keep] for y in ys))


def loop_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Hysteresis loop ``phi`` vs overlap in contact, and both envelopes of the stop."""
    stop = sol.stop
    empty = {"d": _f32([]), "phi": _f32([])}
    if sol.values["stop_type"] != "hysteretic" or stop is None:
        return {"loop": empty, "comp": empty, "exp": empty}
    if sol.program is not None:
        d, phi = sol.program.overlap, sol.program.force
    elif sol.result is not None:
        ov, f = np.asarray(sol.result.overlap), np.asarray(sol.result.contact_force)
        inside = ov > 0
        # Break the line between contacts so separate loops are not joined.
        gap = np.concatenate(([False], np.diff(inside.astype(int)) == 1))
        d = np.where(inside, ov, np.nan)
        phi = np.where(inside, f, np.nan)
        keep = inside | np.roll(inside, -1) | gap
        d, phi = d[keep][-MAX_LOOP_POINTS:], phi[keep][-MAX_LOOP_POINTS:]
    else:
        d = phi = np.zeros(0)
    d_max = float(np.nanmax(d)) if np.isfinite(d).any() else stop.limit_overlap / 2
    grid = np.linspace(0.0, min(1.15 * d_max, 0.95 * stop.limit_overlap), ENVELOPE_SAMPLES)
    return {
        "loop": {"d": _f32(d), "phi": _f32(phi * scales.force)},
        "comp": {"d": _f32(grid), "phi": _f32(phi_compression(grid, stop) * scales.force)},
        "exp": {"d": _f32(grid), "phi": _f32(phi_expansion(grid, stop) * scales.force)},
    }


def friction_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Coulomb's law (paper Fig. 1b) over the relative velocity ``u_r = v - x'``, and the
    operating points of the trajectory: ``(u_r, a sign(u_r))`` in slip and ``(0, x +
    phi/k)`` in stick (the friction that holds the mass)."""
    a, b = sol.osc.a, sol.osc.b
    res = sol.result
    u_max = 1.2 * max(float(np.max(np.abs(sol.osc.v - res.v))) if res is not None and
                      len(res.v) else 0.0, sol.osc.v, 1e-3)
    fs, us = scales.force, scales.velocity
    law = {"u": _f32(np.array([-u_max, 0.0, 0.0, 0.0, 0.0, u_max]) * us),
           "f": _f32(np.array([-a, -a, -b, b, a, a]) * fs)}
    if res is None:
        return {"law": law, "ops": {"u": _f32([]), "f": _f32([]), "color": []}}
    idx = np.linspace(0, len(res.t) - 1, min(len(res.t), MAX_OPERATING_POINTS)).astype(int)
    u = sol.osc.v - res.v[idx]
    mode = res.mode[idx]
    hold = res.x[idx] + np.asarray(res.contact_force)[idx]
    f = np.where(mode == Mode.STICK, hold, a * np.sign(u))
    u = np.where(mode == Mode.STICK, 0.0, u)
    return {"law": law, "ops": {"u": _f32(u * us), "f": _f32(f * fs),
                                "color": [MODE_COLORS[int(m)] for m in mode]}}


def energy_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, np.ndarray]:
    """Cumulative energy terms (per unit ``k``; in SI, joules), as a budget of what the belt
    puts in: ``belt_input = (mechanical - mechanical[0]) + friction_heat + stop_loss +
    stop_stored``, where ``friction_heat = belt_input - friction_work`` is the heat of the
    sliding contact (``int F u_r dt >= 0``) and ``friction_work`` the work of friction on
    the mass (:class:`core.Energy`)."""
    res = sol.result
    names = tuple(ENERGY_COLORS)
    if res is None:
        return {"t": _f32([]), **{n: _f32([]) for n in names}}
    e = res.energy
    terms = {"mechanical": e.mechanical, "belt_input": e.belt_input,
             "friction_heat": np.asarray(e.belt_input) - np.asarray(e.friction_work),
             "stop_loss": e.stop_loss, "stop_stored": e.stop_stored}
    t, *ys = _thinned(res, tuple(np.asarray(terms[n], float) for n in names))
    cols = {"t": _f32(t * scales.time)}
    for n, y in zip(names, ys, strict=True):
        cols[n] = _f32(y * scales.energy)
    return cols


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
        self.sources = {
            name: self.shared.source(cols)
            for name, cols in _EMPTY.items()
        }
        self.spans: dict[str, Span] = {}
        self.labels: dict[str, Label] = {}
        self.figures: dict[str, Any] = {}
        self.legends: dict[str, pn.pane.HTML] = {}
        self.panes: dict[str, Any] = {}
        self._theory_renderers: list[Any] = []
        self.rest_axis: LinearAxis | None = None
        self.point_labels: LabelSet | None = None
        self._last: Solution | None = None
        self._kinds_stop: str | None = None
        self._kinds_shown: set[str] = set()
        self._dirty: set[str] = set()
        self._map_shown: Mapping[str, Any] | None = None
        self._map_scales: Scales | None = None
        self._map_frame: tuple[float, float, float] | None = None
        self._map_frame_key: tuple | None = None
        self._bands = (np.zeros(0), np.zeros(0), np.zeros(0, np.int8))
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
            before = set(self.figures)
            # Built with Bokeh's checks on, also under a caller's ``validate(False)``: they
            # turn values such as a title's text into models.
            with validate(True):
                getattr(self, f"_build_{name}")(self.sources)
            for key in set(self.figures) - before:
                self.shared.lighten(self.figures[key])
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

    @staticmethod
    def _figure(title: str, size: tuple[int, int], **kw) -> Any:
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

    def _build_phase(self, s) -> None:
        # Equal aspect: the browser fits the ranges to the frame it lays out
        # (``match_aspect``; ``aspect_scale`` is omega in SI units, so that x and x'/omega
        # share one scale). The server does not know the frame's size, so this figure's
        # ranges are the one thing computed in the browser.
        # One padding for both: BokehJS pads after fitting the aspect, each axis by a
        # fraction of its own span, which keeps the ratio only if the fractions are equal.
        x_range = DataRange1d(range_padding=PHASE_X_PADDING, only_visible=True)
        y_range = DataRange1d(range_padding=PHASE_X_PADDING, only_visible=True)
        fig = self._figure("Phase portrait (x, x')", PHASE_SIZE, x_axis_label="x",
                           y_axis_label="x'", x_range=x_range, y_range=y_range,
                           match_aspect=True)
        theory = self._theory_renderers = []
        ranged = [add_glyph(fig, "line", "x", "v", source=s["gamma0"], **PHASE_STYLE["gamma0"]),
                  add_glyph(fig, "line", "x", "v", source=s["cycle"], **PHASE_STYLE["cycle"]),
                  add_glyph(fig, "line", "x", "v", source=s["removed"], **PHASE_STYLE["removed"])]
        theory += ranged
        for name in MODE_NAMES.values():
            ranged.append(add_glyph(fig, "line", "x", "v", source=s[f"path_{name}"],
                                    **PHASE_STYLE[name]))
        add_glyph(fig, "scatter", "x", "v", source=s["trans"], marker="marker", color="color",
                  size=7, fill_alpha=0.6)
        theory.append(add_glyph(fig, "scatter", "x", "v", source=s["points"],
                                **PHASE_STYLE["points"]))
        ranged.append(theory[-1])
        # The stop, when near the motion (:func:`_stop_in_view`), is in the ranges too.
        ranged.append(add_glyph(fig, "scatter", "x", "v", source=s["stop_pt"], size=0, alpha=0.0))
        # On a light backing: a label next to the stop line was crossed by it ("stick end"
        # of Fig. 5a, "limit" of Fig. 7c).
        labels = LabelSet(x="x", y="v", text="name", source=s["points"], x_offset="dx",
                          text_align="align", text_baseline="baseline", y_offset="dy",
                          text_font_size=f"{LABEL_FONT_PX}px",
                          background_fill_color="#ffffff", background_fill_alpha=0.8)
        fig.add_layout(labels)
        theory.append(labels)
        self.point_labels = labels
        # Where a periodic steady state closes: drawn once, its repeats counted.
        add_glyph(fig, "scatter", "x", "v", source=s["repeat"], **PHASE_STYLE["repeat"])
        ranged.append(add_glyph(fig, "scatter", "x", "v", source=s["start"],
                                **PHASE_STYLE["start"]))
        x_range.renderers = y_range.renderers = ranged
        # Underlay: the stick segment runs along the belt line and must stay visible.
        self.spans["stop"] = Span(location=0.0, dimension="height", line_color="#000000",
                                  line_width=3, level="underlay")
        self.spans["belt"] = Span(location=0.0, dimension="width", line_color="#2ca02c",
                                  line_dash="dotted", line_width=2, level="underlay")
        fig.add_layout(self.spans["stop"])
        fig.add_layout(self.spans["belt"])
        self._place_labels(fig, labels)
        # The legend is HTML below the figure (one model, drawn by the browser's layout,
        # not a Bokeh legend with a stand-in renderer per entry).
        self.legends["phase"] = _legend_pane()
        self.figures["phase"] = fig
        self.panes["phase"] = fig

    def _place_labels(self, fig: Any, labels: LabelSet) -> None:
        """Let the browser place the theory points' labels (:data:`PLACE_LABELS_JS`) each
        time the frame, the ranges, the labels' font or what the portrait draws changes
        (renderers added later are avoided but not watched: the animation's marker moves
        on every frame): one ``CustomJS`` model for the page."""
        stop = self.spans["stop"]
        place = CustomJS(args={"labels": labels, "fig": fig, "stop": stop},
                         code=_place_labels_code())
        watched = [(fig, ("inner_width", "inner_height")),
                   (fig.x_range, ("start", "end")), (fig.y_range, ("start", "end")),
                   (labels, ("text_font_size", "text_font_style", "text")),
                   (stop, ("location", "visible"))]
        sources = {r.data_source for r in fig.renderers if isinstance(r, GlyphRenderer)}
        watched += [(src, ("data",)) for src in sources]
        for model, attrs in watched:
            for attr in attrs:
                model.js_on_change(attr, place)

    def _build_time(self, s) -> None:
        fig_x = self._figure("Displacement x(t)", TIME_SIZE, y_axis_label="x")
        fig_v = self._figure("Velocity x'(t)", TIME_SIZE, x_axis_label="t",
                             y_axis_label="x'", x_range=fig_x.x_range)
        for fig, col in ((fig_x, "x"), (fig_v, "v")):
            add_glyph(fig, "quad", left="left", right="right", bottom=-BAND_EXTENT, top=BAND_EXTENT,
                      source=s["bands"], fill_color="color", line_color=None)
            add_glyph(fig, "line", "t", col, source=s["traj"], line_color="#222222", line_width=1.5)
        self.spans["stop_t"] = Span(location=0.0, dimension="width", line_color="#000000",
                                    line_width=2, level="underlay")
        self.spans["belt_t"] = Span(location=0.0, dimension="width", line_color="#2ca02c",
                                    line_dash="dotted", line_width=2, level="underlay")
        fig_x.add_layout(self.spans["stop_t"])
        fig_v.add_layout(self.spans["belt_t"])
        self.figures["time_x"], self.figures["time_v"] = fig_x, fig_v
        self.panes["time"] = column(fig_x, fig_v, sizing_mode="stretch_width")

    def _build_force(self, s) -> None:
        fig = self._figure(FORCE_TITLE, SMALL_SIZE, x_axis_label="t",
                           y_axis_label="impulse / force")
        add_glyph(fig, "segment", "t", 0.0, "t", "j", source=s["stems"], line_color=MODE_COLORS[2],
                  line_width=1.5)
        add_glyph(fig, "scatter", "t", "j", source=s["stems"], size=5, color=MODE_COLORS[2])
        add_glyph(fig, "line", "t", "phi", source=s["force"], line_color=MODE_COLORS[2],
                  line_width=1.5)
        # The force holding the mass on a rigid stop (a force, not an impulse): own axis.
        fig.extra_y_ranges = {"rest": Range1d(0.0, 1.0)}
        self.rest_axis = LinearAxis(y_range_name="rest", axis_label="force at rest",
                                    axis_label_text_color=REST_COLOR, visible=False,
                                    axis_label_text_font_size=AXIS_LABEL_FONT,
                                    major_label_text_font_size=TICK_LABEL_FONT)
        fig.add_layout(self.rest_axis, "right")
        add_glyph(fig, "line", "t", "f", source=s["rest"], y_range_name="rest",
                  line_color=REST_COLOR, line_width=2, line_dash="dashed")
        self.figures["force"] = fig
        self.panes["force"] = fig

    def _build_loop(self, s) -> None:
        fig = self._figure("Hysteresis loop phi(overlap)", SMALL_SIZE,
                           x_axis_label="overlap x - x_bar", y_axis_label="phi / k")
        items = []
        for name, label, style in (
            ("comp", "compression envelope", {"line_color": "#444444", "line_dash": "dashed"}),
            ("exp", "expansion envelope", {"line_color": "#888888", "line_dash": "dotdash"}),
            ("loop", "contact force", {"line_color": MODE_COLORS[2], "line_width": 2}),
        ):
            add_glyph(fig, "line", "d", "phi", source=s[name], **style)
            items.append((label, _swatch("line", **style), ""))
        self.legends["loop"] = _legend_pane(legend_html(items))
        self.figures["loop"] = fig
        self.panes["loop"] = fig

    def _build_friction(self, s) -> None:
        fig = self._figure("Friction law (Fig. 1b)", SMALL_SIZE,
                           x_axis_label="relative velocity u_r = v - x'",
                           y_axis_label="friction force / k")
        add_glyph(fig, "line", "u", "f", source=s["law"], line_color="#000000", line_width=2)
        add_glyph(fig, "scatter", "u", "f", source=s["ops"], color="color", size=6, alpha=0.5)
        self.figures["friction"] = fig
        self.panes["friction"] = fig

    def _build_energy(self, s) -> None:
        fig = self._figure("Energy", SMALL_SIZE, x_axis_label="t", y_axis_label="energy / k")
        items = []
        for name, color in ENERGY_COLORS.items():
            add_glyph(fig, "line", "t", name, source=s["energy"], line_color=color, line_width=1.5)
            items.append((name.replace("_", " "),
                          _swatch("line", line_color=color, line_width=1.5), ""))
        self.legends["energy"] = _legend_pane(legend_html(items))
        self.figures["energy"] = fig
        self.panes["energy"] = fig

    def _build_map(self, s) -> None:
        fig = self._figure("Regime map (tap to move there)", MAP_SIZE,
                           x_axis_label="belt speed v", y_axis_label="clearance x_bar",
                           x_range=Range1d(0, 1), y_range=Range1d(0, 1))
        self.map_mapper = LinearColorMapper(palette=list(MAP_PALETTE), low=-0.5,
                                            high=len(MAP_PALETTE) - 0.5)
        add_glyph(fig, "image", image="image", x="x", y="y", dw="dw", dh="dh", source=s["map"],
                  color_mapper=self.map_mapper)
        # Overlay level: moving the marker repaints only the overlay canvas, not the image.
        add_glyph(fig, "scatter", "v", "x", source=s["here"], marker="circle_cross", size=14,
                  fill_color="#ffffff", line_color="#000000", line_width=2, level="overlay")
        fig.center = [r for r in fig.center if not isinstance(r, Grid)]  # a map: no grid
        self.figures["map"] = fig
        self.panes["map"] = fig

    # --- updating ------------------------------------------------------------------------

    def update(self, sol: Solution, scales: Scales, visible: tuple[str, ...],
               map_data: Mapping[str, Any] | None = None) -> None:
        """Assign the new columns of every visible plot (call under ``pn.io.hold``).

        Hidden plots are marked stale and filled by :meth:`refresh` when shown.
        """
        self._last, self._scales = sol, scales
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
        _assign(self.sources["start"], {"x": [sol.x0], "v": [sol.v0 * scales.velocity]})
        self._draw_motion(sol, scales)
        cols = force_columns(sol, scales)
        _assign(self.sources["stems"], cols["stems"])
        _assign(self.sources["force"], cols["line"])
        _assign(self.sources["rest"], cols["rest"])
        self._set_spans(sol, scales)
        self._set_ranges({"phase", "time", "force"} & self.built, sol)

    def _draw_motion(self, sol: Solution, scales: Scales) -> None:
        """The phase path, the transitions it passes, and the time histories."""
        s = self.sources
        step = self._phase_step(sol, scales)
        traj = trajectory_columns(sol, scales)
        self._bands = traj.pop("bands", (np.zeros(0), np.zeros(0), np.zeros(0, np.int8)))
        _assign(s["traj"], traj)
        phase = phase_columns(sol, scales, step)
        for name in MODE_NAMES.values():
            _assign(s[f"path_{name}"], phase[name])
        _assign(s["repeat"], phase["repeat"])
        _assign(s["trans"], transition_columns(sol, scales, phase["t_draw"]))

    def _phase_legend(self) -> list[tuple[str, str, str]]:
        """Entries of what the phase portrait draws: ``(label, swatch, explanation)``."""
        d = {name: src.data for name, src in self.sources.items()}
        out = []
        for key in ("gamma0", "cycle", "removed"):
            if len(d[key]["x"]):
                label, note = PHASE_LABELS[key]
                out.append((label, _swatch("line", **PHASE_STYLE[key]), note))
        for name in MODE_NAMES.values():
            if len(d[f"path_{name}"]["x"]):
                out.append((name, _swatch("line", **PHASE_STYLE[name]), ""))
        for kind, (marker, color) in TRANSITION_STYLE.items():
            if kind in self._kinds_shown:
                out.append((TRANSITION_LABELS.get(kind, kind),
                            _swatch(marker, fill_color=color, line_color=color), ""))
        for key in ("points", "repeat", "start"):
            if len(d[key]["x"]):
                label, note = PHASE_LABELS[key]
                if key == "repeat":  # with the count of repeats
                    label = f"{label} ({d[key]['text'][0]})"
                style = PHASE_STYLE[key]
                out.append((label, _swatch(**style), note))
        return out + list(self.more_legend())

    def refresh_legend(self) -> None:
        """Write the phase portrait's legend again (its entries changed, not its data)."""
        if "phase" in self.legends:
            text = legend_html(self._phase_legend())
            if self.legends["phase"].object != text:
                self.legends["phase"].object = text

    def _set_theory_visible(self, visible: bool) -> None:
        for r in self._theory_renderers:
            if r.visible != visible:
                r.visible = visible

    def _phase_step(self, sol: Solution, scales: Scales) -> tuple[float, float]:
        """Chord bound of the phase path (:func:`phase_step`) for a view that shows the
        motion and the reference curves (dimensionless)."""
        d = {name: self.sources[name].data for name in ("gamma0", "cycle")}
        (x0, x1), (v0, v1) = _sample_bounds(sol)
        for ref in d.values():
            if len(ref["x"]):
                x0, x1 = min(x0, float(np.min(ref["x"]))), max(x1, float(np.max(ref["x"])))
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
        s = self.sources
        # Only built figures (and the mechanism, which reads the trajectory) are filled;
        # a plot built later is stale until the refresh after it (:meth:`build`).
        todo = self._dirty.intersection(visible).intersection({*self.panes, "anim"})
        if todo & {"phase", "time", "anim", "friction"}:
            self._set_theory_visible(True)
            refs = reference_columns(sol, scales)
            _assign(s["gamma0"], refs["gamma0"])
            _assign(s["cycle"], refs["cycle"])
            _assign(s["removed"], refs["removed"])
            _assign(s["start"], {"x": [sol.x0], "v": [sol.v0 * scales.velocity]})
            self._draw_motion(sol, scales)
            _assign(s["points"], _applicable_points(refs["points"], s))
            # Entries stay once shown (until the stop type changes): a legend that changes
            # size relayouts and repaints its figure once more after each release.
            stop_type = sol.values["stop_type"]
            if stop_type != self._kinds_stop:
                self._kinds_stop, self._kinds_shown = stop_type, set()
            self._kinds_shown.update(s["trans"].data["kind"])
            text = legend_html(self._phase_legend())
            if "phase" in self.legends and self.legends["phase"].object != text:
                self.legends["phase"].object = text
            self._dirty -= {"phase", "anim"}
        if "time" in todo:
            _assign(s["bands"], band_columns(self._bands, scales))
            self._dirty.discard("time")
        if "force" in todo:
            cols = force_columns(sol, scales)
            _assign(s["stems"], cols["stems"])
            _assign(s["force"], cols["line"])
            _assign(s["rest"], cols["rest"])
            self.rest_axis.visible = bool(np.isfinite(cols["rest"]["f"]).any())
            self._dirty.discard("force")
        if "loop" in todo:
            cols = loop_columns(sol, scales)
            for name in ("loop", "comp", "exp"):
                _assign(s[name], cols[name])
            self._dirty.discard("loop")
        if "friction" in todo:
            cols = friction_columns(sol, scales)
            _assign(s["law"], cols["law"])
            _assign(s["ops"], cols["ops"])
            self._dirty.discard("friction")
        if "energy" in todo:
            _assign(s["energy"], energy_columns(sol, scales))
            self._dirty.discard("energy")
        if "map" in todo and map_data is not None:
            self._set_map(sol, scales, map_data)
            self._dirty.discard("map")
        self._set_spans(sol, scales)
        self._set_labels(sol, scales)
        self._set_ranges(todo, sol)

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
        d = {name: src.data for name, src in self.sources.items()}
        f = self.figures
        plots = set(plots) & self.built
        more = self.more_extents() if plots & {"time", "force", "loop"} else {}
        stop = _stop_in_view(d["traj"]["x"], sol) if plots & {"phase", "time"} else []
        if "phase" in plots:  # ranges fitted in the browser (match_aspect); the stop:
            _assign(self.sources["stop_pt"], {"x": stop, "v": [0.0] * len(stop)})
        if "time" in plots:
            traj = d["traj"]
            _set_range(f["time_x"].x_range, (traj["t"], more.get(("time_x", "x"), ())), 0.0)
            _set_range(f["time_x"].y_range, (traj["x"], stop, more.get(("time_x", "y"), ())),
                       RANGE_PADDING)
            _set_range(f["time_v"].y_range, (traj["v"], more.get(("time_v", "y"), ())),
                       RANGE_PADDING)
        if "force" in plots:
            _set_range(f["force"].x_range, (d["stems"]["t"], d["force"]["t"], d["rest"]["t"],
                                            more.get(("force", "x"), ())), RANGE_PADDING)
            _set_range(f["force"].y_range, ((0.0,), d["stems"]["j"], d["force"]["phi"],
                                            more.get(("force", "y"), ())), RANGE_PADDING)
            _set_range(f["force"].extra_y_ranges["rest"], ((0.0,), d["rest"]["f"]),
                       RANGE_PADDING)
        if "loop" in plots:
            _set_range(f["loop"].x_range, (d["loop"]["d"], d["comp"]["d"], d["exp"]["d"],
                                           more.get(("loop", "x"), ())), RANGE_PADDING)
            _set_range(f["loop"].y_range, (d["loop"]["phi"], more.get(("loop", "y"), ())),
                       RANGE_PADDING)
        if "friction" in plots:
            _set_range(f["friction"].x_range, (d["law"]["u"], d["ops"]["u"]), RANGE_PADDING)
            _set_range(f["friction"].y_range, (d["law"]["f"], d["ops"]["f"]), RANGE_PADDING)
        if "energy" in plots:
            energy = d["energy"]
            _set_range(f["energy"].x_range, (energy["t"],), RANGE_PADDING)
            _set_range(f["energy"].y_range, tuple(energy[n] for n in ENERGY_COLORS),
                       RANGE_PADDING)

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
                span.location = sol.stop.clearance if has_stop else 0.0
        for name in ("belt", "belt_t"):
            if name in self.spans:
                self.spans[name].location = sol.osc.v * scales.velocity

    def _set_labels(self, sol: Solution, scales: Scales) -> None:
        f = self.figures
        if "phase" in f:
            f["phase"].xaxis.axis_label = scales.length_label
            f["phase"].yaxis.axis_label = scales.velocity_label
            if f["phase"].aspect_scale != scales.velocity:  # x'/omega and x on one scale
                f["phase"].aspect_scale = scales.velocity
        if "time_x" in f:
            f["time_x"].yaxis.axis_label = scales.length_label
            f["time_v"].yaxis.axis_label = scales.velocity_label
            f["time_v"].xaxis.axis_label = scales.time_label
        if "energy" in f:
            f["energy"].xaxis.axis_label = scales.time_label
            f["energy"].yaxis.axis_label = scales.energy_label
        if "friction" in f:
            f["friction"].yaxis.axis_label = scales.friction_label
        if "force" in f:
            program = sol.program is not None
            f["force"].xaxis.axis_label = "program phase s" if program else scales.time_label
            f["force"].left[0].axis_label = (scales.impulse_label
                                             if force_quantity(sol) == IMPULSES
                                             else scales.force_label)
            self.rest_axis.axis_label = f"force at rest: {scales.force_label}"
        if "loop" in f:
            f["loop"].yaxis.axis_label = scales.force_label
            f["loop"].xaxis.axis_label = "overlap x - x_bar" + (" (m)" if scales.si else "")
        if "map" in f:
            f["map"].xaxis.axis_label = ("belt speed v_dr (m/s)" if scales.si
                                         else "belt speed v")
            f["map"].yaxis.axis_label = "clearance x_bar" + (" (m)" if scales.si else "")

    def _set_map(self, sol: Solution, scales: Scales, data: Mapping[str, Any]) -> None:
        v_hi = data["v_hi"] * scales.velocity
        x_lo, x_hi = data["x_lo"], data["x_hi"]
        if data is not self._map_shown or scales is not self._map_scales:  # cached maps
            self._map_shown, self._map_scales = data, scales
            codes = np.asarray(data["codes"]) % len(MAP_PALETTE)
            self.sources["map"].data = {"image": [codes.astype(np.float32)], "x": [0.0],
                                        "y": [x_lo], "dw": [v_hi], "dh": [x_hi - x_lo]}
        fig = self.figures["map"]
        fig.x_range.update(start=0.0, end=v_hi)
        fig.y_range.update(start=x_lo, end=x_hi)
        # Without a stop the regime does not depend on the clearance: no clearance axis.
        has_stop = sol.values["stop_type"] != "none"
        if fig.yaxis[0].visible != has_stop:
            fig.yaxis[0].visible = has_stop
        clearance = sol.values["clearance"]
        _assign(self.sources["here"], {"v": [sol.osc.v * scales.velocity], "x": [clearance]})


def _swatch(marker: str = "line", **style: Any) -> str:
    """A small inline SVG of a line style or a marker, for an HTML legend."""
    color = style.get("line_color", style.get("color", "#000000"))
    fill = style.get("fill_color", style.get("color", color))
    width = style.get("line_width", 1.5)
    if marker == "line":
        dash = {"dashed": "4 3", "dotted": "1 2", "dotdash": "1 2 4 2"}.get(
            style.get("line_dash", ""), "")
        shape = (f'<line x1="1" y1="6" x2="17" y2="6" stroke="{color}" '
                 f'stroke-width="{width}" stroke-dasharray="{dash}"/>')
    else:
        shape = {
            "triangle": '<polygon points="9,1 15,11 3,11"',
            "inverted_triangle": '<polygon points="3,1 15,1 9,11"',
            "diamond": '<polygon points="9,0 15,6 9,12 3,6"',
            "square": '<rect x="4" y="2" width="9" height="9"',
            "square_pin": '<rect x="4" y="2" width="9" height="9"',
        }.get(marker, '<circle cx="9" cy="6" r="4.5"')
        shape += f' fill="{fill}" stroke="{color}" stroke-width="{min(width, 2)}"/>'
    return (f'<svg width="18" height="12" viewBox="0 0 18 12" aria-hidden="true" '
            f'style="vertical-align:-1px;margin-right:4px">{shape}</svg>')


def legend_html(entries: list[tuple[str, str, str]]) -> str:
    """An HTML legend: each entry's swatch and label, its explanation as a tooltip.

    >>> legend_html([("slip", "<svg/>", "")])
    '<span style="display:inline-block;margin-right:12px;white-space:nowrap"><svg/>slip</span>'
    """
    parts = []
    for label, swatch, note in entries:
        title = f' title="{html.escape(note)}"' if note else ""
        parts.append(f'<span style="display:inline-block;margin-right:12px;'
                     f'white-space:nowrap"{title}>{swatch}{html.escape(label)}</span>')
    return "".join(parts)


#: Lines of an HTML legend's height kept free (20 px each): entries that come and go
#: with the state do not move the plots below on every release.
LEGEND_LINES = 3


def _legend_pane(text: str = "") -> pn.pane.HTML:
    """An HTML legend below a figure. A Panel HTML pane, not a Bokeh ``Div``: BokehJS
    answers any change of a ``Div`` by laying out the whole page again, which resizes and
    repaints every figure (28-48 ms in Chromium on each release whose legend changed, e.g.
    the count of a cycle's repeats); the pane only replaces its inner HTML."""
    return pn.pane.HTML(text, sizing_mode="stretch_width", margin=(0, 10, 4, 50),
                        min_height=20 * LEGEND_LINES,
                        styles={"font-size": "12px", "line-height": "20px"})


def data_bounds(arrays: tuple[Any, ...], padding: float) -> tuple[float, float]:
    """``(start, end)`` of an axis showing every finite value of ``arrays``, widened by
    ``padding`` times the span (half on each side, as ``DataRange1d.range_padding``).

    >>> data_bounds((np.array([0.0, 2.0]), [np.nan, 4.0]), 0.5)
    (-1.0, 5.0)
    >>> data_bounds(([3.0],), 0.1)
    (2.5, 3.5)
    """
    finite = [a[np.isfinite(a)] for a in (np.asarray(x, dtype=float).ravel() for x in arrays)]
    values = np.concatenate(finite) if finite else np.zeros(0)
    if len(values) == 0:
        return 0.0, 1.0
    lo, hi = float(values.min()), float(values.max())
    if hi - lo <= EMPTY_SPAN * max(abs(lo), abs(hi), 1.0):
        return lo - 0.5, hi + 0.5
    half = 0.5 * padding * (hi - lo)
    return lo - half, hi + half


def _stop_in_view(x: Any, sol: Solution) -> list[float]:
    """``[x_bar]`` if the stop should widen the displacement axes, else ``[]``: always when
    the motion reaches it, and when it lies within :data:`STOP_VIEW_REACH` of the motion's
    span beyond it.

    >>> from types import SimpleNamespace as NS
    >>> _stop_in_view([0.0, 0.2], NS(stop=NS(clearance=0.25)))
    [0.25]
    >>> _stop_in_view([0.0, 0.2], NS(stop=NS(clearance=0.5)))
    []
    >>> _stop_in_view([0.0, 0.2], NS(stop=None))
    []
    """
    if sol.stop is None:
        return []
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    if len(x) == 0:
        return []
    clearance = float(sol.stop.clearance)
    lo, hi = float(x.min()), float(x.max())
    return [clearance] if clearance <= hi + STOP_VIEW_REACH * (hi - lo) else []


def _set_range(rng: Range1d, arrays: tuple[Any, ...], padding: float) -> None:
    """Show ``arrays`` in ``rng``; the reset tool returns to the same view."""
    start, end = data_bounds(arrays, padding)
    if (rng.start, rng.end, rng.reset_start, rng.reset_end) != (start, end, start, end):
        # Setting equal values sends nothing but still costs Bokeh's checks and change
        # bookkeeping; most ranges of a release (time axes, a fixed map) stay as they are.
        rng.update(start=start, end=end, reset_start=start, reset_end=end)


_EMPTY: Mapping[str, Mapping[str, list]] = {
    "traj": {k: [] for k in ("t", "x", "v", "mode")},
    **{f"path_{name}": {"x": [], "v": []} for name in MODE_NAMES.values()},
    "repeat": {"x": [], "v": [], "text": []},
    "stop_pt": {"x": [], "v": []},
    "trans": {k: [] for k in ("x", "v", "t", "kind", "marker", "color")},
    "bands": {"left": [], "right": [], "color": []},
    "gamma0": {"x": [], "v": []},
    "removed": {"x": [], "v": []},
    "cycle": {"x": [], "v": []},
    "points": {"x": [], "v": [], "name": [], "paper": [], "align": [], "baseline": [],
               "dx": [], "dy": [], "side": []},
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
}
