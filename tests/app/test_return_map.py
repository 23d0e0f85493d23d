"""The return map of the friction–impact map against the theory (docs/physics.md, "Zeno
and grazing sums", "Steady states") and core's own transition records."""

from __future__ import annotations

import doctest

import numpy as np
import pytest

import app.return_map
from app.return_map import return_map
from app.state import core_inputs, scene_values
from core import TransitionKind, simulate

#: The closed-form solver's impact speeds carry rounding only (a few ulps per arc).
RTOL = 1e-9


def _run(scene: str, t_end: float | None = None):
    values = scene_values(scene)
    osc, stop, x0, v0, horizon = core_inputs(values)
    t_end = horizon if t_end is None else t_end
    return values, simulate(osc, stop, t_end, x0, v0), t_end


def test_a_grazing_sequence_falls_as_r_to_the_h():
    """Fig. 7c (0 < r < 1, x_bar > a): the rebound leaves at r w and the mirror arc brings
    the block back at that speed, so the return map's points lie on s_{n+1} = r s_n."""
    values, res, t_end = _run("7c")
    m = return_map(res, "rigid", t_end)
    assert m.quantity == "impact speed" and len(m.values) >= 5
    s_n, s_next = m.pairs
    np.testing.assert_allclose(s_next / s_n, values["restitution"], rtol=RTOL)
    # And, from core's records: each approach speed is the rebound speed before it.
    impacts = [tr for tr in res.transitions
               if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)]
    np.testing.assert_allclose(s_next, [abs(tr.v_after) for tr in impacts[:-1]], rtol=RTOL)
    assert m.fixed.size == 0  # grazing approaches its circle; no periodic fixed point


@pytest.mark.parametrize("t_end", [None, 2000.0])
def test_a_periodic_orbit_is_a_fixed_point(t_end):
    """Fig. 5a (r = 1): one impact per period at the steady state's impact speed, which
    the map repeats; every impact of the run is a point (counted, none lost at a long
    horizon)."""
    _, res, t_end = _run("5a", t_end)
    m = return_map(res, "rigid", t_end)
    counts = res.transition_counts
    assert m.total == counts["impact"] + counts.get("stick->impact", 0) == len(m.values)
    np.testing.assert_allclose(m.fixed, [res.steady.impact_speed], rtol=RTOL)
    s_n, s_next = m.pairs
    late = s_n > 0  # all of them: an elastic stop returns every speed it receives
    np.testing.assert_allclose(s_next[late], s_n[late], rtol=RTOL)


def test_without_a_stop_the_map_follows_the_stick_onsets():
    """No stop (Fig. 3b): the stick onsets' positions, each the block's x at a
    slip->stick transition."""
    _, res, t_end = _run("3b")
    m = return_map(res, "none", t_end)
    sticks = [tr.x for tr in res.transitions if tr.kind is TransitionKind.SLIP_STICK]
    assert m.quantity == "stick position" and len(sticks) > 0
    np.testing.assert_array_equal(m.values, sticks)


def test_doctests():
    assert doctest.testmod(app.return_map).failed == 0
