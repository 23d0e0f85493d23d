"""Server time of drawing a solution for the screen (app/sampling.py), per slider release.

A release solves (cached here: this measures only the drawing) and then samples the motion
for the phase portrait (``phase_columns``: the path to the end of the first steady cycle,
chords of at most 2 px on the largest frame) and for the time histories
(``trajectory_columns``: fine samples reduced per pixel column, and the mode bands). For
scenes with a rigid stop, no stop and a deformable one, at the scene's horizon and at
``t_end`` = 1000 and 5000, it prints the median and 95th percentile of each, the points
sent, and the solve time for scale.

    python benchmarks/sampling_speed.py            # a minute or two on two shared cores
    python benchmarks/sampling_speed.py --quick    # fewer repeats
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from app import plots  # noqa: E402
from app.solve.pool import solve  # noqa: E402
from app.state import DIMENSIONLESS, scene_values  # noqa: E402

SCENES = ("4b", "5a", "5b", "5d", "7c", "7d", "10")
HORIZONS = (None, 1000.0, 5000.0)


def _times(fn, repeats: int) -> tuple[float, float]:
    out = []
    for _ in range(repeats):
        plots.DRAWING_CACHE.clear()  # a release draws a new solution
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    out.sort()
    return statistics.median(out) * 1e3, out[min(len(out) - 1, int(0.95 * len(out)))] * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    args = parser.parse_args()
    repeats = 7 if args.quick else 25
    head = (f"{'scene':>5} {'t_end':>6} {'steady':>9} {'solve ms':>8} "
            f"{'phase ms med/p95':>17} {'pts':>6} {'history ms med/p95':>19} {'pts':>6}")
    print(head)
    print("-" * len(head))
    for key in SCENES:
        for horizon in HORIZONS:
            values = dict(scene_values(key))
            if horizon is not None:
                values["t_end"] = horizon
            t0 = time.perf_counter()
            sol = solve(values)
            solve_ms = (time.perf_counter() - t0) * 1e3
            phase = plots.phase_columns(sol, DIMENSIONLESS)
            n_phase = sum(len(phase[n]["x"]) for n in plots.MODE_NAMES.values())
            traj = plots.trajectory_columns(sol, DIMENSIONLESS)
            p_med, p_95 = _times(lambda s=sol: plots.phase_columns(s, DIMENSIONLESS), repeats)
            h_med, h_95 = _times(lambda s=sol: plots.trajectory_columns(s, DIMENSIONLESS),
                                 repeats)
            print(f"{key:>5} {sol.t_end:>6g} {sol.result.steady.kind.value:>9} "
                  f"{solve_ms:>8.1f} {p_med:>8.2f}/{p_95:<8.2f} {n_phase:>6} "
                  f"{h_med:>9.2f}/{h_95:<9.2f} {len(traj['t']):>6}")


if __name__ == "__main__":
    main()
