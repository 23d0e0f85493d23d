"""Sweeps spread over a Dask cluster: a local one by default, or any by its address.

The parameter points are cut into chunks, each solved by :func:`core.sweep.solve_block`
on a worker (the vectorised closed form where it applies, else :func:`core.simulate` per
point). Chunks are sized from a pilot solved here first, so that each task does at least
``task_seconds`` of work: Dask's per-task overhead (~1 ms) is then negligible and the
scheduler still has many tasks to balance.

Dask is imported only here, so ``import core`` stays fast and free of it.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop
from core.sweep import GridPlan, plan_grid, solve_block, takes_plan_options, vectorised
from core.sweep.lanes import Lanes
from core.sweep.result import LaneRecords, SweepResult

#: Points in the pilot that estimates the cost per point: the closed form needs a block
#: for numpy's per-call cost to amortise; a scalar solve is timed on a few points.
PILOT_VECTORISED = 2048
PILOT_SCALAR = 6


def pilot_cost(lanes: Lanes, t_end: float, x0: float, v0: float, method: str) -> float:
    """Seconds per point, measured on points spread evenly over the sweep."""
    size = PILOT_VECTORISED if vectorised(lanes.stop, method) else PILOT_SCALAR
    size = min(size, len(lanes))
    idx = np.unique(np.linspace(0, len(lanes) - 1, size).round().astype(int))
    start = time.perf_counter()
    solve_block(lanes.take(idx), t_end, x0, v0, method)
    return (time.perf_counter() - start) / len(idx)


def chunk_size(cost: float, n: int, task_seconds: float) -> int:
    """Points per task so that each does at least ``task_seconds`` of work (at most all)."""
    return int(min(n, max(1, math.ceil(task_seconds / max(cost, 1e-12)))))


def progress_bar(done: int, total: int, started: float) -> None:
    """A plain progress bar on stderr: chunks done of all, seconds since the start."""
    width = 30
    filled = int(width * done / total)
    sys.stderr.write(
        f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} chunks "
        f"{time.perf_counter() - started:6.1f} s"
    )
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def run_chunks(
    plan: GridPlan,
    *,
    client=None,
    task_seconds: float = 0.5,
    progress: Callable[[int, int, float], None] | None = None,
) -> tuple[LaneRecords, dict]:
    """Solve the lanes of ``plan`` in chunks on a Dask ``client`` (``None``: here, one chunk
    after another). Returns the records in order and facts about the run (cost, chunks)."""
    lanes, t_end, x0, v0, method = plan.lanes, plan.t_end, plan.x0, plan.v0, plan.method
    cost = pilot_cost(lanes, t_end, x0, v0, method)
    size = chunk_size(cost, len(lanes), task_seconds)
    bounds = list(range(0, len(lanes), size)) + [len(lanes)]
    chunks = [lanes.take(slice(i, j)) for i, j in zip(bounds[:-1], bounds[1:], strict=True)]
    started = time.perf_counter()
    parts: list[LaneRecords | None] = [None] * len(chunks)
    if client is None:
        for k, chunk in enumerate(chunks):
            parts[k] = solve_block(chunk, t_end, x0, v0, method)
            if progress:
                progress(k + 1, len(chunks), started)
    else:
        from dask.distributed import as_completed

        futures = client.map(
            solve_block, chunks, t_end=t_end, x0=x0, v0=v0, method=method, pure=False
        )
        order = {f.key: k for k, f in enumerate(futures)}
        for done, future in enumerate(as_completed(futures), start=1):
            parts[order[future.key]] = future.result()
            if progress:
                progress(done, len(chunks), started)
    info = {"cost_per_point": cost, "chunk_size": size, "chunks": len(chunks)}
    return LaneRecords.concat(parts), info


@takes_plan_options
def sweep_distributed(
    osc: Oscillator,
    stop: RigidStop | HystereticStop | None,
    axes: dict,
    *,
    scheduler: str | None = None,
    n_workers: int | None = None,
    processes: bool = True,
    dashboard_address: str | None = None,
    task_seconds: float = 0.5,
    progress: Callable[[int, int, float], None] | None = None,
    client=None,
    **options,
) -> SweepResult:
    """:func:`core.sweep.sweep_grid` on a Dask cluster.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``); its workers need this
        package importable. ``None``: a ``LocalCluster`` with ``n_workers`` workers of one
        thread each (``processes=False``: threads in this process), closed afterwards.
    dashboard_address : str, optional
        Where the local cluster serves its dashboard (``":5116"``); ``None``: none.
    task_seconds : float
        Least work per task, from the pilot's cost per point.
    progress : callable, optional
        Called as ``progress(chunks_done, chunks, start_time)`` after each chunk, e.g.
        :func:`progress_bar`.
    client : dask.distributed.Client, optional
        Use this client (and leave it open) instead of making one.

    The other arguments (``options``: ``quantity``, ``t_end``, ``method``, ``x0``,
    ``v0``) are those of :func:`core.sweep.sweep_grid` (:func:`core.sweep.plan_grid`); the
    result is the one it returns, point for point.
    """
    plan = plan_grid(osc, stop, axes, **options)
    from dask.distributed import Client, LocalCluster

    owned = []
    if client is None:
        if scheduler is not None:
            client = Client(scheduler)
        else:
            cluster = LocalCluster(
                n_workers=n_workers,
                threads_per_worker=1,
                processes=processes,
                dashboard_address=dashboard_address,
            )
            owned.append(cluster)
            client = Client(cluster)
        owned.insert(0, client)
    try:
        rec, _ = run_chunks(plan, client=client, task_seconds=task_seconds, progress=progress)
    finally:
        for thing in owned:
            thing.close()
    return plan.finish(rec)
