"""The columns the figures draw, checked against the motion they show."""

from __future__ import annotations

import html

import numpy as np
import pytest

from app import sampling
from app.plots import phase_step, sample_bounds
from app.scenes import SCENES
from app.solve.pool import solve
from app.state import scene_values

#: Scenes with a rigid stop (the impacts are jumps of the velocity at x = x_bar).
RIGID_SCENES = [k for k, s in SCENES.items() if s.values.get("stop_type", "rigid") == "rigid"
                and not s.values.get("program")]
#: Largest mismatch allowed between a drawn segment's displacement and the trapezoidal
#: integral of its end velocities: absolute [length] plus relative to the displacement.
#: A chord between samples that are not neighbours on the motion misses by ~1e-3 and more
#: (about all of its displacement); neighbours on a sampled sine arc miss by the
#: trapezoid's error, ~1e-5 of a full solve's step and up to 0.2 % of a preview's.
SEGMENT_ABS_TOL = 1e-4
SEGMENT_REL_TOL = 0.02


@pytest.mark.parametrize("key", RIGID_SCENES)
@pytest.mark.parametrize("preview", [False, True])
def test_phase_trajectory_jumps_at_the_stop_and_joins_only_neighbours(key, preview):
    """Regression (scene 5a): in the periodic steady state the core repeated the approach
    velocity at each impact, and the portrait joined it to the rebound arc with a chord,
    one per period, drawing a filled wedge beside the stop."""
    sol = solve(scene_values(key), preview=preview)
    res = sol.result
    evaluate, _ = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0,
                                     sol.method)
    step = phase_step(*sample_bounds(sol))
    path = sampling.phase_path(res, evaluate, sampling.draw_horizon(res, sol.t_end, step),
                               step)
    t, x, v = path.t, path.x, path.v
    x_bar, r = sol.stop.clearance, sol.stop.restitution
    assert np.all(x <= x_bar + 1e-12), "the trajectory passes the stop"
    jumps = 0
    for i in range(len(t) - 1):
        j = i + 1
        assert t[j] >= t[i], f"segment {i}-{j} runs back in time"
        if t[j] == t[i]:
            if v[j] == v[i]:
                continue  # a transition without a jump (the two sides of it)
            # An impact: a vertical jump at the stop, x'+ = -r x'-.
            jumps += 1
            # Both sides at the stop, to rounding (an evaluated side and a stored one).
            assert x[i] == pytest.approx(x_bar, abs=1e-12)
            assert x[j] == pytest.approx(x[i], abs=1e-12)
            assert v[j] == pytest.approx(-r * v[i], rel=1e-9, abs=1e-12)
        else:
            dx = 0.5 * (v[i] + v[j]) * (t[j] - t[i])
            tol = SEGMENT_ABS_TOL + SEGMENT_REL_TOL * abs(x[j] - x[i])
            assert abs(x[j] - x[i] - dx) < tol, (
                f"segment {i}-{j} at t={t[i]:.4f} joins samples that are not neighbours")
    if len(res.impulses) and res.impulses[0, 0] <= path.t[-1]:
        assert jumps > 0


def test_axis_ranges_come_with_the_data():
    """The server sets every visible figure's range from the data it sends (no
    ``DataRange1d`` computed in the browser and echoed back), except the phase portrait's:
    only the browser knows its frame, and equal aspect needs it (``match_aspect``)."""
    from bokeh.models import DataRange1d

    from app.explorer import Explorer

    ex = Explorer()
    figs = ex.plots.figures
    assert not any(isinstance(r, DataRange1d) for name, f in figs.items()
                   for r in (f.x_range, f.y_range) if name != "phase")


@pytest.mark.parametrize("units, omega", [("dimensionless", 1.0), ("SI", None)])
def test_phase_portrait_has_equal_aspect_in_both_unit_systems(units, omega):
    """A slip arc is a circle about (+-a, 0) (paper Eq. 7): the portrait fits its ranges
    to the frame with one scale for x and x' (dimensionless) or x and x'/omega (SI, x in mm,
    x' in m/s), so circles are drawn as circles (the browser test measures them)."""
    from bokeh.models import DataRange1d

    from app.explorer import Explorer

    ex = Explorer()
    ex.units.value = units
    fig = ex.plots.figures["phase"]
    assert fig.match_aspect
    assert isinstance(fig.x_range, DataRange1d) and isinstance(fig.y_range, DataRange1d)
    scales = ex.state.scales()
    # x' in m/s over x in mm: omega L / (1e3 L) = omega / 1e3, whatever the length unit.
    scale = scales.velocity / scales.length
    assert fig.aspect_scale == pytest.approx(omega or scale)
    if units == "SI":
        assert scale == pytest.approx(ex.state.omega / 1e3, rel=1e-15)
    # The references the caption names are in the ranges' renderers.
    ranged = set(fig.x_range.renderers) & set(fig.y_range.renderers)
    sources = {r.data_source for r in ranged}
    for name in ("gamma0", "cycle", "points", "start", "path_slip"):
        assert ex.plots.sources[name] in sources, name


def test_the_browser_places_the_point_labels_on_every_change_of_the_frame():
    """The server cannot tell which labels leave the frame or run into each other (it does
    not know the frame's pixel size): one ``CustomJS`` places them again whenever the
    frame, the ranges, the labels' font or anything the portrait draws changes (but the
    animation's moving marker). The server decides nothing of a label's place: it sends
    the points, their names and the slip arcs' centre, every label unplaced."""
    from bokeh.models import CustomJS

    from app.explorer import Explorer

    ex = Explorer()
    fig, labels = ex.plots.figures["phase"], ex.plots.point_labels
    callbacks = {id(cb): cb for model in fig.references()
                 for cbs in model.js_property_callbacks.values() for cb in cbs}
    assert [type(cb) for cb in callbacks.values()] == [CustomJS]
    place = next(iter(callbacks.values()))
    assert place.args["labels"] is labels and place.args["fig"] is fig
    watched = {
        (fig, "inner_width"), (fig, "inner_height"), (fig.x_range, "start"),
        (fig.x_range, "end"), (fig.y_range, "start"), (fig.y_range, "end"),
        (labels, "text_font_size"), (labels, "text"),
        *((src, "data") for src in ex.plots.sources.values()
          if any(getattr(r, "data_source", None) is src for r in fig.renderers)),
    }
    for model, attr in watched:
        assert place in model.js_property_callbacks.get(f"change:{attr}", []), (model, attr)
    data = labels.source.data
    assert data["name"] and "side" not in data
    assert set(data["align"]) == {"center"} and set(data["baseline"]) == {"middle"}
    assert set(data["dx"]) == set(data["dy"]) == {0}
    assert data["centre"] == [ex.solution.osc.a] * len(data["x"])


def test_legends_are_html_and_list_only_what_is_drawn():
    """No legend stand-in renderers (234 of a page's ~950 models): the legends are HTML,
    and the phase portrait's lists what it draws (a pure slip orbit has no stick)."""
    from bokeh.models import Legend

    from app.explorer import Explorer

    ex = Explorer()
    assert not [m for f in ex.plots.figures.values() for m in f.select(type=Legend)]
    for fig in ex.plots.figures.values():
        for r in fig.renderers:
            data = r.data_source.data if hasattr(r, "data_source") else {}
            assert not (data.get("x") is not None and len(data["x"]) == 1
                        and np.isnan(data["x"][0])), "a stand-in renderer"
    ex.scene_select.value = "4a"  # impactless, fast belt: pure slip
    text = ex.plots.legends["phase"].object
    assert "slip" in text and ">stick<" not in text and "slip-&gt;stick" not in text
    ex.scene_select.value = "5b"
    text = ex.plots.legends["phase"].object
    assert ">stick<" in text and "impact" in text


def test_legend_lists_the_transition_kinds_of_the_scene():
    from app.explorer import Explorer
    from app.plots import TRANSITION_LABELS, TRANSITION_STYLE

    def listed(ex):
        text = ex.plots.legends["phase"].object
        return {k for k in TRANSITION_STYLE
                if f">{html.escape(TRANSITION_LABELS.get(k, k))}</span>" in text}

    ex = Explorer()
    ex.scene_select.value = "10"
    assert listed(ex) == set(ex.plots.sources["trans"].data["kind"])
    ex.scene_select.value = "11"  # a new scene forgets the kinds of the last one
    assert listed(ex) == set(ex.plots.sources["trans"].data["kind"])


@pytest.mark.parametrize("beyond, shown", [(0.3, True), (2.0, False)])
def test_a_stop_the_motion_misses_is_shown_when_near(beyond, shown):
    """With the clearance past the motion's reach (no impact), the stop line stays in the
    phase portrait and x(t) when it is near the motion, not when it would squeeze it."""
    from app.explorer import Explorer
    from app.state import ExplorerState

    state = ExplorerState()
    state.load_scene("7b")
    ex = Explorer(state)
    x = np.asarray(ex.plots.sources["traj"].data["x"], float)
    span = x.max() - x.min()
    clearance = round(float(x.max() + beyond * span), 4)
    ex.state.param.update(clearance=clearance)
    assert ex.error is None
    x = np.asarray(ex.plots.sources["traj"].data["x"], float)
    assert x.max() < clearance  # no impact: the motion does not reach the stop
    figs = ex.plots.figures
    assert (figs["time_x"].y_range.end > clearance) is shown
    # The phase portrait's ranges are fitted in the browser to what its renderers hold.
    stop_pt = ex.plots.sources["stop_pt"].data["x"]
    assert (list(stop_pt) == [clearance]) is shown


@pytest.mark.parametrize("key", ["10", "11"])
def test_deformable_contacts_are_drawn_from_the_contact_itself(key):
    """Scenes 10 and 11: the force history and the hysteresis loop reach the solution's peak force,
    and the loop's chords stay under the compression envelope (within 1 % of the peak: the
    envelope is convex, so a chord between two samples on it lies above it by a sliver).
    With only the uniform samples and the transition times a contact is a few chords,
    which cut up to 6 % of the peak above the envelope."""
    from app.plots import force_columns, loop_columns
    from core.deformable.law import phi_compression

    sol = solve(scene_values(key))
    peak = float(np.max(sol.result.contact_force))
    loop, line = loop_columns(sol)["loop"], force_columns(sol)["line"]
    d, phi = np.asarray(loop["d"], float), np.asarray(loop["phi"], float)
    assert np.nanmax(phi) >= 0.99 * peak and np.max(line["phi"]) >= 0.99 * peak
    both = np.isfinite(d[:-1]) & np.isfinite(d[1:])
    mid_d, mid_phi = (0.5 * (d[:-1] + d[1:]))[both], (0.5 * (phi[:-1] + phi[1:]))[both]
    assert np.max(mid_phi - phi_compression(mid_d, sol.stop)) < 0.01 * peak


@pytest.mark.parametrize("key", ["5b", "7c", "10"])
def test_energy_plot_is_a_budget_of_the_belt_input(key):
    """What the belt puts in is the change of mechanical energy plus the friction heat plus
    what the stop took: the plotted columns close the budget (float32 columns: 1e-5 of the
    belt input), and the heat of a sliding contact never decreases."""
    from app.plots import energy_columns

    cols = {k: np.asarray(v, float) for k, v in energy_columns(solve(scene_values(key))).items()}
    budget = (cols["mechanical"] - cols["mechanical"][0] + cols["friction_heat"]
              + cols["stop_loss"] + cols["stop_stored"])
    np.testing.assert_allclose(budget, cols["belt_input"],
                               atol=1e-5 * np.abs(cols["belt_input"]).max())
    assert np.all(np.diff(cols["friction_heat"]) >= -1e-6 * cols["friction_heat"].max())


@pytest.mark.parametrize("key", ["10", "11"])
def test_tick_labels_of_the_loop_overlaps_are_decimals(key):
    """The hysteresis loop's overlaps are a few 1e-3 and its ticks a few 1e-4: every axis
    writes such ticks as decimals (Bokeh switches to 5.000e-4 below its power limit)."""
    from app.plots import BUILT_HERE, PlotSet, loop_columns

    plots = PlotSet()
    for name in BUILT_HERE:
        plots.build(name)
    d = np.asarray(loop_columns(solve(scene_values(key)))["loop"]["d"], float)
    tick = (np.nanmax(d) - np.nanmin(d)) / 10  # Bokeh aims at ~10 ticks or fewer
    axes = [a for f in plots.figures.values() for a in (*f.xaxis, *f.yaxis)]
    axes.append(plots.rest_axis)
    assert all(tick > 10.0 ** a.formatter.power_limit_low for a in axes)


def test_the_regime_map_keeps_its_axes_for_a_scene():
    """A tap on the map or a new start point does not reframe it (a tap near its right
    edge used to widen the belt speed axis, a new x0 moved the clearance axis); without a
    stop it has no clearance axis; its legend says what its words mean."""
    from app.explorer import Explorer

    ex = Explorer()
    ex.scene_select.value = "5b"
    fig = ex.plots.figures["map"]

    def axes():
        return fig.x_range.start, fig.x_range.end, fig.y_range.start, fig.y_range.end

    before = axes()
    x0, x1, y0, y1 = before
    # Where a tap near the right edge moves the point (app.explorer: rounded values).
    ex.state.param.update(belt_speed=round(x0 + 0.95 * (x1 - x0), 4),
                          clearance=round(y0 + 0.9 * (y1 - y0), 4))
    assert ex.solution.values["belt_speed"] == round(x0 + 0.95 * (x1 - x0), 4)
    assert axes() == before
    ex.state.param.update(x0=-0.1)
    assert axes() == before
    legend = ex.map_legend.object
    assert "critical speed" in legend and "case a / b / c" in legend
    assert fig.yaxis[0].visible
    ex.stop_type.value = "none"
    assert not fig.yaxis[0].visible


@pytest.mark.parametrize("key", ["6b", "7d", "7c", "5a"])
def test_the_stop_removed_circle_of_figs_6b_and_7d(key):
    """Sec. 4.6: once the mass rests on the stop (Figs. 6b, 7d), removing the stop leaves
    a pure slip circle about (a, 0) through the rest point (x_bar, 0), dotted in the paper:
    drawn there and listed in the legend, nowhere else."""
    from app.explorer import Explorer

    ex = Explorer()
    ex.scene_select.value = key
    data = ex.plots.sources["removed"].data
    drawn = key in ("6b", "7d")
    assert bool(len(data["x"])) is drawn
    assert ("stop removed" in ex.plots.legends["phase"].object) is drawn
    if drawn:
        sol = ex.solution
        a, x_bar = sol.osc.a, sol.stop.clearance
        r = np.hypot(np.asarray(data["x"], float) - a, np.asarray(data["v"], float))
        np.testing.assert_allclose(r, a - x_bar, rtol=1e-6)  # float32 columns


@pytest.mark.parametrize("start, sticks", [((0.2, 0.05), False), ((0.0, 0.0), True)])
def test_theory_points_only_where_the_motion_can_have_them(start, sticks):
    """A start inside Gamma_0 (scene 3a's slow belt, x0 = a, x'0 < v) slips for ever: the
    stick points of the impactless cycle are not drawn over that pure slip orbit."""
    from app.explorer import Explorer

    ex = Explorer()
    ex.scene_select.value = "3a"
    ex.state.param.update(x0=start[0], v0=start[1])
    assert ex.solution.theory.points  # the theory has its stick points either way
    names = ex.plots.sources["points"].data["name"]
    assert bool(len(ex.plots.sources["path_stick"].data["x"])) is sticks
    assert bool([n for n in names if "stick" in n]) is sticks


@pytest.mark.parametrize("module", ["columns", "labels", "legends", "ranges", "sources",
                                    "style", "figures", "plot_set", "map_boundaries",
                                    "colour_vision"])
def test_docstring_examples_of_the_plot_modules(module):
    """The examples of each module of :mod:`app.plots` hold (those with none pass)."""
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(f"app.plots.{module}"))
    assert result.failed == 0


def test_the_mode_bands_behind_the_time_histories_have_a_legend():
    """The coloured bands behind x(t) and x'(t) were explained nowhere: a legend below
    them names each band's mode in its colour, and the figures and the legend keep the
    height the page reserves for the plot before it is built (two ``TIME_SIZE``)."""
    from app.plots import BAND_COLORS, MODE_NAMES, TIME_SIZE, PlotSet

    plots = PlotSet()
    view = plots.view("time")
    legend = plots.legends["time"]
    assert legend in view.objects
    for mode, color in BAND_COLORS.items():
        assert f'fill="{color}"' in legend.object
        assert MODE_NAMES[mode] in legend.object
    figs = (plots.figures["time_x"], plots.figures["time_v"])
    legend_height = legend.min_height + legend.margin[2]
    assert sum(f.height for f in figs) + legend_height == 2 * TIME_SIZE[1]


@pytest.mark.parametrize("palette", ["map", "bands", "steady states"])
def test_palettes_stay_apart_to_red_green_colour_blind_viewers(palette):
    """The regime map's blues, greens and reds read as one class to a deuteranope (least
    CIEDE2000 difference 0.9), the bands' amber and red tints came to less than half as
    far apart as to normal vision: every two classes of the map, the mode bands and the
    simulated steady states now differ by at least
    :data:`app.plots.style.MIN_CLASS_DIFFERENCE` to normal, protanope and deuteranope
    vision (Machado et al. 2009), and a dichromat keeps
    :data:`app.plots.style.CVD_KEPT_FRACTION` of the normal separation."""
    from app.bifurcation import LABEL_COLORS
    from app.plots import BAND_COLORS, MAP_PALETTE
    from app.plots.colour_vision import CVD_MATRICES, min_difference
    from app.plots.style import CVD_KEPT_FRACTION, MIN_CLASS_DIFFERENCE

    colours = {"map": MAP_PALETTE, "bands": tuple(BAND_COLORS.values()),
               "steady states": tuple(LABEL_COLORS.values())}[palette]
    assert len(set(colours)) == len(colours)
    normal = min_difference(colours, "normal")
    for vision in CVD_MATRICES:
        least = min_difference(colours, vision)
        assert least >= MIN_CLASS_DIFFERENCE, vision
        assert least >= CVD_KEPT_FRACTION * normal, vision


#: Step [relative to the frame's span] across a boundary: far above rounding, far below
#: the smallest region of the scenes' maps.
ACROSS = 1e-7


@pytest.mark.parametrize("key", ["5a", "5b", "7c", "6b", "10", "3a"])
def test_the_map_s_boundary_lines_separate_the_theory_s_regimes(key):
    """The closed forms drawn over the regime map (v*, the impactless x_max, b, x*) lie
    where the theory's own classification of the grid (core.theory.classify_grid, a
    decision tree) changes: just either side of each drawn point, the word the line names
    differs (slow/fast, impact/none, case a/b/c)."""
    from app.plots.map_boundaries import boundary_lines
    from app.solve.regime_map import map_ranges
    from app.state import core_inputs
    from core import equivalent_rigid, theory

    values = scene_values(key)
    frame = map_ranges(values)
    osc, stop, x0, v0, _ = core_inputs({**values, "t_end": 1.0, "program": False})
    rigid = equivalent_rigid(stop)
    dv, dx = ACROSS * frame[0], ACROSS * (frame[2] - frame[1])
    vc = theory.critical_speed(osc, x0, v0)
    lines = boundary_lines(values, frame)
    assert [text for _, _, text in lines][:1] == ["v*"]

    def grid(speeds, clearances):
        return theory.classify_grid(osc, rigid, np.asarray(speeds), np.asarray(clearances),
                                    x0, v0)

    checked = 0
    for vs, xs, text in lines:
        if text == "v*":
            g = grid([vc - dv, vc + dv], [0.5 * (frame[1] + frame[2])])
            assert g.belt[0].tolist() == ["slow", "fast"]
            continue
        for v, x in zip(vs, xs, strict=True):
            if not (np.isfinite(x) and v > dv and abs(v - vc) > 10 * dv):
                continue
            g = grid([v], [x - dx, x + dx])
            field = g.impactless if text.startswith("x_max") else g.case
            assert field[0, 0] != field[1, 0], (text, v, x)
            checked += 1
    assert checked > 0 or stop is None  # without a stop, only v*


def test_the_regime_map_draws_the_theory_s_boundaries_in_the_page_s_units():
    """The map shows v*, the impactless x_max, b and x* as lines (at belt speeds in m/s in
    SI units), each named; without a stop only v* remains."""
    from app.explorer import Explorer
    from core import theory

    ex = Explorer()
    ex.scene_select.value = "5b"
    bounds = ex.plots.sources["bounds"].data
    assert set(bounds["text"]) == {"v*", "x_max (no impact above)", "b", "x*"}
    assert {n for n, label in ex.plots.map_labels.items() if label.visible} == \
        set(bounds["text"])
    ex.units.value = "SI"
    bounds = ex.plots.sources["bounds"].data
    sol, omega = ex.solution, ex.state.scales().velocity
    vc = theory.critical_speed(sol.osc, sol.x0, sol.v0)
    v_star = bounds["xs"][bounds["text"].index("v*")]
    assert v_star == pytest.approx([vc * omega] * 2, rel=1e-12)
    ex.stop_type.value = "none"
    assert ex.plots.sources["bounds"].data["text"] == ["v*"]
    assert [n for n, label in ex.plots.map_labels.items() if label.visible] == ["v*"]
