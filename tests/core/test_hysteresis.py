"""Properties of the hysteretic contact law in core.deformable.law (paper Eqs. 9-13,
docs/contact-law.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from core.deformable.law import (
    FIRST_LOADING,
    Branch,
    branch_work,
    contact_force,
    dphi_ddelta,
    force_and_slope,
    phi_compression,
    phi_expansion,
    program_work,
    reverse,
    stored_energy,
)
from core.params import HystereticStop

#: The paper's Fig. 2b stop (k_c0 = 2 k_e0, beta = 5), stiffness relative to k.
PAPER_STOP = HystereticStop(
    clearance=0.0, k_c0=1000.0, k_e0=500.0, limit_overlap=0.05, beta_c=5.0, beta_e=5.0
)
D = PAPER_STOP.limit_overlap
#: Closed forms against adaptive quadrature: both near double precision, the forces are
#: O(1e2), so 1e-12 relative leaves room for the quadrature's own error estimate.
WORK_RTOL = 1e-12
#: Passivity slack per unit work scale: the closed-form work of one leg is accurate to a
#: few ulps of its magnitude, and a program has at most ~40 legs.
PASSIVITY_RTOL = 1e-12

STOPS = [
    PAPER_STOP,
    HystereticStop(clearance=0.0, k_c0=10.0, k_e0=1.0, limit_overlap=1.0, beta_c=0.1, beta_e=0.1),
    HystereticStop(clearance=0.0, k_c0=1e8, k_e0=2.5e7, limit_overlap=1e-3, beta_c=1e3, beta_e=1e3),
    HystereticStop(clearance=0.0, k_c0=1e3, k_e0=1e3, limit_overlap=0.05, beta_c=5.0, beta_e=5.0),
    HystereticStop(
        clearance=0.0, k_c0=1e3, k_e0=100.0, limit_overlap=0.05, beta_c=2.0, beta_e=50.0
    ),
]


def _on_branch(delta, branch, stop):
    return contact_force(np.asarray(delta), branch, stop)


def test_envelopes_are_the_hyperbolas():
    d = np.linspace(0.0, 0.99 * D, 101)
    np.testing.assert_allclose(phi_compression(d, PAPER_STOP), 1000.0 * D * d / (D - d))
    np.testing.assert_allclose(phi_expansion(d, PAPER_STOP), 500.0 * D * d / (D - d))
    assert phi_compression(-1.0, PAPER_STOP) == 0.0
    assert phi_compression(D, PAPER_STOP) == math.inf
    assert phi_compression(2 * D, PAPER_STOP) == math.inf


@pytest.mark.parametrize("stop", STOPS)
def test_first_loading_is_the_compression_envelope(stop):
    d = np.linspace(0.0, 0.99 * stop.limit_overlap, 201)
    np.testing.assert_allclose(
        contact_force(d, FIRST_LOADING, stop), phi_compression(d, stop), rtol=1e-15
    )


@pytest.mark.parametrize("stop", STOPS)
def test_zero_out_of_contact_and_inf_beyond_limit(stop):
    branch = Branch(False, 0.5 * stop.limit_overlap, 0.0)
    assert contact_force(0.0, branch, stop) == 0.0
    assert contact_force(-1.0, branch, stop) == 0.0
    assert contact_force(stop.limit_overlap, branch, stop) == math.inf
    assert not np.isnan(contact_force(np.array([-1.0, 0.0, 2.0]), branch, stop)).any()


def _reversal_branches(stop):
    """Unloading from points on phi_C, and reloading from points on those unloadings."""
    out = []
    for frac in (0.05, 0.3, 0.7, 0.95):
        d_r = frac * stop.limit_overlap
        unload = reverse(d_r, float(phi_compression(d_r, stop)), FIRST_LOADING)
        out.append(unload)
        d_r2 = 0.5 * d_r
        out.append(reverse(d_r2, float(contact_force(d_r2, unload, stop)), unload))
    return out


@pytest.mark.parametrize("stop", STOPS)
def test_bounds_continuity_and_scalar_path(stop):
    d = np.linspace(0.0, 0.98 * stop.limit_overlap, 4001)
    for branch in _reversal_branches(stop):
        phi = contact_force(d, branch, stop)
        assert np.all(phi >= phi_expansion(d, stop))
        assert np.all(phi <= phi_compression(d, stop))
        assert np.all(phi >= 0.0)
        # Continuity: a jump over h shrinks like h (slope bounded), here from h = 1e-6 D to
        # 1e-9 D by 1e-3; a discontinuity would keep it O(1). The probes include the reversal
        # point, where the curve has a kink. Slack: 10x, plus rounding of phi (1e-13 phi).
        probes = np.append(d[1:-1], branch.delta_r)
        steps = []
        for h in (1e-6, 1e-9):
            hh = h * stop.limit_overlap
            steps.append(
                np.abs(
                    contact_force(probes + hh, branch, stop) - contact_force(probes, branch, stop)
                )
            )
        tol = 1e-13 * contact_force(probes, branch, stop)
        assert np.all(steps[1] <= 1e-2 * steps[0] + tol)
        slope = dphi_ddelta(d, branch, stop)
        # The force is continuous at the reversal point: the new branch starts there.
        assert contact_force(branch.delta_r, branch, stop) == pytest.approx(branch.phi_r)
        scalar = np.array([force_and_slope(x, branch, stop) for x in d])
        np.testing.assert_allclose(scalar[:, 0], phi, rtol=1e-13, atol=1e-300)
        np.testing.assert_allclose(scalar[:, 1], slope, rtol=1e-13, atol=1e-300)


@pytest.mark.parametrize("stop", STOPS)
def test_tangent_is_the_derivative(stop):
    """Central differences of the force match the tangent away from the clip kinks."""
    d = np.linspace(0.02, 0.9, 60) * stop.limit_overlap
    h = 1e-7 * stop.limit_overlap
    for branch in _reversal_branches(stop):
        fd = (contact_force(d + h, branch, stop) - contact_force(d - h, branch, stop)) / (2 * h)
        tangent = dphi_ddelta(d, branch, stop)
        left = dphi_ddelta(d - h, branch, stop)
        right = dphi_ddelta(d + h, branch, stop)
        smooth = np.isclose(left, right, rtol=1e-4)  # no kink within the stencil
        # Central difference error ~ h^2 f''' / 6 plus rounding eps*phi/h: 1e-5 relative.
        np.testing.assert_allclose(fd[smooth], tangent[smooth], rtol=1e-5)


def test_unloading_approaches_expansion_envelope_and_reloading_compression():
    beta = 50.0  # sharp enough that phi_C does not clip the curves probed below
    stop = HystereticStop(
        clearance=0.0, k_c0=1000.0, k_e0=500.0, limit_overlap=D, beta_c=beta, beta_e=beta
    )
    d_r = 0.9 * D
    unload = reverse(d_r, float(phi_compression(d_r, stop)), FIRST_LOADING)
    d = np.array([0.85, 0.8, 0.6, 0.4]) * D
    gap_e = contact_force(d, unload, stop) - phi_expansion(d, stop)
    # The gap to phi_E decays as exp(-beta (delta_r - delta)/D); the gap is the difference
    # of two O(1e2) forces, hence an absolute slack of a few ulps of phi.
    atol = 1e-13 * float(phi_compression(d_r, stop))
    np.testing.assert_allclose(
        gap_e, gap_e[0] * np.exp(-beta * (d[0] - d) / D), rtol=1e-10, atol=atol
    )
    d_r2 = 0.3 * D
    reload = reverse(d_r2, float(contact_force(d_r2, unload, stop)), unload)
    d = np.array([0.32, 0.36, 0.4, 0.5]) * D
    gap_c = phi_compression(d, stop) - contact_force(d, reload, stop)
    np.testing.assert_allclose(
        gap_c, gap_c[0] * np.exp(-beta * (d - d[0]) / D), rtol=1e-10, atol=atol
    )


def test_small_overlap_contact_is_elastic():
    """Unloading from phi_C below beta*delta*(D-delta) = D^2 stays on phi_C (docs/contact-law.md,
    "Restitution against impact speed")."""
    stop = PAPER_STOP
    d_r = 0.5 * D / stop.beta_e  # beta*d*(D-d) < D^2
    unload = reverse(d_r, float(phi_compression(d_r, stop)), FIRST_LOADING)
    d = np.linspace(0.0, d_r, 50)
    np.testing.assert_allclose(contact_force(d, unload, stop), phi_compression(d, stop))
    assert stored_energy(d_r, float(phi_compression(d_r, stop)), stop) == pytest.approx(
        branch_work(0.0, d_r, FIRST_LOADING, stop), rel=1e-14
    )


@pytest.mark.parametrize("stop", STOPS)
def test_branches_of_one_direction_never_cross(stop):
    """Unloading curves from different reversal points never cross one another, nor do
    reloading curves: along one direction the law keeps the order of the states. (Both are
    ``envelope +- c * exp(+-beta * delta / D)``: two of them differ by a factor of one sign.)"""
    d_lim = stop.limit_overlap
    d = np.linspace(0.0, 0.97 * d_lim, 500)
    unloads = [
        reverse(f * d_lim, float(phi_compression(f * d_lim, stop)), FIRST_LOADING)
        for f in (0.2, 0.5, 0.8, 0.97)
    ]
    reloads = [reverse(0.1 * d_lim, float(contact_force(0.1 * d_lim, b, stop)), b) for b in unloads]
    for family, span in ((unloads, d <= 0.2 * d_lim), (reloads, d >= 0.1 * d_lim)):
        curves = [contact_force(d[span], b, stop) for b in family]
        for one, other in zip(curves[:-1], curves[1:], strict=False):
            diff = one - other
            apart = np.abs(diff) > 1e-13 * np.maximum(one, other)  # beyond rounding
            assert np.all(diff[apart] > 0) or np.all(diff[apart] < 0)


def test_reload_leaves_the_unloading_curve_upwards():
    """Reloading from a point of an unloading curve starts above it (the new branch is the
    steeper one there). It cannot stay above it all the way back: the
    unloading started on phi_C and a reloading curve only approaches phi_C, so the two meet
    again before the old reversal point; this reading of Eq. (13) has no memory of it."""
    stop = HystereticStop(
        clearance=0.0, k_c0=1000.0, k_e0=500.0, limit_overlap=D, beta_c=50.0, beta_e=50.0
    )
    d_r = 0.9 * D
    unload = reverse(d_r, float(phi_compression(d_r, stop)), FIRST_LOADING)
    d_r2 = 0.5 * D
    reload = reverse(d_r2, float(contact_force(d_r2, unload, stop)), unload)
    d = d_r2 + np.linspace(1e-4, 0.05, 20) * D
    assert np.all(contact_force(d, reload, stop) > contact_force(d, unload, stop))
    assert contact_force(d_r, reload, stop) < contact_force(d_r, unload, stop)


@pytest.mark.parametrize("stop", STOPS)
def test_branch_work_matches_quadrature(stop):
    d_lim = stop.limit_overlap
    for branch in _reversal_branches(stop):
        lo, hi = (branch.delta_r, 0.97 * d_lim) if branch.loading else (0.0, branch.delta_r)
        exact, err = quad(
            lambda s, b=branch: float(contact_force(s, b, stop)),
            lo,
            hi,
            epsabs=0.0,
            epsrel=1e-13,
            limit=500,
        )
        assert branch_work(lo, hi, branch, stop) == pytest.approx(exact, rel=WORK_RTOL, abs=err)
        assert branch_work(hi, lo, branch, stop) == -branch_work(lo, hi, branch, stop)


def _run_program(turns, stop):
    """Work done on the stop along the overlap program 0 -> turns[0] -> ... -> 0, and the
    work of first loading to the largest overlap (the scale of the rounding error)."""
    return program_work(stop, turns), branch_work(0.0, max(turns), FIRST_LOADING, stop)


#: beta = beta_c = beta_e from which the law is NOT passive. Random searches over programs
#: of 2-5 turning points (k_e0/k_c0 from 0.01 to 0.9) found gains from 4.05 to 6.15 (a
#: fresh-seed run: 4.007, 1e-5 of the loading work); a fresh-seed run of the search below,
#: then over beta up to 1e3, found one at beta = 17.8 among programs that reverse on phi_C
#: above s+ (docs/contact-law.md, the first mechanism; test below). No passivity is claimed
#: from here up; below it, beta_e <= 4 leaves no s+ on phi_C.
NON_PASSIVE_BETA = 3.9


@given(
    log_beta=st.floats(-1.0, math.log10(NON_PASSIVE_BETA) - 0.01),
    log_ratio=st.floats(-2.0, 0.0),
    blocks=st.lists(
        st.tuples(
            st.floats(0.01, 0.97),  # peak of the block, over D
            st.floats(0.0, 1.0),  # valley, as a fraction of the peak
            st.floats(1e-4, 0.1),  # amplitude of the small cycles above the valley, over D
            st.integers(0, 40),  # number of small cycles
        ),
        min_size=1,
        max_size=4,
    ),
)
def test_passivity_of_closed_overlap_programs(log_beta, log_ratio, blocks):
    """No closed overlap program (from separation back to separation) creates energy.

    Programs are blocks of a large excursion followed by many small cycles above its valley:
    the small cycles are where this law can give back more than it took (see the
    counterexamples below). Range: beta_c = beta_e from 0.1 to NON_PASSIVE_BETA, and
    k_e0/k_c0 from 0.01 to 1: the property is only claimed where it was searched and held.
    """
    beta = 10.0**log_beta
    stop = HystereticStop(
        clearance=0.0,
        k_c0=1000.0,
        k_e0=1000.0 * 10.0**log_ratio,
        limit_overlap=D,
        beta_c=beta,
        beta_e=beta,
    )
    turns = []
    for peak, valley, amp, n in blocks:
        low = valley * peak
        turns += [peak * D, low * D] + [min(0.98, low + amp) * D, low * D] * n
    work, scale = _run_program(turns, stop)
    assert work >= -PASSIVITY_RTOL * scale * (len(turns) + 1)


def test_law_is_not_passive_for_beta_c_below_beta_e():
    """A documented limit of the paper reading (docs/contact-law.md): with beta_e = 10 beta_c two
    blocks of small cycles give back about 2 % more than the loading work (found by a random search
    over closed programs). Guards the finding: if the law changes so that this program becomes
    passive, the documentation of the limit must change with it."""
    stop = HystereticStop(
        clearance=0.0, k_c0=1000.0, k_e0=500.0, limit_overlap=D, beta_c=0.45, beta_e=4.5
    )
    turns = (
        [0.44 * D, 0.42 * D]
        + [0.43 * D, 0.42 * D] * 80
        + [0.8 * D, 0.24 * D]
        + [0.2407 * D, 0.24 * D] * 70
    )
    work, scale = _run_program(turns, stop)
    # Energy gain well above the rounding bound used for the passive cases.
    assert work < -100 * PASSIVITY_RTOL * scale * (len(turns) + 1)


def test_law_is_not_passive_at_the_papers_beta():
    """A documented limit of the paper reading (docs/contact-law.md): at beta_c = beta_e = 5
    (the paper's value) the program 0 -> 0.641 D -> 0.537 D -> 0.896 D -> 0.093 D -> 0 gives back
    about 0.7 % more work than it took (k_e0/k_c0 = 0.1; found by a random search)."""
    stop = HystereticStop(
        clearance=0.0, k_c0=1000.0, k_e0=100.0, limit_overlap=D, beta_c=5.0, beta_e=5.0
    )
    work, scale = _run_program([0.641 * D, 0.537 * D, 0.896 * D, 0.093 * D], stop)
    assert work < -1e-3 * scale


def test_law_is_not_passive_for_deep_programs_at_larger_beta():
    """A documented limit: beta_c = beta_e = 10^1.25 = 17.8, k_e0/k_c0 = 0.1, two blocks
    of peak 0.969 D (above s+ = 0.94 D), valley 0.89 D and 17 and 19 cycles of 0.0625 D
    above it give back 0.6 % of the loading work (found by a fresh-seed run of the
    property search, which claimed passivity there)."""
    beta = 10.0**1.25
    stop = HystereticStop(
        clearance=0.0, k_c0=1000.0, k_e0=100.0, limit_overlap=D, beta_c=beta, beta_e=beta
    )
    turns = []
    for n in (17, 19):
        low = 0.921875 * 0.96875
        turns += [0.96875 * D, low * D] + [(low + 0.0625) * D, low * D] * n
    work, scale = _run_program(turns, stop)
    assert work < -1e-3 * scale


def test_elastic_stop_dissipates_nothing():
    stop = STOPS[3]  # k_e0 = k_c0
    work, scale = _run_program([0.9 * D, 0.2 * D, 0.7 * D, 0.1 * D], stop)
    assert abs(work) <= 1e-13 * scale


def _fig2b_program(n=6000):
    """Paper Fig. 2b: sinusoidal overlap of decreasing amplitude about D/2, from 0."""
    theta = np.linspace(0.0, 8 * 2 * np.pi, n)
    return theta, 0.5 * D * (1.0 - np.exp(-theta / 20.0) * np.cos(theta))


def _trace(delta, stop):
    """Force along an overlap history: reversals where the overlap rate changes sign."""
    branch = FIRST_LOADING
    phi = np.zeros_like(delta)
    reversals = []
    for i in range(1, len(delta)):
        rate = delta[i] - delta[i - 1]
        if (rate < 0) == branch.loading and rate != 0.0:
            branch = reverse(delta[i - 1], phi[i - 1], branch)
            reversals.append(i - 1)
        phi[i] = contact_force(delta[i], branch, stop)
    return phi, reversals


def test_fig2b_loop():
    stop = PAPER_STOP
    theta, delta = _fig2b_program()
    phi, reversals = _trace(delta, stop)
    assert np.all(phi <= phi_compression(delta, stop) * (1 + 1e-14))
    assert np.all(phi >= phi_expansion(delta, stop) * (1 - 1e-14))
    # First loading follows the compression envelope up to the first reversal.
    first = reversals[0]
    np.testing.assert_allclose(phi[: first + 1], phi_compression(delta[: first + 1], stop))
    # Dissipation per cycle, from one overlap minimum to the next: the work done on the stop
    # minus the change in the energy it would still give back; trapezoid rule on the trace
    # (6000 points over 8 cycles: relative error ~1e-4, far below the loop areas).
    work = np.concatenate([[0.0], np.cumsum(0.5 * (phi[1:] + phi[:-1]) * np.diff(delta))])
    minima = reversals[1::2]
    losses = []
    for i0, i1 in zip(minima[:-1], minima[1:], strict=False):
        stored0 = stored_energy(delta[i0], phi[i0], stop)
        stored1 = stored_energy(delta[i1], phi[i1], stop)
        losses.append(work[i1] - work[i0] - (stored1 - stored0))
    assert len(losses) >= 6
    assert all(loss > 0 for loss in losses)
    # The amplitude decreases, so do the loops (after the first, which starts from the
    # virgin state's deep valley and is not comparable).
    assert all(b < a for a, b in zip(losses[1:-1], losses[2:], strict=True))
    # The loops drift towards the middle: valleys rise and peaks fall.
    peaks, valleys = delta[reversals[0::2]], delta[reversals[1::2]]
    assert np.all(np.diff(peaks) < 0) and np.all(np.diff(valleys) > 0)
