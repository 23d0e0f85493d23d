"""The exact solver (no stop, rigid stop) against an independent 40-digit solution, on the
edges of its geometry.

Random scenes are drawn where rounding decides the most: starts within 1e-16..1e-12 of the
belt speed, belts down to 1e-16 a, clearances 1e-12..1e-4 from a, b, x* = a + v sqrt(1 - r^2),
2a and the impactless amplitude a + sqrt((b - a)^2 + v^2) (docs/physics.md), starts a
hair below the stop, mu_s equal to or barely above mu_k, r in {0, 1 - 1e-9, 1} and horizons
up to 1e5. The reference is :mod:`tests.core.mp_reference`: the same physics written
independently with mpmath at 40 digits.

What is compared, while the reference calls every decision before it conditioned (margins
larger than the rounding the float solution carries, see mp_reference):

* the transition sequence (kinds), and each transition's time to 1e-10 relative (an event
  time is a sum of phases each rounded to ~1e-15; 1e-10 leaves room for a few hundred
  events) plus the slack the reference states for it: rounding an ulp of a position is
  amplified by a stick, which takes (b - x0) / v, and by an event near a tangency, which
  moves by ~eps S / (h R) (mp_reference.ROUNDING);
* positions and speeds at the transitions to 1e-10 of the length scale (they are points
  of the geometry, which the slack in time does not move);
* the state at ``t_end`` and ``x_max`` to 1e-10 of the length scale, plus the slack in time
  times the speed (< 2 scale), plus, over a tiled periodic state, the drift of its period:
  the period is a difference of two event times below ~1e3, each rounded to ~1e-13, so
  ``n`` periods later the phase is off by ``n * 1e-13`` at most.

When the reference stops at its event cap (impact sequences with r = 1 - 1e-9) the state is
compared between its last two transitions instead of at ``t_end``.
"""

from __future__ import annotations

import math

import mpmath as mp
from hypothesis import example, given
from hypothesis import strategies as st

from core import Oscillator, RigidStop, simulate
from tests.core.mp_reference import DIGITS, MpReference

#: Transitions compared per scene.
CAP = 40
#: Relative tolerance of times, and of states against the length scale (see the docstring).
RTOL = 1e-10
#: Rounding of one period of a tiled cycle (see the docstring), per period.
PERIOD_DRIFT = 1e-13


def _tiny(lo: float, hi: float):
    """Magnitudes spread evenly over the decades ``10**lo .. 10**hi``."""
    return st.floats(lo, hi).map(lambda e: 10.0**e)


def _moderate(lo: float, hi: float):
    """Floats in ``[lo, hi]`` that are zero or at least 1e-6 in size: hypothesis likes
    subnormals, and a start or stop 1e-300 from another point is beyond 40 digits (the
    edges that matter are drawn on purpose, by :func:`_tiny`)."""
    return st.floats(lo, hi).filter(lambda f: f == 0.0 or abs(f) > 1e-6)


def _signed_tiny(lo: float, hi: float):
    return st.tuples(st.sampled_from([-1.0, 1.0]), _tiny(lo, hi)).map(lambda p: p[0] * p[1])


@st.composite
def scenes(draw):
    a = draw(st.floats(0.05, 1.0))
    b = a * (1.0 + draw(st.one_of(st.just(0.0), _tiny(-12, -4), st.floats(0.01, 1.0))))
    v = a * draw(st.one_of(
        st.floats(0.05, 2.0),                       # slow and fast belts
        _tiny(-16, -12),                            # a belt that barely moves
        _signed_tiny(-12, -4).map(lambda e: 1.0 + e),  # next to the critical speed a
    ))
    osc = Oscillator(mu_s=b, mu_k=a, belt_speed=v)
    a, b, v = osc.a, osc.b, osc.v
    r = draw(st.sampled_from([0.0, 1.0 - 1e-9, 1.0]))
    stop = None
    if draw(st.booleans()):
        anchors = [a, b, a + v * math.sqrt(1.0 - r * r), 2.0 * a, a + math.hypot(b - a, v)]
        anchor = draw(st.sampled_from(anchors))
        xb = draw(st.one_of(
            _signed_tiny(-12, -4).map(lambda e: anchor * (1.0 + e)),
            _moderate(-0.5, 2.0).map(lambda f: f * a),
        ))
        stop = RigidStop(xb, r)
    top = stop.clearance if stop is not None else 2.0 * b
    kind = draw(st.sampled_from(["rest", "belt", "stop", "any"]))
    # Speeds of 1e-6 a and more, or none: a speed below ~eps a is rest to the float solution
    # (its square vanishes beside a^2), and an arc of that speed escapes 40 digits too.
    speeds = st.one_of(st.just(0.0), _signed_tiny(-6, 0))
    if kind == "belt":  # next to the stick line, on either side
        x0 = draw(_moderate(-1.5, 1.5)) * b
        v0 = v * (1.0 + draw(_signed_tiny(-16, -12)))
    elif kind == "stop" and stop is not None:  # a hair below the stop
        x0 = top - draw(_tiny(-16, -6)) * max(abs(top), a)
        v0 = draw(speeds) * a
    elif kind == "any":
        x0 = draw(_moderate(-1.5, 1.5)) * b
        v0 = draw(speeds) * a
    else:
        x0 = v0 = 0.0
    x0 = min(x0, top)
    t_end = draw(st.one_of(st.sampled_from([30.0, 1e3, 1e5]), st.floats(10.0, 1e5)))
    return osc, stop, x0, v0, t_end


def _close(value: float, reference, tol: float) -> bool:
    return abs(value - float(reference)) <= tol


def _compare_transitions(res, ref, sol, t_end):
    """Kinds, times and states of the transitions the reference calls conditioned."""
    expected = sol.tiled(CAP, t_end)
    got = res.transitions[:CAP]
    n = min(len(expected), sol.conditioned_until)
    complete = sol.t_stop == mp.inf and n == len(expected)
    if complete:
        assert len(got) == n, (got, expected)
    assert len(got) >= n, (got, expected)
    for tr, (kind, t, x, v, slack) in zip(got[:n], expected[:n], strict=True):
        assert tr.kind.value == kind, (tr, kind, float(t))
        assert _close(tr.t, t, RTOL * max(1.0, float(t)) + float(slack)), (tr, float(t))
        assert _close(tr.x, x, RTOL * float(ref.scale)), (tr, float(x))
        assert _close(tr.v, v, RTOL * float(ref.scale)), (tr, float(v))
    return complete


def _compare_state(res, sol, ref, t, side):
    x, v = res.evaluate(t, side)
    x_ref, v_ref = sol.state(t)
    drift = 0.0
    if sol.period is not None:
        drift = PERIOD_DRIFT * float(t / sol.period)
    # A motion late by its slack in time is off by that times its speed (< 2 scale).
    tol = (RTOL + drift + 2.0 * float(sol.slack_at(t))) * float(ref.scale)
    assert _close(float(x), x_ref, tol), (float(x), float(x_ref), t)
    assert _close(float(v), v_ref, tol), (float(v), float(v_ref), t)


@given(scenes())
@example((Oscillator(0.3, 0.2, 0.1), None, 0.0, 0.1 * (1.0 - 1e-13), 20.0))
@example((Oscillator(0.3, 0.2, 2e-14), RigidStop(0.25, 0.5), 0.0, 0.0, 20.0))
@example((Oscillator(0.3, 0.2, 0.15), RigidStop(0.2 - 5.6e-9, 1.0), 0.0, 0.0, 1e4))
@example((Oscillator(0.2 * (1 + 1e-7), 0.2, 0.1), None, 0.0, 0.0, 1e4))
# found by a random search: a start 1e-13 below the belt speed slipped round a circle
@example((Oscillator(1.0, 1.0, 1.0), None, 0.0, 0.9999999999999, 30.0))
def test_exact_solver_matches_a_40_digit_reference(scene):
    osc, stop, x0, v0, t_end = scene
    xb = stop.clearance if stop is not None else None
    r = stop.restitution if stop is not None else 1.0
    ref = MpReference(osc.a, osc.b, osc.v, xb, r, x0, v0, t_end)
    sol = ref.sol
    res = simulate(osc, stop, t_end, x0=x0, v0=v0, t_eval=[t_end], transition_cap=CAP)
    complete = _compare_transitions(res, ref, sol, t_end)
    if sol.conditioned_until != math.inf:
        return  # a decision within rounding: what follows may rightly differ
    if sol.t_stop != mp.inf:  # the event cap: between the last two transitions
        with mp.workdps(DIGITS):
            t_mid = (sol.transitions[-2][1] + sol.transitions[-1][1]) / 2
        _compare_state(res, sol, ref, float(t_mid), side=1)
        return
    _compare_state(res, sol, ref, t_end, side=-1)
    if complete:
        x_max = sol.x_max(t_end)
        assert _close(res.x_max, x_max, RTOL * float(ref.scale)), (res.x_max, float(x_max))
