"""A refused value is shown so that it differs from the bounds it misses."""

from __future__ import annotations

import pytest

from core import Oscillator, RigidStop, simulate
from core.validation import MAX_T_END, check_range


@pytest.mark.parametrize(("name", "value", "low", "high"), [
    ("restitution", 1.0000000000000002, 0.0, 1.0),
    ("t_end", 5000.0000001, 0.1, 5000.0),
    ("t_end", 0.1 - 1e-9, 0.1, 5000.0),
    ("clearance", -1.0000001e100, -1e100, 1e100),
])
def test_a_value_just_past_a_bound_is_not_shown_as_the_bound(name, value, low, high):
    """Regression: six significant digits turned 5000.0000001 into 'got 5000' beside
    '[0.1, 5000]', a message that contradicts itself. The value shown must read back as
    the value refused (and so differ from both bounds)."""
    with pytest.raises(ValueError) as info:
        check_range(name, value, low, high)
    shown = str(info.value).rsplit("got ", 1)[1]
    assert float(shown) == value


def test_a_horizon_one_ulp_past_the_limit_names_its_value():
    """The same through simulate: t_end one ulp above MAX_T_END."""
    t_end = MAX_T_END * (1.0 + 2.0**-52)
    with pytest.raises(ValueError, match="t_end must lie in") as info:
        simulate(Oscillator(0.3, 0.2, 0.1), RigidStop(0.25, 0.7), t_end)
    assert float(str(info.value).rsplit("got ", 1)[1]) == t_end


def test_a_value_far_from_the_bounds_keeps_six_digits():
    with pytest.raises(ValueError, match=r"got 1\.5$"):
        check_range("restitution", 1.5, 0.0, 1.0)
