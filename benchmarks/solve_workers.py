"""Wall time of scene 10's full solve in a worker process against the same solve in the
calling thread, as the page's integrating lane runs it (``app.solver._solve_cached``).

Each round solves a new clearance twice (a value no cache holds): once in a child process
(``app.solve_process``), once in this thread. The difference is what the process costs a
release: starting and ending it, sending the answer back, and a solve in a process whose
memory is not yet its own.

    PYTHONPATH=. python benchmarks/solve_workers.py [rounds]
"""

from __future__ import annotations

import statistics
import sys
import time

from app import solve_process, solver
from app.state import scene_values


def _solve(values: dict, isolated: bool) -> float:
    solver._WORKER.isolated = isolated
    try:
        start = time.perf_counter()
        solver._solve_cached(solver._key(values), False, None)
        return time.perf_counter() - start
    finally:
        solver._WORKER.isolated = False


def main(rounds: int = 15) -> None:
    solve_process.warm_up(wait=True)
    base = scene_values("10")
    child, thread = [], []
    for i in range(rounds):
        clearance = base["clearance"] + 1e-4 * i
        child.append(_solve({**base, "clearance": clearance + 0.01}, True))
        thread.append(_solve({**base, "clearance": clearance + 0.02}, False))
    c, t = statistics.median(child) * 1e3, statistics.median(thread) * 1e3
    print(f"scene 10, {rounds} rounds, medians [ms]")
    print("| in a worker process | in this thread | difference |")
    print("|---|---|---|")
    print(f"| {c:.1f} | {t:.1f} | {c - t:+.1f} |")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
