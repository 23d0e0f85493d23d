"""Command line: ``python -m core.sweep --param belt_speed 0.01:1:2000 --out sweep.npz``.

Sweeps one or two parameters (``--param NAME START:STOP:NUM``, evenly spaced and both ends
included) of a base scene given by the other options, and writes a ``.npz`` (see
:meth:`core.sweep.SweepResult.to_npz`) or, when pyarrow is installed, a ``.parquet`` table
with one row per point and the Poincaré samples as a list column. Scenes the closed form
covers run here; the others run on a Dask ``LocalCluster``, or on the cluster at
``--scheduler``. docs/sweeps.md has examples.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from core.params import HystereticStop, Oscillator, RigidStop
from core.simulate import METHODS
from core.sweep import plan_grid, vectorised
from core.sweep.lanes import PARAMETERS
from core.sweep.result import LABELS, QUANTITIES, SweepResult


def parse_range(text: str) -> np.ndarray:
    """``START:STOP:NUM`` -> ``NUM`` evenly spaced values from START to STOP inclusive."""
    try:
        start, stop, num = text.split(":")
        values = np.linspace(float(start), float(stop), int(num))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"a range is START:STOP:NUM, e.g. 0.01:1:2000; got {text!r}"
        ) from None
    if len(values) < 1:
        raise argparse.ArgumentTypeError(f"NUM must be at least 1; got {text!r}")
    return values


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m core.sweep",
        description="Steady states of the friction-impact oscillator over swept parameters.",
    )
    p.add_argument(
        "--param", nargs=2, action="append", metavar=("NAME", "START:STOP:NUM"), required=True,
        help=f"a swept parameter (once or twice), one of {', '.join(PARAMETERS)}",
    )
    p.add_argument("--mu-s", type=float, default=0.3)
    p.add_argument("--mu-k", type=float, default=0.2)
    p.add_argument("--belt-speed", type=float, default=0.1)
    p.add_argument("--u-s", type=float, default=1.0)
    p.add_argument("--stop", choices=("none", "rigid", "hysteretic"), default=None,
                   help="default: rigid if a clearance is given or swept, else none")
    p.add_argument("--clearance", type=float, default=None)
    p.add_argument("--restitution", type=float, default=1.0)
    p.add_argument("--k-c0", type=float, default=1000.0)
    p.add_argument("--k-e0", type=float, default=500.0)
    p.add_argument("--limit-overlap", type=float, default=0.05)
    p.add_argument("--beta-c", type=float, default=5.0)
    p.add_argument("--beta-e", type=float, default=5.0)
    p.add_argument("--t-end", type=float, default=200.0)
    p.add_argument("--method", choices=METHODS, default="exact")
    p.add_argument("--quantity", choices=tuple(QUANTITIES), default=None)
    p.add_argument("--out", required=True, help="output file, .npz or .parquet")
    p.add_argument("--scheduler", default=None, help="address of a Dask scheduler, tcp://...")
    p.add_argument("--workers", type=int, default=None,
                   help="workers of the local Dask cluster (default: one per core)")
    p.add_argument("--serial", action="store_true",
                   help="solve here, without Dask (default for closed-form scenes)")
    p.add_argument("--dashboard", default=None,
                   help="address of the local cluster's dashboard, e.g. :5116 (default: none)")
    p.add_argument("--task-seconds", type=float, default=0.5,
                   help="least work per Dask task, from a pilot's cost per point")
    return p


def scene(args) -> tuple[Oscillator, RigidStop | HystereticStop | None]:
    osc = Oscillator(mu_s=args.mu_s, mu_k=args.mu_k, belt_speed=args.belt_speed, u_s=args.u_s)
    swept = {name for name, _ in args.param}
    kind = args.stop
    if kind is None:
        kind = "rigid" if args.clearance is not None or "clearance" in swept else "none"
    if kind == "none":
        return osc, None
    clearance = args.clearance
    if clearance is None:
        if "clearance" not in swept:
            raise SystemExit("--clearance is needed with a stop (or sweep it with --param)")
        clearance = float(dict(args.param)["clearance"].split(":")[0])
    if kind == "rigid":
        return osc, RigidStop(clearance=clearance, restitution=args.restitution)
    return osc, HystereticStop(
        clearance=clearance, k_c0=args.k_c0, k_e0=args.k_e0, limit_overlap=args.limit_overlap,
        beta_c=args.beta_c, beta_e=args.beta_e,
    )


def check_out(path: str) -> None:
    """Refuse an output the sweep could not be written to, before the sweep runs."""
    if path.endswith(".npz"):
        return
    if not path.endswith(".parquet"):
        raise SystemExit(f"--out must end in .npz or .parquet; got {path!r}")
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise SystemExit(
            "writing .parquet needs pyarrow, which is not installed; use .npz"
        ) from None


def write(result: SweepResult, path: str) -> None:
    """``.npz`` always; ``.parquet`` when pyarrow is installed (it is not a dependency)."""
    if path.endswith(".npz"):
        result.to_npz(path)
        return
    import pyarrow as pa
    import pyarrow.parquet as pq
    grids = np.meshgrid(*(result.axes[p] for p in result.parameters), indexing="ij")
    values, offsets = result.samples()
    columns = {name: g.ravel() for name, g in zip(result.parameters, grids, strict=True)}
    columns.update(
        label=np.asarray(LABELS)[result.label],
        regime=np.asarray(result.regimes)[result.regime],
        period=result.period,
        transitions_per_period=result.transitions_per_period,
        x_max=result.x_max,
        impact_speed=result.impact_speed,
        fallback=result.fallback,
    )
    table = pa.table({k: pa.array(v) for k, v in columns.items()})
    samples = pa.ListArray.from_arrays(pa.array(offsets.astype(np.int32)), pa.array(values))
    table = table.append_column(result.quantity, samples)
    pq.write_table(table, path)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    check_out(args.out)
    if len(args.param) > 2:
        raise SystemExit("--param may be given once or twice")
    try:
        axes = {name: parse_range(text) for name, text in args.param}
    except argparse.ArgumentTypeError as err:
        raise SystemExit(str(err)) from None
    try:
        osc, stop = scene(args)
        local = args.scheduler is None and args.workers is None
        serial = args.serial or (local and vectorised(stop, args.method))
        started = time.perf_counter()
        if serial:
            from core.sweep.distributed import progress_bar, run_chunks

            plan = plan_grid(osc, stop, axes, quantity=args.quantity, t_end=args.t_end,
                             method=args.method)
            rec, _ = run_chunks(plan, client=None, task_seconds=args.task_seconds,
                                progress=progress_bar)
            result = plan.finish(rec)
        else:
            from core.sweep.distributed import progress_bar, sweep_distributed

            result = sweep_distributed(
                osc, stop, axes, quantity=args.quantity, t_end=args.t_end, method=args.method,
                scheduler=args.scheduler, n_workers=args.workers,
                dashboard_address=args.dashboard, task_seconds=args.task_seconds,
                progress=progress_bar,
            )
    except ValueError as err:
        raise SystemExit(f"error: {err}") from None
    elapsed = time.perf_counter() - started
    write(result, args.out)
    counts = np.bincount(result.label, minlength=len(LABELS))
    summary = ", ".join(f"{LABELS[i]} {c}" for i, c in enumerate(counts) if c)
    sys.stderr.write(
        f"{len(result)} points in {elapsed:.2f} s ({summary}; "
        f"{int(result.fallback.sum())} solved one by one) -> {args.out}\n"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
