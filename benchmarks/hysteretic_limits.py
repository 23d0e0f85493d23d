"""Wall time and status of a default call of the exact method on a deformable stop at long
horizons.

``simulate(osc, HystereticStop(...), t_end=T)`` with no ``max_steps``: the solve stops at
``core.deformable.solver.DEFAULT_MAX_STEPS`` steps (contact steps, arcs, transitions solved;
``info["work_steps"]``), which should come within
a few seconds whatever the horizon. Scenes: 10 and 11 (the page's deformable stop,
``Oscillator(0.3, 0.2, 0.07)``, x_bar = 0.24 and 0.15), a grazing train (the same stop, belt
speed 0.5, x_bar = 0.3), and with ``--grid`` the 80 cells of benchmarks/hysteretic_speed.py
(a mass pressed on the stop) at the longest horizon only.

Columns: the scene and horizon; the wall time; the status; the time reached (``t[-1]``);
the steps counted (``info["work_steps"]``) and the contacts.

    PYTHONPATH=. .venv/bin/python benchmarks/hysteretic_limits.py [--grid]
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, simulate  # noqa: E402
from core.deformable.solver import DEFAULT_MAX_STEPS  # noqa: E402

PAGE_STOP = dict(k_c0=400.0, k_e0=36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
SCENES = {
    "10": (Oscillator(0.3, 0.2, 0.07), HystereticStop(clearance=0.24, **PAGE_STOP)),
    "11": (Oscillator(0.3, 0.2, 0.07), HystereticStop(clearance=0.15, **PAGE_STOP)),
    "grazing": (Oscillator(0.3, 0.2, 0.5), HystereticStop(clearance=0.3, **PAGE_STOP)),
}
HORIZONS = (1e3, 1e4, 1e5, 1e7, 1e9)


def line(name: str, osc, stop, t_end: float) -> str:
    start = time.perf_counter()
    res = simulate(osc, stop, t_end=t_end)
    wall = time.perf_counter() - start
    return (f"{name:<22} {t_end:7.0e} {wall:9.2f} {res.status.value:<11} "
            f"{float(res.t[-1]):10.4g} {res.info['work_steps']:8d} "
            f"{res.info['n_contacts']:9d}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", action="store_true",
                        help="also the 80 pressed cells of hysteretic_speed.py at 1e9")
    args = parser.parse_args()
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC {platform.node()} "
          f"python {platform.python_version()} numpy {np.__version__} "
          f"scipy {scipy.__version__}; DEFAULT_MAX_STEPS {DEFAULT_MAX_STEPS}")
    print(f"{'scene':<22} {'t_end':>7} {'wall [s]':>9} {'status':<11} {'t reached':>10} "
          f"{'steps':>8} {'contacts':>9}")
    for name, (osc, stop) in SCENES.items():
        for t_end in HORIZONS:
            print(line(name, osc, stop, t_end), flush=True)
    if args.grid:
        from hysteretic_speed import BETA, K_C0, OSC, D, stop_of

        for k_c0, beta, d in itertools.product(K_C0, BETA, D):
            name = f"{k_c0:.0e} {beta:g} {d:g}"
            print(line(name, OSC, stop_of(k_c0, beta, d, "paper"), HORIZONS[-1]), flush=True)


if __name__ == "__main__":
    main()
