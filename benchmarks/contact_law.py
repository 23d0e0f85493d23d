"""The two readings of the contact law compared: loops and restitution vs impact speed.

For docs/contact-law.md. Three tables:

1. One contact of a free mass on the stop (``x'' = -phi(delta)``, no spring, no friction)
   at approach speed ``w``: the restitution (rebound over approach speed) and the largest
   overlap, for ``law = "paper"`` and ``"passive"``, against Eq. 16's ``sqrt(k_e0/k_c0)``.
2. The loops of paper Fig. 2b's program (a sine of decreasing amplitude about D/2, from 0):
   work done on the stop and the loss over the program, per law.
3. The closed programs that return energy under the paper's reading (work < 0).

    PYTHONPATH=. .venv/bin/python benchmarks/contact_law.py
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop  # noqa: E402
from core.deformable.law import (  # noqa: E402
    FIRST_LOADING,
    contact_force,
    force_and_slope,
    program_work,
    reverse,
)

#: The paper's Fig. 2b stop, and the app's scene stop (k_e0/k_c0 = 0.09, beta = 300).
STOPS = {
    "Fig. 2b (k_e0/k_c0 0.5, beta 5)": dict(k_c0=1000.0, k_e0=500.0, limit_overlap=0.05,
                                            beta_c=5.0, beta_e=5.0),
    "scenes 10-11 (0.09, beta 300)": dict(k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                                          beta_c=300.0, beta_e=300.0),
}
SPEEDS = (1e-3, 1e-2, 0.03, 0.1, 0.3, 1.0, 3.0)


def one_contact(stop: HystereticStop, w: float) -> tuple[float, float]:
    """Restitution and largest overlap of one contact at approach speed ``w``."""
    opts = dict(rtol=1e-11, atol=1e-14, method="DOP853")

    def rhs(branch):
        return lambda t, y: [y[1], -force_and_slope(y[0], branch, stop)[0]]

    turn = lambda t, y: y[1]  # noqa: E731
    turn.terminal, turn.direction = True, -1
    t_scale = math.pi / math.sqrt(stop.k_c0)
    up = solve_ivp(rhs(FIRST_LOADING), (0.0, 100 * t_scale), [0.0, w], events=turn, **opts)
    d_max = float(up.y_events[0][0][0])
    branch = reverse(d_max, float(contact_force(d_max, FIRST_LOADING, stop)), FIRST_LOADING)
    out = lambda t, y: y[0]  # noqa: E731
    out.terminal, out.direction = True, -1
    down = solve_ivp(rhs(branch), (0.0, 100 * t_scale), [d_max, 0.0], events=out, **opts)
    return -float(down.y_events[0][0][1]) / w, d_max


def fig2b_turns(d_lim: float) -> list[float]:
    """Turning points of Fig. 2b's program: D/2 (1 + a_k (-1)^k) with a_k falling to 0."""
    amps = np.linspace(0.9, 0.05, 12)
    return [0.5 * d_lim * (1.0 + a * (1 if k % 2 == 0 else -1)) for k, a in enumerate(amps)]


def main() -> None:
    print("1. Restitution of one contact (largest overlap / D in brackets)")
    for name, kw in STOPS.items():
        r_eq = math.sqrt(kw["k_e0"] / kw["k_c0"])
        print(f"\n{name}: Eq. 16 r_eq = {r_eq:.3f}")
        print(f"{'w':>7} {'paper':>16} {'passive':>16}")
        for w in SPEEDS:
            cols = []
            for law in ("paper", "passive"):
                stop = HystereticStop(0.0, law=law, **kw)
                try:
                    r, d_max = one_contact(stop, w)
                    cols.append(f"{r:.4f} ({d_max / kw['limit_overlap']:.3f})")
                except (IndexError, ValueError):
                    cols.append("limit overlap")
            print(f"{w:>7g} {cols[0]:>16} {cols[1]:>16}")
    print("\n2. Fig. 2b program (12 turning points about D/2): work on the stop / k_c0 D^2")
    for name, kw in STOPS.items():
        cols = []
        for law in ("paper", "passive"):
            stop = HystereticStop(0.0, law=law, **kw)
            scale = kw["k_c0"] * kw["limit_overlap"] ** 2
            cols.append(f"{program_work(stop, fig2b_turns(kw['limit_overlap'])) / scale:.5f}")
        print(f"{name:>34}: paper {cols[0]}, passive {cols[1]}")
    print("\n3. Closed programs that return energy under the paper's reading (work / k_c0 D^2)")
    d = 0.05
    cases = {
        "beta 5, k_e0/k_c0 0.1: 0.641 0.537 0.896 0.093 D": (
            dict(k_c0=1000.0, k_e0=100.0, beta_c=5.0, beta_e=5.0),
            [0.641 * d, 0.537 * d, 0.896 * d, 0.093 * d]),
        "beta_c 0.45 beta_e 4.5: small cycles": (
            dict(k_c0=1000.0, k_e0=500.0, beta_c=0.45, beta_e=4.5),
            [0.44 * d, 0.42 * d] + [0.43 * d, 0.42 * d] * 80 + [0.8 * d, 0.24 * d]
            + [0.2407 * d, 0.24 * d] * 70),
    }
    for name, (kw, turns) in cases.items():
        cols = []
        for law in ("paper", "passive"):
            stop = HystereticStop(0.0, law=law, limit_overlap=d, **kw)
            cols.append(f"{program_work(stop, turns) / (kw['k_c0'] * d * d):+.2e}")
        print(f"{name:>50}: paper {cols[0]}, passive {cols[1]}")


if __name__ == "__main__":
    main()
