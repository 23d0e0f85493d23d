"""The state of a pressed mass at horizons just past its rest, against every loop followed.

``benchmarks/hysteretic_speed.py`` measures the error at ``t_end = 100`` only. A rest is
declared while loops are left on the stop; by ``t = 100`` they may have died out further
than when the rest was declared, so a single horizon can hide a rest declared too early.
This script solves each cell (the grid's oscillator and stops, ``k_e0 = k_c0 / 2``) at the
standard preset to ``t_end = 100`` to find its time of rest, then again to horizons one time
unit past it and at 40, 60 and 100, and compares each end state with a solve that follows
every loop (``reduce=False``, rtol 1e-10) evaluated there.

Columns: the time of rest and of the switch into a reduced model at ``t_end = 100``; for
each horizon, ``max(|dx|, |dx'|)`` over the length scale and what the run states: the
larger of the preset's 1e-6 and ``info['reduced_error']`` over the scale (``!`` marks an
error above it).

    PYTHONPATH=. .venv/bin/python benchmarks/rest_horizons.py [--cells k_c0,beta,D ...]
"""

from __future__ import annotations

import argparse
import datetime
import platform
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hysteretic_speed import CLEARANCE, OSC, PRESET, STATED_ERROR, stop_of  # noqa: E402

from core import TransitionKind, simulate  # noqa: E402
from core.deformable.solver import simulate_hysteretic  # noqa: E402

CELLS = ("1e4,1000,1e-2", "1e4,100,1e-3", "1e5,1000,1e-3", "1e4,1000,1e-3", "1e3,1000,0.1")
HORIZONS = (40.0, 60.0, 100.0)


def first(res, kind: TransitionKind) -> float:
    return next((tr.t for tr in res.transitions if tr.kind is kind), float("nan"))


def row(cell: str) -> str:
    k_c0, beta, d = (float(v) for v in cell.split(","))
    stop = stop_of(k_c0, beta, d)
    scale = max(OSC.a, OSC.b, OSC.v, CLEARANCE, d)
    res = simulate(OSC, stop, 100.0, **PRESET)
    rest, switch = first(res, TransitionKind.REST), first(res, TransitionKind.REDUCED)
    ref = simulate_hysteretic(OSC, stop, 100.0, 0.0, 0.0, reduce=False, rtol=1e-10,
                              atol=1e-13, transition_cap=10, n_samples=10)
    horizons = sorted({*HORIZONS, *([min(rest + 1.0, 100.0)] if rest == rest else [])})
    cols = []
    for t_end in horizons:
        run = simulate(OSC, stop, t_end, **PRESET)
        x, v = ref.evaluate(np.array([t_end]))
        error = max(abs(run.x[-1] - x[0]), abs(run.v[-1] - v[0])) / scale
        stated = max(STATED_ERROR, run.info.get("reduced_error", 0.0) / scale)
        cols.append(f"{t_end:7.2f}: {error:.1e} ({stated:.1e}){'!' if error > stated else ' '}")
    return f"{cell:>16} {rest:7.2f} {switch:7.2f}  " + "  ".join(cols)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", nargs="*", default=list(CELLS))
    args = parser.parse_args()
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, "
          f"{platform.node()}, Python {platform.python_version()}, numpy {np.__version__}")
    print(f"{'k_c0,beta,D':>16} {'rest':>7} {'switch':>7}  t_end: error (stated)")
    for cell in args.cells:
        print(row(cell), flush=True)


if __name__ == "__main__":
    main()
