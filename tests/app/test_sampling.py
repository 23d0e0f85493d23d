"""The pictures at long horizons: drawn from the exact motion, checked against it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app import sampling
from app.plots import (
    HISTORY_COLUMNS,
    MODE_NAMES,
    PHASE_FRAME_MAX,
    PlotSet,
    band_columns,
    force_columns,
    phase_step,
    sample_bounds,
)
from app.solve.pool import solve
from app.solve.presets import ACCURACY
from app.state import DIMENSIONLESS, scene_values
from core import SteadyKind, TransitionKind, simulate

#: The longest horizon the issue reports artefacts at.
LONG = 5000.0
#: Longest chord allowed in the phase portrait on its largest frame [px]: "a few pixels".
MAX_CHORD_PX = 3.0


#: Budget [s] of these long solves: they test the drawing, not the page's 2 s budget (scene 10
#: to t_end = 5000 takes ~2 s here, more on a busy machine, and would come back cut short).
LONG_BUDGET_S = 120.0


def _long(key: str, t_end: float = LONG):
    return solve({**scene_values(key), "t_end": t_end}, budget=LONG_BUDGET_S)


def _drawn(key: str, t_end: float = LONG) -> PlotSet:
    plots = PlotSet()
    plots.update(_long(key, t_end), DIMENSIONLESS, ("phase", "time", "force"))
    return plots


def _exact(sol):
    """The closed form at any times, independently of app.sampling."""
    def at(t):
        res = simulate(sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0,
                       t_eval=np.asarray(t, float))
        return np.asarray(res.x), np.asarray(res.v)
    return at


@pytest.mark.parametrize("key", ["5a", "5d", "7c", "4b"])
def test_phase_portrait_has_no_long_chords_at_a_long_horizon(key):
    """Scene 5a at t_end = 5000 drew a fan of chords: a fixed sample count gave one sample
    every ~2 radians. Every drawn segment, except an impact's vertical jump at the stop,
    is at most a few pixels long on the largest frame the portrait is laid out in, with
    the ranges the figure shows."""
    plots = _drawn(key)
    fig = plots.figures["phase"]
    sol = plots.last
    # The browser fits the ranges to what the ranged renderers hold, padded, at equal
    # aspect (match_aspect): pixels per unit are the smaller of the two axes' ratios.
    xs, vs = [], []
    for r in fig.x_range.renderers:
        data = r.data_source.data
        xs.append(np.asarray(data["x"], float))
        vs.append(np.asarray(data["v"], float))
    x_all, v_all = np.concatenate(xs), np.concatenate(vs)
    x_span = np.ptp(x_all[np.isfinite(x_all)]) * (1 + fig.x_range.range_padding)
    v_span = np.ptp(v_all[np.isfinite(v_all)]) * (1 + fig.y_range.range_padding)
    px_x = px_v = min(PHASE_FRAME_MAX[0] / x_span, PHASE_FRAME_MAX[1] / v_span)
    longest = 0.0
    for name in MODE_NAMES.values():
        data = plots.sources[f"path_{name}"].data
        x, v = np.asarray(data["x"], float), np.asarray(data["v"], float)
        dx, dv = np.diff(x) * px_x, np.diff(v) * px_v
        drawn = np.isfinite(dx) & np.isfinite(dv)
        if sol.stop is not None:  # impacts: vertical jumps at x = x_bar
            at_stop = np.abs(x[1:] - sol.stop.clearance) < 1e-6
            drawn &= ~((np.abs(dx) < 1e-6) & at_stop)
        if drawn.any():
            longest = max(longest, float(np.hypot(dx, dv)[drawn].max()))
    assert 0.0 < longest <= MAX_CHORD_PX


def test_a_periodic_steady_state_is_drawn_once_and_its_repeats_counted():
    sol = _long("5a")
    plots = _drawn("5a")
    steady = sol.result.steady
    assert steady.kind is SteadyKind.PERIODIC
    repeat = plots.sources["repeat"].data
    assert len(repeat["x"]) == 1
    n = int((sol.t_end - steady.t_reached - steady.period) // steady.period)
    assert repeat["text"] == [f"repeats {n}x"]
    assert f"cycle closes (repeats {n}x)" in plots.legends["phase"].object
    # Markers only for the transitions up to the end of the first cycle.
    t_marks = np.asarray(plots.sources["trans"].data["t"], float)
    assert t_marks.max() <= steady.t_reached + steady.period * (1 + 1e-6)
    # The drawn orbit closes: it ends where the cycle started.
    x, v = _exact(sol)([steady.t_reached])
    assert repeat["x"][0] == pytest.approx(x[0], abs=1e-6)
    assert repeat["v"][0] == pytest.approx(v[0], abs=1e-6)


@pytest.mark.parametrize("key", ["5a", "10", "7c"])
def test_time_history_envelope_matches_the_exact_extremes(key):
    """Per pixel column, the lowest and highest drawn x(t) and x'(t) are those of the
    exact motion. The reference evaluates the closed form every 0.01 (a sampled arc's
    extreme misses by R(1 - cos 0.005) ~ 1e-5 R) on 40 columns; the drawing samples every
    0.1 (misses by at most R(1 - cos 0.05) = 1.25e-3 R, a quarter of a pixel on a 200 px
    plot), so they agree within 2e-3 of the span. Scene 10 (deformable stop) is drawn
    from its samples: its reference is the solve's own samples, which must be dense
    enough that no column is empty."""
    sol = _long(key)
    plots = _drawn(key)
    traj = plots.sources["traj"].data
    # The drawn columns are float32 (times of ~5000 to 2.4e-4, which moves a sample across
    # a column's edge): the columns are checked in float64, as the plot module made them.
    columns = HISTORY_COLUMNS
    evaluate, exact = sampling.evaluator(sol.result, sol.osc, sol.stop, sol.t_end, sol.x0,
                                         sol.v0, sol.method)
    # (The window of a long run adds its own columns' samples: of the exact motion too.)
    h = sampling.history(sol.result, evaluate, sol.t_end, exact, columns,
                         phase_step(*sample_bounds(sol)), plots.run_window.window)
    t, x, v = h.t, h.x, h.v
    np.testing.assert_array_equal(traj["x"], x.astype(np.float32))
    np.testing.assert_array_equal(traj["t"], t.astype(np.float32))  # dimensionless
    width = sol.t_end / columns
    res = sol.result
    span_x = float(np.ptp(res.x))
    span_v = float(np.ptp(res.v))
    rng = np.random.default_rng(1)
    for c in rng.choice(columns, 40, replace=False):
        lo, hi = c * width, (c + 1) * width
        if key == "10":
            sel = (res.t >= lo) & (res.t <= hi)
            ts = np.r_[lo, np.asarray(res.t)[sel], hi]
            ref_x, ref_v = (np.interp(ts, res.t, res.x), np.interp(ts, res.t, res.v))
        else:
            ref_x, ref_v = _exact(sol)(np.linspace(lo, hi, int(width / 0.01) + 2))
        # What the line draws in the column: its samples there and where it crosses the
        # column's edges.
        mine = (t > lo) & (t < hi)
        assert mine.any(), f"column {c} is not drawn"
        xs = np.r_[x[mine], np.interp([lo, hi], t, x)]
        vs = np.r_[v[mine], np.interp([lo, hi], t, v)]
        assert xs.max() == pytest.approx(ref_x.max(), abs=2e-3 * span_x)
        assert xs.min() == pytest.approx(ref_x.min(), abs=2e-3 * span_x)
        assert vs.max() == pytest.approx(ref_v.max(), abs=2e-3 * span_v)
        assert vs.min() == pytest.approx(ref_v.min(), abs=2e-3 * span_v)
    # The largest drawn displacement is the exact x_max of the closed form.
    assert x.max() == pytest.approx(res.x_max, abs=1e-6 * max(1.0, abs(res.x_max)))


@pytest.mark.parametrize(("key", "restitution"),
                         [("5b", 0.0), ("6a", 0.0), ("7c", 0.0), ("5a", None), ("4b", None),
                          ("7d", None)])
def test_every_drawn_history_sample_is_on_the_exact_motion(key, restitution):
    """A plastic impact onto a grazing circle (``5b&r=0``) drew x'(t) spikes up to the belt
    speed every period: the tiled cycle repeated the impact's approach speed. Every drawn
    sample of x(t) and x'(t) away from a logged transition is the closed form's state at
    its time. The columns are float32 (a time of ~60 is off by up to 4e-6, x' by as much
    times the acceleration, < 1); samples within 1e-4 of a transition may hold either
    side's velocity."""
    values = scene_values(key) | ({} if restitution is None else {"restitution": restitution})
    sol = solve(values)
    plots = PlotSet()
    plots.update(sol, DIMENSIONLESS, ("time",))
    traj = plots.sources["traj"].data
    t = np.asarray(traj["t"], float)
    x, v = np.asarray(traj["x"], float), np.asarray(traj["v"], float)
    ref_x, ref_v = _exact(sol)(t)
    marks = np.array([tr.t for tr in sol.result.transitions])
    near = np.zeros(len(t), bool)
    if len(marks):
        j = np.clip(np.searchsorted(marks, t), 1, len(marks) - 1)
        near = np.minimum(abs(marks[j] - t), abs(marks[j - 1] - t)) < 1e-4
    assert (~near).sum() > 30
    np.testing.assert_allclose(x[~near], ref_x[~near], atol=1e-5)
    np.testing.assert_allclose(v[~near], ref_v[~near], atol=1e-5)


def test_every_stick_interval_keeps_a_band_and_every_impact_a_stem():
    """Scene 5a at t_end = 5000: ~900 stick intervals and as many impacts. Each stick
    interval lies in a stick band (one narrower than a pixel column covers its column),
    and each stored impact is drawn (the force plot kept only the last 400)."""
    sol = _long("5a")
    plots = _drawn("5a")
    bands = band_columns(plots.bands)
    stick = np.array([c == "#fbe7cc" for c in bands["color"]])
    left = np.asarray(bands["left"], float)[stick]
    right = np.asarray(bands["right"], float)[stick]
    starts = [tr.t for tr in sol.result.transitions if tr.kind is TransitionKind.SLIP_STICK]
    assert len(starts) > 500
    # float32 columns: times of ~5000 to 5e-4.
    inside = [bool(np.any((left <= t + 5e-4) & (t - 5e-4 <= right))) for t in starts]
    assert all(inside)
    stems = force_columns(sol)["stems"]
    assert len(stems["t"]) == len(sol.result.impulses) > 500


def test_the_exact_evaluator_is_the_solution():
    """The evaluator reproduces the solver's own samples at its uniform sample times."""
    sol = solve(scene_values("5b"))
    res = sol.result
    evaluate, exact = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0,
                                         sol.method)
    assert exact
    t = np.linspace(0.0, sol.t_end, ACCURACY[sol.values["accuracy"]]["n_samples"])
    x, v = evaluate(t)
    # Away from the transitions, the result's sample at t is the same closed form.
    idx = np.searchsorted(res.t, t)
    idx = np.clip(idx, 0, len(res.t) - 1)
    same = np.abs(res.t[idx] - t) == 0
    assert same.sum() > 100
    np.testing.assert_allclose(x[same], res.x[idx[same]], rtol=0, atol=1e-13)
    np.testing.assert_allclose(v[same], res.v[idx[same]], rtol=0, atol=1e-13)


def test_m4_keeps_each_columns_extremes_in_time_order():
    t = np.linspace(0.0, 100.0, 100_001)
    y = np.sin(7.3 * t) * np.exp(-t / 50)
    idx = sampling.m4(t, (y,), 0.0, 100.0, 200)
    assert np.all(np.diff(idx) > 0) and len(idx) <= 4 * 200
    col = np.minimum((t / 0.5).astype(int), 199)
    for c in (0, 57, 199):
        sel = col == c
        kept = idx[col[idx] == c]
        assert y[kept].max() == y[sel].max() and y[kept].min() == y[sel].min()


def _chord_error(t, y, kept):
    """Per sample, how far the line through ``kept`` passes from it (at its time; a
    sample at a kept one's time is that one)."""
    r = np.clip(np.searchsorted(kept, np.arange(len(t)), "right") - 1, 0, len(kept) - 2)
    lo, hi = kept[r], kept[r + 1]
    on = np.isin(np.arange(len(t)), kept)
    with np.errstate(invalid="ignore", divide="ignore"):
        chord = y[lo] + (y[hi] - y[lo]) * (t - t[lo]) / (t[hi] - t[lo])
    return np.where(on, 0.0, np.abs(y - chord))


@pytest.mark.parametrize("seed", range(8))
def test_a_thinned_line_stays_within_its_tolerance_of_every_sample(seed):
    """Random smooth, flat and noisy series with jumps (two samples at one time) and
    breaks (nan): every dropped sample lies within tolerance of the kept line; ends,
    extremes, jumps and breaks stay."""
    rng = np.random.default_rng(seed)
    n = 3000
    t = np.sort(rng.uniform(0.0, 60.0, n))
    t[rng.choice(n - 1, 20, replace=False)] = t[rng.choice(n - 1, 20, replace=False)]
    t = np.sort(t)
    flat = np.where(np.sin(t) > 0.3, np.sin(3 * t), 0.0)
    smooth = np.cumsum(rng.uniform(0, 1, n)) + np.sin(t)
    noisy = rng.normal(size=n).cumsum()
    noisy[rng.choice(n, 5, replace=False)] = np.nan
    series = (flat, smooth, noisy)
    tols = tuple(sampling.thin_tolerance(y) for y in series)
    kept = sampling.thin(t, series, tols)
    assert np.all(np.diff(kept) > 0) and kept[0] == 0 and kept[-1] == n - 1
    for y, tol in zip(series, tols, strict=True):
        # rounding of the chord's arithmetic only
        assert np.nanmax(_chord_error(t, y, kept)) <= tol * (1 + 1e-9)
        assert np.nanargmax(y) in kept and np.nanargmin(y) in kept
        bad = np.flatnonzero(~np.isfinite(y))
        assert np.isin(bad, kept).all()
    jumps = np.flatnonzero(np.diff(t) == 0)
    assert np.isin(jumps, kept).all() and np.isin(jumps + 1, kept).all()
    assert len(kept) < n  # the flat and smooth stretches lose samples


def test_the_contact_force_and_energies_of_scene_10_are_drawn_with_few_points():
    """Scene 10's contact force is zero between contacts and its energies are cumulative:
    they were drawn with every one of the solve's 2057 samples (a browser paints each,
    ~1 us). Now a fraction of them, each line within a quarter pixel of a 1400 px frame of
    the line through every sample."""
    from app.plots import ENERGY_COLORS, energy_columns

    sol = solve(scene_values("10"))
    res = sol.result
    t = np.asarray(res.t, float)
    force = force_columns(sol)["line"]
    energy = energy_columns(sol)
    e = res.energy
    full = {"mechanical": e.mechanical, "belt_input": e.belt_input,
            "friction_heat": np.asarray(e.belt_input) - np.asarray(e.friction_work),
            "stop_loss": e.stop_loss, "stop_stored": e.stop_stored}
    assert len(force["t"]) < len(t) / 4 and len(energy["t"]) < len(t) / 4
    for cols, names, shared in ((force, {"phi": res.contact_force}, False),
                                (energy, {n: full[n] for n in ENERGY_COLORS}, True)):
        drawn_t = np.asarray(cols["t"], float)
        # The drawn times are float32 copies of samples: each is the nearest one.
        right = np.clip(np.searchsorted(t, drawn_t), 1, len(t) - 1)
        kept = np.where(drawn_t - t[right - 1] < t[right] - drawn_t, right - 1, right)
        np.testing.assert_allclose(t[kept], drawn_t, rtol=1e-6)
        tol = sampling.thin_tolerance(*(np.asarray(y, float) for y in names.values()))
        for name, y in names.items():
            y = np.asarray(y, float)
            own = tol if shared else sampling.thin_tolerance(y)
            # float32 columns: the values' own rounding (6e-8 of the span) on top
            assert _chord_error(t, y, kept).max() <= own * (1 + 1e-3), name


def test_a_long_run_of_a_deformable_stop_gets_samples_for_its_horizon():
    """A method that only samples returns enough samples to draw a slip arc within a
    pixel at any horizon (scene 10 at t_end = 5000 had 4510 samples: 0.9 per radian)."""
    assert sampling.samples_for(LONG, 1600) >= LONG / sampling.HISTORY_DT
    sol = _long("10")
    assert len(sol.result.t) >= sampling.samples_for(LONG, 1600)
    assert np.max(np.diff(sol.result.t)) <= 2 * sampling.HISTORY_DT


def test_the_first_slip_arc_is_smooth():
    """Scenes 5d and 7d: the first slip arc was a 5-8 segment polyline. Consecutive
    drawn chords turn by at most a few degrees on it."""
    for key in ("5d", "7d"):
        sol = solve(scene_values(key))
        res = sol.result
        evaluate, _ = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0,
                                         sol.method)
        step = (1e-3 * float(np.ptp(res.x)),) * 2
        first = res.transitions[0].t
        path = sampling.phase_path(res, evaluate, first, step)
        dx, dv = np.diff(path.x), np.diff(path.v)
        keep = np.hypot(dx, dv) > 0
        angle = np.unwrap(np.arctan2(dv[keep], dx[keep]))
        assert len(angle) > 50
        assert np.max(np.abs(np.diff(angle))) < math.radians(5)


def test_a_mass_at_rest_from_the_start_is_drawn():
    """A still belt and a start inside the stick zone: equilibrium from t = 0 with no
    transition at all (drawing it raised a TypeError in the server, seen under load)."""
    from core import Oscillator

    res = simulate(Oscillator(0.3, 0.2, 0.0), None, 50.0)
    assert res.steady.kind is SteadyKind.EQUILIBRIUM and not res.transitions
    assert sampling.draw_horizon(res, 50.0, (0.01, 0.01)) == 0.0
    plots = PlotSet()
    plots.update(solve({**scene_values("4a"), "belt_speed": 0.0, "x0": 0.0, "v0": 0.0}),
                 DIMENSIONLESS, ("phase", "time", "force"))
    assert len(plots.sources["traj"].data["x"]) > 0


def test_a_path_from_the_results_own_samples_is_the_same_curve_for_fewer_evaluations():
    """Scene 10 (deformable stop, no closed form): the phase path that takes the result's
    own samples as they are (``known``) lies on the solution, has no chord longer than a
    step, and evaluates the solution at fewer times (each contact sample costs a Python
    loop in the core)."""
    sol = solve(scene_values("10"))
    res = sol.result
    evaluate, exact = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0,
                                         sol.method)
    assert not exact
    step = phase_step(*sample_bounds(sol))
    t_draw = sampling.draw_horizon(res, sol.t_end, step)
    counted = {}
    paths = {}
    for known in (False, True):
        calls = []

        def counting(t, calls=calls):
            calls.append(len(t))
            return evaluate(t)
        paths[known] = sampling.phase_path(res, counting, t_draw, step, known=known)
        counted[known] = sum(calls)
    path = paths[True]
    assert counted[True] < 0.8 * counted[False]
    # On the solution: the samples are the solver's values at their times (the same
    # evaluation: equal to rounding; 1e-9 of the motion's span).
    x, v = evaluate(path.t)
    span = float(np.ptp(res.x))
    np.testing.assert_allclose(path.x, x, rtol=0, atol=1e-9 * span)
    np.testing.assert_allclose(path.v, v, rtol=0, atol=1e-9 * span)
    assert np.all(np.diff(path.t) >= 0)
    # No chord longer than a step, either way (the motion is continuous at a deformable
    # stop; 1e-9 for rounding). One pass of subdivision left chords of 4.6 steps in a
    # contact, where the speed along the curve changes within an interval.
    def longest(p):
        return float(np.max(np.hypot(np.diff(p.x) / step[0], np.diff(p.v) / step[1])))
    assert longest(path) <= 1.0 + 1e-9 and longest(paths[False]) <= 1.0 + 1e-9
    assert len(path.t) >= 0.8 * len(paths[False].t)  # as finely drawn
