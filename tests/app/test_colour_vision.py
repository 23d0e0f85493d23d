"""The colour-difference and colour-blindness checks behind the palettes
(app.plots.colour_vision), against published values."""

from __future__ import annotations

import numpy as np
import pytest

from app.plots.colour_vision import CVD_MATRICES, delta_e2000, linear_to_lab, simulate

#: Pairs of Sharma, Wu and Dalal (2005), Table 1, with their CIEDE2000 differences (given
#: to 4 decimals: the tolerance is half the last digit).
SHARMA_PAIRS = [
    ((50.0, 2.6772, -79.7751), (50.0, 0.0, -82.7485), 2.0425),
    ((50.0, 0.0, 0.0), (50.0, -1.0, 2.0), 2.3669),
    ((50.0, 2.5, 0.0), (73.0, 25.0, -18.0), 27.1492),
    ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
    ((2.0776, 0.0795, -1.1350), (0.9033, -0.0636, -0.5514), 0.9082),
]


@pytest.mark.parametrize("lab1, lab2, expected", SHARMA_PAIRS)
def test_ciede2000_matches_sharma_s_table(lab1, lab2, expected):
    assert delta_e2000(lab1, lab2) == pytest.approx(expected, abs=5e-5)
    assert delta_e2000(lab2, lab1) == pytest.approx(expected, abs=5e-5)  # symmetric


def test_white_is_l_100_and_greys_stay_grey_to_a_dichromat():
    """The D65 white is L* = 100, a* = b* = 0; Machado's matrices keep every grey (their
    rows sum to one, to their 6 printed decimals)."""
    np.testing.assert_allclose(linear_to_lab(np.ones(3)), [100.0, 0.0, 0.0], atol=1e-9)
    for vision in CVD_MATRICES:
        for grey in ("#000000", "#777777", "#ffffff"):
            seen = simulate(grey, vision)
            np.testing.assert_allclose(seen, simulate(grey, "normal"), atol=2e-6)


@pytest.mark.parametrize("vision, red, green", [("deuteranopia", "#d62728", "#2ca02c"),
                                                ("protanopia", "#b8860b", "#228b22")])
def test_red_and_green_become_alike_to_a_dichromat(vision, red, green):
    """A red and a green far apart to normal vision are close to a dichromat (the
    confusion the simulation exists to show): a fifth of the difference or less."""

    def diff(v):
        return delta_e2000(linear_to_lab(simulate(red, v)), linear_to_lab(simulate(green, v)))

    assert diff(vision) < 0.2 * diff("normal")
