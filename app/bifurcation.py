"""Bifurcation diagrams and the regime map from simulation: :mod:`core.sweep` in the page.

The view is built when the user first opens it (a new page holds none of its models). A
sweep runs in the solver's worker pool (:func:`app.solve.pool.executor_for`), one chunk of
parameter values at a time: each chunk's answer is drawn on the session's event loop, and
the next chunk is submitted only then, so a cancel (or a new sweep) stops the work after the
chunk that is running. A sweep of more than :data:`DENSITY_SAMPLES` samples is drawn as a
2-D histogram (one image) instead of one marker per sample. A sweep has a budget
(:mod:`app.sweep_budget`): its card says it before the sweep starts, and a sweep stopped at
it keeps what it has and says so.

The theory is drawn on the diagram (docs/physics.md): the critical speed ``v*`` (Eq. 25),
the slip centre ``a``, the stick limit ``b``, the critical clearance ``x*`` (Eq. 35), the
largest impactless excursion, and a line wherever the closed-form regime
(:func:`core.theory.classify`) changes along the swept range.

Examples
--------
>>> from app.state import scene_values
>>> data = sweep_points(scene_values("5a"), "belt_speed", [0.1, 0.2], "impact_speed")
>>> data.x.tolist()  # one impact per period at each speed
[0.1, 0.2]
"""

from __future__ import annotations

import html
import math
import threading
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any

import numpy as np
import panel as pn
from bokeh.events import Tap
from bokeh.models import (
    ColumnDataSource,
    LabelSet,
    LinearColorMapper,
    Range1d,
    Span,
)
from bokeh.plotting import figure
from panel.io.state import set_curdoc

from app import sweep_budget as budget
from app.session_loop import from_any_thread
from app.solve import process as solve_process
from app.solve.pool import executor_for
from app.solve.presets import choose_method
from app.solve.regime_map import map_ranges
from app.state import DIMENSIONLESS, Scales, core_inputs
from core import HystereticStop, RigidStop, equivalent_rigid, theory
from core import sweep as sweeps

#: Swept parameters the page offers (:data:`core.sweep.PARAMETERS`), with their labels.
PARAMETER_LABELS: Mapping[str, str] = {
    "belt_speed": "belt speed v",
    "clearance": "clearance x_bar",
    "restitution": "restitution r",
    "mu_s": "static friction mu_s",
    "mu_k": "kinetic friction mu_k",
    "u_s": "static deflection u_s",
}
#: Quantities on the diagram's y axis: the Poincaré samples of :mod:`core.sweep` (one
#: steady period's transitions, Eq. 20) and two per-point values.
QUANTITY_LABELS: Mapping[str, str] = {
    "impact_speed": "impact speed before (at each impact)",
    "rebound_speed": "rebound speed after (at each impact)",
    "stick_x": "x at each slip→stick",
    "transition_x": "x at every transition",
    "force_peak": "contact force peak / k (each contact)",
    "x_max": "steady x_max",
    "period": "period",
}
#: What the card's numbers are in, when the page shows the core's dimensionless units.
UNITS_NOTE = "dimensionless units"
#: In SI units (app.state.Scales): a swept parameter's label, the factor of
#: :class:`app.state.Scales` that turns the core's number into it, and its unit. Lengths
#: are metres in both systems (the dimensionless form scales time only: docs/physics.md,
#: "Dimensionless form"), friction and restitution have no unit; the static deflection is
#: shown as the normal force ``N = k u_s``, as in the sidebar.
PARAMETER_SI: Mapping[str, tuple[str, str | None, str]] = {
    "belt_speed": ("belt speed v_dr", "velocity", "m/s"),
    "clearance": ("clearance x_bar", None, "m"),
    "restitution": ("restitution r", None, ""),
    "mu_s": ("static friction mu_s", None, ""),
    "mu_k": ("kinetic friction mu_k", None, ""),
    "u_s": ("normal force N", "force", "N"),
}
#: The same for the quantity on the y axis.
QUANTITY_SI: Mapping[str, tuple[str, str | None, str]] = {
    "impact_speed": ("impact speed before (at each impact)", "velocity", "m/s"),
    "rebound_speed": ("rebound speed after (at each impact)", "velocity", "m/s"),
    "stick_x": ("x at each slip→stick", None, "m"),
    "transition_x": ("x at every transition", None, "m"),
    "force_peak": ("contact force peak (each contact)", "force", "N"),
    "x_max": ("steady x_max", None, "m"),
    "period": ("period", "time", "s"),
}
#: Quantities read per point rather than per transition.
PER_POINT = ("x_max", "period")
#: Points of a new diagram.
DEFAULT_POINTS = 1000
#: Most points a diagram may ask for.
MAX_POINTS = 200_000
#: Samples above which the diagram is a density image (a marker each costs the browser).
DENSITY_SAMPLES = 20_000
#: Bins of the density image (parameter, quantity): about one per two screen pixels.
DENSITY_BINS = (450, 200)
#: Horizon of a closed-form sweep (no stop, rigid stop): past the transients of the
#: paper's scenes (the sweep's default, docs/sweeps.md).
CLOSED_FORM_T_END = 200.0
#: Wall time [s] a chunk aims at: short enough for a prompt cancel and a live progress
#: bar, long enough that a chunk's round trip costs little: through the event loop for the
#: closed form, plus a worker process where it integrates (measured ~1 s each
#: in the served page at load 8, so such chunks are longer).
CHUNK_SECONDS = {"closed": 0.25, "integrated": 2.0}
#: Points of a sweep's first chunk, closed form and integrated (a deformable stop or a
#: numerical method costs 10-1000 ms per point).
FIRST_CHUNK = {"closed": 1000, "integrated": 2}
#: Most points in one chunk.
MAX_CHUNK = 50_000
#: Values at which the closed-form regime is classified along the swept range.
THEORY_SAMPLES = 600
#: Cells per side of the simulated regime map: the theory map's grid for the closed form,
#: a coarse grid for a deformable stop (simulated point by point, tens of ms each).
SIM_MAP_CELLS = {"closed": 128, "integrated": 16}
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


def applicable_parameters(values: Mapping[str, Any]) -> list[str]:
    """The parameters a sweep of this scene can vary (a clearance needs a stop, a
    restitution a rigid one)."""
    stop = values["stop_type"]
    return [p for p in PARAMETER_LABELS
            if not (p == "clearance" and stop == "none")
            and not (p == "restitution" and stop != "rigid")]


def applicable_quantities(values: Mapping[str, Any]) -> list[str]:
    """The quantities this scene has: no impact without a stop, force peaks only with a
    deformable stop."""
    stop = values["stop_type"]
    out = []
    for q in QUANTITY_LABELS:
        if q in ("impact_speed", "rebound_speed") and stop == "none":
            continue
        if q == "force_peak" and stop != "hysteretic":
            continue
        out.append(q)
    return out


def default_quantity(values: Mapping[str, Any]) -> str:
    """Impact speed with a stop, the stick onset without (as :func:`core.sweep.sweep`)."""
    return "stick_x" if values["stop_type"] == "none" else "impact_speed"


@dataclass(frozen=True)
class AxisUnits:
    """How the card shows a sweep in the page's units: the factors from the core's
    dimensionless numbers to the parameter and the quantity shown, and their axis labels.

    >>> from app.state import ExplorerState
    >>> units = axis_units("belt_speed", "period", ExplorerState(units="SI").scales())
    >>> units.parameter, units.quantity, units.parameter_label  # omega = 10 rad/s
    (10.0, 0.1, 'belt speed v_dr (m/s)')
    """

    parameter: float
    quantity: float
    parameter_label: str
    quantity_label: str


def parameter_name(parameter: str, scales: Scales = DIMENSIONLESS) -> str:
    """What the card calls a swept parameter in the page's units."""
    return PARAMETER_SI[parameter][0] if scales.si else PARAMETER_LABELS[parameter]


def quantity_name(quantity: str, scales: Scales = DIMENSIONLESS) -> str:
    """What the card calls a quantity in the page's units."""
    return QUANTITY_SI[quantity][0] if scales.si else QUANTITY_LABELS[quantity]


def axis_units(parameter: str, quantity: str, scales: Scales = DIMENSIONLESS) -> AxisUnits:
    """The :class:`AxisUnits` of a sweep of ``parameter`` showing ``quantity``."""
    if not scales.si:
        return AxisUnits(1.0, 1.0, f"{PARAMETER_LABELS[parameter]} ({UNITS_NOTE})",
                         f"{QUANTITY_LABELS[quantity]} ({UNITS_NOTE})")

    def shown(name: str, table: Mapping[str, tuple[str, str | None, str]]):
        label, factor, unit = table[name]
        return (getattr(scales, factor) if factor else 1.0,
                f"{label} ({unit})" if unit else label)

    p_factor, p_label = shown(parameter, PARAMETER_SI)
    q_factor, q_label = shown(quantity, QUANTITY_SI)
    return AxisUnits(float(p_factor), float(q_factor), p_label, q_label)


def default_range(values: Mapping[str, Any], parameter: str) -> tuple[float, float]:
    """A range of ``parameter`` around its current value: the regime map's axes for the
    belt speed and the clearance (they reach past ``v*`` and the impactless excursion),
    the whole allowed range of ``r`` and ``mu_k``, and a band about the others."""
    v_hi, x_lo, x_hi = map_ranges(values)
    if parameter == "belt_speed":
        return v_hi / 100.0, v_hi
    if parameter == "clearance":
        return x_lo + (x_hi - x_lo) / 100.0, x_hi
    if parameter == "restitution":
        return 0.0, 1.0
    if parameter == "mu_k":
        return 0.0, values["mu_s"]
    if parameter == "mu_s":
        return values["mu_k"], max(2.0 * values["mu_s"], values["mu_k"] + 0.1)
    cur = values[parameter]
    return 0.25 * cur, 2.0 * cur


@dataclass(frozen=True)
class SweepSpec:
    """One bifurcation diagram asked for: the scene's values and what to sweep."""

    values: Mapping[str, Any]
    parameter: str
    lo: float
    hi: float
    n: int
    quantity: str

    def grid(self) -> np.ndarray:
        """The swept values, evenly spaced, both ends included."""
        return np.linspace(self.lo, self.hi, self.n)


def check_spec(values: Mapping[str, Any], parameter: str, lo: float, hi: float, n: int,
               quantity: str) -> SweepSpec:
    """A valid :class:`SweepSpec`, or a ``ValueError`` that names what is wrong."""
    if parameter not in applicable_parameters(values):
        raise ValueError(f"parameter must be one of {', '.join(applicable_parameters(values))}"
                         f" for this stop; got {parameter!r}")
    if quantity not in applicable_quantities(values):
        raise ValueError(f"quantity must be one of {', '.join(applicable_quantities(values))}"
                         f" for this stop; got {quantity!r}")
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"the range of {parameter} must have from < to; got {lo:g} to {hi:g}")
    if not 2 <= n <= MAX_POINTS:
        raise ValueError(f"points must be in [2, {MAX_POINTS}]; got {n}")
    budget.check_cost(int(n), **sweep_cost(values))
    spec = SweepSpec(dict(values), parameter, float(lo), float(hi), int(n), quantity)
    # The core checks each value against its range (its message names both).
    sweep_points(spec.values, parameter, [spec.lo, spec.hi], quantity)
    return spec


def _inputs(values: Mapping[str, Any]):
    """``(osc, stop, x0, v0, t_end, method)`` of a sweep of the scene ``values``."""
    osc, stop, x0, v0, t_end = core_inputs({**values, "program": False})
    method = choose_method(values["method"], values["stop_type"])
    closed = method == "exact" and not isinstance(stop, HystereticStop)
    return osc, stop, x0, v0, (CLOSED_FORM_T_END if closed else t_end), method


def sweep_cost(values: Mapping[str, Any]) -> dict[str, Any]:
    """What a point of a sweep of ``values`` costs (:func:`app.sweep_budget.point_cost_s`'s
    arguments): closed form or integrated, and its horizon."""
    return {"closed": closed_form(values), "t_end": _inputs(values)[4]}


def closed_form(values: Mapping[str, Any]) -> bool:
    """True when the sweep of ``values`` is the vectorised closed form (fast)."""
    return (choose_method(values["method"], values["stop_type"]) == "exact"
            and values["stop_type"] != "hysteretic")


@dataclass(frozen=True)
class Points:
    """Diagram points of some parameter values: one per sample (``x``, ``y``, the steady
    label of its point), and the swept values with their labels."""

    x: np.ndarray
    y: np.ndarray
    label: np.ndarray
    swept: np.ndarray
    swept_label: np.ndarray

    @staticmethod
    def join(parts: list[Points]) -> Points:
        if not parts:
            return Points(*(np.zeros(0) for _ in range(2)), np.zeros(0, object),
                          np.zeros(0), np.zeros(0, object))
        return Points(*(np.concatenate([getattr(p, f) for p in parts])
                        for f in ("x", "y", "label", "swept", "swept_label")))


def sweep_points(values: Mapping[str, Any], parameter: str, swept, quantity: str,
                 cancelled: threading.Event | None = None) -> Points:
    """The diagram's points at the values ``swept`` of ``parameter`` (:func:`core.sweep`;
    with ``cancelled``, an integrating sweep runs in a child process, :func:`run_core`)."""
    osc, stop, x0, v0, t_end, method = _inputs(values)
    swept = np.asarray(swept, dtype=float)
    poincare = quantity not in PER_POINT
    res = run_core(values, cancelled, sweeps.sweep, osc, stop, parameter, swept,
                   quantity=quantity if poincare else None, t_end=t_end, method=method,
                   x0=x0, v0=v0)
    labels = res.labels
    if poincare:
        x, y = res.points(quantity)
        _, offsets = res.samples(quantity)
        label = np.repeat(labels, np.diff(offsets))
    else:
        y = np.asarray(getattr(res, quantity), dtype=float)
        keep = np.isfinite(y)
        x, y, label = swept[keep], y[keep], labels[keep]
    return Points(np.asarray(x, float), np.asarray(y, float), np.asarray(label, object),
                  swept, labels)


def run_core(values: Mapping[str, Any], cancelled: threading.Event | None, fn: Callable,
             *args: Any, **kwargs: Any) -> Any:
    """``fn(*args, **kwargs)``, a :mod:`core.sweep` function: here for the closed form
    (milliseconds) or without ``cancelled``; else in a child process
    (:mod:`app.solve.process`), as the page's own integrating solves are, so that it holds
    neither the server's interpreter lock nor outlives a cancel. Only core objects cross
    to the child (it has :mod:`core` loaded; the page's modules would cost it a second)."""
    if cancelled is None or closed_form(values):
        return fn(*args, **kwargs)
    return solve_process.call(fn, *args, cancelled=cancelled, **kwargs)


def density(points: Points, x_range: tuple[float, float]) -> dict[str, Any]:
    """The diagram as an image: log counts of a 2-D histogram of the samples."""
    y = points.y[np.isfinite(points.y)]
    x = points.x[np.isfinite(points.y)]
    lo, hi = (float(y.min()), float(y.max())) if len(y) else (0.0, 1.0)
    if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1.0):
        lo, hi = lo - 0.5, hi + 0.5
    counts, _, _ = np.histogram2d(x, y, bins=DENSITY_BINS, range=(x_range, (lo, hi)))
    image = np.log1p(counts.T).astype(np.float32)
    image[counts.T == 0] = np.nan  # empty bins stay white
    return {"image": [image], "x": [x_range[0]], "y": [lo], "dw": [x_range[1] - x_range[0]],
            "dh": [hi - lo]}


# --- theory ------------------------------------------------------------------------------

def theory_lines(values: Mapping[str, Any], parameter: str, lo: float, hi: float,
                 quantity: str) -> tuple[list[tuple[float, str]], list[tuple[float, str]]]:
    """Vertical lines (at parameter values) and horizontal ones (at quantity values) of
    the closed-form theory, each with its label (docs/physics.md).

    Named values: ``v*`` (Eq. 25) on a belt-speed axis; ``a``, ``b``, ``x*`` (Eq. 35) and
    the impactless ``x_max`` on a clearance axis; and a line where the regime that
    :func:`core.theory.classify` gives changes along the range, labelled with the new one.
    """
    osc, stop, x0, v0, _, _ = _inputs(values)
    rigid = equivalent_rigid(stop)
    r = rigid.restitution if rigid is not None else 1.0
    vertical: list[tuple[float, str]] = []
    try:
        if parameter == "belt_speed":
            vertical.append((theory.critical_speed(osc, x0, v0), "v*"))
        elif parameter == "clearance":
            vertical += [(osc.a, "a"), (osc.b, "b"), (theory.x_star(osc, r), "x*"),
                         (theory.x_max_impactless(osc, x0, v0), "x_max without stop")]
    except (ValueError, ZeroDivisionError, OverflowError):
        pass
    # A regime change at a named value (the belt turns fast at v*) joins its label.
    near = 1.5 * (hi - lo) / THEORY_SAMPLES
    for x, text in regime_changes(values, parameter, lo, hi):
        named = [i for i, (y, _) in enumerate(vertical) if abs(y - x) <= near]
        if named:
            y, name = vertical[named[0]]
            vertical[named[0]] = (y, f"{name}: {text}")
        else:
            vertical.append((x, text))
    vertical = [(float(x), text) for x, text in vertical if lo <= x <= hi and math.isfinite(x)]
    horizontal: list[tuple[float, str]] = []
    if quantity in ("stick_x", "transition_x", "x_max"):
        if parameter not in ("mu_k", "u_s"):
            horizontal.append((osc.a, "a"))
        if parameter not in ("mu_s", "u_s"):
            horizontal.append((osc.b, "b"))
        if stop is not None and parameter != "clearance":
            horizontal.append((stop.clearance, "x_bar (stop)"))
    elif quantity in ("impact_speed", "rebound_speed") and parameter != "belt_speed":
        horizontal.append((osc.v, "v (belt)"))
    return vertical, horizontal


def regime_changes(values: Mapping[str, Any], parameter: str, lo: float, hi: float
                   ) -> list[tuple[float, str]]:
    """Where the closed-form regime changes along ``[lo, hi]`` (sampled at
    :data:`THEORY_SAMPLES` values), labelled with the regime that follows."""
    from app.solve.regime_map import regime_labels

    grid = np.linspace(lo, hi, THEORY_SAMPLES)
    v, x = values["belt_speed"], values["clearance"]
    if parameter == "belt_speed":
        words = regime_labels(values, grid, [x])[0]
    elif parameter == "clearance":
        words = regime_labels(values, [v], grid)[:, 0]
    else:
        words = np.array([regime_labels({**values, parameter: float(p)}, [v], [x])[0, 0]
                          for p in grid])
    change = np.flatnonzero(words[1:] != words[:-1])
    return [(0.5 * (grid[i] + grid[i + 1]), str(words[i + 1])) for i in change]


# --- the simulated regime map ------------------------------------------------------------

@dataclass(frozen=True)
class SimMap:
    """The regime map from simulation over the regime map's frame: the steady label per
    cell (rows: clearance, columns: belt speed), the theory's expected steady state, and
    where they disagree."""

    labels: np.ndarray
    expected: np.ndarray
    disagree: np.ndarray
    frame: tuple[float, float, float]
    deformable: bool
    t_end: float


def map_cells(frame: tuple[float, float, float], cells: int) -> tuple[np.ndarray, np.ndarray]:
    """Cell centres ``(speeds, clearances)`` of a ``cells`` x ``cells`` map on ``frame``
    (as :func:`app.solve.regime_map.regime_map`)."""
    v_hi, x_lo, x_hi = frame
    speeds = (np.arange(cells) + 0.5) * v_hi / cells
    clearances = x_lo + (np.arange(cells) + 0.5) * (x_hi - x_lo) / cells
    return speeds, clearances


def simulate_map_rows(values: Mapping[str, Any], speeds, clearances,
                      cancelled: threading.Event | None = None) -> np.ndarray:
    """Steady labels of the simulation at ``speeds`` x ``clearances`` (rows: speeds), by
    :func:`core.sweep.sweep_grid` (or :func:`core.sweep.sweep` without a stop, where the
    clearance plays no part); ``cancelled`` as :func:`sweep_points`."""
    osc, stop, x0, v0, t_end, method = _inputs(values)
    options = {"t_end": t_end, "method": method, "x0": x0, "v0": v0}
    speeds = np.asarray(speeds, float)
    if stop is None:
        res = run_core(values, cancelled, sweeps.sweep, osc, None, "belt_speed", speeds, **options)
        return np.repeat(res.labels[:, None], len(clearances), axis=1)
    res = run_core(values, cancelled, sweeps.sweep_grid, osc, stop,
                   {"belt_speed": speeds, "clearance": np.asarray(clearances, float)},
                   **options)
    return res.labels


def compare_map(values: Mapping[str, Any], frame, labels_rows: np.ndarray) -> SimMap:
    """Simulated labels (rows: speeds) against :func:`core.theory.classify_grid`.

    A plastic stop's slip circle touching the stop (``r = 0``, ``a < x_bar``) is labelled
    ``pure_slip`` by the simulation and ``grazing`` by the theory: the same motion, so it
    counts as agreement (docs/sweeps.md); so does an oscillation on a deformable stop where
    the theory expects rest (not settled by the horizon).
    """
    cells = labels_rows.shape[0]
    speeds, clearances = map_cells(frame, cells)
    labels = labels_rows.T
    osc, stop, x0, v0, t_end, _ = _inputs(values)
    rigid = equivalent_rigid(stop)
    grid = theory.classify_grid(osc, rigid, speeds, clearances if stop is not None
                                else clearances[:1], x0, v0)
    expected = np.asarray(grid.expected_steady, dtype=object)
    valid = np.asarray(grid.valid)
    if stop is None:
        expected = np.repeat(expected, len(clearances), axis=0)
        valid = np.repeat(valid, len(clearances), axis=0)
    # A cell whose motion has not settled by the horizon has no label to compare: nothing
    # found, or loops on a deformable stop still swinging beyond the rule for rest on their
    # way to the rest the theory expects.
    same = ((labels == expected) | (labels == "none")
            | ((labels == "oscillation") & (expected == "rest")))
    if isinstance(rigid, RigidStop) and rigid.restitution == 0.0:
        same |= (labels == "pure_slip") & (expected == "grazing")
    return SimMap(labels=labels, expected=expected, disagree=valid & ~same, frame=frame,
                  deformable=isinstance(stop, HystereticStop), t_end=t_end)


def rgba(sim: SimMap) -> tuple[np.ndarray, np.ndarray]:
    """The two layers as RGBA images (uint32, rows from the lowest clearance up): the
    simulated labels, and the disagreement (transparent where they agree)."""
    table = np.zeros((len(sweeps.LABELS), 4), np.uint8)
    for i, name in enumerate(sweeps.LABELS):
        c = LABEL_COLORS.get(name, "#000000")
        table[i] = (int(c[1:3], 16), int(c[3:5], 16), int(c[5:7], 16), SIM_ALPHA)
    code = np.searchsorted(np.asarray(sweeps.LABELS, dtype=object), sim.labels,
                           sorter=np.argsort(sweeps.LABELS))
    code = np.argsort(sweeps.LABELS)[np.clip(code, 0, len(sweeps.LABELS) - 1)]
    sim_img = table[code]
    dis_img = np.zeros((*sim.disagree.shape, 4), np.uint8)
    dis_img[sim.disagree] = DISAGREE_RGBA
    return (np.ascontiguousarray(sim_img).view(np.uint32)[..., 0],
            np.ascontiguousarray(dis_img).view(np.uint32)[..., 0])


# --- the worker: chunks of a sweep ---------------------------------------------------------

class ChunkedSweep:
    """One session's sweep, computed chunk by chunk in the worker pool.

    :meth:`start` cancels the running sweep and submits the first chunk; each chunk's
    answer comes back on the session's event loop (:func:`app.session_loop.from_any_thread`)
    and goes to ``on_chunk(done, total, part)``; the next chunk is submitted then, sized to
    take about ``target_s`` (:data:`CHUNK_SECONDS`). :meth:`cancel` (or a new
    :meth:`start`) drops the answer of the chunk that runs and submits no other. Without a
    server session (scripts, tests) the chunks run one after the other before
    :meth:`start` returns. A sweep with a budget stops at it with the values it has: no
    chunk is submitted past it, each is sized to end before it, and one in a solver process
    still running a chunk's aim past it is stopped; ``on_cut(done, total)`` says so.

    Parameters
    ----------
    work : callable(task, items, cancelled) -> part
        Computes one chunk (in a worker thread); ``cancelled`` is a
        :class:`threading.Event` set when the sweep is cancelled (a chunk run in a child
        process, :func:`run_core`, is stopped by it).
    on_chunk : callable(done, total, part)
    on_failed : callable(Exception)
    on_cut : callable(done, total), optional
    """

    def __init__(self, work: Callable[[Any, np.ndarray, threading.Event], Any],
                 on_chunk: Callable[[int, int, Any], None],
                 on_failed: Callable[[Exception], None],
                 on_cut: Callable[[int, int], None] | None = None) -> None:
        self.work, self.on_chunk, self.on_failed = work, on_chunk, on_failed
        self.on_cut = on_cut
        self._token = 0
        self._lock = threading.Lock()
        #: Chunks submitted since this object was made (tests count them).
        self.submitted = 0
        self.running = False
        self._cancelled = threading.Event()
        self._deadline: solve_process.Deadline | None = None

    def cancel(self) -> None:
        """Stop: the running chunk's answer is dropped (a chunk in a child process is
        stopped), no further chunk is submitted."""
        with self._lock:
            self._token += 1
            self._cancelled.set()
        self.running = False

    def start(self, task: Any, items: np.ndarray, first: int, pool_values: Mapping[str, Any],
              target_s: float = CHUNK_SECONDS["closed"], budget_s: float | None = None
              ) -> None:
        """Compute ``work(task, chunk)`` over ``items`` (along the first axis), in the pool
        that solves ``pool_values`` (:func:`app.solve.pool.executor_for`), within ``budget_s``
        seconds (``None``: no budget)."""
        self.cancel()
        with self._lock:
            token = self._token
            self._cancelled = threading.Event()
        self.running = True
        self._target_s = target_s
        self._deadline = None if budget_s is None else solve_process.Deadline(budget_s)
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is None:
            doc = None
        self._next(token, doc, executor_for(pool_values), task, items, 0, first)

    def _next(self, token: int, doc, pool, task, items, done: int, size: int) -> None:
        total = len(items)
        chunk = items[done:done + size]
        self.submitted += 1
        started = time.perf_counter()
        stop: Any = self._cancelled
        if self._deadline is not None:  # a chunk in a solver process ends by the deadline
            stop = solve_process.Deadline(self._deadline.left() + self._target_s, stop)
        future: Future = pool.submit(self.work, task, chunk, stop)

        def answered() -> None:
            if token != self._token:
                return
            try:
                part = future.result()
            except solve_process.Abandoned as exc:
                if self._over():
                    self._cut(token, done, total)
                else:
                    self._fail(token, exc)
                return
            except Exception as exc:  # noqa: BLE001 - any failure is shown, the page lives
                self._fail(token, exc)
                return
            elapsed = max(time.perf_counter() - started, 1e-4)
            now = done + len(chunk)
            if now >= total:
                self.running = False
            self.on_chunk(now, total, part)
            if now < total and token == self._token:
                if self._over():
                    self._cut(token, now, total)
                    return
                aim = self._target_s if self._deadline is None else min(
                    self._target_s, self._deadline.left())
                nxt = int(min(max(len(chunk) / elapsed * aim, 1), MAX_CHUNK))
                self._next(token, doc, pool, task, items, now, nxt)

        if doc is None:
            future.exception()  # waits for the chunk
            answered()
            return

        def on_loop() -> None:
            with set_curdoc(doc):
                answered()

        answer = from_any_thread(doc, on_loop)
        future.add_done_callback(lambda _: answer())

    def _fail(self, token: int, exc: Exception) -> None:
        if token == self._token:
            self.running = False
            self.on_failed(exc)

    def _over(self) -> bool:
        """The budget has run out."""
        return self._deadline is not None and self._deadline.left() <= 0.0

    def _cut(self, token: int, done: int, total: int) -> None:
        if token == self._token:
            self.running = False
            if self.on_cut is not None:
                self.on_cut(done, total)


# --- the view --------------------------------------------------------------------------

class BifurcationView:
    """The sweep card of one session: the bifurcation diagram and its controls, and the
    regime map's simulated layers (drawn on the explorer's map figure).

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
        self._on_layers = on_layers
        self._map_figure, self._map_frame = map_figure, map_frame
        self.scales = scales
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
        self.sim_layer = pn.widgets.Checkbox(
            label="regime map: from simulation", value=False, css_classes=["fie-bif-sim"])
        self.disagree_layer = pn.widgets.Checkbox(
            label="regime map: where simulation and theory disagree", value=False,
            css_classes=["fie-bif-disagree"])
        self.map_status = pn.pane.HTML("", sizing_mode="stretch_width",
                                       css_classes=["fie-bif-map-status"])
        self.parameter.param.watch(self._on_parameter, "value")
        self.run.on_click(lambda e: self.start())
        self.stop.on_click(lambda e: self.cancel())
        self.sim_layer.param.watch(lambda e: self._layers_changed(), "value")
        self.disagree_layer.param.watch(lambda e: self._layers_changed(), "value")
        self._build_figure()
        self.job = ChunkedSweep(self._work, self._on_chunk, self._failed, self._cut)
        self.map_job = ChunkedSweep(self._map_work, self._on_map_chunk, self._map_failed,
                                    self._map_cut)
        self.spec: SweepSpec | None = None
        self.parts: list[Points] = []
        self.data = Points.join([])
        self._map_rows: list[np.ndarray] = []
        self._map_key: tuple | None = None
        self.sim_map: SimMap | None = None
        self._map_renderers: tuple[Any, Any] | None = None
        self._map_fig: Any = None
        self._map_title_text: str | None = None
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
            if self.sim_map is not None and self._map_renderers is not None:
                self._show_layers()

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
        self.map_job.cancel()

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
                f"steady states: {found}.{_no_samples(data, spec)} {_legend()}")

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

    def _on_tap(self, event: Tap) -> None:
        value = self.pick(event.x)
        if value is None or self.spec is None:
            return
        self.current.location = value * self._units(self.spec).parameter
        self.on_pick(self.spec.parameter, value)

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
        if self.sim_layer.value or self.disagree_layer.value:
            self._layers_changed()

    def _refresh_options(self, values: Mapping[str, Any]) -> None:
        params = applicable_parameters(values)
        self.parameter.options = self._parameter_options(params)
        if self.parameter.value not in params:
            self.parameter.value = params[0]
        quantities = applicable_quantities(values)
        self.quantity.options = self._quantity_options(quantities)
        if self.quantity.value not in quantities:
            self.quantity.value = default_quantity(values)

    # --- the map's layers --------------------------------------------------------------

    def _layers_changed(self) -> None:
        """Draw (computing if need be) or hide the simulated layers of the regime map."""
        want = self.sim_layer.value or self.disagree_layer.value
        if not want:
            self.map_job.cancel()
            if self._map_renderers is not None:
                for r in self._map_renderers:
                    r.visible = False
                self._map_title(None)
            self.map_status.object = ""
            return
        values = self._values()
        frame = tuple(self._map_frame())
        # The point's own belt speed and clearance are the map's axes: moving it changes
        # nothing of the map.
        key = (tuple(sorted((k, v) for k, v in values.items()
                            if k not in ("belt_speed", "clearance"))), frame)
        if key == self._map_key and self.sim_map is not None:
            self._show_layers()
            return
        if key == self._map_key and self.map_job.running:
            return
        self._map_key, self.sim_map, self._map_rows = key, None, []
        kind = "closed" if closed_form(values) else "integrated"
        cells = SIM_MAP_CELLS[kind]
        try:
            budget.check_cost(cells * cells, **sweep_cost(values))
        except ValueError as exc:
            self.map_job.cancel()
            self.map_status.object = (
                "<div class='fie-bif-error'>The regime map is not simulated: its "
                f"{cells} x {cells} cells exceed the sweep's budget ({html.escape(str(exc))})"
                "</div>")
            return
        speeds, clearances = map_cells(frame, cells)
        self._map_spec = (values, frame, clearances)
        self.map_status.object = self._map_note(values, cells, 0)
        self.map_job.start(self._map_spec, speeds, cells if kind == "closed" else 1, values,
                           CHUNK_SECONDS[kind], budget.SWEEP_BUDGET_S)

    @staticmethod
    def _map_work(spec, speeds: np.ndarray, cancelled: threading.Event) -> np.ndarray:
        values, _, clearances = spec
        return simulate_map_rows(values, speeds, clearances, cancelled)

    def _on_map_chunk(self, done: int, total: int, rows: np.ndarray) -> None:
        self._map_rows.append(rows)
        values, frame, _ = self._map_spec
        self.map_status.object = self._map_note(values, total, done)
        if done < total:
            return
        self.sim_map = compare_map(values, frame, np.concatenate(self._map_rows, axis=0))
        self._show_layers()

    def _map_cut(self, done: int, total: int) -> None:
        self.map_status.object = (
            f"<div class='fie-bif-error'>The simulated map stopped at the sweep's budget of "
            f"{budget.SWEEP_BUDGET_S:g} s after {done} of {total} belt speeds: not drawn. A "
            "shorter horizon t_end finishes within it.</div>")

    def _map_failed(self, exc: Exception) -> None:
        self.map_status.object = (f"<div class='fie-bif-error'>The simulated map failed: "
                                  f"{html.escape(type(exc).__name__)}: "
                                  f"{html.escape(str(exc))}</div>")

    def _map_note(self, values, cells: int, done: int) -> str:
        deformable = values["stop_type"] == "hysteretic"
        note = (" A deformable stop has no closed form: core.sweep simulates it point by "
                f"point, so this map is a coarse {cells} x {cells} grid, compared with the "
                "theory of its equivalent rigid stop (r_eq = sqrt(k_e0/k_c0), Eq. 16)."
                if deformable else "")
        cost = budget.budget_note(budget.estimate_s(cells * cells, **sweep_cost(values)),
                                  partial=False)
        return (f"<div class='fie-bif-running'>Simulating the regime map: {done} of {cells} "
                f"belt speeds ({cost}).{html.escape(note)}</div>")

    def _show_layers(self) -> None:
        sim = self.sim_map
        fig = self._map_figure()
        if fig is None or sim is None:
            return
        v_hi, x_lo, x_hi = sim.frame
        sim_img, dis_img = rgba(sim)
        # On the map's axes: its belt speeds in the page's units (app.plots).
        geometry = {"x": [0.0], "y": [x_lo], "dw": [v_hi * self.scales.velocity],
                    "dh": [x_hi - x_lo]}
        with pn.io.hold():
            if self._map_renderers is None:
                self._sim_source = ColumnDataSource({"image": [sim_img], **geometry})
                self._dis_source = ColumnDataSource({"image": [dis_img], **geometry})
                sim_r = fig.image_rgba(image="image", x="x", y="y", dw="dw", dh="dh",
                                       source=self._sim_source)
                dis_r = fig.image_rgba(image="image", x="x", y="y", dw="dw", dh="dh",
                                       source=self._dis_source)
                # Over the theory's image, under the current point's marker.
                base = [r for r in fig.renderers if r is not sim_r and r is not dis_r]
                fig.renderers = [base[0], sim_r, dis_r, *base[1:]]
                self._map_renderers, self._map_fig = (sim_r, dis_r), fig
                if self._shared is not None:
                    self._shared.lighten(fig)
                    for src in (self._sim_source, self._dis_source):
                        src.selection_policy = self._shared.policy
            else:
                self._sim_source.data = {"image": [sim_img], **geometry}
                self._dis_source.data = {"image": [dis_img], **geometry}
            self._map_renderers[0].visible = self.sim_layer.value
            self._map_renderers[1].visible = self.disagree_layer.value
            self._map_title(fig)
            self.map_status.object = self._map_summary(sim)

    def _map_title(self, fig: Any) -> None:
        """Say on the map which layers it shows (its legend below names the theory's)."""
        fig = fig if fig is not None else self._map_fig
        if fig is None:
            return
        if self._map_title_text is None:
            self._map_title_text = fig.title.text
        shown = [name for name, on in (("steady states", self.sim_layer.value),
                                       ("disagreement in red", self.disagree_layer.value))
                 if on]
        fig.title.text = self._map_title_text + (
            f"; simulated: {', '.join(shown)}" if shown else "")
        if self._on_layers is not None:
            self._on_layers()

    @property
    def sim_layer_shown(self) -> bool:
        """Whether the simulated steady states cover the regime map now."""
        return bool(self._map_renderers is not None and self._map_renderers[0].visible)

    def _map_summary(self, sim: SimMap) -> str:
        n = sim.labels.size
        bad = int(sim.disagree.sum())
        found = sorted(set(sim.labels.ravel().tolist()))
        swatches = "".join(
            f"<span style='margin-right:10px;white-space:nowrap'><i style='display:inline-"
            f"block;width:11px;height:11px;background:{LABEL_COLORS.get(k, '#000')};"
            f"margin-right:3px'></i>{html.escape(k)}</span>" for k in found)
        unsettled = int(np.sum(sim.labels == "none"))
        where = (f"Simulation and theory disagree in {bad} of {n} cells (red)."
                 if bad else "Simulation and theory agree in every cell that settled.")
        if unsettled:
            unit = " s" if self.scales.si else ""
            where += (f" {unsettled} cells had not settled by t = "
                      f"{sim.t_end * self.scales.time:.4g}{unit} (grey, not compared).")
        lesson = ""
        if sim.deformable:
            lesson = " The theory is that of the equivalent rigid stop (Eq. 16)" + (
                ": where they differ, the stop's compliance and hysteresis change the "
                "motion." if bad else ".")
        return (f"<div class='fie-bif-done'>Simulated steady states: {swatches}<br>"
                f"{where}{html.escape(lesson)}</div>")


def _no_samples(data: Points, spec: SweepSpec) -> str:
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


def _legend() -> str:
    colours = ", ".join(f"<span style='color:{c}'>{k}</span>" for k, c in LABEL_COLORS.items())
    return (f"Colours: {colours}. <span style='color:{CURRENT_COLOR}'>Red line</span>: the "
            "explorer's value; dashed: the theory's boundaries (each labelled with the regime "
            "that follows it), dotted: a, b, the stop.")


def _round(x: float) -> float:
    """``x`` to 4 significant digits (a box the user reads)."""
    return float(f"{x:.4g}")
