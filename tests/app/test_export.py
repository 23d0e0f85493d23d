"""The numbers of the exports and the readout read as a person writes them (app.export,
app.readout): CSV cells with the shortest digits that give back the solver's float, an SI
header without the float noise of a unit conversion, durations in seconds past a second."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from app.export import si_header_number, trajectory_csv, transitions_csv
from app.readout import duration_text, readout_rows
from app.solve.pool import solve
from app.state import ExplorerState, scene_values


def _cells(text: str) -> list[str]:
    """The numeric cells of a CSV's data rows."""
    rows = [line.split(",") for line in text.splitlines()[3:] if not line.startswith("#")]
    return [c for row in rows for c in row if c and re.fullmatch(r"[-+0-9.eE]+|nan|-?inf", c)]


@pytest.mark.parametrize("write", [trajectory_csv, transitions_csv])
def test_csv_cells_are_the_shortest_digits_that_give_back_the_float(write):
    """Cells were written with 17 significant digits: 0.07 read 0.070000000000000007. Each
    is now the float's repr (the shortest string that reads back to the same double), so
    nothing is lost and nothing is added."""
    sol = solve(scene_values("7c"))
    cells = _cells(write(sol).getvalue())
    assert len(cells) > 20
    assert all(cell == repr(float(cell)) for cell in cells)
    # Read back exactly: the solver's own floats, bit for bit.
    if write is trajectory_csv:
        first = write(sol).getvalue().splitlines()[3].split(",")
        assert float(first[0]) == sol.result.t[0] and float(first[1]) == sol.result.x[0]
        times = [float(line.split(",")[0]) for line in write(sol).getvalue().splitlines()[3:]]
        np.testing.assert_array_equal(times, np.asarray(sol.result.t))  # exact: no tolerance


def test_the_si_header_has_no_float_noise():
    """v = 0.07 at omega = 10 rad/s is v_dr = 0.7 m/s, but 0.07 * 10 is
    0.7000000000000001 in binary floating point, and the header printed that."""
    state = ExplorerState(units="SI", mass=1.0, stiffness=100.0, length_unit=1.0)
    sol = solve({**scene_values("5a"), "belt_speed": 0.07})
    head = trajectory_csv(sol, state.scales()).getvalue().splitlines()[0]
    assert 0.07 * 10.0 != 0.7  # the noise this guards against
    assert "v_dr=0.7 m/s" in head
    shown = head.split("; the core's dimensionless values")[0]
    for number in re.findall(r"=([-0-9.e+]+) ", shown):
        assert len(re.sub(r"e.*|[-.]|^0+", "", number).lstrip("0")) <= 12, number


@pytest.mark.parametrize("step", [0.001, 0.005, 0.01, 0.1, 1.0])
def test_the_si_header_keeps_every_slider_step(step):
    """The header's digits round-trip any value on a slider's step grid (steps of
    app.control_specs), up to values 1e6 times the step."""
    for k in (1, 7, 123, 98765, 999999):
        value = k * step
        assert float(si_header_number(value)) == pytest.approx(value, rel=1e-12, abs=0)
        assert float(si_header_number(value)) == float(f"{value:.12g}")


@pytest.mark.parametrize(("seconds", "text"), [
    (0.0123, "12.3 ms"), (0.9994, "999.4 ms"), (1.0, "1 s"), (19.42, "19.4 s"),
    (194.2, "194 s"), (1e-4, "0.1 ms"),
])
def test_a_duration_reads_in_seconds_past_a_second(seconds, text):
    """A 19.42 s solve read "1.942e+04 ms"."""
    assert duration_text(seconds) == text


def test_the_solve_row_gives_a_long_solve_in_seconds():
    sol = dataclasses.replace(solve(scene_values("5a")), solve_time=19.42)
    row = dict(readout_rows(sol))["Solve"]
    assert "19.4 s" in row and "e+" not in row and " ms" not in row
