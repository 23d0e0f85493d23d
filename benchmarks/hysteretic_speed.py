"""Speed of the default hysteretic solve on the paper's slow-belt scenes (issue 3).

Scenes "10" and "11" of app/scenes.py (mu_s = 0.3, mu_k = 0.2, v = 0.07; HystereticStop with
k_c0 = 400, k_e0 = 36, limit_overlap = 0.01, beta_c = beta_e = 300; clearance 0.24 and 0.15),
2,000 samples, from rest at the origin. For each horizon: median wall time, contact-phase
right-hand-side evaluations (Dormand-Prince stages), semi-analytic arcs, contacts, and the
largest residual of the energy balance over the samples. ``--legacy`` adds the rows of the
step-by-step contact integration (``arcs=False``) for comparison.

    .venv/bin/python benchmarks/hysteretic_speed.py [--legacy] [--repeat N]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator  # noqa: E402
from core.hysteretic import simulate_hysteretic  # noqa: E402

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
STOP = dict(k_c0=400.0, k_e0=36.0, limit_overlap=0.01, beta_c=300.0, beta_e=300.0)
SCENES = {"10": 0.24, "11": 0.15}
HORIZONS = (80.0, 100.0, 1e3, 1e4)


def balance(res) -> float:
    e = res.energy
    lhs = e.mechanical - e.mechanical[0]
    return float(np.abs(lhs - (e.friction_work - e.stop_loss - e.stop_stored)).max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--legacy", action="store_true", help="also time arcs=False")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    variants = [True, False] if args.legacy else [True]
    print(
        f"{'scene':>5} {'path':>7} {'t_end':>7} {'median ms':>10} {'rhs evals':>10} "
        f"{'arcs':>7} {'contacts':>8} {'reversals':>9} {'steady':>9} {'energy resid':>12}"
    )
    for key, xb in SCENES.items():
        stop = HystereticStop(xb, **STOP)
        for t_end in HORIZONS:
            for arcs in variants:
                times = []
                for _ in range(args.repeat if t_end <= 1e3 else max(1, args.repeat // 2)):
                    t0 = time.perf_counter()
                    res = simulate_hysteretic(SLOW, stop, t_end, 0.0, 0.0, arcs=arcs)
                    times.append(time.perf_counter() - t0)
                st = res.stats
                print(
                    f"{key:>5} {'arcs' if arcs else 'steps':>7} {t_end:>7g} "
                    f"{1e3 * float(np.median(times)):>10.1f} {st['rhs_evals']:>10.0f} "
                    f"{st.get('arcs', 0.0):>7.0f} {st['n_contacts']:>8.0f} "
                    f"{res.transition_counts.get('reversal', 0):>9d} "
                    f"{res.steady.kind.value:>9} {balance(res):>12.2e}"
                )


if __name__ == "__main__":
    main()
