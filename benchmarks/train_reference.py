"""Long trains of contacts at ``t_end = 1e4``, against a reference solved in pieces.

``hysteretic_speed.py --reference-long`` follows every contact of a train to ``t = 1e4``
in one solve; on the stiffest stops that is over two million transitions and more memory
than a 2-core machine with 23 GB can spare. The motion is autonomous, and between two
contacts of a train the mass is in free flight, where the contact law keeps nothing (every
contact starts on the compression envelope from zero overlap): so a solve restarted from
the state in the middle of a flight continues the same motion. The reference here is a
chain of such solves (``reduce=False``, rtol 1e-11), each over ``t_end / pieces``, each
started from the middle of the last flight of the one before.

Columns: the candidate's time (one run, standard preset), its label and reduced-model
bound over the scale, the state error at ``t_end`` over the scale, the transitions the
reference's pieces solved (the part of each piece past its restart is solved twice) and
its CPU time. The first default cell's one-piece reference finished
(hysteretic_speed_2026-11-27h.txt, section 9: 1.4e-8): it checks the pieces.

    PYTHONPATH=. .venv/bin/python benchmarks/train_reference.py [--pieces 8]
        [--cells k_c0,beta,D ...]
"""

from __future__ import annotations

import argparse
import datetime
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hysteretic_speed import CLEARANCE, OSC, PRESET, REFERENCE, stop_of  # noqa: E402

from core import TransitionKind, simulate  # noqa: E402
from core.deformable.solver import simulate_hysteretic  # noqa: E402

T_END = 1e4
#: The grid's trains whose one-piece references did not finish (hysteretic_speed.py),
#: after one whose reference did.
CELLS = ("1e4,10,1e-3", "1e5,100,1e-3", "1e5,1000,1e-2", "1e6,100,1e-3", "1e6,1000,1e-2",
         "1e6,1000,1e-3")


def mid_flight(res) -> float | None:
    """A time in the middle of the last flight that ends before the solve does (between a
    separation and the next contact), or ``None``."""
    trs = [tr for tr in res.transitions
           if tr.kind in (TransitionKind.SEPARATION, TransitionKind.CONTACT)]
    for a, b in zip(reversed(trs[:-1]), reversed(trs[1:]), strict=True):
        if a.kind is TransitionKind.SEPARATION and b.kind is TransitionKind.CONTACT:
            return 0.5 * (a.t + b.t)
    return None


def reference_end(stop, pieces: int) -> tuple[float, float, int, float]:
    """End state at ``T_END`` of the chained reference, its transitions and CPU s."""
    t, x, v, count = 0.0, 0.0, 0.0, 0
    cpu = time.process_time()
    while True:
        span = min(T_END / pieces, T_END - t)
        last = t + span >= T_END * (1.0 - 1e-15)
        res = simulate_hysteretic(OSC, stop, T_END - t if last else span, x, v,
                                  reduce=False, transition_cap=10**7, n_samples=10,
                                  max_steps=10**12, **REFERENCE)
        count += res.n_transitions
        if last:
            return float(res.x[-1]), float(res.v[-1]), count, time.process_time() - cpu
        cut = mid_flight(res)
        if cut is None or cut <= 0.0:
            raise RuntimeError("no flight to restart from")
        xs, vs = res.evaluate(np.array([cut]))
        t, x, v = t + cut, float(xs[0]), float(vs[0])


def row(cell: str, pieces: int) -> str:
    k_c0, beta, d = (float(s) for s in cell.split(","))
    stop = stop_of(k_c0, beta, d)
    scale = max(OSC.a, OSC.b, OSC.v, CLEARANCE, d)
    t0 = time.perf_counter()
    cand = simulate(OSC, stop, T_END, **PRESET)
    ms = 1e3 * (time.perf_counter() - t0)
    bound = cand.info.get("reduced_error", 0.0) / scale
    x, v, n, cpu = reference_end(stop, pieces)
    error = max(abs(cand.x[-1] - x), abs(cand.v[-1] - v)) / scale
    return (f"{cell:>16} {ms:8.1f} {cand.steady.kind.value:>14} {bound:9.1e} {error:9.1e} "
            f"{n:>10} {cpu:8.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pieces", type=int, default=8)
    parser.add_argument("--cells", nargs="*", default=list(CELLS))
    args = parser.parse_args()
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, "
          f"{platform.node()}, Python {platform.python_version()}, numpy {np.__version__}; "
          f"reference in {args.pieces} pieces, rtol {REFERENCE['rtol']:g}")
    print(f"{'k_c0,beta,D':>16} {'ms 1e4':>8} {'steady':>14} {'bound':>9} {'state':>9} "
          f"{'ref trans':>10} {'ref cpu':>8}")
    for cell in args.cells:
        print(row(cell, args.pieces), flush=True)


if __name__ == "__main__":
    main()
