"""The regime map: the paper's regime at every belt speed and clearance of a grid about the
state on screen (:func:`core.theory.classify_grid`), its axes, and the maps kept.

>>> from app.state import scene_values
>>> data = regime_map(scene_values("5b"))
>>> data["codes"].shape == (MAP_CELLS, MAP_CELLS), data["labels"][0]
(True, 'slow, elastic, case c')
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from app.solve.cache import Lru
from app.state import core_inputs
from core import equivalent_rigid, theory

#: Grid of the regime map: cells along belt speed and clearance.
MAP_CELLS = 128
#: Regime maps kept, least recently used first out (shared by the server's sessions).
MAP_CACHE_ITEMS = 32
#: The server's regime maps.
MAPS = Lru(MAP_CACHE_ITEMS)


def regime_map(values: Mapping[str, Any], *, compute: bool = True,
               frame: tuple[float, float, float] | None = None,
               cache: Lru | None = None) -> dict[str, Any] | None:
    """Regime codes over a (belt speed, clearance) grid for the current friction, stop and
    start (:func:`core.theory.classify`); cached on what the map depends on.

    A new map is :data:`MAP_CELLS` squared classifications at once (~4 ms at 128 x 128,
    :func:`core.theory.classify_grid`); with ``compute=False`` only a cached one is
    returned, else ``None`` (the page then draws the rest first). ``frame`` gives the axes
    ``(v_hi, x_lo, x_hi)`` (default :func:`map_ranges` of ``values``); ``cache`` the maps
    kept (default :data:`MAPS`, the server's).
    """
    key = tuple(
        (name, values[name])
        for name in ("mu_s", "mu_k", "u_s", "stop_type", "restitution", "k_c0", "k_e0",
                     "limit_overlap", "beta_c", "beta_e", "x0", "v0")
    )
    v_hi, x_lo, x_hi = frame if frame is not None else map_ranges(values)
    key += (("v_hi", v_hi), ("x_lo", x_lo), ("x_hi", x_hi))
    maps = MAPS if cache is None else cache
    data = maps.get(key)
    if data is not None or not compute:
        return data
    data = _compute_regime_map(key)
    maps.put(key, data)
    return data


def map_ranges(values: Mapping[str, Any]) -> tuple[float, float, float]:
    """Axes of the regime map: belt speed ``[0, v_hi]``, clearance ``[x_lo, x_hi]``.

    Twice the critical speed of the start, and clearances from the start to a fifth past
    the largest impactless excursion; widened to keep the current point inside.
    """
    a = values["mu_k"] * values["u_s"]
    b = values["mu_s"] * values["u_s"]
    v_crit = math.hypot(values["x0"] - a, values["v0"])
    v_hi = _nice(max(2.0 * v_crit, 1.25 * values["belt_speed"], 1e-3))
    x_hi = max(a + max(v_crit, math.hypot(b - a, v_hi)), 1.1 * values["clearance"])
    x_lo = values["x0"]
    return v_hi, x_lo, _nice(x_lo + 1.2 * (x_hi - x_lo)) if x_hi > x_lo else x_lo + 1.0


def _nice(x: float) -> float:
    """Round up to 1, 2, 2.5 or 5 times a power of ten (stable axes while dragging)."""
    if x <= 0:
        return 1.0
    exp = math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * 10**exp >= x * (1 - 1e-12):
            return m * 10**exp
    return 10.0 ** (exp + 1)


def _compute_regime_map(key: tuple) -> dict[str, Any]:
    values = dict(key)
    v_hi, x_lo, x_hi = values["v_hi"], values["x_lo"], values["x_hi"]
    speeds = (np.arange(MAP_CELLS) + 0.5) * v_hi / MAP_CELLS
    clearances = x_lo + (np.arange(MAP_CELLS) + 0.5) * (x_hi - x_lo) / MAP_CELLS
    cells, names = _regime_cells(values, speeds, clearances)
    # Regimes numbered in the order they first appear going up each speed's column.
    found, first, inverse = np.unique(cells.T.ravel(), return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    codes = rank[inverse].reshape(MAP_CELLS, MAP_CELLS).T.astype(np.int32)
    return {"codes": np.ascontiguousarray(codes), "labels": [names[c] for c in found[order]],
            "v_hi": v_hi, "x_lo": x_lo, "x_hi": x_hi}


def regime_labels(values: Mapping[str, Any], speeds, clearances) -> np.ndarray:
    """Short words for the regime (e.g. ``'slow, inelastic, case b'``) at every belt speed
    (columns) and clearance (rows), the rest of ``values`` fixed
    (:func:`core.theory.classify_grid`); ``'invalid'`` where the theory refuses the inputs."""
    cells, names = _regime_cells(values, speeds, clearances)
    found, inverse = np.unique(cells, return_inverse=True)
    return np.array([names[c] for c in found])[inverse].reshape(cells.shape)


#: Case letters and the steady states a map label names, by their code in _regime_cells.
_CASES, _SETTLES = ("", "a", "b", "c"), ("", "grazing", "rest")


def _regime_cells(values: Mapping[str, Any], speeds, clearances
                  ) -> tuple[np.ndarray, dict[int, str]]:
    """An integer per grid cell that names its regime, and the words of each integer.

    The parameters other than belt speed and clearance are checked once, with the grid's
    largest speed and clearance (a stop behind the start is refused cell by cell).
    """
    shape = (len(clearances), len(speeds))
    try:
        osc, stop, x0, v0, _ = core_inputs({
            **values, "belt_speed": float(np.max(speeds)),
            "clearance": float(np.max(clearances)), "t_end": 1.0, "program": False})
        grid = theory.classify_grid(osc, equivalent_rigid(stop), speeds, clearances, x0, v0)
    except ValueError:
        return np.zeros(shape, dtype=np.int64), {0: "invalid"}
    impacts = ("none", *sorted(set(np.unique(grid.impact).tolist()) - {"none"}))
    case = sum(k * (grid.case == c) for k, c in enumerate(_CASES) if c)
    settles = sum(k * (grid.expected_steady == e) for k, e in enumerate(_SETTLES) if e)
    impact = sum(k * (grid.impact == name) for k, name in enumerate(impacts) if k)
    fields = (grid.valid, grid.impactless, grid.belt == "fast", case, settles, impact)
    cells = np.zeros(shape, dtype=np.int64)
    for digit, radix in zip(fields, (2, 2, 2, 4, 3, len(impacts)), strict=True):
        cells = cells * radix + np.asarray(digit, dtype=np.int64)
    cells = np.where(grid.valid, cells, 0)  # one code for every refused cell
    names = {}
    for cell in np.unique(cells).tolist():
        rest, impact_k = divmod(cell, len(impacts))
        rest, settle_k = divmod(rest, 3)
        rest, case_k = divmod(rest, 4)
        rest, fast = divmod(rest, 2)
        valid, impactless = divmod(rest, 2)
        belt = "fast" if fast else "slow"
        if not valid:
            words = ["invalid"]
        elif impactless:
            words = [belt, "no impact"]
        else:
            words = [belt, impacts[impact_k]]
            words += [f"case {_CASES[case_k]}"] if case_k else []
            words += [_SETTLES[settle_k]] if settle_k else []
        names[cell] = ", ".join(words)
    return cells, names
