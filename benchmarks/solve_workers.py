"""Wall time of scene 10's full solve in a worker process against the same solve in the
calling thread, as the page's integrating lane runs it (``app.solve.solution.compute``).

Each round solves a new clearance twice (a value no cache holds): once in a child process
(``app.solve.process``), once in this thread. The difference is what the process costs a
release: starting and ending it, sending the answer back, and a solve in a process whose
memory is not yet its own.

    PYTHONPATH=. python benchmarks/solve_workers.py [rounds]
"""

from __future__ import annotations

import statistics
import sys
import time

from app.solve import process as solve_process
from app.solve.cache import SolveCache
from app.solve.presets import SOLVE_BUDGET_S
from app.solve.process import Caller
from app.solve.solution import compute, solve_key
from app.state import scene_values
from core import simulate


def _solve(values: dict, isolated: bool) -> float:
    start = time.perf_counter()
    compute(solve_key(values), False, budget=SOLVE_BUDGET_S,
            simulate=Caller(simulate, isolated=isolated), kept=SolveCache().reference)
    return time.perf_counter() - start


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
