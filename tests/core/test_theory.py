"""Closed-form results of core.theory (paper Secs. 3-4, Eqs. 21-37, A.1-A.12).

Three kinds of checks:

* geometry: every steady point lies where the model puts it (slip circles about
  ``(a, 0)``, the stick line ``x' = v``, Newton's impact law);
* continuity: the closed forms of neighbouring cases agree on the case boundaries;
* an independent simulation: the non-smooth equations integrated here with
  ``scipy.integrate.solve_ivp`` and events, sharing no code with core.theory.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp

from core.params import HystereticStop, Oscillator, RigidStop
from core.result import SteadyKind, TransitionKind
from core.theory import (
    LimitCycle,
    Prediction,
    Regime,
    accumulation_time,
    classify,
    classify_grid,
    critical_speed,
    first_stick_point,
    gamma0_radius,
    impact_sequence,
    impactless_limit_cycle,
    is_fast_belt,
    steady_points,
    steady_prediction,
    x_max_impactless,
    x_star,
)

#: Closed forms agree with each other to rounding: a few hundred ulps of O(1) numbers.
EXACT = 1e-12
#: Gap used to approach a case boundary from one side; the closed forms are continuous
#: (Lipschitz or square-root) there, so the two sides differ by at most ~sqrt(gap).
GAP = 1e-12
BOUNDARY_TOL = 1e-5

#: The reference scene: a = 0.2, b = 0.3; v = 0.1 is a slow belt, v = 0.25 a fast one.
SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
FAST = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.25)
#: Slow belt with mu_s close to mu_k, so that x* > b for moderate r.
NARROW = Oscillator(mu_s=0.22, mu_k=0.2, belt_speed=0.1)
#: Belt at rest; and no kinetic friction, where the natural start is the slip centre.
STILL = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.0)
FRICTIONLESS = Oscillator(mu_s=0.3, mu_k=0.0, belt_speed=0.1)

STEADY_KINDS = {k.value for k in SteadyKind}
TRANSITION_KINDS = {k.value for k in TransitionKind}


# ---------------------------------------------------------------- strategies


@st.composite
def slow_scenes(draw, elastic: bool | None = None):
    """Slow belt (natural start), a stop that is hit, restitution in [0, 1]."""
    mu_k = draw(st.floats(0.05, 0.5))
    mu_s = mu_k + draw(st.floats(0.0, 0.3))
    v = draw(st.floats(0.01, 1.0)) * mu_k  # v <= a = v*: slow
    osc = Oscillator(mu_s=mu_s, mu_k=mu_k, belt_speed=v)
    x_max = impactless_limit_cycle(osc).x_max
    x_bar = draw(st.floats(0.0, 1.0, exclude_max=True)) * x_max
    if elastic is None:
        r = draw(st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 1.0)))
    else:
        r = 1.0 if elastic else draw(st.floats(0.0, 0.999))
    return osc, RigidStop(clearance=x_bar, restitution=r)


@st.composite
def fast_scenes(draw):
    mu_k = draw(st.floats(0.05, 0.5))
    mu_s = mu_k + draw(st.floats(0.0, 0.3))
    v = mu_k * (1.0 + draw(st.floats(0.01, 2.0)))  # v > a = v*: fast
    osc = Oscillator(mu_s=mu_s, mu_k=mu_k, belt_speed=v)
    x_bar = draw(st.floats(0.0, 1.0, exclude_max=True)) * 2.0 * osc.a
    r = draw(st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 1.0)))
    return osc, RigidStop(clearance=x_bar, restitution=r)


def radius2(osc: Oscillator, p: tuple[float, float]) -> float:
    """Squared radius of the slip circle about (a, 0) through p."""
    return (p[0] - osc.a) ** 2 + p[1] ** 2


# ---------------------------------------------------------------- impactless (Sec. 3)


def test_critical_speed_and_belt_split():
    assert critical_speed(SLOW) == pytest.approx(SLOW.a, abs=EXACT)  # natural start: v* = a
    assert critical_speed(SLOW, 0.5, -0.3) == pytest.approx(math.hypot(0.3, 0.3), abs=EXACT)
    assert not is_fast_belt(SLOW) and is_fast_belt(FAST)
    # v = v* is slow: the circle touches the stick line and the mass sticks.
    assert not is_fast_belt(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.2))
    assert gamma0_radius(FAST) == FAST.v


def test_limit_cycle_geometry():
    lc = impactless_limit_cycle(SLOW)
    assert isinstance(lc, LimitCycle)
    a, b, v = SLOW.a, SLOW.b, SLOW.v
    assert lc.centre == (a, 0.0)
    assert lc.stick_start == pytest.approx((2 * a - b, v), abs=EXACT)
    assert lc.stick_end == (b, v)
    # Both ends of the stick segment lie on the slip circle (Eq. 23).
    for p in (lc.stick_start, lc.stick_end):
        assert radius2(SLOW, p) == pytest.approx(lc.radius**2, abs=EXACT)
    assert lc.x_max == pytest.approx(a + math.hypot(b - a, v), abs=EXACT)
    assert lc.stick_time == pytest.approx(2 * (b - a) / v, abs=EXACT)
    assert lc.period == pytest.approx(lc.stick_time + lc.slip_time, abs=EXACT)
    assert math.pi < lc.slip_time < 2 * math.pi


def test_limit_cycle_degenerate_cases():
    equal = impactless_limit_cycle(Oscillator(mu_s=0.2, mu_k=0.2, belt_speed=0.1))
    assert equal.stick_time == 0.0
    assert equal.period == pytest.approx(2 * math.pi, abs=EXACT)  # a full slip circle
    still = impactless_limit_cycle(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.0))
    assert still.period == math.inf
    assert still.slip_time == pytest.approx(math.pi, abs=EXACT)


@given(mu_k=st.floats(0.01, 1.0), frac=st.floats(0.0, 1.0))
def test_first_stick_point_is_the_first_intersection(mu_k, frac):
    osc = Oscillator(mu_s=mu_k, mu_k=mu_k, belt_speed=frac * mu_k)
    x, xd = first_stick_point(osc)
    a = osc.a
    assert xd == osc.v
    assert radius2(osc, (x, xd)) == pytest.approx(a * a, rel=1e-12, abs=1e-15)
    # Clockwise from the origin the motion climbs the left half (x <= a) first: the minus
    # root of Eq. (30). The printed plus root lies on the right half.
    assert 0.0 <= x <= a * (1 + 1e-15)


def test_first_stick_point_none_for_fast_belt():
    assert first_stick_point(FAST) is None


def test_x_max_jumps_at_the_critical_speed_unless_mu_s_equals_mu_k():
    a, b = 0.2, 0.3
    below = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=a)  # v = v*: slow, limit cycle
    above = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=a * (1 + GAP))
    jump = x_max_impactless(below) - x_max_impactless(above)
    # Sec. 3.2 (b)-(c): a + sqrt((b-a)^2 + v*^2) against a + v*.
    assert jump == pytest.approx(math.hypot(b - a, a) - a, abs=1e-9)
    eq_below = Oscillator(mu_s=0.2, mu_k=0.2, belt_speed=a)
    eq_above = Oscillator(mu_s=0.2, mu_k=0.2, belt_speed=a * (1 + GAP))
    assert x_max_impactless(eq_below) == pytest.approx(x_max_impactless(eq_above), abs=1e-9)


def test_x_max_on_a_still_belt_is_the_rest_position():
    osc = Oscillator(mu_s=0.3, mu_k=0.1, belt_speed=0.0)
    assert x_max_impactless(osc) == 0.0
    # From x0 = 1 at rest: swings to 2a - 1 = -0.8, then -2a + 0.8 = 0.6, ... until |x| <= b.
    assert x_max_impactless(osc, 1.0, 0.0) == pytest.approx(0.2, abs=EXACT)


# ---------------------------------------------------------------- x* (Eq. 35)


@given(scene=slow_scenes(elastic=False))
def test_x_star_is_where_the_rebound_circle_touches_the_stick_line(scene):
    osc, stop = scene
    xs = x_star(osc, stop.restitution)
    # After a stick->impact at speed v the rebound circle through (x*, -r v) has radius v.
    assert radius2(osc, (xs, stop.restitution * osc.v)) == pytest.approx(
        osc.v**2, rel=1e-12, abs=1e-15
    )


def test_x_star_limits():
    assert x_star(SLOW, 1.0) == SLOW.a  # the elastic case b/c boundary (Eqs. 32-33)
    assert x_star(SLOW, 0.0) == pytest.approx(SLOW.a + SLOW.v, abs=EXACT)
    with pytest.raises(ValueError, match="restitution"):
        x_star(SLOW, 1.5)


# ---------------------------------------------------------------- classify


# (osc, x_bar, r) -> (belt, impact, case, expected_steady)
REGIMES = [
    (SLOW, None, None, ("slow", "none", None, "periodic")),
    (SLOW, 0.5, 0.5, ("slow", "none", None, "periodic")),
    (FAST, None, None, ("fast", "none", None, "pure_slip")),
    (FAST, 0.45, 1.0, ("fast", "none", None, "pure_slip")),
    (FAST, 0.30, 1.0, ("fast", "elastic", None, "periodic")),
    (FAST, 0.15, 1.0, ("fast", "elastic", None, "periodic")),
    (FAST, 0.30, 0.5, ("fast", "inelastic", None, "grazing")),
    (FAST, 0.15, 0.5, ("fast", "inelastic", None, "rest")),
    (FAST, 0.30, 0.0, ("fast", "plastic", None, "grazing")),
    (FAST, 0.15, 0.0, ("fast", "plastic", None, "rest")),
    (SLOW, 0.32, 1.0, ("slow", "elastic", "a", "periodic")),
    (SLOW, 0.25, 1.0, ("slow", "elastic", "b", "periodic")),
    (SLOW, 0.15, 1.0, ("slow", "elastic", "c", "periodic")),
    (SLOW, 0.05, 1.0, ("slow", "elastic", "c", "periodic")),  # Fig. 5d: x_bar < 2a - b
    (SLOW, 0.02, 1.0, ("slow", "elastic", "c", "periodic")),  # hit before the first stick
    (SLOW, 0.32, 0.6, ("slow", "inelastic", "a", "periodic")),
    (SLOW, 0.29, 0.6, ("slow", "inelastic", "b", "periodic")),  # x* = 0.28
    (SLOW, 0.275, 0.6, ("slow", "inelastic", "c", "grazing")),
    (SLOW, 0.15, 0.6, ("slow", "inelastic", "c", "rest")),
    (SLOW, 0.02, 0.6, ("slow", "inelastic", "c", "rest")),
    (SLOW, 0.32, 0.0, ("slow", "plastic", "a", "periodic")),
    (SLOW, 0.25, 0.0, ("slow", "plastic", "c", "grazing")),  # x* = a + v = b
    (SLOW, 0.15, 0.0, ("slow", "plastic", "c", "rest")),
    (NARROW, 0.25, 0.5, ("slow", "inelastic", "a", "grazing")),  # x* = 0.287 > b
    (NARROW, 0.30, 0.5, ("slow", "inelastic", "a", "periodic")),
    (NARROW, 0.21, 0.5, ("slow", "inelastic", "c", "grazing")),
    (STILL, 0.1, 0.5, ("slow", "none", None, "equilibrium")),
    (FRICTIONLESS, 0.1, 0.5, ("fast", "none", None, "equilibrium")),
]


@pytest.mark.parametrize(("osc", "x_bar", "r", "expected"), REGIMES)
def test_classify_grid(osc, x_bar, r, expected):
    stop = None if x_bar is None else RigidStop(clearance=x_bar, restitution=r)
    reg = classify(osc, stop)
    assert isinstance(reg, Regime)
    assert (reg.belt, reg.impact, reg.case, reg.expected_steady) == expected
    assert reg.impactless == (expected[1] == "none")
    assert "Sec." in reg.description
    pred = steady_prediction(osc, stop)
    assert pred.kind == reg.expected_steady


def test_classify_description_names_case_and_figure():
    reg = classify(SLOW, RigidStop(clearance=0.29, restitution=0.6))
    assert reg.description.startswith("Slow belt, inelastic impact, case b (x* <= x_bar < b)")
    assert "Sec. 4.4, Fig. 7b" in reg.description
    assert "Fig. 5d" in classify(SLOW, RigidStop(clearance=0.05)).description
    assert "Fig. 4b" in classify(FAST, RigidStop(clearance=0.15)).description


def test_classify_general_start_sets_the_fast_circle():
    # From (0.2, 0.1) the fast circle has radius 0.1 < v: x_max = 0.3, so a stop at 0.35
    # is never reached although it lies below the natural 2a = 0.4.
    reg = classify(FAST, RigidStop(clearance=0.35), x0=0.2, v0=0.1)
    assert reg.impactless and reg.expected_steady == "pure_slip"
    assert classify(FAST, RigidStop(clearance=0.25), x0=0.2, v0=0.1).impact == "elastic"
    assert classify(FAST, None, x0=FAST.a).expected_steady == "equilibrium"


def test_classify_rejects_bad_input():
    with pytest.raises(ValueError, match="ahead of the start"):
        classify(SLOW, RigidStop(clearance=-0.1))
    with pytest.raises(TypeError, match="equivalent_restitution"):
        classify(SLOW, HystereticStop(clearance=0.2))
    with pytest.raises(ValueError, match="x0"):
        classify(SLOW, None, x0=math.nan)


@given(scene=st.one_of(slow_scenes(), fast_scenes()))
def test_classify_is_total_and_consistent(scene):
    osc, stop = scene
    reg = classify(osc, stop)
    pred = steady_prediction(osc, stop)
    assert reg.expected_steady in STEADY_KINDS - {"none"}
    assert pred.kind == reg.expected_steady
    assert set(pred.sequence) <= TRANSITION_KINDS
    assert reg.case in (None, "a", "b", "c")
    assert (reg.case is None) == (reg.belt == "fast" or reg.impactless)
    if reg.expected_steady == "periodic":
        assert 0.0 < pred.period < math.inf
        assert pred.sequence
    else:
        assert math.isnan(pred.period)
    if not reg.impactless:
        assert pred.x_max == stop.clearance
    if reg.case == "a":
        assert stop.clearance >= osc.b
    if reg.case == "b":
        assert x_star(osc, stop.restitution) <= stop.clearance < osc.b
    if reg.expected_steady == "rest":
        assert stop.clearance <= osc.a
    if reg.expected_steady == "grazing":
        assert stop.clearance >= osc.a and stop.restitution < 1.0


# ---------------------------------------------------------------- steady points (A.1-A.12)


@given(scene=st.one_of(slow_scenes(), fast_scenes()))
def test_steady_points_lie_on_circles_lines_and_obey_the_impact_law(scene):
    osc, stop = scene
    pts = steady_points(osc, stop)
    b, v, x_bar, r = osc.b, osc.v, stop.clearance, stop.restitution
    tol = dict(rel=1e-9, abs=1e-13)
    if "P_impact_in" in pts:
        (xi, wi), (xo, wo) = pts["P_impact_in"], pts["P_impact_out"]
        assert xi == xo == x_bar
        assert wi > 0.0
        assert wo == pytest.approx(-r * wi, **tol)
    for key in ("P_stick_start", "P_stick_end"):
        if key in pts:
            x, xd = pts[key]
            assert xd == v
            assert -b <= x <= b
    if "P_stick_start" in pts and "P_impact_out" in pts:
        # The rebound slip arc runs on one circle about (a, 0) from the impact to the stick.
        assert radius2(osc, pts["P_stick_start"]) == pytest.approx(
            radius2(osc, pts["P_impact_out"]), **tol
        )
        assert pts["P_stick_start"][0] <= pts["P_stick_end"][0]
    if classify(osc, stop).case == "a" and "P_impact_in" in pts:
        # The incoming arc of the periodic case a is the limit cycle's (A.2, A.7).
        lc = impactless_limit_cycle(osc)
        assert radius2(osc, pts["P_impact_in"]) == pytest.approx(lc.radius**2, **tol)
        assert pts["P_stick_end"] == (b, v)
    if "P_limit" in pts:
        assert pts["P_limit"] == (x_bar, 0.0)
    if not pts:
        assert classify(osc, stop).expected_steady in ("pure_slip", "equilibrium")


def test_steady_points_match_appendix():
    a, b, v = SLOW.a, SLOW.b, SLOW.v
    # A.1: fast elastic impact at (x_bar, +-sqrt(x_bar (2a - x_bar))).
    p = steady_points(FAST, RigidStop(clearance=0.3))
    assert p["P_impact_in"] == pytest.approx((0.3, math.sqrt(0.3 * 0.1)), abs=EXACT)
    # A.3-A.4: elastic case b, stick from 2a - x_bar.
    p = steady_points(SLOW, RigidStop(clearance=0.25))
    assert p["P_stick_start"] == pytest.approx((2 * a - 0.25, v), abs=EXACT)
    assert p["P_impact_out"] == pytest.approx((0.25, -v), abs=EXACT)
    # A.10-A.11: inelastic case b.
    r, x_bar = 0.6, 0.29
    p = steady_points(SLOW, RigidStop(clearance=x_bar, restitution=r))
    onset = a - math.sqrt((x_bar - a) ** 2 - v**2 * (1 - r**2))
    assert p["P_stick_start"] == pytest.approx((onset, v), abs=EXACT)
    assert p["P_impact_out"] == pytest.approx((x_bar, -r * v), abs=EXACT)
    # A.7-A.9 (A.9 rederived with the case a impact speed w).
    x_bar = 0.32
    w = math.sqrt(v**2 + (b - a) ** 2 - (x_bar - a) ** 2)
    p = steady_points(SLOW, RigidStop(clearance=x_bar, restitution=r))
    assert p["P_impact_in"] == pytest.approx((x_bar, w), abs=EXACT)
    assert p["P_impact_out"] == pytest.approx((x_bar, -r * w), abs=EXACT)
    onset = a - math.sqrt((x_bar - a) ** 2 + r**2 * w**2 - v**2)
    assert p["P_stick_start"] == pytest.approx((onset, v), abs=EXACT)
    # A.12: limit point.
    assert steady_points(SLOW, RigidStop(0.275, 0.6)) == {"P_limit": (0.275, 0.0)}
    assert steady_points(FAST, None) == {}


# ---------------------------------------------------------------- continuity at boundaries


def _pred(osc, x_bar, r):
    return steady_prediction(osc, RigidStop(clearance=x_bar, restitution=r))


@pytest.mark.parametrize("r", [1.0, 0.8, 0.2])
def test_case_a_meets_case_b_at_b(r):
    b = SLOW.b
    lo, hi = _pred(SLOW, b * (1 - GAP), r), _pred(SLOW, b, r)
    assert classify(SLOW, RigidStop(b * (1 - GAP), r)).case in ("b", "c")
    assert classify(SLOW, RigidStop(b, r)).case == "a"
    assert lo.kind == hi.kind
    if hi.kind == "periodic":
        assert lo.period == pytest.approx(hi.period, abs=BOUNDARY_TOL)
        assert lo.impact_speed == pytest.approx(hi.impact_speed, abs=BOUNDARY_TOL)
        p_lo = steady_points(SLOW, RigidStop(b * (1 - GAP), r))
        p_hi = steady_points(SLOW, RigidStop(b, r))
        for key in ("P_stick_start", "P_impact_in", "P_impact_out", "P_stick_end"):
            assert p_lo[key] == pytest.approx(p_hi[key], abs=BOUNDARY_TOL)


@pytest.mark.parametrize("r", [1.0, 0.6, 0.0])
def test_case_a_meets_the_limit_cycle_at_x_max(r):
    lc = impactless_limit_cycle(SLOW)
    inside = _pred(SLOW, lc.x_max * (1 - GAP), r)
    assert inside.kind == "periodic"
    assert inside.period == pytest.approx(lc.period, abs=BOUNDARY_TOL)
    assert inside.impact_speed == pytest.approx(0.0, abs=BOUNDARY_TOL)
    p = steady_points(SLOW, RigidStop(lc.x_max * (1 - GAP), r))
    assert p["P_stick_start"] == pytest.approx(lc.stick_start, abs=BOUNDARY_TOL)


@pytest.mark.parametrize("r", [0.9, 0.6, 0.2])
def test_case_b_stick_onset_tends_to_the_top_of_the_circle_at_x_star(r):
    xs = x_star(SLOW, r)
    p = steady_points(SLOW, RigidStop(xs, r))
    assert p["P_stick_start"] == pytest.approx((SLOW.a, SLOW.v), abs=BOUNDARY_TOL)
    assert classify(SLOW, RigidStop(xs * (1 - 1e-9), r)).expected_steady == "grazing"


def test_elastic_case_b_meets_case_c_at_a():
    a = SLOW.a
    assert _pred(SLOW, a, 1.0).period == pytest.approx(math.pi + 0.0, abs=EXACT)
    assert _pred(SLOW, a * (1 - GAP), 1.0).period == pytest.approx(math.pi, abs=BOUNDARY_TOL)


def test_elastic_case_c_meets_the_first_slip_circle():
    x1 = first_stick_point(SLOW)[0]
    above, below = _pred(SLOW, x1, 1.0), _pred(SLOW, x1 * (1 - GAP), 1.0)
    assert above.impact_speed == pytest.approx(below.impact_speed, abs=BOUNDARY_TOL)
    assert above.period == pytest.approx(below.period, abs=BOUNDARY_TOL)


def test_fast_elastic_period():
    a = FAST.a
    for x_bar in (0.05, 0.15, 0.2, 0.3, 0.39):
        pred = _pred(FAST, x_bar, 1.0)
        # Sec. 4.1 with the factor 2 the extracted text drops.
        assert pred.period == pytest.approx(2 * math.acos(1 - x_bar / a), abs=EXACT)
    assert _pred(FAST, 2 * a * (1 - GAP), 1.0).period == pytest.approx(2 * math.pi, abs=1e-5)
    assert steady_prediction(FAST, None).period == 2 * math.pi


def test_case_a_grazing_band_when_x_star_exceeds_b():
    a, b, v, r = NARROW.a, NARROW.b, NARROW.v, 0.5
    assert x_star(NARROW, r) > b
    # The rebound circle radius^2 = (x-a)^2 + r^2 (R_LC^2 - (x-a)^2) reaches v^2 at x_a.
    x_a = a + math.sqrt(v**2 - r**2 * (b - a) ** 2 / (1 - r**2))
    assert _pred(NARROW, x_a * (1 - 1e-9), r).kind == "grazing"
    above = steady_points(NARROW, RigidStop(x_a * (1 + 1e-12), r))
    assert above["P_stick_start"] == pytest.approx((a, v), abs=BOUNDARY_TOL)


# ---------------------------------------------------------------- impact sequences, Zeno


def test_impact_sequence():
    w0 = math.sqrt(0.15 * (2 * FAST.a - 0.15))  # A.5
    seq = impact_sequence(FAST, RigidStop(0.15, 0.5), 5)
    np.testing.assert_allclose(seq, w0 * 0.5 ** np.arange(5), rtol=EXACT)
    np.testing.assert_allclose(impact_sequence(SLOW, RigidStop(0.15, 0.6), 3), [0.1, 0.06, 0.036])
    assert impact_sequence(SLOW, RigidStop(0.25, 1.0), 4).tolist() == [0.1] * 4
    assert impact_sequence(SLOW, None, 4).size == 0
    with pytest.raises(ValueError, match="n must"):
        impact_sequence(SLOW, None, -1)


def _brute_force(w0, r, d):
    terms = []
    y = w0 / d
    while y > 1e-19:
        terms.append(2.0 * math.atan(y))
        y *= r
    return math.fsum(terms)


@pytest.mark.parametrize("r", [0.1, 0.5, 0.9, 0.99, 0.999])
@pytest.mark.parametrize("y0", [1e-3, 0.3, 0.7, 1.9, 2.1, 50.0, 1e4])
def test_accumulation_time_matches_the_plain_sum(r, y0):
    d = 0.05
    assert accumulation_time(y0 * d, r, d) == pytest.approx(_brute_force(y0 * d, r, d), rel=1e-13)


@pytest.mark.parametrize("y0", [0.2, 3.0, 1e3])
def test_accumulation_time_near_elastic_is_finite_fast_and_right(y0):
    r = 0.999999
    lam = -math.log(r)
    t0 = time.perf_counter()
    total = accumulation_time(y0, r, 1.0)
    assert time.perf_counter() - t0 < 1.0
    # Euler-Maclaurin with f(h) = atan(y0 exp(-lam h)): the integral is Ti2(y0)/lam, the
    # first correction f(0)/2 - f'(0)/12; the next is O(lam^3), far below the tolerance.
    ti2, _ = quad(lambda u: math.atan(u) / u, 0.0, y0, epsabs=0.0, epsrel=1e-13, limit=200)
    estimate = 2.0 * (ti2 / lam + math.atan(y0) / 2 + lam * y0 / (12 * (1 + y0 * y0)))
    assert total == pytest.approx(estimate, rel=1e-11)


@pytest.mark.parametrize("r", [0.01, 0.5, 0.9])
def test_accumulation_time_with_a_subnormal_distance_is_the_plain_sum(r):
    # w0 / d overflows: the stop sits at the slip centre to within a subnormal distance.
    w0, d = 0.05, 5e-324
    log_y0 = math.log(w0) - math.log(d)
    terms, h = [], 0
    while (log_y := log_y0 + h * math.log(r)) > math.log(1e-19):
        # atan(y) = pi/2 - atan(1/y): the first ratios (~1e322) overflow exp.
        terms.append(math.pi - 2.0 * math.atan(math.exp(-log_y)) if log_y > 0
                     else 2.0 * math.atan(math.exp(log_y)))
        h += 1
    # Each term's ratio comes from exp(log y), relative error ~|log y| * eps ~ 2e-13, and
    # the large terms are all near pi, where atan is flat: the sums agree far closer.
    assert accumulation_time(w0, r, d) == pytest.approx(math.fsum(terms), rel=1e-12)


def test_classify_a_stop_at_the_slip_centre_to_a_subnormal_distance():
    regime = classify(Oscillator(mu_s=0.3, mu_k=0.0, belt_speed=0.05), RigidStop(-5e-324, 0.5),
                      x0=-1.0)
    assert regime.expected_steady == "rest"


def test_accumulation_time_edges():
    assert accumulation_time(0.0, 0.5, 1.0) == 0.0
    assert accumulation_time(1.0, 0.0, 1.0) == pytest.approx(math.pi / 2, abs=EXACT)
    assert accumulation_time(1.0, 1.0, 1.0) == math.inf
    with pytest.raises(ValueError, match="d = a - x_bar"):
        accumulation_time(1.0, 0.5, 0.0)


@given(w=st.floats(1e-6, 10.0), r=st.floats(0.0, 0.99), d=st.floats(1e-3, 1.0))
def test_accumulation_time_is_monotone(w, r, d):
    t = accumulation_time(w, r, d)
    assert 2 * math.atan(w / d) <= t * (1 + 1e-14)
    assert t <= accumulation_time(w * 1.5, r, d) * (1 + 1e-14)
    assume(r < 0.98)
    assert t <= accumulation_time(w, r + 0.01, d) * (1 + 1e-14)


def test_prediction_accumulation_time_for_rest():
    pred = _pred(SLOW, 0.15, 0.6)
    assert isinstance(pred, Prediction)
    assert pred.accumulation_time == pytest.approx(accumulation_time(0.06, 0.6, 0.05), abs=EXACT)
    assert math.isnan(_pred(SLOW, 0.25, 0.6).accumulation_time)


# ---------------------------------------------------------------- independent simulation


#: solve_ivp tolerances. The slip equations are linear with O(1) solutions of size ~0.3,
#: so DOP853 at rtol = 1e-11 keeps the local error ~1e-12; event times are then located to
#: about the same accuracy. Over the ~10-30 arcs simulated the errors add to ~1e-10, and
#: every stick phase resets the phase error. Comparisons use VERIFY_TOL, a hundred times
#: that, which still catches a wrong factor, sign or root in any closed form.
IVP_RTOL = 1e-11
IVP_ATOL = 1e-13
VERIFY_TOL = 1e-8


#: The elastic case c cycle returns to the stop exactly on the stick line (x_bar, v); a
#: slip->stick found within this distance of the stop is that tangency, and the impact is
#: what happens there. Event states are accurate to ~1e-12, far below it.
TIE = 1e-9


def _event(g, direction, terminal=True):
    def event(_t, y):
        return g(y)

    event.direction, event.terminal = direction, terminal
    return event


def simulate_reference(a, b, v, x_bar, r, n_transitions, max_step=math.inf):
    """Integrate x'' + x = s a (slip), x' = v (stick), x'(+) = -r x'(-) at x = x_bar.

    Natural initial conditions. Returns the transitions as (kind, t, x, x'_before) and the
    local maxima (t, x) in slip. Deliberately plain and independent of core. Events are
    found from sign changes between steps, so near-grazing arcs, which stay beyond the stop
    for a time of order ``2 w / (x_bar - a)``, need ``max_step`` below that.
    """
    t, x, xd = 0.0, 0.0, 0.0
    mode, s = "slip", 1.0
    out, peaks = [], []
    while len(out) < n_transitions:
        if mode == "stick":

            def rhs(_t, y):
                return [v, 0.0]

            events = [
                _event(lambda y: y[0] - x_bar, 1),  # stick -> impact
                _event(lambda y: y[0] - b, 1),  # stick -> slip
            ]
        else:

            def rhs(_t, y, s=s):
                return [y[1], s * a - y[0]]

            events = [
                _event(lambda y: y[0] - x_bar, 1),  # impact
                _event(lambda y: y[1] - v, s),  # relative velocity reaches zero
                _event(lambda y: y[1], -1, terminal=False),  # local maximum of x
            ]
        sol = solve_ivp(
            rhs,
            (t, t + 50.0),
            [x, xd],
            method="DOP853",
            rtol=IVP_RTOL,
            atol=IVP_ATOL,
            max_step=max_step,
            events=events,
        )
        if mode == "slip":
            peaks += [(te, ye[0]) for te, ye in zip(sol.t_events[2], sol.y_events[2], strict=True)]
        times = [sol.t_events[i][0] if sol.t_events[i].size else math.inf for i in range(2)]
        assert min(times) < math.inf, "no transition within 50 time units"
        i = 0 if times[0] <= times[1] else 1
        t = float(times[i])
        x, xd = (float(c) for c in sol.y_events[i][0])
        if i == 1 and mode == "slip" and x_bar - x < TIE:
            i = 0
        if i == 0:  # at the stop
            kind = "stick->impact" if mode == "stick" else "impact"
            xd = v if mode == "stick" else xd
            out.append((kind, t, x_bar, xd))
            x, xd, mode = x_bar, -r * xd, "slip"
            s = 1.0 if xd < v else -1.0
        elif mode == "stick":
            out.append(("stick->slip", t, x, v))
            xd, mode, s = v, "slip", 1.0
        elif abs(x) <= b:
            out.append(("slip->stick", t, x, v))
            xd, mode = v, "stick"
        else:
            xd, s = v, -s  # the relative velocity changes sign: slip about the other centre
    return out, peaks


def steady_from_reference(out, peaks, first_kind, n_kinds):
    """Period, x_max and impact speed over the last full period of the reference run."""
    starts = [tr for tr in out if tr[0] == first_kind]
    t0, t1 = starts[-2][1], starts[-1][1]
    last = [tr for tr in out if t0 <= tr[1] < t1]
    kinds = tuple(tr[0] for tr in last)
    assert len(kinds) == n_kinds
    xs = [tr[2] for tr in last] + [p[1] for p in peaks if t0 <= p[0] < t1]
    impacts = [tr[3] for tr in last if tr[0] in ("impact", "stick->impact")]
    return t1 - t0, max(xs), (impacts[-1] if impacts else math.nan), kinds


CHECKED_SCENES = [
    (SLOW, None, 1.0),  # limit cycle (Eqs. 23-24)
    (FAST, 0.30, 1.0),  # Sec. 4.1, Fig. 4a
    (FAST, 0.15, 1.0),  # Sec. 4.1, Fig. 4b
    (SLOW, 0.32, 1.0),  # case a elastic
    (SLOW, 0.25, 1.0),  # case b elastic
    (SLOW, 0.15, 1.0),  # case c elastic
    (SLOW, 0.02, 1.0),  # stop hit before the first stick
    (SLOW, 0.32, 0.6),  # case a inelastic (A.9 rederived)
    (SLOW, 0.29, 0.6),  # case b inelastic, just above x* = 0.28
    (SLOW, 0.33, 0.0),  # case a plastic
    (NARROW, 0.30, 0.5),  # case a above the grazing band
]


@pytest.mark.parametrize(("osc", "x_bar", "r"), CHECKED_SCENES)
def test_periodic_predictions_against_an_independent_integration(osc, x_bar, r):
    pred = steady_prediction(osc, None if x_bar is None else RigidStop(x_bar, r))
    assert pred.kind == "periodic"
    stop_at = math.inf if x_bar is None else x_bar
    out, peaks = simulate_reference(osc.a, osc.b, osc.v, stop_at, r, n_transitions=12)
    period, x_max, speed, kinds = steady_from_reference(
        out, peaks, pred.sequence[0], len(pred.sequence)
    )
    assert kinds == pred.sequence
    assert period == pytest.approx(pred.period, rel=VERIFY_TOL)
    assert x_max == pytest.approx(pred.x_max, abs=VERIFY_TOL)
    if x_bar is not None:
        assert speed == pytest.approx(pred.impact_speed, abs=VERIFY_TOL)


@pytest.mark.parametrize(
    ("osc", "x_bar", "r"),
    [(SLOW, 0.275, 0.6), (NARROW, 0.25, 0.5), (FAST, 0.3, 0.5), (FAST, 0.15, 0.5)],
)
def test_decaying_impacts_against_an_independent_integration(osc, x_bar, r):
    """Grazing and Zeno: no stick after the first impact, speeds r^h w0, arc times."""
    stop = RigidStop(x_bar, r)
    n = 6
    # The 6th grazing excursion beyond the stop lasts >= 0.05: steps of 1e-2 cannot skip it.
    out, _ = simulate_reference(osc.a, osc.b, osc.v, x_bar, r, n + 3, max_step=1e-2)
    impacts = [tr for tr in out if tr[0] in ("impact", "stick->impact")]
    first = out.index(impacts[0])
    assert all(tr[0] == "impact" for tr in out[first + 1 :])  # never sticks again
    speeds = np.array([tr[3] for tr in impacts[:n]])
    np.testing.assert_allclose(speeds, impact_sequence(osc, stop, n), rtol=1e-7, atol=1e-12)
    if x_bar < osc.a:  # Zeno: the h-th rebound arc lasts 2 atan(r^(h+1) w0 / (a - x_bar))
        times = np.array([tr[1] for tr in impacts[:n]])
        d, w0 = osc.a - x_bar, speeds[0]
        arcs = 2 * np.arctan(w0 * r ** np.arange(1, n) / d)
        np.testing.assert_allclose(np.diff(times), arcs, rtol=1e-7)
        pred = steady_prediction(osc, stop)
        assert pred.accumulation_time == pytest.approx(accumulation_time(r * w0, r, d), rel=1e-9)


def test_x_star_separates_periodic_from_grazing_in_the_integration():
    """Eq. (35) as rederived, x* = a + v sqrt(1 - r^2) = 0.28 here, not a + v/sqrt(1-r^2)."""
    r = 0.6
    xs = x_star(SLOW, r)
    for x_bar, sticks in ((xs + 0.003, True), (xs - 0.003, False)):
        out, _ = simulate_reference(SLOW.a, SLOW.b, SLOW.v, x_bar, r, n_transitions=6)
        after = [tr[0] for tr in out[out.index(next(t for t in out if "impact" in t[0])) :]]
        assert ("slip->stick" in after) == sticks


def _grid_draws(n: int):
    """Random frictions, restitutions and starts, with the edge values classify treats
    apart (r = 0 and 1, mu_s = mu_k, natural and other starts, no stop)."""
    rng = np.random.default_rng(7)
    for k in range(n):
        mu_s = rng.uniform(0.05, 0.6)
        mu_k = mu_s if k % 7 == 0 else rng.uniform(0.0, mu_s)
        u_s = rng.uniform(0.3, 2.0)
        r = (0.0, 1.0, rng.uniform(0.0, 1.0))[k % 3]
        x0, v0 = (0.0, 0.0) if k % 2 == 0 else (rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3))
        yield Oscillator(mu_s=mu_s, mu_k=mu_k, belt_speed=0.1, u_s=u_s), r, x0, v0, k % 11 == 0


def test_vectorised_classify_grid_agrees_with_classify_everywhere():
    """classify_grid answers what classify answers at every point: on random grids and
    exactly on the boundaries (x_max, the first stick point, b, x*, a and v*), where a
    formula evaluated differently would flip a point."""
    for osc, r, x0, v0, no_stop in _grid_draws(60):
        a, b = osc.a, osc.b
        vc = critical_speed(osc, x0, v0)
        rng = np.random.default_rng(int(1e6 * osc.mu_s))
        speeds = np.concatenate(([0.0, vc, a, 0.5 * vc], rng.uniform(0.0, 2.0 * vc + 0.05, 12)))
        bounds = [a, b, x0, 2 * a - b]
        for v in speeds[1:4]:
            o = Oscillator(mu_s=osc.mu_s, mu_k=osc.mu_k, belt_speed=float(v), u_s=osc.u_s)
            bounds += [x_max_impactless(o, x0, v0), x_star(o, r), a + float(v)]
            if v <= a:
                bounds.append(a - math.sqrt((a - v) * (a + v)))
        clearances = np.concatenate((bounds, rng.uniform(x0, x0 + 3.0 * (b + vc) + 0.1, 14)))
        stop = None if no_stop else RigidStop(clearance=1.0, restitution=r)
        grid = classify_grid(osc, stop, speeds, clearances, x0, v0)
        for j, v in enumerate(speeds.tolist()):
            o = Oscillator(mu_s=osc.mu_s, mu_k=osc.mu_k, belt_speed=v, u_s=osc.u_s)
            for i, x_bar in enumerate(clearances.tolist()):
                where = f"mu_s={osc.mu_s}, mu_k={osc.mu_k}, r={r}, x0={x0}, v={v}, x_bar={x_bar}"
                if stop is not None and x_bar < x0:
                    assert not grid.valid[i, j], where
                    with pytest.raises(ValueError):
                        classify(o, RigidStop(x_bar, r), x0, v0)
                    continue
                reg = classify(o, None if stop is None else RigidStop(x_bar, r), x0, v0)
                got = (grid.belt[i, j], grid.impact[i, j], grid.case[i, j] or None,
                       bool(grid.impactless[i, j]), grid.expected_steady[i, j])
                assert grid.valid[i, j], where
                assert got == (reg.belt, reg.impact, reg.case, reg.impactless,
                               reg.expected_steady), where


def test_classify_grid_rejects_bad_grids():
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    with pytest.raises(ValueError, match="belt_speed"):
        classify_grid(osc, RigidStop(0.3), [-0.1, 0.1], [0.3])
    with pytest.raises(ValueError, match="clearance"):
        classify_grid(osc, RigidStop(0.3), [0.1], [math.nan])
    with pytest.raises(TypeError, match="RigidStop"):
        classify_grid(osc, HystereticStop(clearance=0.3), [0.1], [0.3])


def test_classify_grid_agrees_to_the_last_bit_of_a_boundary():
    """Points one ulp either side of a boundary: a square computed as x ** 2 in one
    function and x * x in the other once flipped them (a fast belt at twice the critical
    speed hitting a stop at its start; the edge of case a's grazing band)."""
    cases = [  # (mu_s, mu_k, v, x0, r, x_bar)
        (1.5 * 0.13583893694860305, 0.13583893694860305, 2 * 0.13583893694860305, 0.0,
         1.0, 0.0),
        (0.3, 0.2, 1.0, -0.1861167882863629, 1.0, -0.1861167882863629),
    ]
    rng = np.random.default_rng(11)
    while len(cases) < 300:  # the clearance where case a's disc (Eq. A.9) is zero
        mu_s = rng.uniform(0.2, 0.6)
        mu_k = rng.uniform(0.5, 0.9) * mu_s
        a, b, r = mu_k, mu_s, rng.uniform(0.05, 0.6)
        v = rng.uniform(0.5, 0.95) * a
        t = v * v - (r * (b - a)) ** 2 / ((1 - r) * (1 + r))
        if t > 0 and a + math.sqrt(t) >= b:
            cases.append((mu_s, mu_k, v, 0.0, r, a + math.sqrt(t)))
    for mu_s, mu_k, v, x0, r, root in cases:
        xs = [root]
        for direction in (math.inf, -math.inf):
            x = root
            for _ in range(4):
                x = math.nextafter(x, direction)
                xs.append(x)
        xs = [x for x in xs if x >= x0]
        osc = Oscillator(mu_s=mu_s, mu_k=mu_k, belt_speed=v)
        grid = classify_grid(osc, RigidStop(1.0, r), [v], xs, x0, 0.0)
        for i, x in enumerate(xs):
            reg = classify(osc, RigidStop(x, r), x0, 0.0)
            assert grid.expected_steady[i, 0] == reg.expected_steady, (mu_s, mu_k, v, r, x)
            assert (grid.case[i, 0] or None) == reg.case, (mu_s, mu_k, v, r, x)
