"""The columns each figure's sources hold: pure functions from a solution to arrays.

Each ``*_columns`` function turns a :class:`~app.solve.solution.Solution` into the columns of one
source, in the page's units (:class:`app.state.Scales`), float32 and sampled for the
screen from the exact motion (:mod:`app.sampling`); they are tested without a browser.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from app import sampling
from app.plots.labels import theory_points
from app.plots.style import (
    BAND_COLORS,
    ENERGY_COLORS,
    MODE_COLORS,
    MODE_NAMES,
    PHASE_SIZE,
    PLOT_WIDTHS,
    TRANSITION_STYLE,
)
from app.solve.solution import Solution
from app.state import DIMENSIONLESS, Scales
from core import Mode, phi_compression, phi_expansion

#: Points of the full trajectory sent to the browser (a few per pixel of a plot's width).
MAX_POINTS = 1600
#: Points of the hysteresis loop sent at most (of many contacts, the latest loops).
MAX_LOOP_POINTS = 4 * MAX_POINTS
#: Transition markers drawn at most (the latest ones).
MAX_MARKERS = 400
#: Operating points drawn on the friction law.
MAX_OPERATING_POINTS = 500
#: Vertices of the reference circles (Gamma_0, limit cycle).
CIRCLE_VERTICES = 181
#: Samples of the hysteresis envelopes.
ENVELOPE_SAMPLES = 120
#: Relative span below which data are a single value (the axis then spans one unit).
EMPTY_SPAN = 1e-12
#: The largest frame of the phase portrait [px] (the widest plot, and its height): the
#: chord bound is set for it, so a wider window does not show chords.
PHASE_FRAME_MAX = (PLOT_WIDTHS[1] - 80, PHASE_SIZE[1] - 80)
#: Longest chord of the phase path on the largest frame [px]: below what the eye tells from
#: a curve (a 2 px chord of a 100 px radius arc deviates from it by 0.005 px).
CHORD_PX = 2.0
#: Pixel columns the time histories are reduced to (a wide screen's plot, the largest).
HISTORY_COLUMNS = 1600


def f32(a) -> np.ndarray:
    """``a`` as the float32 array a source sends."""
    return np.asarray(a, dtype=np.float32)


def _drawing(sol: Solution):
    """The solution as a function of time (:func:`app.sampling.evaluator`), cached on
    the solution (one evaluator serves the phase portrait and the time histories)."""
    res = sol.result
    cache = DRAWING_CACHE
    key = id(sol)
    hit = cache.get(key)
    if hit is not None and hit[0] is sol:
        return hit[1]
    value = sampling.evaluator(res, sol.osc, sol.stop, sol.t_end, sol.x0, sol.v0, sol.method)
    cache.clear()  # one solution at a time: the last drawn
    cache[key] = (sol, value)
    return value


DRAWING_CACHE: dict[int, tuple[Solution, Any]] = {}


def phase_step(x_bounds: tuple[float, float], v_bounds: tuple[float, float]
               ) -> tuple[float, float]:
    """Longest chord along each axis [data units] for :data:`CHORD_PX` on the largest
    frame, for equal-aspect ranges that hold both bounds (dimensionless ``v``)."""
    (x0, x1), (v0, v1) = x_bounds, v_bounds
    per_px = max((x1 - x0) / PHASE_FRAME_MAX[0], (v1 - v0) / PHASE_FRAME_MAX[1], EMPTY_SPAN)
    return CHORD_PX * per_px, CHORD_PX * per_px


def trajectory_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                       columns: int = HISTORY_COLUMNS,
                       window: tuple[float, float] | None = None) -> dict[str, np.ndarray]:
    """Columns of the trajectory source (time histories and the animation): ``t``
    (shown units, also read by the animation), ``x``, ``v`` and
    ``mode``, reduced to the first, last, lowest and highest sample of each of
    ``columns`` pixel columns from samples of the exact motion
    (:func:`app.sampling.history`), and as many more of the ``window`` (dimensionless
    times) that the time histories show; ``bands`` holds the mode bands."""
    res = sol.result
    if res is None:
        return {**{k: f32([]) for k in ("t", "x", "v")},
                "mode": np.zeros(0, np.int8)}
    evaluate, exact = _drawing(sol)
    step = phase_step(*sample_bounds(sol))
    h = sampling.history(res, evaluate, sol.t_end, exact, columns, step, window)
    return {"t": f32(h.t * scales.time), "x": f32(h.x * scales.length),
            "v": f32(h.v * scales.velocity), "mode": np.asarray(h.mode, dtype=np.int8),
            "bands": h.bands}


def sample_bounds(sol: Solution) -> tuple[tuple[float, float], tuple[float, float]]:
    res = sol.result
    x, v = np.asarray(res.x, float), np.asarray(res.v, float)
    if len(x) == 0:
        return (0.0, 1.0), (0.0, 1.0)
    return (float(x.min()), float(x.max())), (float(v.min()), float(v.max()))


def phase_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                  step: tuple[float, float] | None = None) -> dict[str, Any]:
    """The phase portrait's path up to the end of the first steady cycle
    (:func:`app.sampling.draw_horizon`): per mode name the columns ``x``, ``v`` of its
    pieces (NaN between pieces), each piece sampled so that no chord is longer than
    ``step`` (default :func:`phase_step` of the samples' bounds); ``t_draw`` the time
    drawn to, and ``repeat`` the state where a steady cycle closes (drawn once) with the
    number of its repeats within the horizon."""
    res = sol.result
    empty = {"x": f32([]), "v": f32([])}
    out: dict[str, Any] = {name: dict(empty) for name in MODE_NAMES.values()}
    out["t_draw"], out["repeat"] = 0.0, {"x": f32([]), "v": f32([]), "text": []}
    if res is None or len(res.t) == 0:
        return out
    if step is None:
        step = phase_step(*sample_bounds(sol))
    evaluate, exact = _drawing(sol)
    t_draw = sampling.draw_horizon(res, sol.t_end, step)
    # Without the closed form, evaluating costs (a deformable stop's contacts: ~3 ms per
    # thousand points): the result's own samples are taken as they are.
    path = sampling.phase_path(res, evaluate, t_draw, step, known=not exact)
    x, v, mode = path.x * scales.length, path.v * scales.velocity, path.mode
    # Consecutive pieces meet at their transition's state, so each mode's runs are drawn
    # as they are, one NaN after each run to break the line.
    for m, name in MODE_NAMES.items():
        sel = mode == m
        keep = sel | np.r_[False, sel[:-1]]
        out[name] = {"x": f32(np.where(sel, x, np.nan)[keep]),
                     "v": f32(np.where(sel, v, np.nan)[keep])}
    out["t_draw"] = t_draw
    steady = res.steady
    if t_draw < sol.t_end and math.isfinite(steady.period) and steady.period > 0 and (
            steady.kind.value == "periodic"):
        repeats = int((sol.t_end - t_draw) // steady.period)
        xr, vr = evaluate(np.array([t_draw]))
        out["repeat"] = {"x": f32(xr * scales.length), "v": f32(vr * scales.velocity),
                         "text": [f"repeats {repeats}x"]}
    return out


def transition_columns(sol: Solution, scales: Scales = DIMENSIONLESS,
                       t_draw: float = math.inf) -> dict[str, list]:
    """Markers of the transitions the phase portrait draws (up to ``t_draw``; the later
    ones repeat them)."""
    res = sol.result
    trs = [tr for tr in res.transitions if tr.t <= t_draw] if res is not None else []
    trs = trs[-MAX_MARKERS:]
    styles = [TRANSITION_STYLE.get(tr.kind.value, ("circle", "#000000")) for tr in trs]
    return {
        "x": f32([tr.x * scales.length for tr in trs]),
        "v": f32([tr.v * scales.velocity for tr in trs]),
        "t": f32([tr.t * scales.time for tr in trs]),
        "kind": [tr.kind.value for tr in trs],
        "marker": [s[0] for s in styles],
        "color": [s[1] for s in styles],
    }


def band_columns(bands, scales: Scales = DIMENSIONLESS) -> dict[str, Any]:
    """Mode bands behind the time histories: ``left``, ``right``, ``color``, from
    :func:`app.sampling.mode_bands` (a stick interval narrower than a pixel column covers
    the column)."""
    left, right, mode = bands
    return {
        "left": f32(np.asarray(left) * scales.time),
        "right": f32(np.asarray(right) * scales.time),
        "color": [BAND_COLORS[int(m)] for m in mode],
    }


def reference_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """The thin references of the phase portrait: Gamma_0, the impactless limit cycle (or
    the pure slip circle of a fast belt), and the theory's steady-state points."""
    empty = {"x": f32([]), "v": f32([])}
    th = sol.theory
    if th is None:
        return {"gamma0": empty, "cycle": empty, "removed": empty,
                "points": theory_points({}, scales)}
    a, v = sol.osc.a, sol.osc.v
    phi = np.linspace(0.0, 2.0 * math.pi, CIRCLE_VERTICES)
    gamma0 = {"x": f32((a + th.gamma0_radius * np.cos(phi)) * scales.length),
              "v": f32(th.gamma0_radius * np.sin(phi) * scales.velocity)}
    if th.fast or th.limit_cycle is None:
        radius = th.critical_speed
        cycle = {"x": f32((a + radius * np.cos(phi)) * scales.length),
                 "v": f32(radius * np.sin(phi) * scales.velocity)}
    else:
        lc = th.limit_cycle
        cx = lc.centre[0] + lc.radius * np.cos(phi)
        cv = lc.radius * np.sin(phi)
        # The slip arc is the part of the circle below the stick line x' = v.
        arc = cv <= v * (1 + 1e-12)
        cv = np.where(arc, cv, np.nan)
        start = int(np.argmax(~arc)) if (~arc).any() else len(phi)
        order = np.r_[start:len(phi), 0:start]  # begin the arc inside the cut
        cx, cv = cx[order], cv[order]
        cx = np.r_[cx, np.nan, lc.stick_start[0], lc.stick_end[0]]
        cv = np.r_[cv, np.nan, v, v]
        cycle = {"x": f32(cx * scales.length), "v": f32(cv * scales.velocity)}
    return {"gamma0": gamma0, "cycle": cycle, "removed": removed_circle(sol, scales),
            "points": theory_points(th.points, scales, a)}


def removed_circle(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, np.ndarray]:
    """The pure slip circle the mass would follow if the stop were removed once it rests
    pressed on it (paper Sec. 4.6, dotted in Figs. 6b and 7d): centre ``(a, 0)`` through
    the rest point ``(x_bar, 0)``. Empty unless the motion ends at rest on a rigid stop
    short of ``a`` on a moving belt."""
    res, stop = sol.result, sol.stop
    a = sol.osc.a
    if (res is None or stop is None or sol.values["stop_type"] != "rigid"
            or res.steady.kind.value != "rest" or sol.osc.v <= 0 or stop.clearance >= a):
        return {"x": f32([]), "v": f32([])}
    radius = a - stop.clearance
    phi = np.linspace(0.0, 2.0 * math.pi, CIRCLE_VERTICES)
    return {"x": f32((a + radius * np.cos(phi)) * scales.length),
            "v": f32(radius * np.sin(phi) * scales.velocity)}



FORCE_TITLE = "Contact force"
#: What the contact-force plot's left axis shows, by run (:func:`force_quantity`).
IMPULSES, CONTACT_FORCE, PROGRAM_FORCE = ("impulses", "contact force",
                                          "contact force over the program phase")


def force_quantity(sol: Solution) -> str:
    """What the contact-force plot draws of ``sol`` on its left axis: a rigid stop's
    impulses (:data:`IMPULSES`), the overlap program's force over its phase
    (:data:`PROGRAM_FORCE`), otherwise the contact force over time (:data:`CONTACT_FORCE`).
    Runs of different quantities are not drawn on one axis.

    >>> from app.state import scene_values
    >>> from app.solve.pool import solve
    >>> force_quantity(solve(scene_values("7c"))), force_quantity(solve(scene_values("10")))
    ('impulses', 'contact force')
    """
    if sol.program is not None:
        return PROGRAM_FORCE
    return IMPULSES if sol.values["stop_type"] == "rigid" else CONTACT_FORCE


def force_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Contact force: rigid impulses as stems (``t``, ``j``) and, once the mass rests on a
    rigid stop, the force that holds it there (``rest``: ``k (a - x_bar)``, docs/physics.md,
    "Rest at the stop"; on an axis of its own); deformable ``phi(t)``."""
    res, prog = sol.result, sol.program
    stems = {"t": f32([]), "j": f32([])}
    line = {"t": f32([]), "phi": f32([])}
    rest = {"t": f32([]), "f": f32([])}
    if prog is not None:
        line = {"t": f32(prog.s), "phi": f32(prog.force * scales.force)}
    elif res is not None and sol.values["stop_type"] == "rigid":
        # Every stored impact (the core stores the first ``transition_cap``).
        imp = np.asarray(res.impulses).reshape(-1, 2)
        stems = {"t": f32(imp[:, 0] * scales.time), "j": f32(imp[:, 1] * scales.impulse)}
        pressed = np.asarray(res.mode) == int(Mode.CONTACT)
        if pressed.any():
            idx = _columns(res, (np.asarray(res.contact_force),))
            f = np.where(pressed[idx], np.asarray(res.contact_force)[idx], np.nan)
            rest = {"t": f32(res.t[idx] * scales.time), "f": f32(f * scales.force)}
    elif res is not None and sol.values["stop_type"] == "hysteretic":
        t, phi = _thinned(res, (np.asarray(res.contact_force),))
        line = {"t": f32(t * scales.time), "phi": f32(phi * scales.force)}
    return {"stems": stems, "line": line, "rest": rest}


def _columns(res, series: tuple[np.ndarray, ...]) -> np.ndarray:
    """Indices of the result's samples that draw ``series`` over time as every sample
    would, on :data:`HISTORY_COLUMNS` pixel columns (:func:`app.sampling.m4`)."""
    t = np.asarray(res.t, float)
    if len(t) == 0:
        return np.zeros(0, np.int64)
    return sampling.m4(t, series, float(t[0]), float(t[-1]), HISTORY_COLUMNS)


def _thinned(res, series: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """``t`` and ``series`` at the samples that draw them, on one axis, as every sample
    would: reduced per pixel column (:func:`_columns`), then thinned
    (:func:`app.sampling.thin`)."""
    idx = _columns(res, series)
    t = np.asarray(res.t, float)[idx]
    ys = tuple(np.asarray(y, float)[idx] for y in series)
    tol = sampling.thin_tolerance(*ys)
    keep = sampling.thin(t, ys, (tol,) * len(ys))
    return (t[keep], *(y[keep] for y in ys))


def loop_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Hysteresis loop ``phi`` vs overlap in contact, and both envelopes of the stop."""
    stop = sol.stop
    empty = {"d": f32([]), "phi": f32([])}
    if sol.values["stop_type"] != "hysteretic" or stop is None:
        return {"loop": empty, "comp": empty, "exp": empty}
    if sol.program is not None:
        d, phi = sol.program.overlap, sol.program.force
    elif sol.result is not None:
        ov, f = np.asarray(sol.result.overlap), np.asarray(sol.result.contact_force)
        inside = ov > 0
        # Break the line between contacts so separate loops are not joined.
        gap = np.concatenate(([False], np.diff(inside.astype(int)) == 1))
        d = np.where(inside, ov, np.nan)
        phi = np.where(inside, f, np.nan)
        keep = inside | np.roll(inside, -1) | gap
        d, phi = d[keep][-MAX_LOOP_POINTS:], phi[keep][-MAX_LOOP_POINTS:]
    else:
        d = phi = np.zeros(0)
    d_max = float(np.nanmax(d)) if np.isfinite(d).any() else stop.limit_overlap / 2
    grid = np.linspace(0.0, min(1.15 * d_max, 0.95 * stop.limit_overlap), ENVELOPE_SAMPLES)
    return {
        "loop": {"d": f32(d * scales.length), "phi": f32(phi * scales.force)},
        "comp": {"d": f32(grid * scales.length),
                 "phi": f32(phi_compression(grid, stop) * scales.force)},
        "exp": {"d": f32(grid * scales.length),
                "phi": f32(phi_expansion(grid, stop) * scales.force)},
    }


def friction_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """Coulomb's law (paper Fig. 1b) over the relative velocity ``u_r = v - x'``, and the
    operating points of the trajectory: ``(u_r, a sign(u_r))`` in slip and ``(0, x +
    phi/k)`` in stick (the friction that holds the mass)."""
    a, b = sol.osc.a, sol.osc.b
    res = sol.result
    u_max = 1.2 * max(float(np.max(np.abs(sol.osc.v - res.v))) if res is not None and
                      len(res.v) else 0.0, sol.osc.v, 1e-3)
    fs, us = scales.force, scales.velocity
    law = {"u": f32(np.array([-u_max, 0.0, 0.0, 0.0, 0.0, u_max]) * us),
           "f": f32(np.array([-a, -a, -b, b, a, a]) * fs)}
    if res is None:
        return {"law": law, "ops": {"u": f32([]), "f": f32([]), "color": []}}
    idx = np.linspace(0, len(res.t) - 1, min(len(res.t), MAX_OPERATING_POINTS)).astype(int)
    u = sol.osc.v - res.v[idx]
    mode = res.mode[idx]
    hold = res.x[idx] + np.asarray(res.contact_force)[idx]
    f = np.where(mode == Mode.STICK, hold, a * np.sign(u))
    u = np.where(mode == Mode.STICK, 0.0, u)
    return {"law": law, "ops": {"u": f32(u * us), "f": f32(f * fs),
                                "color": [MODE_COLORS[int(m)] for m in mode]}}


def energy_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, np.ndarray]:
    """Cumulative energy terms (per unit ``k``; in SI, joules), as a budget of what the belt
    puts in: ``belt_input = (mechanical - mechanical[0]) + friction_heat + stop_loss +
    stop_stored``, where ``friction_heat = belt_input - friction_work`` is the heat of the
    sliding contact (``int F u_r dt >= 0``) and ``friction_work`` the work of friction on
    the mass (:class:`core.Energy`)."""
    res = sol.result
    names = tuple(ENERGY_COLORS)
    if res is None:
        return {"t": f32([]), **{n: f32([]) for n in names}}
    e = res.energy
    terms = {"mechanical": e.mechanical, "belt_input": e.belt_input,
             "friction_heat": np.asarray(e.belt_input) - np.asarray(e.friction_work),
             "stop_loss": e.stop_loss, "stop_stored": e.stop_stored}
    t, *ys = _thinned(res, tuple(np.asarray(terms[n], float) for n in names))
    cols = {"t": f32(t * scales.time)}
    for n, y in zip(names, ys, strict=True):
        cols[n] = f32(y * scales.energy)
    return cols
