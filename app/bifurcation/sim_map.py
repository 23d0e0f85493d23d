"""The regime map from simulation: its cells, their steady labels, where theory disagrees."""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from app.bifurcation.spec import run_core, sweep_inputs
from app.bifurcation.style import DISAGREE_RGBA, LABEL_COLORS, SIM_ALPHA
from core import HystereticStop, RigidStop, equivalent_rigid, theory
from core import sweep as sweeps

#: Cells per side of the simulated regime map: the theory map's grid for the closed form,
#: a coarse grid for a deformable stop (simulated point by point, tens of ms each).
SIM_MAP_CELLS = {"closed": 128, "integrated": 16}


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
    osc, stop, x0, v0, t_end, method = sweep_inputs(values)
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
    osc, stop, x0, v0, t_end, _ = sweep_inputs(values)
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
