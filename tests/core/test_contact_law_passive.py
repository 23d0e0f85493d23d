"""The two readings of the contact law (docs/contact-law.md): the passive one never returns
energy and its loss never falls; the paper's one does both on the programs that show it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from core import HystereticStop, Oscillator
from core.deformable.law import (
    FIRST_LOADING,
    Branch,
    BranchPrimitive,
    branch_work,
    contact_force,
    force_and_slope,
    force_on_branches,
    leaving_overlap,
    passive_as_paper,
    passive_branch_force,
    passive_force_and_slope,
    phi_compression,
    phi_expansion,
    reverse,
    stored_energy,
    stored_energy_many,
)
from core.deformable.solver import simulate_hysteretic

D = 0.05
#: Loss may fall by rounding only: each leg's work is a quadrature to 1e-12 relative of
#: the work scale (the passive law) or a closed form (the paper's).
ROUNDING = 1e-10


def _stop(law, beta_c, beta_e, ratio):
    return HystereticStop(clearance=0.0, k_c0=1000.0, k_e0=1000.0 * ratio, limit_overlap=D,
                          beta_c=beta_c, beta_e=beta_e, law=law)


def _stored(delta, branch, stop):
    """Energy the stop gives back on unloading from the law's state (``delta``, branch)."""
    if delta <= 0.0:
        return 0.0
    if branch.loading:
        return stored_energy(delta, float(contact_force(delta, branch, stop)), stop)
    return branch_work(0.0, delta, branch, stop)


def _losses(turns, stop, points_per_leg=6):
    """Work done on the stop and its loss (work minus stored) along the program
    0 -> turns[0] -> ... -> 0, at a few points of every leg."""
    delta, branch, work = 0.0, FIRST_LOADING, 0.0
    works, losses = [], []
    for target in [*turns, 0.0]:
        if target == delta:
            continue
        if (target > delta) != branch.loading:
            branch = reverse(delta, float(contact_force(delta, branch, stop)), branch, stop)
        for s in np.linspace(delta, target, points_per_leg + 1)[1:]:
            work += branch_work(delta, float(s), branch, stop)
            delta = float(s)
            works.append(work)
            losses.append(work - _stored(delta, branch, stop))
        if delta <= 0.0:
            branch = FIRST_LOADING
    scale = branch_work(0.0, max(turns), FIRST_LOADING, stop)
    return np.array(works), np.array(losses), scale


#: Programs as fractions: each up-leg goes that fraction of the way to 0.97 D, each
#: down-leg to that fraction of the current overlap (so legs alternate in direction).
PROGRAMS = st.lists(st.floats(0.01, 0.99), min_size=1, max_size=10)


def _program(fractions):
    turns, cur = [], 0.0
    for i, f in enumerate(fractions):
        cur = cur + f * (0.97 - cur) if i % 2 == 0 else cur * f
        turns.append(cur * D)
    return turns


@given(
    turns=PROGRAMS,
    log_beta_c=st.floats(-1.0, 3.0),
    beta_factor=st.floats(1.0, 10.0),
    log_ratio=st.floats(-2.0, 0.0),
)
def test_passive_law_loss_never_falls(turns, log_beta_c, beta_factor, log_ratio):
    """Random overlap programs (alternating up and down, from and back to separation) over
    beta_c from 0.1 to 1e3, beta_e up to 10 beta_c, k_e0/k_c0 from 0.01 to 1: the passive
    law's loss never falls, so no closed program returns energy."""
    beta_c = 10.0**log_beta_c
    stop = _stop("passive", beta_c, beta_c * beta_factor, 10.0**log_ratio)
    works, losses, scale = _losses(_program(turns), stop)
    assert np.diff(losses).min() >= -ROUNDING * scale
    assert works[-1] >= -ROUNDING * scale
    assert losses.min() >= -ROUNDING * scale


@given(
    turns=PROGRAMS,
    log_beta_c=st.floats(-1.0, 3.0),
    beta_factor=st.floats(1.0, 10.0),
    log_ratio=st.floats(-2.0, 0.0),
    ends=st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
)
def test_the_solver_s_passive_force_and_work_are_the_law_s(turns, log_beta_c, beta_factor,
                                                           log_ratio, ends):
    """The contact solver evaluates the passive law through a closure bound to the branch
    (core.deformable.law.passive_branch_force) and its work through a primitive with the clip
    points found once (BranchPrimitive): on the branch reached by a random program they
    give the law's force to the bit and its work to rounding (the primitive sums the same
    closed forms in another order: 9e-16 of the scale seen over 3,000 random branches);
    where a branch is one of the paper's reading, the solver evaluates the paper's closure
    and the states' stored energy in the paper's vectorised pass."""
    beta_c = 10.0**log_beta_c
    stop = _stop("passive", beta_c, beta_c * beta_factor, 10.0**log_ratio)
    delta, branch = 0.0, FIRST_LOADING
    for target in _program(turns):
        if (target > delta) != branch.loading:
            branch = reverse(delta, float(contact_force(delta, branch, stop)), branch, stop)
        delta = target
    force = passive_branch_force(branch, stop)
    overlaps = np.linspace(0.0, 0.999 * D, 201)[1:]
    assert [force(d) for d in overlaps] == [passive_force_and_slope(d, branch, stop)[0]
                                            for d in overlaps]
    lo, hi = sorted(e * 0.99 * D for e in ends[:2])
    primitive = BranchPrimitive(branch, stop, lo, hi)
    scale = branch_work(0.0, 0.99 * D, FIRST_LOADING, stop)
    # (the face too: a sample's stored energy on its branch is F(delta) - F(0); the
    # primitive once extrapolated its first piece below lo there, 15 % of the scale off)
    for d in (lo, hi, lo + ends[2] * (hi - lo), 0.0, ends[2] * lo):
        assert primitive(d) == pytest.approx(branch_work(lo, d, branch, stop),
                                             abs=1e-13 * scale)
    # Where the branch is one of the paper's reading (passive_as_paper), the solver takes
    # the paper's closure: the same force, to rounding, wherever the overlap goes on it.
    as_paper = passive_as_paper(branch, stop)
    if as_paper is not None:
        paper = _stop("paper", beta_c, beta_c * beta_factor, 10.0**log_ratio)
        reach = overlaps if branch.loading else overlaps[overlaps <= branch.delta_r]
        for d in reach:
            assert force_and_slope(d, as_paper, paper)[0] == pytest.approx(
                force(d), rel=1e-13)
    # The stored energy of states on the curve, in one pass as for a response's samples.
    phis = [force(d) for d in overlaps]
    assert stored_energy_many(overlaps, np.array(phis), stop) == pytest.approx(
        [stored_energy(d, p, stop) for d, p in zip(overlaps, phis, strict=True)],
        abs=1e-13 * scale)


@pytest.mark.parametrize(
    ("beta_c", "beta_e", "ratio", "turns"),
    [
        # The documented counterexamples of the paper's reading (tests/core/test_hysteresis.py):
        (0.45, 4.5, 0.5, [0.44, 0.42] + [0.43, 0.42] * 80 + [0.8, 0.24] + [0.2407, 0.24] * 70),
        (5.0, 5.0, 0.1, [0.641, 0.537, 0.896, 0.093]),
    ],
)
def test_programs_that_return_energy_under_the_paper_law(beta_c, beta_e, ratio, turns):
    program = [t * D for t in turns]
    paper, _, scale = _losses(program, _stop("paper", beta_c, beta_e, ratio), 1)
    passive, _, _ = _losses(program, _stop("passive", beta_c, beta_e, ratio), 1)
    assert paper[-1] < -1e-3 * scale  # the paper's reading gives energy back ...
    assert passive[-1] >= -ROUNDING * scale  # ... the passive one does not


def test_paper_law_loss_falls_while_loading_near_the_asymptote():
    """The paper's reading returns more the further it is loaded near D: from phi_C above
    s+ its unloading restarts the exponent at the reversal and keeps to phi_C longer. So
    'stop_loss' (work minus what the stop would give back) falls during a first loading
    (beta = 10, k_e0/k_c0 = 0.5: the first contact of a beta = 10 stop)."""
    stop = _stop("paper", 10.0, 10.0, 0.5)
    _, losses, scale = _losses([0.97 * D], stop, points_per_leg=40)
    assert np.diff(losses).min() < -1e-2 * scale
    passive_stop = _stop("passive", 10.0, 10.0, 0.5)
    _, losses, scale = _losses([0.97 * D], passive_stop, points_per_leg=40)
    assert np.diff(losses).min() >= -ROUNDING * scale


def test_passive_law_curves():
    """Loading from the envelope is phi_C; unloading from phi_C above s+ keeps to phi_C
    down to s+ and leaves there; reloading inside the band retraces the unloading curve;
    the force stays between the envelopes and is continuous at reversals."""
    stop = _stop("passive", 20.0, 20.0, 0.2)
    s_plus = leaving_overlap(stop)
    assert s_plus == pytest.approx(0.5 * D * (1 + math.sqrt(1 - 4 / 20.0)), rel=1e-15)
    top = 0.97 * D
    phi_top = float(phi_compression(top, stop))
    down = reverse(top, phi_top, Branch(True, 0.0, 0.0))
    grid = np.linspace(1e-4 * D, top, 400)
    f_down = contact_force(grid, down, stop)
    above = grid >= s_plus
    assert np.allclose(f_down[above], phi_compression(grid[above], stop), rtol=1e-12)
    assert np.all(f_down[~above] < phi_compression(grid[~above], stop))
    assert np.all(f_down >= phi_expansion(grid, stop) * (1 - 1e-12))
    # Reload from a point inside the band: the same curve back up.
    mid = 0.3 * D
    phi_mid = float(contact_force(mid, down, stop))
    up = reverse(mid, phi_mid, down, stop)
    assert up.anchor == (s_plus, float(phi_compression(s_plus, stop)))  # the curve kept
    sel = grid > mid
    assert np.allclose(contact_force(grid[sel], up, stop), f_down[sel], rtol=1e-12)
    # The slope is the derivative of the force.
    for d in (0.1 * D, 0.5 * D, 0.8 * D):
        h = 1e-7 * D
        num = (force_and_slope(d + h, down, stop)[0] - force_and_slope(d - h, down, stop)[0])
        assert force_and_slope(d, down, stop)[1] == pytest.approx(num / (2 * h), rel=1e-5)
    # Work is the integral of the force.
    exact, _ = quad(lambda s: float(contact_force(s, down, stop)), 0.0, top, limit=200,
                    points=[s_plus])
    assert branch_work(0.0, top, down, stop) == pytest.approx(exact, rel=1e-10)


@pytest.mark.parametrize("exponent", [20.0, 30.0, 40.0])
def test_passive_loops_inside_the_band_retrace_their_curve_exactly(exponent):
    """Many small loops inside the band, each swing ``exponent = beta_e swing / D`` deep:
    the curve is kept through every reversal (its anchor, where it left phi_C), so each
    loop comes back to the same force at its top and does no work on the stop. Recomputed
    from each reversal point, the curve's constant at a loop's bottom, where the curve is
    ``phi_C exp(-exponent)`` above phi_E (9e-14 of it for 30, below one ulp for 40), kept
    only the rounding of the force: the tops walked by ~1e-3 relative per reversal at 30,
    and at 40 the loops fell onto phi_E."""
    stop = HystereticStop(clearance=0.0, k_c0=100.0, k_e0=50.0, limit_overlap=0.01,
                          beta_c=1000.0, beta_e=1000.0, law="passive")
    d_lim = stop.limit_overlap
    first, top = 0.5 * d_lim, 0.499 * d_lim
    bottom = top - exponent * d_lim / stop.beta_e
    branch = reverse(first, float(phi_compression(first, stop)), FIRST_LOADING, stop)
    phi_top = float(contact_force(top, branch, stop))
    assert phi_expansion(top, stop) < phi_top < phi_compression(top, stop)
    branch = reverse(top, phi_top, branch, stop)  # the loops start here, unloading
    tops, work, scale = [], 0.0, abs(branch_work(top, bottom, branch, stop))
    for _ in range(200):
        work += branch_work(top, bottom, branch, stop)
        branch = reverse(bottom, float(contact_force(bottom, branch, stop)), branch, stop)
        work += branch_work(bottom, top, branch, stop)
        tops.append(float(contact_force(top, branch, stop)))
        branch = reverse(top, tops[-1], branch, stop)
    # The same curve evaluated at the same overlap: the same bits (a few ulps allowed).
    assert np.max(np.abs(np.array(tops) - phi_top)) <= 4.0 * math.ulp(phi_top)
    assert abs(work) <= 1e-13 * scale
    assert branch.anchor == (first, float(phi_compression(first, stop)))
    # The vectorised evaluation (a response's samples) reads the same curve.
    grid = np.linspace(bottom, top, 7)
    fields = (branch.loading, branch.delta_r, branch.phi_r)
    assert np.array_equal(force_on_branches(grid, *fields, stop, *branch.anchor),
                          contact_force(grid, branch, stop))


def test_passive_law_response_closes_the_balance_and_never_loses_less():
    """A whole response with the passive law: the energy balance closes to the integration
    tolerance and stop_loss never falls."""
    osc = Oscillator(0.3, 0.2, 0.1)
    stop = HystereticStop(0.25, 1000.0, 500.0, limit_overlap=1e-3, beta_c=10.0, beta_e=10.0,
                          law="passive")
    res = simulate_hysteretic(osc, stop, 20.0, 0.0, 0.0)
    e = res.energy
    balance = np.abs(e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss
                                                       - e.stop_stored)).max()
    assert balance < 1e-8  # rtol 1e-9 on O(0.01) energies, a few contacts
    assert np.diff(e.stop_loss).min() >= -1e-12
    assert res.info["law"] == "passive"


def test_law_is_validated():
    with pytest.raises(ValueError, match="law must be one of 'paper', 'passive'"):
        HystereticStop(0.1, law="elastic")


def test_passive_loops_on_the_stop_repeat():
    """A mass pressed on a passive stop ends in loops that retrace their curve, a
    sustained oscillation (the paper's reading shrinks towards rest instead). Once they
    retrace one curve their last cycle is repeated from a 'reduced' transition, with its
    error stated (core/deformable/oscillation.py, repeat_retracing); the repeated cycles
    close the balance as the followed ones did."""
    osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=0.25, u_s=2.0)
    kw = dict(k_c0=400.0, k_e0=200.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
    res = simulate_hysteretic(osc, HystereticStop(0.42, law="passive", **kw), 80.0, 0.0, 0.0,
                              rtol=1e-8, atol=1e-11)
    assert res.steady.kind.value == "periodic"
    assert res.steady.sequence == ("reversal", "reversal")
    assert any(tr.kind.value == "reduced" for tr in res.transitions)
    assert 0.0 < res.info["reduced_error"] <= 1e-5 * res.info["length_scale"]
    e = res.energy
    balance = np.abs(e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss
                                                       - e.stop_stored)).max()
    assert balance < 1e-7  # rtol 1e-8 on O(0.1) energies
    assert np.diff(e.stop_loss).min() >= -1e-12
