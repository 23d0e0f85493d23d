"""Speed and agreement of parameter sweeps: the vectorised closed form against simulate.

For sweeps of 10^5 parameter points (``t_end = 200``, steady-state quantities) over the
regimes of the paper (no stop; rigid stop elastic, inelastic and plastic over a belt speed
x clearance grid) this prints

* the sweep's wall time and cost per point (``core.sweep.sweep_grid``, one process),
* the cost per point of ``core.simulate`` one point at a time (``exact``, 2 samples, on
  ``--reference`` points spread over the sweep), and the ratio,
* the agreement on those points: labels, transitions per period and regime labels equal
  (count of differences), and the largest difference of period, ``x_max``, impact speed
  and the steady period's transitions (position, speeds),
* how many points the sweep left to ``simulate`` (``fallback``).

Target: 10^5 points in <= 5 s on this 2-core machine, agreement to 1e-9.

``--deformable N`` adds a deformable-stop sweep of N belt speeds (``simulate`` per point):
the pilot's cost per point, the chunk size it gives, and the wall time in this process
against a 2-worker Dask ``LocalCluster`` (processes), with a check that both are equal.

    python benchmarks/sweep_speed.py              # about a minute on two cores
    python benchmarks/sweep_speed.py --points 20000 --reference 200
    python benchmarks/sweep_speed.py --points 0 --deformable 40
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, RigidStop  # noqa: E402
from core.sweep import plan_grid, sweep_grid  # noqa: E402
from core.sweep.lanes import make_lanes  # noqa: E402
from core.sweep.scalar import solve_lanes  # noqa: E402

T_END = 200.0
TARGET_SECONDS = 5.0
OSC = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)  # a = 0.2, b = 0.3


def scenes(points: int):
    side = int(round(math.sqrt(points)))
    speeds = np.linspace(0.005, 0.45, side)  # v* = a = 0.2: slow and fast belts
    clearances = np.linspace(0.0, 0.6, side)  # below a - sqrt(a^2 - v^2) to beyond 2a
    yield "no stop (belt_speed)", None, {"belt_speed": np.linspace(0.0, 0.45, side * side)}
    for r, name in ((1.0, "elastic"), (0.7, "inelastic"), (0.0, "plastic")):
        yield (
            f"rigid {name} r={r:g} (v x c grid)",
            RigidStop(0.25, r),
            {"belt_speed": speeds, "clearance": clearances},
        )


def agreement(res, ref, idx) -> dict[str, float]:
    """Differences between the sweep at points ``idx`` and the one-by-one reference."""
    out = {
        "label": int(np.sum(res.label[idx] != ref.label)),
        "tpp": int(np.sum(res.transitions_per_period[idx] != ref.transitions_per_period)),
    }
    names = np.asarray(res.regimes, dtype=object)[res.regime[idx]]
    ref_res = ref.finish(res.parameters, res.axes, res.quantity, res.t_end, res.method)
    out["regime"] = int(np.sum(names != np.asarray(ref_res.regimes, dtype=object)[ref_res.regime]))
    worst = 0.0
    for name in ("period", "x_max", "impact_speed"):
        a, b = getattr(res, name)[idx], getattr(ref, name)
        if np.any(np.isnan(a) != np.isnan(b)):
            worst = math.inf
        both = ~np.isnan(a) & ~np.isnan(b)
        worst = max(worst, float(np.max(np.abs(a[both] - b[both]), initial=0.0)))
    cyc = 0.0
    for k, i in enumerate(idx):
        lo, hi = res.offsets[i], res.offsets[i + 1]
        rlo, rhi = ref.offsets[k], ref.offsets[k + 1]
        if hi - lo != rhi - rlo:
            cyc = math.inf
            continue
        for name in ("cycle_x", "cycle_v", "cycle_v_after"):
            diff = np.abs(getattr(res, name)[lo:hi] - getattr(ref, name)[rlo:rhi])
            cyc = max(cyc, float(np.max(diff, initial=0.0)))
    out["scalars"] = worst
    out["cycle"] = cyc
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=100_000)
    parser.add_argument("--reference", type=int, default=300, help="points solved by simulate")
    parser.add_argument("--repeat", type=int, default=3, help="sweep timings (best is shown)")
    parser.add_argument("--deformable", type=int, default=0, help="deformable-stop points")
    args = parser.parse_args()
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.machine()}, t_end = {T_END:g}"
    )
    header = (
        f"{'scene':34s} {'points':>7s} {'wall s':>7s} {'us/pt':>7s} {'simulate us/pt':>15s} "
        f"{'ratio':>6s} {'fallback':>8s} {'labels':>6s} {'regime':>6s} {'max |diff|':>10s}"
    )
    if args.points:
        print(header)
        print("-" * len(header))
    total_worst = 0.0
    for name, stop, axes in scenes(args.points) if args.points else ():
        times = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            res = sweep_grid(OSC, stop, axes, t_end=T_END)
            times.append(time.perf_counter() - start)
        wall = min(times)
        rng = np.random.default_rng(18)
        idx = np.sort(rng.choice(len(res), size=min(args.reference, len(res)), replace=False))
        lanes = make_lanes(OSC, stop, axes, 0.0).take(idx)
        start = time.perf_counter()
        ref = solve_lanes(lanes, T_END, 0.0, 0.0, "exact")
        sim = (time.perf_counter() - start) / len(idx)
        agree = agreement(res, ref, idx)
        worst = max(agree["scalars"], agree["cycle"])
        total_worst = max(total_worst, worst)
        per = wall / len(res)
        print(
            f"{name:34s} {len(res):7d} {wall:7.2f} {per * 1e6:7.1f} {sim * 1e6:15.1f} "
            f"{sim / per:6.0f} {int(res.fallback.sum()):8d} "
            f"{agree['label'] + agree['tpp']:6d} {agree['regime']:6d} {worst:10.1e}"
        )
    if args.points:
        print(
            f"\ntarget: {args.points} points in <= {TARGET_SECONDS:g} s per sweep; agreement "
            f"<= 1e-9 (worst here {total_worst:.1e}). 'labels' counts points whose steady label "
            "or transitions per period differ from simulate's, 'regime' whose regime label does."
        )
    if args.deformable:
        deformable(args.deformable)


def deformable(n: int) -> None:
    """A deformable-stop sweep here and on a 2-worker LocalCluster."""
    from dask.distributed import Client, LocalCluster

    from core.sweep.distributed import chunk_size, pilot_cost, run_chunks

    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    stop = HystereticStop(
        clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.02, beta_c=40.0, beta_e=40.0
    )
    t_end = 100.0
    axes = {"belt_speed": np.linspace(0.02, 0.3, n)}
    plan = plan_grid(osc, stop, axes, t_end=t_end)
    cost = pilot_cost(plan.lanes, t_end, 0.0, 0.0, "exact")
    start = time.perf_counter()
    serial, _ = run_chunks(plan)
    wall_serial = time.perf_counter() - start
    start = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            up = time.perf_counter() - start
            rec, info = run_chunks(plan, client=client)
    wall_dask = time.perf_counter() - start
    same = all(
        np.array_equal(getattr(serial, f), getattr(rec, f), equal_nan=True)
        for f in ("period", "x_max", "impact_speed", "cycle_x", "cycle_v", "cycle_force")
    ) and np.array_equal(serial.label, rec.label)
    print(
        f"\ndeformable stop, {n} belt speeds, t_end = {t_end:g}: pilot {cost * 1e3:.0f} ms/point"
        f" -> {chunk_size(cost, n, 0.5)} points per task ({info['chunks']} tasks)\n"
        f"  this process: {wall_serial:.1f} s; 2-worker LocalCluster: {wall_dask:.1f} s "
        f"(of which {up:.1f} s starting it); identical results: {same}"
    )


if __name__ == "__main__":
    main()
