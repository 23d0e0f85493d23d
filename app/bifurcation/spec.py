"""A sweep as a value: what a bifurcation diagram asks for, checked, and the points it finds.

Pure of the page: the swept parameters and quantities with their labels in either unit
system, a scene's default range, :class:`SweepSpec` (checked by :func:`check_spec`), what a
point costs, and :func:`sweep_points`, which runs :mod:`core.sweep` on some of a spec's
values (in a child process where it integrates) and returns :class:`Points`.

Examples
--------
>>> from app.state import scene_values
>>> data = sweep_points(scene_values("5a"), "belt_speed", [0.1, 0.2], "impact_speed")
>>> data.x.tolist()  # one impact per period at each speed
[0.1, 0.2]
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from app import sweep_budget as budget
from app.solve import process as solve_process
from app.solve.presets import choose_method
from app.solve.regime_map import map_ranges
from app.state import DIMENSIONLESS, Scales, core_inputs
from core import HystereticStop
from core import sweep as sweeps

PARAMETER_LABELS: Mapping[str, str] = {
    "belt_speed": "belt speed v",
    "clearance": "clearance x̄",
    "restitution": "restitution r",
    "mu_s": "static friction μₛ",
    "mu_k": "kinetic friction μₖ",
    "u_s": "static deflection uₛ",
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
    "clearance": ("clearance x̄", "length", "mm"),
    "restitution": ("restitution r", None, ""),
    "mu_s": ("static friction μₛ", None, ""),
    "mu_k": ("kinetic friction μₖ", None, ""),
    "u_s": ("normal force N", "force", "N"),
}
#: The same for the quantity on the y axis.
QUANTITY_SI: Mapping[str, tuple[str, str | None, str]] = {
    "impact_speed": ("impact speed before (at each impact)", "velocity", "m/s"),
    "rebound_speed": ("rebound speed after (at each impact)", "velocity", "m/s"),
    "stick_x": ("x at each slip→stick", "length", "mm"),
    "transition_x": ("x at every transition", "length", "mm"),
    "force_peak": ("contact force peak (each contact)", "force", "N"),
    "x_max": ("steady x_max", "length", "mm"),
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
    >>> si = ExplorerState(units="SI", mass=1.0, stiffness=100.0, length_unit=0.5).scales()
    >>> units = axis_units("belt_speed", "period", si)
    >>> units.parameter, units.quantity, units.parameter_label  # omega L = 5 m/s
    (5.0, 0.1, 'belt speed v_dr (m/s)')
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


def sweep_inputs(values: Mapping[str, Any]):
    """``(osc, stop, x0, v0, t_end, method)`` of a sweep of the scene ``values``."""
    osc, stop, x0, v0, t_end = core_inputs({**values, "program": False})
    method = choose_method(values["method"], values["stop_type"])
    closed = method == "exact" and not isinstance(stop, HystereticStop)
    return osc, stop, x0, v0, (CLOSED_FORM_T_END if closed else t_end), method


def sweep_cost(values: Mapping[str, Any]) -> dict[str, Any]:
    """What a point of a sweep of ``values`` costs (:func:`app.sweep_budget.point_cost_s`'s
    arguments): closed form or integrated, and its horizon."""
    return {"closed": closed_form(values), "t_end": sweep_inputs(values)[4]}


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
    osc, stop, x0, v0, t_end, method = sweep_inputs(values)
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
