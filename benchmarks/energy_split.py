"""The numerical methods' energy split on random deformable stops, against the exact method.

Random scenes of ``benchmarks/event_accuracy.py`` (:func:`event_accuracy.scene`: both laws,
trains of contacts and masses pressed on the stop), each solved by the event method and the
switch model at ``--rtol`` (atol a thousandth of it) and by the exact method at rtol 1e-12,
atol 1e-15, from rest at 0 to ``--t-end``, all sampled at the same times. Per method, over
the scenes, the distribution of

* ``balance``: the largest residual of ``mechanical - mechanical[0] = friction_work -
  stop_loss - stop_stored`` over the belt's largest input;
* ``dip``: the largest fall of ``stop_loss`` over the same scale, on the passive law's
  scenes (that law returns no energy on any closed program: only rounding may show);
* ``stored`` and ``loss``: the largest difference of ``stop_stored`` and ``stop_loss`` from
  the exact method's, over the same scale, with ``dx``, the largest difference of the
  positions, beside them (the switch model's own error, its stick band, moves the motion).

    PYTHONPATH=. .venv/bin/python benchmarks/energy_split.py [--seeds 0:40] [--rtol 1e-8]
        [--t-end 30]

(~2 minutes for the 40 default seeds on a 2-core machine; results:
benchmarks/results/2026-11-28-energy-split.md.)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from event_accuracy import scene, seeds  # noqa: E402

from core import Status, simulate  # noqa: E402

METHODS = ("event", "switch")
COLUMNS = ("balance", "dip", "stored", "loss", "dx")


def measures(res, ref, passive: bool) -> dict[str, float]:
    """The columns of one run against the reference (module docstring)."""
    e, er = res.energy, ref.energy
    scale = max(float(np.max(np.abs(er.belt_input))), 1e-300)
    budget = e.mechanical - e.mechanical[0] - (e.friction_work - e.stop_loss - e.stop_stored)
    n = min(len(res.t), len(ref.t))  # a run stopped early (limit overlap) has fewer samples
    return {
        "balance": float(np.max(np.abs(budget))) / scale,
        "dip": max(0.0, -float(np.diff(e.stop_loss).min())) / scale if passive else np.nan,
        "stored": float(np.max(np.abs(e.stop_stored[:n] - er.stop_stored[:n]))) / scale,
        "loss": float(np.max(np.abs(e.stop_loss[:n] - er.stop_loss[:n]))) / scale,
        "dx": float(np.max(np.abs(res.x[:n] - ref.x[:n]))),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="0:40")
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--t-end", type=float, default=30.0)
    args = parser.parse_args()
    tol = {"rtol": args.rtol, "atol": 1e-3 * args.rtol}
    t_eval = np.linspace(0.0, args.t_end, 3001)
    rows: dict[str, list[dict[str, float]]] = {m: [] for m in METHODS}
    skipped = 0
    start = time.process_time()
    for seed in seeds(args.seeds):
        osc, stop = scene(np.random.default_rng(seed))
        ref = simulate(osc, stop, args.t_end, rtol=1e-12, atol=1e-15, t_eval=t_eval)
        runs = {m: simulate(osc, stop, args.t_end, method=m, t_eval=t_eval, **tol)
                for m in METHODS}
        if any(r.status not in (Status.SUCCESS, Status.LIMIT_OVERLAP)
               for r in (ref, *runs.values())):
            skipped += 1  # a time budget or a failed stop: not the same motion
            continue
        for m, res in runs.items():
            rows[m].append(measures(res, ref, stop.law == "passive"))
    print(f"# {len(rows['event'])} scenes (seeds {args.seeds}, {skipped} skipped), "
          f"rtol {args.rtol:g}, t_end {args.t_end:g}; "
          f"{time.process_time() - start:.0f} s CPU")
    print(f"{'method':8s} {'column':8s} {'median':>9s} {'p90':>9s} {'largest':>9s}")
    for m in METHODS:
        for col in COLUMNS:
            vals = np.array([r[col] for r in rows[m]])
            vals = vals[np.isfinite(vals)]
            if not len(vals):
                continue
            print(f"{m:8s} {col:8s} {np.median(vals):9.1e} {np.quantile(vals, 0.9):9.1e} "
                  f"{vals.max():9.1e}")


if __name__ == "__main__":
    main()
