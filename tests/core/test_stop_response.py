"""The deformable stop on its own (core.stop_response): its equivalent rigid stop (paper
Eq. 16) and its force under the overlap program of paper Fig. 2b (Eqs. 9-13)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import (
    HystereticStop,
    RigidStop,
    equivalent_rigid,
    overlap_program,
    phi_compression,
    phi_expansion,
)
from core.stop_response import PROGRAM_DECAY, PROGRAM_PEAK

#: The paper's Fig. 2b stop (k_c0 = 2 k_e0, beta = 5) and the scenes' stiff, sharp one.
FIG_2B = HystereticStop(0.0, 1000.0, 500.0, limit_overlap=0.05, beta_c=5.0, beta_e=5.0)
SCENES = HystereticStop(0.15, 400.0, 36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
#: The envelopes are evaluated here and in the law by the same hyperbola, up to a few ulps
#: of forces of O(1e3 D): 1e-12 relative.
RTOL = 1e-12


@pytest.mark.parametrize("stop", [FIG_2B, SCENES])
def test_the_equivalent_rigid_stop_has_restitution_sqrt_ke_over_kc(stop):
    rigid = equivalent_rigid(stop)
    assert isinstance(rigid, RigidStop) and rigid.clearance == stop.clearance
    assert rigid.restitution == pytest.approx(math.sqrt(stop.k_e0 / stop.k_c0), rel=1e-15)


def test_a_rigid_stop_or_none_is_its_own_equivalent():
    rigid = RigidStop(0.2, 0.5)
    assert equivalent_rigid(rigid) is rigid and equivalent_rigid(None) is None


@pytest.mark.parametrize("law", ["paper", "passive"])
@pytest.mark.parametrize("stop", [FIG_2B, SCENES])
def test_the_program_loads_on_the_compression_envelope_and_stays_between_envelopes(stop,
                                                                                  law):
    stop = HystereticStop(stop.clearance, stop.k_c0, stop.k_e0,
                          limit_overlap=stop.limit_overlap, beta_c=stop.beta_c,
                          beta_e=stop.beta_e, law=law)
    prog = overlap_program(stop)
    d = stop.limit_overlap
    # The program: the amplitude falls linearly from PROGRAM_PEAK D at s = 0 to
    # PROGRAM_DECAY of it at the end (4 periods); read at the middle of periods 1 and 4.
    for s_mid in (math.pi, 7 * math.pi):
        i = int(np.argmin(np.abs(prog.s - s_mid)))
        amplitude = PROGRAM_PEAK * d * (1 - (1 - PROGRAM_DECAY) * s_mid / (8 * math.pi))
        assert prog.s[i] == pytest.approx(s_mid, rel=1e-14)
        assert prog.overlap[i] == pytest.approx(amplitude, rel=1e-14)
    # Every period ends at zero overlap, and there the force is zero.
    ends = np.isclose(np.mod(prog.s, 2 * math.pi), 0.0, atol=1e-9) | (prog.s == prog.s[-1])
    np.testing.assert_allclose(prog.force[ends], 0.0, atol=1e-12 * d)
    # First loading, up to the first turn of the overlap rate: on phi_C (Eq. 11).
    first = np.flatnonzero(np.diff(prog.overlap) < 0)[0]
    np.testing.assert_allclose(prog.force[:first + 1],
                               phi_compression(prog.overlap[:first + 1], stop), rtol=RTOL)
    # Everywhere between the envelopes (Eq. 12).
    slack = RTOL * np.abs(prog.force) + 1e-15
    assert np.all(prog.force >= phi_expansion(prog.overlap, stop) - slack)
    assert np.all(prog.force <= phi_compression(prog.overlap, stop) + slack)


def test_the_first_unloading_follows_the_paper_s_exponential_from_the_reversal():
    """docs/contact-law.md, law="paper": after a reversal at (delta_r, phi_r) the force is
    phi_E + (phi_r - phi_E(delta_r)) exp(-beta_e (delta_r - delta) / D), clipped to the
    envelopes; written out here from the formula, not from the law's code."""
    prog = overlap_program(FIG_2B)
    d, beta = FIG_2B.limit_overlap, FIG_2B.beta_e
    turn = np.flatnonzero(np.diff(prog.overlap) < 0)[0]  # last sample still loading
    back = turn + 1 + np.flatnonzero(np.diff(prog.overlap[turn:]) > 0)[0]  # next turn
    delta = prog.overlap[turn:back]
    delta_r, phi_r = prog.overlap[turn], prog.force[turn]
    phi_e = phi_expansion(delta, FIG_2B)
    expected = phi_e + (phi_r - float(phi_expansion(delta_r, FIG_2B))) * np.exp(
        -beta * (delta_r - delta) / d)
    expected = np.clip(expected, phi_e, phi_compression(delta, FIG_2B))
    inside = delta > 0.0
    np.testing.assert_allclose(prog.force[turn:back][inside], expected[inside], rtol=1e-10)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"periods": 0}, r"periods must be an integer in \[1, 1000\]; got 0"),
    ({"periods": 2.5}, r"periods must be an integer in \[1, 1000\]; got 2.5 \(float\)"),
    ({"samples_per_period": 1}, r"samples_per_period must be an integer in \[2, 1000\]; "
                                r"got 1"),
    ({"peak": 1.0}, r"peak must lie in \(0, 1\); got 1"),
    ({"decay": -0.5}, r"decay must lie in \[0, 1\]; got -0.5"),
])
def test_a_bad_program_is_refused_by_name(kwargs, message):
    with pytest.raises(ValueError, match=message):
        overlap_program(FIG_2B, **kwargs)


def test_a_program_needs_a_deformable_stop():
    with pytest.raises(ValueError, match="stop must be a HystereticStop; got RigidStop"):
        overlap_program(RigidStop(0.2, 0.5))
