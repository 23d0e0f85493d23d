"""The regime map: every cell names the regime core.theory.classify gives at that cell."""

from __future__ import annotations

import numpy as np
import pytest

from app.solve.regime_map import MAP_CELLS, map_ranges, regime_labels, regime_map
from app.state import core_inputs, scene_values
from core import equivalent_rigid, theory


def _words(values: dict) -> str:
    """The map's words for one cell, from the scalar classification."""
    try:
        osc, stop, x0, v0, _ = core_inputs({**values, "t_end": 1.0, "program": False})
        reg = theory.classify(osc, equivalent_rigid(stop), x0, v0)
    except ValueError:
        return "invalid"
    if reg.impactless:
        return f"{reg.belt}, no impact"
    words = [reg.belt, reg.impact] + ([f"case {reg.case}"] if reg.case else [])
    if reg.expected_steady in ("grazing", "rest"):
        words.append(reg.expected_steady)
    return ", ".join(words)


@pytest.mark.parametrize("key", ["3a", "5b", "7c", "7d", "8a", "10"])
def test_every_cell_names_the_regime_of_its_belt_speed_and_clearance(key):
    values = scene_values(key)
    data = regime_map(values)
    v_hi, x_lo, x_hi = map_ranges(values)
    assert (data["v_hi"], data["x_lo"], data["x_hi"]) == (v_hi, x_lo, x_hi)
    codes = np.asarray(data["codes"])
    assert codes.shape == (MAP_CELLS, MAP_CELLS)
    assert sorted(set(codes.ravel().tolist())) == list(range(len(data["labels"])))
    rng = np.random.default_rng(3)
    cells = [(i, j) for i in range(MAP_CELLS) for j in (0, MAP_CELLS - 1)]
    cells += [tuple(c) for c in rng.integers(0, MAP_CELLS, size=(400, 2))]
    for i, j in cells:
        speed = (j + 0.5) * v_hi / MAP_CELLS
        clearance = x_lo + (i + 0.5) * (x_hi - x_lo) / MAP_CELLS
        expected = _words({**values, "belt_speed": speed, "clearance": clearance})
        assert data["labels"][codes[i, j]] == expected, (i, j, speed, clearance)


def test_the_scene_itself_lies_in_a_cell_of_its_own_regime():
    """The marker of the current point sits on the colour of the readout's regime."""
    for key in ("5b", "7c", "10"):
        values = scene_values(key)
        data = regime_map(values)
        j = int(values["belt_speed"] / data["v_hi"] * MAP_CELLS)
        i = int((values["clearance"] - data["x_lo"]) / (data["x_hi"] - data["x_lo"])
                * MAP_CELLS)
        cell = data["labels"][data["codes"][i, j]]
        assert cell.split(", ")[:2] == _words(values).split(", ")[:2], key


def test_a_map_refused_by_the_theory_says_so():
    values = {**scene_values("5b"), "mu_k": 0.5, "mu_s": 0.3}  # mu_k > mu_s
    data = regime_map(values)
    assert data["labels"] == ["invalid"] and not np.asarray(data["codes"]).any()


def test_cells_behind_the_start_are_invalid_the_others_classified():
    """A stop behind the start (x0 = 0) is refused cell by cell, under one label; the
    state's own clearance does not decide for the whole grid."""
    values = {**scene_values("5b"), "clearance": -0.5}
    speeds, clearances = [0.05, 0.5], [-0.2, -0.1, 0.2, 0.3]
    labels = regime_labels(values, speeds, clearances)
    assert labels[:2].ravel().tolist() == ["invalid"] * 4
    for i, clearance in enumerate(clearances[2:], start=2):
        for j, speed in enumerate(speeds):
            expected = _words({**values, "belt_speed": speed, "clearance": clearance})
            assert labels[i, j] == expected != "invalid"
