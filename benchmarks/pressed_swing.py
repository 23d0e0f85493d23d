"""How far the loops of a mass pressed on a deformable stop still swing where they are labelled.

Random pressed stops under the paper's law (``HystereticStop`` default), from rest at the
origin on ``Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=v, u_s=2.0)`` (a = 0.6): k_c0 1e2..1e6,
k_e0/k_c0 0.05..1, beta_c 1..1e3 and beta_e from it to 1e3, D 1e-3..1, x_bar 0.3..0.6, v
0.05..0.5 (log-uniform where a range spans decades). Each is solved as the app's standard
preset does (rtol 1e-8, atol 1e-11) to t_end = 400 and 1600. For every run labelled rest or
an oscillation on the stop the table gives, over the length scale ``L = max(a, b, v, x_bar,
D)`` and measured on the solution over the loops' last cycle before t_end (the cycle of the
last stored reversals, 4,096 points):

* ``Ax``, ``Av``: half the range of ``x`` and of ``x'``, and each over what the rule for rest
  lets rest (``10 rtol L`` and ``100 rtol L``, core.deformable.rest.rest_swing);
* ``imb``: the force imbalance ``|a - x - phi|`` at t_end (the acceleration: zero at rest);
* ``swinging``: labelled rest while ``Ax`` or ``Av`` is above the rule's threshold.

    PYTHONPATH=. .venv/bin/python benchmarks/pressed_swing.py [--seed S] [--draws N]
"""

from __future__ import annotations

import argparse
import datetime
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, simulate  # noqa: E402

PRESET = {"rtol": 1e-8, "atol": 1e-11}
HORIZONS = (400.0, 1600.0)
#: The rule for rest's thresholds over ``rtol L`` (core.deformable.rest.rest_swing).
REST_X, REST_V = 10.0, 100.0
POINTS = 4096


def draw(rng: np.random.Generator) -> tuple[float, HystereticStop]:
    k_c0 = 10.0 ** rng.uniform(2.0, 6.0)
    beta_c = 10.0 ** rng.uniform(0.0, 3.0)
    beta_e = min(beta_c * 10.0 ** rng.uniform(0.0, 3.0), 1e3)
    d = 10.0 ** rng.uniform(-3.0, 0.0)
    clearance = rng.uniform(0.3, 0.6)
    belt_speed = rng.uniform(0.05, 0.5)
    k_e0 = k_c0 * 10.0 ** rng.uniform(-1.3, 0.0)
    return belt_speed, HystereticStop(clearance, k_c0, k_e0, limit_overlap=d, beta_c=beta_c,
                                      beta_e=beta_e)


def swing(res, t_end: float) -> tuple[float, float] | None:
    """Half the range of x and x' over the last cycle of the stored reversals."""
    rev = [tr.t for tr in res.transitions if tr.kind.value == "reversal"]
    if len(rev) < 3:
        return None
    t = np.linspace(t_end - (rev[-1] - rev[-3]), t_end, POINTS + 1)
    x, v = res.evaluate(t)
    return 0.5 * float(np.ptp(x)), 0.5 * float(np.ptp(v))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--draws", type=int, default=40)
    args = ap.parse_args()
    print(f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
          f"{platform.machine()}, Python {platform.python_version()}, numpy {np.__version__},"
          f" scipy {scipy.__version__}")
    print(f"# seed {args.seed}, {args.draws} draws; preset rtol {PRESET['rtol']:g} atol "
          f"{PRESET['atol']:g}; Ax, Av, imb over L; /rest: over the rule's threshold")
    print(f"{'k_c0':>8} {'k_e0':>8} {'b_c':>6} {'b_e':>6} {'D':>7} {'x_bar':>5} {'v':>5} "
          f"{'t_end':>5} {'ms':>7} {'label':>13} {'Ax':>8} {'/rest':>7} {'Av':>8} {'/rest':>7} "
          f"{'imb':>8} {'decay/cycle':>11}")
    rng = np.random.default_rng(args.seed)
    swinging, labelled, worst = 0, 0, 0.0
    for _ in range(args.draws):
        belt_speed, stop = draw(rng)
        osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=belt_speed, u_s=2.0)
        scale = max(osc.a, osc.b, osc.v, stop.clearance, stop.limit_overlap)
        for t_end in HORIZONS:
            t0 = time.perf_counter()
            res = simulate(osc, stop, t_end, **PRESET)
            ms = 1e3 * (time.perf_counter() - t0)
            kind = res.steady.kind.value
            head = (f"{stop.k_c0:8.3g} {stop.k_e0:8.3g} {stop.beta_c:6.3g} {stop.beta_e:6.3g} "
                    f"{stop.limit_overlap:7.3g} {stop.clearance:5.3f} {belt_speed:5.3f} "
                    f"{t_end:5.0f} {ms:7.1f} {kind:>13}")
            found = swing(res, t_end) if res.success and kind in ("rest", "oscillation") else None
            if found is None:
                print(head)
                continue
            labelled += 1
            ax, av = found[0] / scale, found[1] / scale
            rx, rv = ax / (REST_X * PRESET["rtol"]), av / (REST_V * PRESET["rtol"])
            imb = abs(osc.a - res.x[-1] - res.contact_force[-1]) / scale
            flag = kind == "rest" and max(rx, rv) > 1.0
            swinging += flag
            worst = max(worst, imb) if flag else worst
            decay = (f"{1.0 - res.steady.decay_rate:11.2e}" if kind == "oscillation"
                     else f"{'':11}")
            print(f"{head} {ax:8.2e} {rx:7.3g} {av:8.2e} {rv:7.3g} {imb:8.2e} {decay}"
                  f"{'  swinging' if flag else ''}", flush=True)
    print(f"# {labelled} runs labelled rest or oscillation; {swinging} labelled rest while "
          f"swinging beyond the rule's threshold (largest imbalance among them {worst:.2e})")


if __name__ == "__main__":
    main()
