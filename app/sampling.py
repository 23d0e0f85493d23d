"""What the plots draw of a solution: arrays sampled from the exact motion for the screen.

A fixed number of samples over the horizon cannot draw a long run: at ``t_end = 5000`` a
slip circle gets a sample every few radians, so the phase portrait turns into chords and
the time histories alias into false envelopes. The plots are therefore drawn from the
solution as a function of time (:func:`evaluator`), sampled for the screen:

* the phase portrait (:func:`phase_path`) shows the motion up to the end of its first
  steady cycle (a periodic steady state is drawn once, as a closed orbit; its repeats are
  only counted), each piece between two transitions sampled so that no chord is longer
  than a given length on the screen. A slip arc is a circle traversed at one radian per
  unit of dimensionless time (paper Eq. 7), so equal times are equal arc lengths and a
  chord bound is a bound on the curvature error too;
* the time histories (:func:`history`) are decimated per pixel column to the first, last,
  lowest and highest sample of the column (an "M4" reduction), so that the drawn line
  covers exactly what a line through every sample would cover, whatever the horizon; the
  periodic part of a steady state is evaluated for one cycle and tiled;
* the mode bands (:func:`history` too) keep every stick or contact interval: one narrower
  than a pixel column is widened to the column, so it stays visible as a stated aggregate;
* the contact force and the energies over time are then thinned (:func:`thin`): a
  sample goes where the line without it stays within :data:`THIN_PX` of a pixel of the
  line through every sample, on the tallest frame a plot gets. A browser paints every
  point of a line, and a flat or slowly bending stretch needs few (a contact force that
  is zero between contacts, the cumulative energies); x(t) and x'(t), made of slip arcs,
  would keep most of theirs, so they are not (benchmarks/results/2026-11-28-thinning.md).

The functions are pure (arrays in, arrays out) and tested without a browser
(tests/app/test_sampling.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from core import (
    HystereticStop,
    Mode,
    Result,
    SteadyCycle,
    SteadyKind,
    TransitionKind,
    first_cycle_end,
    simulate,
    steady_cycle,
)

#: Largest time step [dimensionless time = radians of a slip arc] of the first pass over a
#: piece of the phase path; the second pass subdivides where a chord is still too long.
PATH_DT = 0.05
#: Of the result's own samples :func:`phase_path` keeps one per step of arc length, and at
#: least one per this many ``PATH_DT`` of time: the chords between them are then
#: subdivided as any (a turn of a circle cannot hide between samples 0.2 radians apart).
KNOWN_DT_FACTOR = 4.0
#: Passes of subdivision of the phase path's chords longer than a step at most.
SUBDIVISION_PASSES = 3
#: Result samples closer than this fraction of the horizon (at least of one unit of time)
#: to a transition are not taken as they are by :func:`phase_path`: at an impact the
#: velocity jumps, and such a sample may hold either side's.
BREAK_TOL = 1e-9
#: Points of the phase path at most (a run that never settles, at a long horizon).
MAX_PATH_POINTS = 60_000
#: Step [radians] of the fine samples the time histories are reduced from: a sampled
#: extremum of a slip arc of radius R misses the true one by at most ``R (1 - cos(dt/2))``,
#: 1.2e-3 R at 0.1, a tenth of a pixel in a 200 px high plot.
HISTORY_DT = 0.1
#: Fine samples of the time histories at most; past it the step grows with the horizon.
MAX_HISTORY_SAMPLES = 60_000
#: Largest distance [px] between a thinned line and the line through all its samples
#: (:func:`thin`): below what anti-aliasing shows.
THIN_PX = 0.25
#: Tallest frame [px] a plot over time gets (the presentation mode's single row on a
#: 1440-line screen): the thinning's pixel is a pixel of this frame, a smaller one of any
#: other.
THIN_FRAME_PX = 1400
#: The mode that follows each kind of transition.
MODE_AFTER: dict[str, int] = {
    TransitionKind.SLIP_STICK.value: int(Mode.STICK),
    TransitionKind.STICK_SLIP.value: int(Mode.SLIP),
    TransitionKind.SIGN_CHANGE.value: int(Mode.SLIP),
    TransitionKind.IMPACT.value: int(Mode.SLIP),
    TransitionKind.STICK_IMPACT.value: int(Mode.SLIP),
    TransitionKind.ACCUMULATION.value: int(Mode.CONTACT),
    TransitionKind.REST.value: int(Mode.CONTACT),
    TransitionKind.CONTACT.value: int(Mode.CONTACT),
    TransitionKind.SEPARATION.value: int(Mode.SLIP),
    TransitionKind.REVERSAL.value: int(Mode.CONTACT),
    TransitionKind.FAILURE.value: int(Mode.SLIP),
}

Evaluate = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


def _cat(*parts) -> np.ndarray:
    """``np.r_[parts]`` for 1-d arrays and scalars, without its index-trick parsing (a
    tenth of the time; called some fifty times per drawn solution)."""
    return np.concatenate([np.atleast_1d(p) for p in parts])


def evaluator(result: Result, osc, stop, t_end: float, x0: float, v0: float,
              method: str) -> tuple[Evaluate, bool]:
    """``f(t) -> (x, v)`` on the solution, and whether it is the exact closed form.

    The result's own dense solution (:meth:`core.Result.evaluate`) when it has one; for the
    closed-form method without a deformable stop, the same closed form evaluated at the
    asked times (``simulate(..., t_eval=t)``, which stores no transitions, so it costs only
    the evaluation); otherwise linear interpolation between the result's samples, which
    the solve then takes dense enough (:func:`samples_for`).
    """
    closed_form = method == "exact" and not isinstance(stop, HystereticStop)
    if result.dense is not None:
        # An integrated solution's interpolant is not the closed form: its grazing tail is
        # no exact repeat of a cycle, so it is drawn from its samples, not tiled.
        return (lambda t: result.evaluate(np.asarray(t, dtype=float), -1)), closed_form
    if closed_form:
        def exact(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            t = np.asarray(t, dtype=float)
            if len(t) == 0:
                return np.zeros(0), np.zeros(0)
            res = simulate(osc, stop, t_end, x0, v0, t_eval=np.clip(t, 0.0, t_end),
                           transition_cap=0)
            return np.asarray(res.x), np.asarray(res.v)
        return exact, True
    ts, xs, vs = (np.asarray(a, dtype=float) for a in (result.t, result.x, result.v))

    def interpolate(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(t, dtype=float)
        return np.interp(t, ts, xs), np.interp(t, ts, vs)
    return interpolate, False


def samples_for(t_end: float, n_samples: int) -> int:
    """Samples a method that offers only samples must return for the pictures: at least
    ``n_samples``, and one per :data:`HISTORY_DT` / 2 of the horizon (so that interpolated
    slip arcs stay within a pixel), at most :data:`MAX_HISTORY_SAMPLES`.

    >>> samples_for(60.0, 1600), samples_for(5000.0, 1600)
    (1600, 60000)
    """
    return int(max(n_samples, min(MAX_HISTORY_SAMPLES, math.ceil(2.0 * t_end / HISTORY_DT))))


def draw_horizon(result: Result, t_end: float, step: tuple[float, float]) -> float:
    """Time up to which the phase portrait draws the motion: the end of its first steady
    cycle (:func:`core.steady.first_cycle_end`), where ``step`` is the chord bound (data
    units per axis) and the transitions count as settled within half of it."""
    return first_cycle_end(result, t_end, step)


@dataclass(frozen=True)
class Path:
    """The phase path: samples ``t, x, v`` in time order and the ``mode`` of the piece
    that ends at each sample (a transition is one sample of each side; an impact two
    samples at one time, before and after)."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    mode: np.ndarray


def _pieces(result: Result, t_hi: float):
    """Breakpoints in ``[0, t_hi]`` with the exact states on both sides of each transition,
    and the mode of the piece after each breakpoint."""
    t0 = float(result.t[0]) if len(result.t) else 0.0
    mode0 = int(result.mode[0]) if len(result.mode) else int(Mode.SLIP)
    x0 = float(result.x[0]) if len(result.x) else 0.0
    v0 = float(result.v[0]) if len(result.v) else 0.0
    bt, bx, bv_in, bv_out, bmode = [t0], [x0], [v0], [v0], [mode0]
    mode = mode0
    for tr in result.transitions:
        if tr.t > t_hi:
            break
        mode = MODE_AFTER.get(tr.kind.value, mode)
        if tr.t == bt[-1]:  # several transitions at one time: one breakpoint
            bv_out[-1], bmode[-1] = tr.v_after, mode
            continue
        bt.append(tr.t)
        bx.append(tr.x)
        bv_in.append(tr.v)
        bv_out.append(tr.v_after)
        bmode.append(mode)
    return (np.array(bt), np.array(bx), np.array(bv_in), np.array(bv_out),
            np.array(bmode, dtype=np.int8))


def phase_path(result: Result, evaluate: Evaluate, t_hi: float,
               step: tuple[float, float], known: bool = False) -> Path:
    """The motion over ``[0, t_hi]`` in the phase plane, each piece between transitions
    sampled so that consecutive samples are at most one ``step`` apart, where ``step =
    (dx, dv)`` is the length in data units of the longest chord allowed along each axis
    (the caller derives it from the frame's pixels per unit).

    With ``known``, the result's own samples (values of the same solution, which
    ``evaluate`` would compute again) are taken as they are, and only the gaps between them
    are evaluated: where evaluating is costly (a deformable stop's contacts) the path
    costs a fraction of the evaluations."""
    bt, bx, bv_in, bv_out, bmode = _pieces(result, t_hi)
    ends = _cat(bt[1:], t_hi)
    length = np.maximum(ends - bt, 0.0)
    # First pass: PATH_DT at most, within the point budget.
    dt = max(PATH_DT, float(length.sum()) / MAX_PATH_POINTS)
    if known:
        times, x, v, piece, last = _first_pass_from_samples(result, evaluate, bt, ends,
                                                            t_hi, dt, step)
    else:
        n = np.maximum(1, np.ceil(length / dt).astype(np.int64))
        times, piece = _interior(bt, length, n)
        x, v = evaluate(_cat(times, t_hi))
        x, v, last = x[:-1], v[:-1], (x[-1:], v[-1:])
    # Then subdivide each interval whose chord is longer than a step, again where a chord
    # still is (the speed along the curve changes within an interval: in a contact one
    # pass left chords of 4.6 steps).
    for _ in range(SUBDIVISION_PASSES):
        if not len(times):
            break
        full_t, full_x, full_v, full_p = _with_ends(times, x, v, piece, bt, bx, bv_in,
                                                    bv_out, ends, last)
        chord = np.hypot(np.diff(full_x) / step[0], np.diff(full_v) / step[1])
        same = np.diff(full_p) == 0
        extra = np.where(same & np.isfinite(chord), np.maximum(np.ceil(chord) - 1, 0), 0
                         ).astype(np.int64)
        room = MAX_PATH_POINTS - len(times)
        if extra.sum() > room:  # within the budget: fewer points everywhere
            extra = np.floor(extra * (max(room, 0) / extra.sum())).astype(np.int64)
        if extra.sum() == 0:
            break
        k = np.repeat(np.arange(len(extra)), extra)
        frac = (_ranks(extra) + 1.0) / (extra[k] + 1.0)
        new_t = full_t[k] + frac * (full_t[k + 1] - full_t[k])
        nx, nv = evaluate(new_t)
        times = _cat(times, new_t)
        x, v = _cat(x, nx), _cat(v, nv)
        piece = _cat(piece, full_p[k])
    t_all, x_all, v_all, p_all = _with_ends(times, x, v, piece, bt, bx, bv_in, bv_out, ends,
                                            last)
    return Path(t=t_all, x=x_all, v=v_all, mode=bmode[p_all])


def _first_pass_from_samples(result: Result, evaluate: Evaluate, bt: np.ndarray,
                             ends: np.ndarray, t_hi: float, dt: float,
                             step: tuple[float, float]):
    """The first pass of :func:`phase_path` from the result's samples strictly inside the
    pieces (none within :data:`BREAK_TOL` of a transition, where a sample may hold either
    side's velocity), at most one per ``step`` of arc length or :data:`KNOWN_DT_FACTOR`
    ``dt`` of time, every gap longer than that filled by evaluation at equal steps.
    Returns ``times, x, v, piece`` (unordered) and the state at ``t_hi``."""
    st, sx, sv = (np.asarray(a, dtype=float) for a in (result.t, result.x, result.v))
    tol = BREAK_TOL * max(1.0, t_hi)
    p = np.searchsorted(bt, st, side="right") - 1
    keep = (p >= 0) & (st < t_hi - tol) & np.isfinite(sx) & np.isfinite(sv)
    p = np.clip(p, 0, len(bt) - 1)
    keep &= (st > bt[p] + tol) & (st < ends[p] - tol)
    st, sx, sv, p = st[keep], sx[keep], sv[keep], p[keep]
    coarse = KNOWN_DT_FACTOR * dt
    if len(st) > 1:
        # No more of them than the picture needs: one per step of arc length (the
        # solver's samples are denser than that on most of the path) or per ``dt`` of time.
        arc = _cat(0.0, np.cumsum(np.hypot(np.diff(sx) / step[0], np.diff(sv) / step[1])))
        new = _cat(True, (np.diff(p) != 0) | (np.diff(np.floor(arc)) != 0)
                   | (np.diff(np.floor((st - bt[p]) / coarse)) != 0))
        st, sx, sv, p = st[new], sx[new], sv[new], p[new]
    if len(st) > MAX_PATH_POINTS:  # within the budget: every k-th
        every = math.ceil(len(st) / MAX_PATH_POINTS)
        st, sx, sv, p = st[::every], sx[::every], sv[::every], p[::every]
    m = len(bt)
    # Known times of each piece in order (its ends, its samples); the gaps between them.
    kt, kp = _cat(bt, st, ends), _cat(np.arange(m), p, np.arange(m))
    order = np.lexsort((kt, _cat(np.zeros(m), np.ones(len(st)), np.full(m, 2.0)), kp))
    kt, kp = kt[order], kp[order]
    gap = np.diff(kt)
    fill = np.where(np.diff(kp) == 0, np.maximum(np.ceil(gap / coarse) - 1, 0), 0
                    ).astype(np.int64)
    k = np.repeat(np.arange(len(fill)), fill)
    new_t = kt[k] + (_ranks(fill) + 1.0) / (fill[k] + 1.0) * gap[k]
    nx, nv = evaluate(_cat(new_t, t_hi))
    return (_cat(st, new_t), _cat(sx, nx[:-1]), _cat(sv, nv[:-1]), _cat(p, kp[k]),
            (nx[-1:], nv[-1:]))


def _ranks(counts: np.ndarray) -> np.ndarray:
    """0, 1, ..., c-1 for each count ``c``, concatenated."""
    total = int(counts.sum())
    starts = np.repeat(np.cumsum(counts) - counts, counts)
    return np.arange(total) - starts


def _interior(bt: np.ndarray, length: np.ndarray, n: np.ndarray):
    """Times strictly inside each piece, ``n - 1`` equal steps, and the piece of each."""
    inner = n - 1
    piece = np.repeat(np.arange(len(bt)), inner)
    frac = (_ranks(inner) + 1.0) / n[piece]
    return bt[piece] + frac * length[piece], piece


def _with_ends(times, x, v, piece, bt, bx, bv_in, bv_out, ends, last):
    """Interior samples plus the exact states at each piece's ends, in time order: the
    state after the transition that opens a piece and the one before the transition that
    closes it (at an impact the two differ in velocity only); ``last`` is the state at the
    end of the last piece, which is not a transition."""
    m = len(bt)
    xe, ve = last
    if ends[-1] == bt[-1]:  # a transition at the end: the last piece is its state after
        xe, ve = bx[-1:], bv_out[-1:]
    end_x = _cat(bx[1:], xe)
    end_v = _cat(bv_in[1:], ve)
    t = _cat(bt, times, ends)
    xx = _cat(bx, x, end_x)
    vv = _cat(bv_out, v, end_v)
    pp = _cat(np.arange(m), piece, np.arange(m))
    # Order: by piece, then start, interior by time, end.
    rank = _cat(np.zeros(m), np.ones(len(times)), np.full(m, 2.0))
    order = np.lexsort((t, rank, pp))
    t, xx, vv, pp = t[order], xx[order], vv[order], pp[order]
    return t, xx, vv, pp


@dataclass(frozen=True)
class History:
    """Time histories reduced to what ``columns`` pixel columns show: samples ``t, x, v``
    in time order and the ``mode`` at each; the mode ``bands`` (``left, right, mode``)."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    mode: np.ndarray
    bands: tuple[np.ndarray, np.ndarray, np.ndarray]


def fine_samples(result: Result, evaluate: Evaluate, t_end: float, exact: bool,
                 cycle: SteadyCycle | None = None, column_width: float = 0.0):
    """Samples of the whole horizon at :data:`HISTORY_DT` or finer, with the exact states
    on both sides of each transition. A steady ``cycle`` (:func:`core.steady.steady_cycle`) is
    evaluated for one period and tiled; a mass at rest (on the stop or in equilibrium) is
    evaluated up to the time it stops. Returns ``t, x, v, mode``.

    When a pixel column (``column_width``) is at least a period long, every column holds
    every phase of the cycle, so its extremes are the cycle's: the tiles then carry only
    the cycle's extreme samples and the ends of its mode runs."""
    if not exact:
        return (np.asarray(result.t, float), np.asarray(result.x, float),
                np.asarray(result.v, float), np.asarray(result.mode, np.int8))
    steady = result.steady
    periodic = cycle is not None
    still = (steady.kind in (SteadyKind.REST, SteadyKind.EQUILIBRIUM)
             and math.isfinite(steady.t_reached) and steady.t_reached < t_end)
    if periodic:
        t_hi = cycle[0] + cycle[1]
        # The tiles add (t_end - t_reached) / period copies of the cycle's samples.
        dt = max(HISTORY_DT, t_end / MAX_HISTORY_SAMPLES)
    else:
        t_hi = steady.t_reached if still else t_end
        dt = max(HISTORY_DT, t_hi / MAX_HISTORY_SAMPLES)
    bt, bx, bv_in, bv_out, bmode = _pieces(result, t_hi)
    ends = _cat(bt[1:], t_hi)
    length = np.maximum(ends - bt, 0.0)
    n = np.maximum(1, np.ceil(length / dt).astype(np.int64))
    times, piece = _interior(bt, length, n)
    x, v = evaluate(_cat(times, t_hi, t_end))
    tail_x, tail_v = x[-1:], v[-1:]
    x, v, last = x[:-2], v[:-2], (x[-2:-1], v[-2:-1])
    t, x, v, p = _with_ends(times, x, v, piece, bt, bx, bv_in, bv_out, ends, last)
    mode = bmode[p]
    if still:  # the state at t_reached holds to the horizon
        return (_cat(t, t_end), _cat(x, tail_x), _cat(v, tail_v),
                _cat(mode, mode[-1:]))
    if not periodic:
        return t, x, v, mode
    t0, period = cycle
    # The cycle: its pieces' samples from t0 on. A transition at t0 ends a piece that is
    # not part of the cycle: its state before (an impact's approach speed) happens once,
    # not every period (a plastic impact onto a grazing circle drew a spike each turn).
    cyc = (t > t0) | ((t == t0) & (bt[p] >= t0))
    # One copy of the cycle without its closing end (it is the next copy's start), which
    # is the left limit at each repeat of t0: the tiles open with it.
    ct, cx, cv, cm = t[cyc], x[cyc], v[cyc], mode[cyc]
    keep = ct < t0 + period * (1.0 - 1e-12)
    closing = (ct[-1:] - t0, cx[-1:], cv[-1:], cm[-1:])
    ct, cx, cv, cm = ct[keep] - t0, cx[keep], cv[keep], cm[keep]
    if (~cyc & (t == t0)).any():
        ct, cx, cv, cm = (_cat(0.0, ct), _cat(closing[1], cx), _cat(closing[2], cv),
                          _cat(closing[3], cm))
    if column_width >= period and len(ct) > 2:
        run = np.flatnonzero(cm[1:] != cm[:-1])
        key = np.unique(_cat(0, len(ct) - 1, run, run + 1, np.argmin(cx), np.argmax(cx),
                             np.argmin(cv), np.argmax(cv)))
        ct, cx, cv, cm = ct[key], cx[key], cv[key], cm[key]
    copies = int(math.ceil((t_end - t0) / period))
    tt = (ct[None, :] + (t0 + period * np.arange(copies))[:, None]).ravel()
    n_in = int(np.searchsorted(tt, t_end, side="right"))
    pre = ~cyc

    def join(head, cycle, tail):
        return np.concatenate((head[pre], np.tile(cycle, copies)[:n_in], tail))
    return (np.concatenate((t[pre], tt[:n_in], [t_end])), join(x, cx, tail_x),
            join(v, cv, tail_v), join(mode, cm, cm[-1:]))


def m4(t: np.ndarray, series: tuple[np.ndarray, ...], t_lo: float, t_hi: float,
       columns: int) -> np.ndarray:
    """Indices to keep so that a line through them fills each of ``columns`` pixel
    columns over ``[t_lo, t_hi]`` exactly as a line through every sample would: per column
    the first and last sample and the lowest and highest of each series.

    >>> t = np.linspace(0.0, 1.0, 101); y = np.sin(40 * t)
    >>> idx = m4(t, (y,), 0.0, 1.0, 5)
    >>> len(idx) <= 4 * 5, float(y[idx].max()) == float(y.max())
    (True, True)
    """
    n = len(t)
    if n <= 4 * columns:
        return np.arange(n)
    width = (t_hi - t_lo) / columns if t_hi > t_lo else 1.0
    col = np.clip(((t - t_lo) / width).astype(np.int64), 0, columns - 1)
    starts = np.flatnonzero(_cat(True, col[1:] != col[:-1]))
    ends = _cat(starts[1:], n) - 1
    keep = np.zeros(n, dtype=bool)
    keep[starts] = keep[ends] = True
    group = np.repeat(np.arange(len(starts)), np.diff(np.append(starts, n)))
    for y in series:
        y = np.where(np.isfinite(y), y, 0.0)
        for red in (np.maximum, np.minimum):
            hit = np.flatnonzero(y == red.reduceat(y, starts)[group])
            # The first sample of each column that attains the column's extreme.
            first = np.ones(len(hit), dtype=bool)
            first[1:] = group[hit][1:] != group[hit][:-1]
            keep[hit[first]] = True
    return np.flatnonzero(keep)


def thin(t: np.ndarray, series: tuple[np.ndarray, ...], tolerances: tuple[float, ...]
         ) -> np.ndarray:
    """Indices of the samples to keep so that, for each series, the line through the kept
    samples is within its tolerance of the line through all of them at every ``t``; the
    ends, each series' largest and smallest value, samples that share a time
    (a jump) and the neighbours of non-finite values (breaks) always stay.

    Bottom up, in passes over the kept samples (each pass costs their number): every
    other one goes at once where the chord over its two neighbours passes within
    tolerance of every sample it spans, as bounded by its own distance to that chord plus
    what the spans dropped before (a bound, not a check of each sample); then the other
    parity; until neither drops any.

    >>> t = np.linspace(0.0, 1.0, 101)
    >>> idx = thin(t, (2.0 * t,), (1e-9,))
    >>> idx.tolist()
    [0, 100]
    """
    t = np.asarray(t, dtype=float)
    n = len(t)
    if n <= 2:
        return np.arange(n)
    ys = [np.asarray(y, dtype=float) for y in series]
    must = np.zeros(n, dtype=bool)
    must[[0, -1]] = True
    jump = np.diff(t) <= 0.0
    must[1:] |= jump
    must[:-1] |= jump
    for y in ys:
        bad = ~np.isfinite(y)
        must |= bad
        must[1:] |= bad[:-1]
        must[:-1] |= bad[1:]
        if not bad.all():
            must[[np.nanargmax(y), np.nanargmin(y)]] = True
    # Deviations in units of each series' tolerance (a series of no span has none).
    scale = np.array([1.0 / tol if tol > 0.0 else 0.0 for tol in tolerances])
    z = np.vstack(ys) * scale[:, None]
    kept = np.arange(n)
    # Per interval between two kept samples, a bound on how far the samples dropped inside
    # it lie from its chord, in tolerances: a sample's distance to a new chord is at most
    # its distance to the old one plus the dropped vertex's (the two chords are linear
    # between the same ends).
    inherited = np.zeros(n - 1)
    idle, parity = 0, 1
    while idle < 2 and len(kept) > 2:
        m = len(kept)
        pos = np.arange(max(parity, 2 - parity), m - 1, 2)
        parity = 1 - parity
        c, lo, hi = kept[pos], kept[pos - 1], kept[pos + 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            w = (t[c] - t[lo]) / (t[hi] - t[lo])
            z_lo = z[:, lo]
            dev = np.abs(z[:, c] - z_lo - (z[:, hi] - z_lo) * w).max(axis=0)
            bound = np.maximum(inherited[pos - 1], inherited[pos]) + dev
            # (a span of no time or with a break gives nan: its vertex stays)
            fits = (bound <= 1.0) & ~must[c]
        if not fits.any():
            idle += 1
            continue
        idle = 0
        inherited[pos[fits] - 1] = bound[fits]
        stays = np.ones(m, dtype=bool)
        stays[pos[fits]] = False
        kept, inherited = kept[stays], inherited[stays[:-1]]
    return kept


def thin_tolerance(*series: np.ndarray) -> float:
    """The thinning tolerance (data units) of lines drawn on one axis: :data:`THIN_PX` of
    a :data:`THIN_FRAME_PX` frame that spans them (the axis spans at least that)."""
    finite = [y[np.isfinite(y)] for y in (np.asarray(s, dtype=float) for s in series)]
    finite = [y for y in finite if len(y)]
    if not finite:
        return 0.0
    span = max(float(y.max()) for y in finite) - min(float(y.min()) for y in finite)
    return THIN_PX * span / THIN_FRAME_PX


def mode_bands(t: np.ndarray, mode: np.ndarray, t_lo: float, t_hi: float, columns: int):
    """Mode bands ``(left, right, mode)`` of the samples: every run of one mode; a stick or
    contact run narrower than a pixel column covers its column (drawn above the slip
    bands, which come first), so that no such interval vanishes at a long horizon."""
    if len(t) == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, np.int8)
    change = np.flatnonzero(np.diff(mode) != 0) + 1
    starts = _cat(0, change)
    stops = _cat(change, len(t) - 1)
    left, right, m = t[starts].astype(float), t[stops].astype(float), mode[starts]
    width = (t_hi - t_lo) / columns
    other = m != int(Mode.SLIP)
    narrow = other & (right - left < width)
    col = np.floor((left[narrow] - t_lo) / width)
    left[narrow] = t_lo + col * width
    right[narrow] = t_lo + (col + 1.0) * width
    order = np.argsort(other, kind="stable")  # slip first, the others over it
    left, right, m = left[order], right[order], m[order]
    # Merge neighbouring bands of one mode that touch or overlap (a column of stick per
    # period of a long run becomes a few wide bands instead of thousands).
    out_l, out_r, out_m = [], [], []
    for mode_k in np.unique(m):
        sel = m == mode_k
        ll, rr = left[sel], right[sel]
        o = np.argsort(ll, kind="stable")
        ll, rr = ll[o], np.maximum.accumulate(rr[o])
        new = _cat(True, ll[1:] > rr[:-1] + 1e-9 * width)
        grp = np.cumsum(new) - 1
        out_l.append(ll[new])
        out_r.append(np.maximum.reduceat(rr, np.flatnonzero(new)))
        out_m.append(np.full(int(grp[-1]) + 1, mode_k, np.int8))
    left, right, m = np.concatenate(out_l), np.concatenate(out_r), np.concatenate(out_m)
    order = np.argsort(m != int(Mode.SLIP), kind="stable")
    return left[order], right[order], m[order]


def history(result: Result, evaluate: Evaluate, t_end: float, exact: bool,
            columns: int, step: tuple[float, float],
            window: tuple[float, float] | None = None) -> History:
    """The time histories and mode bands for a plot ``columns`` pixels wide (``step``:
    the phase portrait's chord bound, see :func:`core.steady.steady_cycle`).

    With a ``window`` ``(t_lo, t_hi)`` narrower than the run, the plot shows that window:
    inside it the samples and bands are reduced to ``columns`` columns of the window,
    outside it to columns of the whole run (what an overview of the run and a brush moved
    off the window show until the window follows)."""
    cycle = steady_cycle(result, t_end, step) if exact else None
    whole = window is None or window[1] - window[0] >= t_end
    width = t_end if whole else window[1] - window[0]
    t, x, v, mode = fine_samples(result, evaluate, t_end, exact, cycle, width / columns)
    t_lo = float(t[0]) if len(t) else 0.0
    idx = m4(t, (x, v), t_lo, t_end, columns)
    bands = mode_bands(t, mode, t_lo, t_end, columns)
    if not whole and len(t):
        w_lo, w_hi = window
        # The window's samples and one beyond each end, so its lines run to its edges.
        lo = max(int(np.searchsorted(t, w_lo, side="left")) - 1, 0)
        hi = min(int(np.searchsorted(t, w_hi, side="right")) + 1, len(t))
        inner = lo + m4(t[lo:hi], (x[lo:hi], v[lo:hi]), w_lo, w_hi, columns)
        idx = np.union1d(idx, inner)
        bands = _windowed_bands(bands, mode_bands(t[lo:hi], mode[lo:hi], w_lo, w_hi, columns),
                                w_lo, w_hi)
    return History(t=t[idx], x=x[idx], v=v[idx], mode=mode[idx], bands=bands)


def _windowed_bands(coarse, fine, w_lo: float, w_hi: float):
    """The ``coarse`` bands (columns of the whole run) cut away from ``[w_lo, w_hi]``,
    where the ``fine`` ones (columns of the window) show the modes; slip first."""
    left, right, m = coarse
    before = left < w_lo
    after = right > w_hi
    cut_l = _cat(left[before], np.maximum(left[after], w_hi), fine[0])
    cut_r = _cat(np.minimum(right[before], w_lo), right[after], fine[1])
    cut_m = _cat(m[before], m[after], fine[2]).astype(np.int8)
    order = np.argsort(cut_m != int(Mode.SLIP), kind="stable")
    return cut_l[order], cut_r[order], cut_m[order]
