"""Speed of the closed-form regime classification: ``core.theory.classify`` on one scene and
``core.theory.classify_grid`` per point of a regime map.

Both run the one decision tree of ``core/theory/grid.py``: the grid on numpy arrays, the
scalar on floats. The table gives the median time of one ``classify`` call over scenes of
every branch (impactless, fast belt, slow cases a/b/c, stop hit before the first stick,
still belt) and of ``classify_grid`` per point on maps of growing size.

    python benchmarks/theory_speed.py
    python benchmarks/theory_speed.py --against /work/main   # this tree, then another

``--against TREE`` runs the same measurement in a subprocess that imports ``core`` from
``TREE``, right after this tree's run, and prints both tables.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve()

#: Calls per timing and timings per scene (the median is reported).
CALLS = 500
REPEATS = 15
#: Regime-map sizes (clearances x belt speeds).
GRIDS = ((10, 10), (100, 100), (400, 400))


def scenes():
    from core import Oscillator, RigidStop

    slow = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)  # a = 0.2, b = 0.3, x* = 0.271
    fast = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
    still = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.0)
    return {
        "no stop": (slow, None),
        "impactless (c=0.6)": (slow, RigidStop(0.6, 0.7)),
        "fast belt (c=0.3)": (fast, RigidStop(0.3, 0.7)),
        "slow case a (c=0.32)": (slow, RigidStop(0.32, 0.7)),
        "slow case b (c=0.28)": (slow, RigidStop(0.28, 0.7)),
        "slow case c (c=0.25)": (slow, RigidStop(0.25, 0.7)),
        "first slip (c=0.02)": (slow, RigidStop(0.02, 0.7)),
        "still belt (c=0.3)": (still, RigidStop(0.3, 0.7)),
    }


def median_seconds(fn, calls: int, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        times.append((time.perf_counter() - start) / calls)
    return statistics.median(times)


def measure() -> dict:
    import numpy as np

    import core
    from core import Oscillator, RigidStop, theory

    rows = {}
    for name, (osc, stop) in scenes().items():
        theory.classify(osc, stop)  # warm up
        rows[name] = median_seconds(lambda o=osc, s=stop: theory.classify(o, s), CALLS, REPEATS)
    grid = {}
    osc, stop = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1), RigidStop(0.3, 0.7)
    for n_c, n_v in GRIDS:
        speeds, clearances = np.linspace(0.0, 0.6, n_v), np.linspace(0.0, 0.8, n_c)
        reps = max(3, int(2e5 // (n_c * n_v)))
        t = median_seconds(
            lambda s=speeds, c=clearances: theory.classify_grid(osc, stop, s, c), 1, reps
        )
        grid[f"{n_c} x {n_v}"] = t / (n_c * n_v)
    return {"core": str(Path(core.__file__).parent), "classify": rows, "grid": grid}


def table(result: dict) -> str:
    lines = [f"core: {result['core']}", "", f"{'classify, one scene':<28} {'median us':>10}"]
    for name, t in result["classify"].items():
        lines.append(f"{name:<28} {t * 1e6:>10.1f}")
    median = statistics.median(result["classify"].values())
    lines.append(f"{'median over scenes':<28} {median * 1e6:>10.1f}")
    lines += ["", f"{'classify_grid, map':<28} {'us/point':>10}"]
    for name, t in result["grid"].items():
        lines.append(f"{name:<28} {t * 1e6:>10.3f}")
    return "\n".join(lines)


def header() -> str:
    import numpy as np
    import scipy

    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    return (
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; python "
        f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}; "
        f"{platform.machine()}, {os.cpu_count()} cores; load average {load}"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", metavar="TREE", help="another checkout to measure too")
    parser.add_argument("--tree", help=argparse.SUPPRESS)  # the subprocess of --against
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    sys.path.insert(0, str(Path(args.tree).resolve() if args.tree else HERE.parents[1]))
    result = measure()
    if args.json:
        print(json.dumps(result))
        return
    print(header())
    print()
    print(table(result))
    if args.against:
        out = subprocess.run(
            [sys.executable, str(HERE), "--tree", args.against, "--json"],
            check=True, capture_output=True, text=True,
            env={**os.environ, "PYTHONPATH": str(Path(args.against).resolve())},
        ).stdout
        print()
        print(table(json.loads(out)))


if __name__ == "__main__":
    main()
