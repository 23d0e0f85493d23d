"""Paired speed of the deformable-stop grid between two checkouts of the repository.

Solves the 80 pressed cells of ``benchmarks/hysteretic_speed.py`` (the app's standard preset,
``t_end = 100`` and ``1e4``) in each checkout, one process per run, the checkouts alternating
run by run (A, B, B, A, A, B, ...) so that a change of the machine's load falls on both
alike; prints, per cell and horizon, the median over the rounds of each checkout's time
(itself the median of ``--repeat`` solves), their ratio, the median ratio and the cells
whose ratio lies above ``--flag``. Times are the process's CPU time by default: on a shared
machine the wall time of a 3 ms solve varies tenfold with the load (``--wall`` for it).

    PYTHONPATH=. .venv/bin/python benchmarks/hysteretic_paired.py BEFORE AFTER
        [--rounds N] [--repeat N] [--law paper|passive] [--flag RATIO] [--wall]

``BEFORE`` and ``AFTER`` are checkouts (e.g. ``git worktree add /tmp/base <commit>``).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path


def worker(tree: Path, law: str, repeat: int, wall: bool) -> None:
    """Time every cell in ``tree`` (run in a process of its own) and print JSON."""
    sys.path[:0] = [str(tree), str(tree / "benchmarks")]
    import hysteretic_speed as hs  # the checkout's own grid and preset

    from core import simulate

    clock = time.perf_counter if wall else time.process_time
    out = {}
    for k_c0 in hs.K_C0:
        for beta in hs.BETA:
            for d in hs.D:
                stop = hs.stop_of(k_c0, beta, d, law)
                ms = []
                for t_end in hs.HORIZONS:
                    runs = []
                    for _ in range(repeat):
                        t0 = clock()
                        simulate(hs.OSC, stop, t_end, 0.0, 0.0, **hs.PRESET)
                        runs.append(1e3 * (clock() - t0))
                    ms.append(statistics.median(runs))
                out[f"{k_c0:.0e} {beta:g} {d:g}"] = ms
    print(json.dumps(out))


def run(tree: Path, law: str, repeat: int, wall: bool) -> dict[str, list[float]]:
    cmd = [sys.executable, __file__, str(tree), str(tree), "--worker", "--law", law,
           "--repeat", str(repeat)] + (["--wall"] if wall else [])
    out = subprocess.run(cmd, cwd=tree, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--law", choices=("paper", "passive"), default="paper")
    parser.add_argument("--flag", type=float, default=1.10,
                        help="list the cells slower than this ratio")
    parser.add_argument("--wall", action="store_true", help="wall time, not CPU time")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args.before.resolve(), args.law, args.repeat, args.wall)
        return
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    times: dict[str, dict[str, list[list[float]]]] = {"before": {}, "after": {}}
    for k in range(args.rounds):
        order = ("before", "after") if k % 2 == 0 else ("after", "before")
        for name in order:
            for cell, ms in run(trees[name], args.law, args.repeat, args.wall).items():
                times[name].setdefault(cell, []).append(ms)
    clock = "wall" if args.wall else "CPU"
    print(f"# law {args.law}: {args.rounds} rounds alternating, median of {args.repeat} solves "
          f"per run and of the rounds; {clock} ms")
    print(f"# {'cell':>18}  {'t100 before':>11} {'after':>7} {'ratio':>6}"
          f"  {'t1e4 before':>11} {'after':>7} {'ratio':>6}")
    ratios, flagged = [], []
    for cell in times["before"]:
        cols = []
        for h, label in ((0, "100"), (1, "1e4")):
            b = statistics.median(m[h] for m in times["before"][cell])
            a = statistics.median(m[h] for m in times["after"][cell])
            r = a / b if b > 0 else float("nan")
            ratios.append(r)
            if r > args.flag and a - b > 1.0:  # below a millisecond is the clock's grain
                flagged.append(f"{cell} t_end {label}: {b:.1f} -> {a:.1f}")
            cols.append(f"{b:>11.1f} {a:>7.1f} {r:>6.2f}")
        print(f"  {cell:>18}  {cols[0]}  {cols[1]}")
    print(f"# median ratio after/before over all cells and horizons: "
          f"{statistics.median(ratios):.3f}")
    print(f"# cells above {args.flag} and > 1 ms slower: " + ("; ".join(flagged) or "none"))


if __name__ == "__main__":
    main()
