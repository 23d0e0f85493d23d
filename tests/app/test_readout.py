"""The readout's rows (app.readout), without a browser."""

from __future__ import annotations

from app.readout import readout_rows
from app.solver import solve
from app.state import DIMENSIONLESS, ExplorerState, scene_values


def test_the_period_is_in_the_units_shown():
    sol = solve(scene_values("5b"))
    period = sol.result.steady.period
    plain = dict(readout_rows(sol, DIMENSIONLESS))["Steady state found"]
    assert plain.startswith(f"periodic, period {period:.6g}, ")
    si = ExplorerState(units="SI", mass=1.0, stiffness=400.0).scales()  # omega = 20 rad/s
    rows = dict(readout_rows(sol, si))
    assert rows["Steady state found"].startswith(f"periodic, period {period / 20.0:.6g} s, ")
    assert rows["x_max simulated"].endswith(" m")
