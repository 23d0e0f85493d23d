"""Speed and error of the deformable-stop solve over a grid of stops that press the mass.

``Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=0.25, u_s=2.0)`` (a = 0.6) against
``HystereticStop(clearance=0.42, k_c0, k_e0=k_c0/2, limit_overlap=D, beta_c=beta_e=beta)``
(x_bar = 0.42 < a: the belt presses the mass on the stop), from rest at the origin, for
k_c0 in {1e2 ... 1e6}, beta in {1, 10, 100, 1000}, D in {1e-3 ... 1} (80 cells). Each cell
is solved as the app's "standard" preset does (``core.simulate``, rtol 1e-8, atol 1e-11,
1,600 samples) at ``t_end = 100`` and ``t_end = 1e4``; the table gives the median wall time
of each and, at ``t_end = 100``, the errors against a reference solve that follows every
loop and contact (``reduce=False``) at rtol 1e-11, atol 1e-14:

* ``state``: ``max(|dx|, |dx'|)`` at ``t_end`` over the length scale ``max(a, b, v)``;
* ``x_max``: difference of the maximum displacement over the same scale;
* ``rest``: difference of the time of rest (``-`` if neither rests; ``n/a`` if only one
  does), the reference's being where the candidate's rule would declare it on the
  reference's reversals (:func:`reference_rest_time`: the loops never stop, a time of rest
  is the time a rule says so).

Also: the steady state's label, the time of the switch into a reduced model (``-`` if
none), the reduced model's stated error bound in the position where it ends (``bound``:
``Result.info['reduced_error']`` over the scale; for a train advanced by its
contact-to-contact map, the bound of its own error in the state, from the switch's state
(core/deformable/train_map.py), at most the band; for a train fitted to a loss law, the band it
moves in at the switch, the velocity's being up to twice the approach speed; for an oscillation on
the stop, the velocity's is up to ``2 pi / T`` times its oscillating part), the band it
moves in while it runs (``band``: ``info['reduced_band']``) and whether the energy balance
closes.

    PYTHONPATH=. .venv/bin/python benchmarks/hysteretic_speed.py [--quick] [--repeat N]
        [--repeat-long N] [--no-reference] [--cells k_c0,beta,D ...] [--law paper|passive]
        [--reference-long [--long-steps N]]

``--quick`` runs 8 cells (the corners and the worst cells of the old solver); ``--law``
picks the contact law's reading (docs/contact-law.md; the paper's by default);
``--repeat-long`` the runs at ``t_end = 1e4`` (a third of ``--repeat`` by default).
``--reference-long`` adds the same error columns at ``t_end = 1e4`` (and the switch time
and stated bound there), against a reference to 1e4: every loop and contact followed at
rtol 1e-11, from seconds (loops on the stop: ~36 us a reversal) to many minutes (trains of
contacts: 99 s to t = 1e3 on k_c0 1e6, beta 1000, D 1e-3); a reference past
``--long-steps`` steps (``max_steps``: contact steps, arcs and transitions) stops and its
columns read ``cap``. Use it on a subset
(``--cells``) unless there is the time.
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, Status, TransitionKind, simulate  # noqa: E402
from core.deformable.rest import (  # noqa: E402
    PAGE_RESOLUTION,
    REDUCE_PER_RTOL,
    REST_AMPLITUDE_PER_RTOL,
    rest_rule,
)
from core.deformable.solver import simulate_hysteretic  # noqa: E402
from core.numerics.limits import COUNT_MAX  # noqa: E402

OSC = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=0.25, u_s=2.0)
CLEARANCE = 0.42
K_C0 = (1e2, 1e3, 1e4, 1e5, 1e6)
BETA = (1.0, 10.0, 100.0, 1000.0)
D = (1e-3, 1e-2, 1e-1, 1.0)
#: The app's "standard" accuracy preset (app/solve/presets.py) and its stated relative error.
PRESET = {"rtol": 1e-8, "atol": 1e-11, "n_samples": 1600}
STATED_ERROR = 1e-6
REFERENCE = {"rtol": 1e-11, "atol": 1e-14}
HORIZONS = (100.0, 1e4)
QUICK = [(1e6, 1000.0, 1e-3), (1e6, 1000.0, 1e-2), (1e5, 1000.0, 1e-3), (1e2, 1.0, 1.0),
         (1e4, 100.0, 1e-2), (1e3, 10.0, 1e-1), (1e6, 1.0, 1e-3), (1e2, 1000.0, 1e-3)]


def stop_of(k_c0: float, beta: float, d: float, law: str = "paper") -> HystereticStop:
    return HystereticStop(CLEARANCE, k_c0, 0.5 * k_c0, limit_overlap=d, beta_c=beta,
                          beta_e=beta, law=law)


def balance(res) -> float:
    e = res.energy
    lhs = e.mechanical - e.mechanical[0]
    return float(np.abs(lhs - (e.friction_work - e.stop_loss - e.stop_stored)).max())


def rest_time(res) -> float:
    for tr in reversed(res.transitions):
        if tr.kind is TransitionKind.REST:
            return tr.t
    return math.nan


def reference_rest_time(ref, amplitude: float, tolerance: float, t_end: float) -> float:
    """The candidate's rule for rest (:func:`core.deformable.rest.rest_rule`, as
    ``core.deformable.contact.settled`` applies it) on the reference's reversals: the first
    reversal whose last four (itself included, all in one contact) lie within ``amplitude``,
    the candidate's rest amplitude, in the position and within ten times it in the
    velocity (the position's swing times ``2 pi / T``,
    :func:`~core.deformable.rest.rest_swing_factor`), unless the centre's creep left by
    ``t_end`` is above it, the candidate's rest would then state more than ``tolerance``,
    and the loops left are few enough that the candidate follows them. The loops die like
    ``1/k`` and never stop: a time of rest is the time a rule says so, and the reference's
    own rest is declared at its own, far smaller amplitude. (Before, the first of those
    four reversals was taken: 1.5 cycles before the candidate's rule can say rest, 9e-3 to
    0.12 of time.)"""
    rev, contact, n = [], [], 0  # reversals and the contact each is in
    for tr in ref.transitions:
        n += tr.kind is TransitionKind.CONTACT
        if tr.kind is TransitionKind.REVERSAL:
            rev.append(tr)
            contact.append(n)
    if len(rev) < 4:
        return rest_time(ref)
    ts = np.array([tr.t for tr in rev])
    xs = np.array([tr.x for tr in rev])
    windows = np.lib.stride_tricks.sliding_window_view(xs, 4)
    same = np.lib.stride_tricks.sliding_window_view(np.array(contact), 4)
    # (the position's test first, cheap: rest_rule applies the velocity's too)
    for j in np.nonzero((np.ptp(windows, axis=1) <= amplitude)
                        & (same[:, 0] == same[:, 3]))[0] + 3:
        first = j - 4 if j >= 4 and contact[j - 4] == contact[j] else j - 3
        rule, _ = rest_rule(ts[first:j + 1].tolist(), xs[first:j + 1].tolist(), t_end,
                            amplitude, tolerance)
        if rule in ("rest", "model"):
            return float(ts[j])
    return rest_time(ref)


def errors(res, ref, d: float, t_end: float) -> list[str]:
    """The error columns of ``res`` against the reference ``ref`` at ``t_end``: state,
    x_max and time of rest (module docstring), and the reference's label."""
    scale = max(OSC.a, OSC.b, OSC.v)
    state = max(abs(res.x[-1] - ref.x[-1]), abs(res.v[-1] - ref.v[-1])) / scale
    xmax = abs(res.x_max - ref.x_max) / scale
    t_rest = rest_time(res)
    # the candidate's rest amplitude and tolerance (core.deformable.rest.rest_amplitude and
    # reduce_extent), on its own length scale (core.deformable.state.Solve.scale)
    length = max(OSC.a, OSC.b, OSC.v, CLEARANCE, d)
    amplitude = REST_AMPLITUDE_PER_RTOL * max(PRESET["rtol"] * length, PRESET["atol"])
    tolerance = max(REDUCE_PER_RTOL * PRESET["rtol"], PAGE_RESOLUTION) * length
    t_ref = reference_rest_time(ref, amplitude, tolerance, t_end)
    if math.isnan(t_rest) and math.isnan(t_ref):
        rest = "-"
    elif math.isnan(t_rest) or math.isnan(t_ref):
        rest = "n/a"
    else:
        rest = f"{abs(t_rest - t_ref):.1e}"
    return [f"{state:>8.1e}", f"{xmax:>8.1e}", f"{rest:>8}", f"{ref.steady.kind.value:>13}"]


def reference(stop, t_end: float, max_steps: int):
    """The reference solve (every loop and contact followed) and its CPU time in s."""
    t0 = time.process_time()
    ref = simulate_hysteretic(OSC, stop, t_end, 0.0, 0.0, reduce=False,
                              n_samples=PRESET["n_samples"], transition_cap=2_000_000,
                              max_steps=max_steps, **REFERENCE)
    return ref, time.process_time() - t0


def timed(stop, t_end: float, repeat: int):
    times, res = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = simulate(OSC, stop, t_end, 0.0, 0.0, **PRESET)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), res


def row(cell, args) -> str:
    k_c0, beta, d = cell
    stop = stop_of(k_c0, beta, d, args.law)
    scale = max(OSC.a, OSC.b, OSC.v)
    t100, res = timed(stop, HORIZONS[0], args.repeat)
    long_runs = args.repeat_long if args.repeat_long else max(1, args.repeat // 3)
    t1e4, res_long = timed(stop, HORIZONS[1], long_runs)
    red = [tr.t for tr in res.transitions if tr.kind is TransitionKind.REDUCED]
    err_bound = res.info.get("reduced_error", 0.0) / scale
    band = res.info.get("reduced_band", 0.0) / scale
    cols = [f"{k_c0:>7.0e} {beta:>6g} {d:>6g}", f"{1e3 * t100:>8.1f}", f"{1e3 * t1e4:>8.1f}",
            f"{res.steady.kind.value:>13}", f"{red[0] if red else math.nan:>8.3g}",
            f"{err_bound:>8.1e}", f"{band:>8.1e}", f"{balance(res):>8.1e}"]
    if args.no_reference:
        return " ".join(cols)
    ref, _ = reference(stop, HORIZONS[0], COUNT_MAX)
    cols += errors(res, ref, d, HORIZONS[0])
    if args.reference_long:
        red = [tr.t for tr in res_long.transitions if tr.kind is TransitionKind.REDUCED]
        cols += [f"{red[0] if red else math.nan:>8.3g}",
                 f"{res_long.info.get('reduced_error', 0.0) / scale:>8.1e}"]
        ref, cpu = reference(stop, HORIZONS[1], args.long_steps)
        if ref.status is Status.STEP_LIMIT:
            cols += [f"{'cap':>8}"] * 3 + [f"{ref.steady.kind.value:>13}"]
        else:
            cols += errors(res_long, ref, d, HORIZONS[1])
        cols.append(f"{cpu:>8.1f}")
    return " ".join(cols)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 cells instead of 80")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--repeat-long", type=int, default=0,
                        help="runs at t_end = 1e4 (default: a third of --repeat)")
    parser.add_argument("--no-reference", action="store_true", help="skip the error columns")
    parser.add_argument("--law", choices=("paper", "passive"), default="paper",
                        help="the contact law's reading")
    parser.add_argument("--cells", nargs="*", default=None, help="k_c0,beta,D triples")
    parser.add_argument("--reference-long", action="store_true",
                        help="the error columns at t_end = 1e4 too (slow: every loop and "
                             "contact to 1e4 at rtol 1e-11)")
    parser.add_argument("--long-steps", type=int, default=100_000_000,
                        help="most steps of a reference at t_end = 1e4 ('cap' past it)")
    args = parser.parse_args()
    if args.cells:
        cells = [tuple(float(v) for v in c.split(",")) for c in args.cells]
    elif args.quick:
        cells = QUICK
    else:
        cells = list(itertools.product(K_C0, BETA, D))
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, "
          f"{platform.node()}, {platform.processor() or platform.machine()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}")
    print(f"# preset rtol {PRESET['rtol']:g} atol {PRESET['atol']:g} (stated error "
          f"{STATED_ERROR:g}); reference rtol {REFERENCE['rtol']:g}, reduce=False; "
          f"law {args.law}")
    head = (f"{'k_c0':>7} {'beta':>6} {'D':>6} {'ms t100':>8} {'ms t1e4':>8} {'steady':>13} "
            f"{'reduced':>8} {'bound':>8} {'band':>8} {'balance':>8}")
    if not args.no_reference:
        head += f" {'state':>8} {'x_max':>8} {'rest':>8} {'ref steady':>13}"
        if args.reference_long:
            print(f"# errors at t_end 1e4 too, on {len(cells)} of the grid's 80 cells; a "
                  f"reference past {args.long_steps} steps is not finished ('cap'); "
                  f"last column: the reference's CPU s at 1e4")
            head += (f" {'red 1e4':>8} {'bnd 1e4':>8} {'st 1e4':>8} {'xm 1e4':>8} "
                     f"{'rest 1e4':>8} {'ref st 1e4':>13} {'ref s':>8}")
    print(head)
    for cell in cells:
        print(row(cell, args), flush=True)


if __name__ == "__main__":
    main()
