"""Error of repeating the last cycle of the passive law's retracing loops on a pressed stop.

For each cell ``k_c0,beta,D`` of benchmarks/hysteretic_speed.py's scene with the passive
law, the standard preset's solve (rtol 1e-8, which repeats the loops' last cycle from a
``reduced`` transition, core/deformable/oscillation.py ``repeat_retracing``) is compared at
``t_end`` with

* a tight solve from the same switch: the same solve up to the reversal where the cycle
  was repeated, every loop followed from there at rtol 1e-11, atol 1e-14;
* with ``--from0``, the tight reference of hysteretic_speed.py (every loop followed at
  rtol 1e-11 from ``t = 0``, to at most ``t = 100``);
* with ``--followed``, every loop followed at rtol 1e-8 (the solver before the cycle was
  repeated), against the tight solve from the switch (and from 0).

Past ``--direct`` time units after the switch (and past ``t = 100`` from 0) the tight
solves' own cycle is repeated: the loops retrace one curve of the law, a conservative
motion, so their cycle is exact; it is the slope of the times of every other reversal
(their residuals about it are printed).

    PYTHONPATH=. .venv/bin/python benchmarks/passive_retrace.py --cells 1e2,100,0.1
        [--t-end 1e4] [--direct 100] [--from0] [--followed]

Errors are ``max(|dx|, |dx'|)`` over the length scale ``max(a, b, v)``; ``bound`` is
``info['reduced_error']`` over it.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import core.deformable.contact as contact  # noqa: E402
from core import TransitionKind, simulate  # noqa: E402
from core.deformable.solver import simulate_hysteretic  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hysteretic_speed import OSC, PRESET, REFERENCE, stop_of  # noqa: E402

SCALE = max(OSC.a, OSC.b, OSC.v)
TOLS = {"rtol": PRESET["rtol"], "atol": PRESET["atol"]}


def continued(res, t_from: float, t_end: float):
    """State at ``t_end`` of ``res``'s loops after ``t_from`` with their cycle repeated;
    the cycle, the largest residual of the reversals' times about it, the cycles added."""
    ts = np.array([tr.t for tr in res.transitions
                   if tr.kind is TransitionKind.REVERSAL and tr.t >= t_from])[::2]
    j = np.arange(len(ts))
    cycle, t0 = np.polyfit(j, ts, 1)
    resid = float(np.abs(ts - (t0 + cycle * j)).max())
    k = math.floor((t_end - ts[-2]) / cycle)
    x, v = res.evaluate(np.array([t_end - k * cycle]))
    return float(x[0]), float(v[0]), cycle, resid, k


def end_state(res, t_from: float, t_end: float):
    if res.t[-1] >= t_end:
        return float(res.x[-1]), float(res.v[-1]), ""
    x, v, cycle, resid, k = continued(res, t_from, t_end)
    return x, v, f" (cycle {cycle:.12g} repeated {k} times, residual {resid:.1e})"


def tight_from_switch(stop, t_switch: float, t_stop: float):
    def tighten(sv, st, branch, reversal_x, s):
        if st.t == t_switch:
            sv.rtol, sv.atol, sv.use_reduced = REFERENCE["rtol"], REFERENCE["atol"], False
        return None

    saved = contact.reduce_oscillation
    contact.reduce_oscillation = tighten
    try:
        return simulate_hysteretic(OSC, stop, t_stop, 0.0, 0.0, n_samples=10,
                                   transition_cap=10_000_000, **TOLS)
    finally:
        contact.reduce_oscillation = saved


def followed(stop, t_end: float):
    saved = contact.reduce_oscillation
    contact.reduce_oscillation = lambda *args: None
    try:
        return simulate_hysteretic(OSC, stop, t_end, 0.0, 0.0, n_samples=10, **TOLS)
    finally:
        contact.reduce_oscillation = saved


def error(res, x: float, v: float) -> float:
    return max(abs(float(res.x[-1]) - x), abs(float(res.v[-1]) - v)) / SCALE


def row(cell: str, args) -> str:
    k_c0, beta, d = (float(v) for v in cell.split(","))
    stop = stop_of(k_c0, beta, d, "passive")
    t0 = time.perf_counter()
    res = simulate(OSC, stop, args.t_end, 0.0, 0.0, **PRESET)
    line = (f"{k_c0:7.0e} {beta:6g} {d:6g} t_end {args.t_end:g}: "
            f"{1e3 * (time.perf_counter() - t0):.0f} ms, {res.steady.kind.value}")
    switch = [tr.t for tr in res.transitions if tr.kind is TransitionKind.REDUCED]
    if not switch:
        return line + ", no switch"
    t_s = switch[0]
    line += f", switch t {t_s:.4g}, bound {res.info['reduced_error'] / SCALE:.2e}"
    tight = tight_from_switch(stop, t_s, min(args.t_end, t_s + args.direct))
    x_t, v_t, note = end_state(tight, t_s + 0.2 * args.direct, args.t_end)
    line += f" | from switch {error(res, x_t, v_t):.2e}{note}"
    if args.followed:
        t1 = time.perf_counter()
        fol = followed(stop, args.t_end)
        line += (f" | followed {error(fol, x_t, v_t):.2e} "
                 f"({time.perf_counter() - t1:.0f} s)")
    if args.from0:
        ref = simulate_hysteretic(OSC, stop, min(args.t_end, 100.0), 0.0, 0.0, reduce=False,
                                  n_samples=10, transition_cap=10_000_000, **REFERENCE)
        x_0, v_0, _ = end_state(ref, max(t_s, 50.0), args.t_end)
        line += f" | from 0 {error(res, x_0, v_0):.2e}"
        if args.followed:
            line += f", followed {error(fol, x_0, v_0):.2e}"
    return line


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", nargs="+", required=True, help="k_c0,beta,D triples")
    parser.add_argument("--t-end", type=float, default=100.0)
    parser.add_argument("--direct", type=float, default=100.0,
                        help="time the tight solve follows after the switch")
    parser.add_argument("--from0", action="store_true")
    parser.add_argument("--followed", action="store_true")
    args = parser.parse_args()
    for cell in args.cells:
        print(row(cell, args), flush=True)


if __name__ == "__main__":
    main()
