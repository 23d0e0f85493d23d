"""Paired speed of the deformable-stop grid between two checkouts of the repository.

Runs ``benchmarks/hysteretic_speed.py --no-reference`` (the 80 cells, both horizons) in each
checkout, one process per run, the checkouts alternating run by run (A, B, B, A, A, B, ...)
so that a change of the machine's load falls on both alike; prints, per cell and horizon,
the median over the rounds of each checkout's time (itself the median of ``--repeat``
solves) and their ratio, then the median ratio and the cells whose ratio lies above
``--flag``.

    PYTHONPATH=. .venv/bin/python benchmarks/hysteretic_paired.py BEFORE AFTER
        [--rounds N] [--repeat N] [--law paper|passive] [--flag RATIO]

``BEFORE`` and ``AFTER`` are checkouts (e.g. ``git worktree add /tmp/base <commit>``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path


def run(tree: Path, law: str, repeat: int) -> dict[str, tuple[float, float]]:
    """``{cell: (ms at t_end 100, ms at t_end 1e4)}`` of one run in ``tree``."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(tree)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    out = subprocess.run(
        [sys.executable, str(tree / "benchmarks" / "hysteretic_speed.py"), "--no-reference",
         "--repeat", str(repeat), "--law", law],
        cwd=tree, env=env, capture_output=True, text=True, check=True).stdout
    cells = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 5 and not line.startswith("#") and parts[0][0].isdigit():
            cells[" ".join(parts[:3])] = (float(parts[3]), float(parts[4]))
    return cells


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--law", choices=("paper", "passive"), default="paper")
    parser.add_argument("--flag", type=float, default=1.10,
                        help="list the cells slower than this ratio")
    args = parser.parse_args()
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    times: dict[str, dict[str, list[tuple[float, float]]]] = {"before": {}, "after": {}}
    for k in range(args.rounds):
        order = ("before", "after") if k % 2 == 0 else ("after", "before")
        for name in order:
            for cell, ms in run(trees[name], args.law, args.repeat).items():
                times[name].setdefault(cell, []).append(ms)
    print(f"# law {args.law}, {args.rounds} rounds alternating, median of {args.repeat} "
          "solves per run (t_end 100) and of 1 (t_end 1e4); wall ms")
    print(f"# {'cell':>20}  {'t100 before':>11} {'after':>8} {'ratio':>6}"
          f"  {'t1e4 before':>11} {'after':>8} {'ratio':>6}")
    ratios, flagged = [], []
    for cell in times["before"]:
        cols = []
        for h in (0, 1):
            b = statistics.median(m[h] for m in times["before"][cell])
            a = statistics.median(m[h] for m in times["after"][cell])
            r = a / b if b > 0 else float("nan")
            ratios.append(r)
            if r > args.flag and a - b > 1.0:  # below a millisecond is timer noise
                flagged.append(f"{cell} t_end {'100' if h == 0 else '1e4'}: {b:.1f} -> {a:.1f}")
            cols.append(f"{b:>11.1f} {a:>8.1f} {r:>6.2f}")
        print(f"  {cell:>20}  {cols[0]}  {cols[1]}")
    print(f"# median ratio after/before over all cells and horizons: "
          f"{statistics.median(ratios):.3f}")
    print(f"# cells above {args.flag} (and > 1 ms slower): " + ("; ".join(flagged) or "none"))


if __name__ == "__main__":
    main()
