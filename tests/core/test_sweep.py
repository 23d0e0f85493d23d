"""core.sweep: the vectorised closed form against core.simulate, point by point."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from core import HystereticStop, Oscillator, RigidStop, simulate
from core.flight import Motion, free_flight, start_motion
from core.result import Mode, SteadyKind, TransitionKind
from core.sweep import LABELS, closed_form, sweep, sweep_grid
from core.sweep.result import KIND_CODE, SweepResult
from core.sweep.scalar import cycle_rows
from core.theory import classify, classify_grid

#: Agreement asked of the sweep with simulate (relative to the scene's length scale). Both
#: evaluate the same closed forms; numpy's and math's transcendental functions differ by a
#: few ulps, which a transient of a few dozen events keeps far below this.
AGREE = 1e-9


def _scenes(rng: np.random.Generator):
    """Sweeps with random values spanning the paper's regimes: no stop (fast and slow belt),
    rigid stops that are elastic, inelastic and plastic, slow-belt cases a, b and c, Zeno
    rest, grazing and the fast-belt impact cycle."""
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    u = rng.uniform
    yield osc, None, "belt_speed", u(0.0, 0.5, 20)
    yield osc, None, "mu_s", u(0.2, 0.5, 10)
    for r in (1.0, 0.7, 0.0):
        # x_bar below a - sqrt(a^2 - v^2), between that and a, a..x*, x*..b, above b.
        yield osc, RigidStop(0.25, r), "clearance", u(0.005, 0.45, 25)
        yield osc, RigidStop(0.25, r), "belt_speed", u(0.01, 0.4, 20)
    yield osc, RigidStop(0.12, 0.6), "belt_speed", u(0.01, 0.4, 15)  # Zeno rest
    yield osc, RigidStop(0.26, 0.7), "restitution", u(0.0, 1.0, 15)
    yield Oscillator(mu_s=0.4, mu_k=0.15, belt_speed=0.05), RigidStop(0.3, 0.8), "mu_k", u(
        0.05, 0.4, 15
    )
    yield Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.08), RigidStop(0.28, 0.5), "u_s", u(
        0.5, 2.0, 15
    )


def _scene(osc, stop, name, value):
    if name in ("clearance", "restitution"):
        kw = {"clearance": stop.clearance, "restitution": stop.restitution, name: value}
        return osc, RigidStop(**kw)
    kw = {"mu_s": osc.mu_s, "mu_k": osc.mu_k, "belt_speed": osc.belt_speed, "u_s": osc.u_s}
    kw[name] = value
    if name == "mu_k":
        kw["mu_k"] = min(value, kw["mu_s"])
    return Oscillator(**kw), stop


def _assert_lane(res: SweepResult, i: int, ref, scale: float) -> None:
    steady = ref.steady
    assert LABELS[res.label[i]] == steady.kind.value
    assert res.transitions_per_period[i] == steady.transitions_per_period
    seq = " -> ".join(steady.sequence)
    assert res.regimes[res.regime[i]] == steady.kind.value + (": " + seq if seq else "")
    for mine, theirs in (
        (res.period[i], steady.period),
        (res.x_max[i], steady.x_max),
        (res.impact_speed[i], steady.impact_speed),
    ):
        assert math.isnan(mine) == math.isnan(theirs)
        if not math.isnan(theirs):
            assert abs(mine - theirs) <= AGREE * scale
    cycle = cycle_rows(ref)
    lo, hi = res.offsets[i], res.offsets[i + 1]
    assert hi - lo == len(cycle)
    for j, (kind, x, v, v_after, _) in enumerate(cycle):
        assert res.cycle_kind[lo + j] == kind
        assert abs(res.cycle_x[lo + j] - x) <= AGREE * scale
        assert abs(res.cycle_v[lo + j] - v) <= AGREE * scale
        assert abs(res.cycle_v_after[lo + j] - v_after) <= AGREE * scale


def test_sweep_agrees_with_simulate_across_the_regimes():
    rng = np.random.default_rng(18)
    seen = set()
    n_points = 0
    for osc, stop, name, values in _scenes(rng):
        if name == "mu_k":
            values = np.minimum(values, osc.mu_s)
        res = sweep(osc, stop, name, values, t_end=200.0)
        assert not res.fallback.any()
        for i, value in enumerate(values):
            o, s = _scene(osc, stop, name, float(value))
            ref = simulate(o, s, 200.0, transition_cap=100_000)
            scale = max(o.a, o.b, o.v, abs(s.clearance) if s else 0.0)
            _assert_lane(res, i, ref, scale)
            regime = classify(o, s)
            seen |= {regime.belt, regime.impact, f"case {regime.case}", regime.expected_steady}
            seen.add(ref.steady.kind.value)
            n_points += 1
    # The random points cover every regime the closed form has to get right.
    wanted = {
        "fast", "slow", "none", "elastic", "inelastic", "plastic", "case a", "case b", "case c",
        "periodic", "grazing", "rest", "pure_slip",
    }
    assert wanted <= seen, wanted - seen
    assert n_points > 200


def test_vectorised_free_flight_matches_the_scalar_one():
    rng = np.random.default_rng(7)
    n = 4000
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    x0 = rng.uniform(-0.6, 0.3, n)
    v0 = rng.uniform(-0.5, 0.5, n)
    mode = rng.choice([closed_form.SLIP, closed_form.STICK], n).astype(np.int8)
    x0 = np.where(mode == closed_form.STICK, rng.uniform(-0.3, 0.3, n), x0)
    v0 = np.where(mode == closed_form.STICK, osc.v, v0)
    s = rng.choice([-1, 1], n).astype(np.int8)
    barrier = np.where(rng.random(n) < 0.3, np.inf, 0.3)
    full = np.full(n, 1.0)
    t1, kind, x1, v1, xmax, tie = closed_form.free_flight(
        0.5 * full, x0, v0, mode, s, osc.a * full, osc.b * full, osc.v * full, barrier
    )
    assert not tie.any()  # random states are no near-ties
    for i in range(n):
        motion = Motion(Mode.STICK) if mode[i] == closed_form.STICK else Motion(Mode.SLIP, s[i])
        seg, ev = free_flight(osc, 0.5, x0[i], v0[i], motion, barrier[i])
        if ev is None:
            assert kind[i] == closed_form.ENDLESS
            continue
        assert kind[i] == KIND_CODE[ev.kind]
        # A few ulps of 2 pi: numpy's and math's atan2 round differently.
        assert t1[i] == pytest.approx(ev.t, rel=1e-14, abs=1e-14)
        # The states come from sums, products and square roots alike: bit for bit.
        assert x1[i] == ev.x
        assert v1[i] == ev.v
        cut = type(seg)(seg.mode, seg.t0, ev.t, seg.x0, seg.v0, seg.centre)
        assert xmax[i] == pytest.approx(cut.x_max(), abs=1e-14)


def test_vectorised_start_motion_matches_the_scalar_one():
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    x = np.array([0.0, 0.0, 0.0, 0.5, -0.5, 0.3])
    xd = np.array([0.0, 0.2, 0.1, 0.1, 0.1, 0.1])
    mode, s = closed_form.start_motion(x, xd, osc.v, osc.b)
    for i in range(len(x)):
        m = start_motion(osc, x[i], xd[i])
        assert mode[i] == (closed_form.STICK if m.mode is Mode.STICK else closed_form.SLIP)
        if m.mode is Mode.SLIP:
            assert s[i] == m.s


def test_lanes_past_the_history_fall_back_to_simulate_and_say_so(monkeypatch):
    # With room for only 3 transition states, a lane needs more to close its cycle: the
    # slow-belt cycles with an impact (4+ transitions before the repeat) fall back.
    monkeypatch.setattr(closed_form, "HISTORY", 3)
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    stop = RigidStop(0.25, 0.7)
    values = np.linspace(0.01, 0.4, 30)
    res = sweep(osc, stop, "belt_speed", values)
    assert res.fallback.any() and not res.fallback.all()
    for i, value in enumerate(values):
        o = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=float(value))
        _assert_lane(res, i, simulate(o, stop, 200.0, transition_cap=100_000), 0.4)


def test_grid_shape_labels_and_npz_round_trip(tmp_path):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    speeds, clearances = np.linspace(0.02, 0.3, 7), np.linspace(0.05, 0.5, 5)
    res = sweep_grid(osc, RigidStop(0.25, 0.7), {"belt_speed": speeds, "clearance": clearances})
    assert res.shape == (7, 5) and res.labels.shape == (7, 5)
    # Row-major: the last parameter varies fastest.
    o = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=float(speeds[2]))
    ref = simulate(o, RigidStop(float(clearances[3]), 0.7), 200.0)
    assert res.labels[2, 3] == ref.steady.kind.value
    path = tmp_path / "grid.npz"
    res.to_npz(path)
    back = SweepResult.from_npz(path)
    assert back.parameters == res.parameters and back.regimes == res.regimes
    assert np.array_equal(back.period, res.period, equal_nan=True)
    assert np.array_equal(back.cycle_x, res.cycle_x)
    assert np.array_equal(back.axes["clearance"], clearances)


def test_poincare_quantities_select_the_cycle_transitions():
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    res = sweep(osc, RigidStop(0.25, 0.7), "belt_speed", [0.05, 0.3], quantity="impact_speed")
    values, offsets = res.samples()
    for i, v in enumerate([0.05, 0.3]):
        ref = simulate(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=v), RigidStop(0.25, 0.7))
        impacts = [
            tr.v for tr in ref.transitions
            if tr.kind in (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
            and ref.steady.t_reached < tr.t <= ref.steady.t_reached + ref.steady.period * 1.0001
        ]
        if ref.steady.kind is SteadyKind.GRAZING:
            impacts = [0.0]
        np.testing.assert_allclose(values[offsets[i] : offsets[i + 1]], impacts, atol=1e-12)
    rebound, _ = res.samples("rebound_speed")
    np.testing.assert_allclose(rebound, 0.7 * values, atol=1e-15)
    x, stick_offsets = res.samples("stick_x")
    assert np.all(np.abs(x) <= osc.b)
    p, q = res.points("stick_x")
    assert len(p) == len(q) == stick_offsets[-1]


def test_a_deformable_stop_is_solved_point_by_point_with_force_peaks():
    stop = HystereticStop(
        clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.02, beta_c=40.0, beta_e=40.0
    )
    speeds = [0.05, 0.07]
    res = sweep(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1), stop, "belt_speed", speeds,
                t_end=60.0, quantity="force_peak")
    assert res.fallback.all()
    peaks, offsets = res.samples()
    for i, v in enumerate(speeds):
        osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=v)
        ref = simulate(osc, stop, 60.0)
        assert LABELS[res.label[i]] == ref.steady.kind.value
        assert np.array_equal(res.period[i], ref.steady.period, equal_nan=True)
    # v = 0.05 settles to a cycle with one contact: its peak is the largest force of a
    # steady contact in a run sampled 50,000 times (the peak, at the overlap's reversal,
    # is a sample of both runs, so they agree to rounding).
    assert LABELS[res.label[0]] == "periodic" and offsets[1] - offsets[0] == 1
    dense = simulate(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.05), stop, 60.0,
                     n_samples=50_000)
    t0 = dense.steady.t_reached  # the contact of the steady period the sweep read
    end = min(tr.t for tr in dense.transitions
              if tr.kind is TransitionKind.SEPARATION and tr.t > t0)
    began = max(tr.t for tr in dense.transitions
                if tr.kind is TransitionKind.CONTACT and tr.t < end)
    inside = (dense.t >= began) & (dense.t <= end)
    assert peaks[0] > 0.0
    assert dense.contact_force[inside].max() == pytest.approx(peaks[0], rel=1e-9)


@pytest.mark.parametrize(
    ("stop", "name", "values", "message"),
    [
        (None, "speed", [0.1], "parameter must be one of: belt_speed in"),
        (None, "clearance", [0.1], "needs a stop"),
        (HystereticStop(0.2), "restitution", [0.5], "needs a RigidStop"),
        (RigidStop(0.2), "restitution", [0.5, 1.5], r"restitution must lie in \[0, 1\]; got 1.5"),
        (None, "belt_speed", [0.1, -0.2], r"belt_speed must lie in \[0, inf\); got -0.2"),
        (None, "mu_k", [0.1, 0.4], r"mu_k must lie in \[0, mu_s\]; got 0.4"),
        (RigidStop(0.2), "clearance", [0.1, -0.1], r"clearance must lie in \[x0, inf\)"),
        (None, "u_s", [0.0], r"u_s must lie in \(0, inf\)"),
        (None, "belt_speed", [], "non-empty"),
    ],
)
def test_bad_sweeps_get_errors_that_name_the_parameter_and_range(stop, name, values, message):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    with pytest.raises(ValueError, match=message):
        sweep(osc, stop, name, values)


def test_bad_quantity_and_method_are_refused():
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    with pytest.raises(ValueError, match="quantity must be one of"):
        sweep(osc, None, "belt_speed", [0.1], quantity="speed")
    with pytest.raises(ValueError, match="needs a HystereticStop"):
        sweep(osc, RigidStop(0.2), "belt_speed", [0.1], quantity="force_peak")
    with pytest.raises(ValueError, match="method must be one of"):
        sweep(osc, None, "belt_speed", [0.1], method="rk4")


def test_importing_core_and_the_sweep_does_not_import_dask():
    code = "import sys, core, core.sweep; print('dask' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize(
    ("t_end", "x0", "v0", "stop"),
    [
        (6.0, 0.0, 0.0, RigidStop(0.25, 0.7)),  # horizons that end most transients: 'none'
        (200.0, -0.5, 0.3, RigidStop(0.3, 0.8)),  # another start, a still belt among them
        (200.0, -0.4, 0.0, None),
    ],
)
def test_short_horizons_other_starts_and_a_still_belt_agree_with_simulate(t_end, x0, v0, stop):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    values = np.concatenate(([0.0], np.random.default_rng(3).uniform(0.0, 0.45, 40)))
    res = sweep(osc, stop, "belt_speed", values, t_end=t_end, x0=x0, v0=v0)
    labels = set()
    for i, value in enumerate(values):
        o = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=float(value))
        ref = simulate(o, stop, t_end, x0, v0, transition_cap=100_000)
        _assert_lane(res, i, ref, 0.5)
        labels.add(ref.steady.kind.value)
    if t_end < 10.0:  # the horizon cuts some transients, not all
        assert "none" in labels and len(labels) > 1
    else:
        assert "equilibrium" in labels or "rest" in labels  # the still belt


@pytest.mark.parametrize("restitution", [1.0, 0.7])
def test_simulated_regime_map_equals_the_theory_map_for_a_rigid_stop(restitution):
    # An independent reference: the paper's closed-form classification (core.theory) of
    # every point of a belt speed x clearance map, slow and fast belts, cases a/b/c.
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    clearances, speeds = np.linspace(0.0, 0.6, 61), np.linspace(0.01, 0.45, 45)
    stop = RigidStop(0.25, restitution)
    res = sweep_grid(osc, stop, {"clearance": clearances, "belt_speed": speeds})
    theory = classify_grid(osc, stop, speeds, clearances)
    assert res.labels.shape == theory.expected_steady.shape
    assert np.array_equal(res.labels, theory.expected_steady)
    assert len(set(theory.expected_steady.ravel())) >= 3


def test_simulated_regime_map_of_a_plastic_stop_equals_the_theory_map():
    """r = 0: after the impact the mass leaves on the slip circle that touches the stop,
    grazing it (Sec. 4.3), which the simulation called pure slip in 721 of 2745 cells.
    They may differ only where that circle touches the stick line, x_bar - a = v (a
    tangency that the closed form decides by a comparison of rounded numbers)."""
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    clearances, speeds = np.linspace(0.0, 0.6, 61), np.linspace(0.01, 0.45, 45)
    stop = RigidStop(0.25, 0.0)
    res = sweep_grid(osc, stop, {"clearance": clearances, "belt_speed": speeds})
    theory = classify_grid(osc, stop, speeds, clearances)
    differ = res.labels != theory.expected_steady
    tangent = np.abs(clearances[:, None] - osc.a - speeds[None, :]) < 1e-12
    assert not (differ & ~tangent).any()
    assert {"grazing", "rest", "periodic", "pure_slip"} <= set(theory.expected_steady.ravel())


def test_elastic_case_c_ties_resolve_as_simulate_resolves_them():
    # Elastic case c: the rebound returns to the stop exactly on the stick line, so the
    # next event is a tie between slip->stick and the impact. Both are formed from the same
    # numbers (core.flight.stick_line_event and stop_event, and their numpy copies), so the
    # tie is exact and the impact wins it everywhere: one impact a period, as the paper
    # counts it (core.theory). When the stick line's crossing was an asin near 1, rounding
    # decided it, and this grid (from the benchmark's) held both resolutions.
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    speeds = np.linspace(0.005, 0.45, 316)[:45]
    clearances = np.linspace(0.0, 0.6, 316)[96:106]
    stop = RigidStop(0.25, 1.0)
    res = sweep_grid(osc, stop, {"belt_speed": speeds, "clearance": clearances})
    sequences = set()
    for i, v in enumerate(speeds):
        for j, c in enumerate(clearances):
            o = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=float(v))
            ref = simulate(o, RigidStop(float(c), 1.0), 200.0, transition_cap=100_000)
            _assert_lane(res, i * len(clearances) + j, ref, 0.3)
            sequences.add(ref.steady.sequence)
    assert ("impact",) in sequences
    assert ("slip->stick", "stick->impact") not in sequences


def test_still_belt_accumulation_comes_to_rest_as_simulate_decides():
    # With the belt still the impact sequence has no closed form: the bounces shrink until
    # core.steady.comes_to_rest holds the mass on the stop (a bounce below rounding), or
    # friction stops it away from the stop; the vectorised rest rule must decide as
    # simulate does.
    osc = Oscillator(mu_s=0.05, mu_k=0.05, belt_speed=0.0)
    clearances = np.linspace(-0.3, 0.3, 31)
    res = sweep(osc, RigidStop(0.1, 0.5), "clearance", clearances, x0=-0.5, v0=0.6)
    assert not res.fallback.any()
    for i, c in enumerate(clearances):
        ref = simulate(osc, RigidStop(float(c), 0.5), 200.0, -0.5, 0.6, transition_cap=100_000)
        _assert_lane(res, i, ref, 0.6)
    assert set(res.labels) == {"rest", "equilibrium"}


def test_a_deformable_stops_grazing_limit_is_swept_at_the_elastic_speed():
    """Fig. 10's stop: the bifurcation diagram plotted impact speed 0 at every grazing
    point (the rigid stop's limit) while the label said "towards w_inf = 0.001768", and
    steady x_max, period and force peak had no sample (x_max nan). The limit is the train of
    elastic contacts at w_inf (core.deformable.law.elastic_limit): its speed, its peak, its
    force and its period are sampled."""
    from core.deformable.law import elastic_limit, phi_compression

    stop = HystereticStop(0.24, 400.0, 36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    clearances = [0.23, 0.24]
    res = sweep(osc, stop, "clearance", clearances, t_end=80.0)
    for i, c in enumerate(clearances):
        lim = elastic_limit(osc.a, c, stop)
        assert LABELS[res.label[i]] == "grazing"
        assert res.impact_speed[i] == lim.w_inf
        assert res.x_max[i] == c + lim.r_inf
        assert res.period[i] == pytest.approx(
            2.0 * math.pi - 2.0 * math.atan(lim.w_inf / (c - osc.a)) + lim.duration, rel=1e-12)
    speeds, offsets = res.samples("impact_speed")
    assert np.all(np.diff(offsets) == 1) and np.all(speeds > 0.0)
    forces, _ = res.samples("force_peak")
    assert forces[1] == pytest.approx(float(phi_compression(elastic_limit(
        osc.a, 0.24, stop).r_inf, stop)), rel=1e-12)
