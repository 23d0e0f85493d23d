"""The event method's error on random deformable stops, against the exact method.

Random scenes (ranges in :func:`scene`), each solved by the event method and the exact
method at ``--rtol`` (atol a thousandth of it) and by the exact method at rtol 1e-12, atol
1e-15 (the reference), from rest at 0 to ``--t-end``. Errors are ``max(|dx|, |dx'|)`` at
``t_end`` over the length scale the exact method states (``info['length_scale']``, else
``max(a, clearance)``). Prints a table of the error distribution per method and the scenes
beyond ``--beyond``.

    PYTHONPATH=. .venv/bin/python benchmarks/event_accuracy.py --seeds 0:60,1000:1060
        [--rtol 1e-8] [--t-end 40] [--beyond 1e-6]

(~4 minutes for the 120 default seeds on a 2-core machine; results:
benchmarks/results/2026-11-27-event-kinks.md.)
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

from core import HystereticStop, Oscillator, simulate


def scene(rng: np.random.Generator) -> tuple[Oscillator, HystereticStop]:
    """A random scene: friction, belt and stop drawn over the ranges of the results file."""
    mus = rng.uniform(0.1, 0.6)
    muk = mus * rng.uniform(0.3, 0.95)
    v = 10 ** rng.uniform(-2, -0.5)
    us = rng.uniform(0.5, 3)
    osc = Oscillator(mu_s=mus, mu_k=muk, belt_speed=v, u_s=us)
    clearance = osc.a * rng.uniform(0.5, 1.5)
    k_c0 = 10 ** rng.uniform(2, 5)
    k_e0 = k_c0 * rng.uniform(0.2, 1.0)
    d_lim = 10 ** rng.uniform(-3, 0)
    beta_c = 10 ** rng.uniform(0, 3)
    beta_e = beta_c * 10 ** rng.uniform(0, 0.5)
    law = str(rng.choice(["paper", "passive"]))
    return osc, HystereticStop(clearance=clearance, k_c0=k_c0, k_e0=k_e0,
                               limit_overlap=d_lim, beta_c=beta_c, beta_e=beta_e, law=law)


def seeds(spec: str) -> list[int]:
    """``"0:60,1000:1060"`` -> the seeds of those ranges."""
    out: list[int] = []
    for part in spec.split(","):
        lo, hi = (int(p) for p in part.split(":"))
        out += range(lo, hi)
    return out


def state_error(res, ref, scale: float) -> float:
    """Error of ``res`` at the reference's last time (both end there unless one stopped)."""
    t = min(float(res.t[-1]), float(ref.t[-1]))
    (x, v), (x_ref, v_ref) = res.evaluate([t]), ref.evaluate([t])
    return max(abs(x[0] - x_ref[0]), abs(v[0] - v_ref[0])) / scale


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="0:60,1000:1060")
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--t-end", type=float, default=40.0)
    parser.add_argument("--beyond", type=float, default=1e-6)
    args = parser.parse_args()
    tol = {"rtol": args.rtol, "atol": 1e-3 * args.rtol}
    errors: dict[str, list[float]] = {"event": [], "exact": []}
    times: dict[str, list[float]] = {"event": [], "exact": []}
    beyond = []
    for seed in seeds(args.seeds):
        osc, stop = scene(np.random.default_rng(seed))
        ref = simulate(osc, stop, args.t_end, method="exact", rtol=1e-12, atol=1e-15,
                       n_samples=2)
        scale = ref.info.get("length_scale") or max(osc.a, stop.clearance)
        for method in errors:
            start = time.process_time()
            res = simulate(osc, stop, args.t_end, method=method, n_samples=2, **tol)
            times[method].append(time.process_time() - start)
            errors[method].append(state_error(res, ref, scale))
        if errors["event"][-1] > args.beyond:
            beyond.append((seed, errors["event"][-1], len(ref.transitions), stop))
    print(f"{len(errors['event'])} scenes, rtol {args.rtol:g}, t_end {args.t_end:g}\n")
    print("| method | median | 90th percentile | largest | beyond "
          f"{args.beyond:g} | median time [ms] |")
    print("|---|---|---|---|---|---|")
    for method, errs in errors.items():
        errs = sorted(errs)
        p90 = errs[min(len(errs) - 1, math.ceil(0.9 * len(errs)) - 1)]
        print(f"| {method} | {statistics.median(errs):.2g} | {p90:.2g} | {errs[-1]:.2g} | "
              f"{sum(e > args.beyond for e in errs)} | "
              f"{1e3 * statistics.median(times[method]):.0f} |")
    print(f"\nevent beyond {args.beyond:g}: seed, error, transitions, stop")
    for seed, err, n, stop in beyond:
        print(f"  {seed}  {err:.2g}  {n}  k_c0 {stop.k_c0:.3g} D {stop.limit_overlap:.3g} "
              f"beta_c {stop.beta_c:.3g} {stop.law}")


if __name__ == "__main__":
    main()
