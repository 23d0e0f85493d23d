"""A digest of deformable-stop solves on seeded random draws, to compare two checkouts
digit for digit: the end state in full precision, hashes of the samples, the energy terms
and a dense evaluation, the steady state's label and ``info``.

Draws: the pressed stops of tests/core/test_pressed_swing.py (seeds 7 and 11, both laws, at
the app's standard preset) and the random passive scenes of tests/core/test_stop_work.py
(exact, event and switch methods). Public ``core`` API only, so that any two checkouts run
it alike:

    cd CHECKOUT && .venv/bin/python benchmarks/deformable_digest.py > digest.txt

(results/2026-11-29-deformable-restructure.md: identical before and after.)
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, simulate  # noqa: E402


def h(a) -> str:
    return hashlib.sha1(np.ascontiguousarray(np.asarray(a, dtype=float)).tobytes()).hexdigest()[:12]


def draws(seed, n, law):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        k_c0 = 10.0 ** rng.uniform(2.0, 6.0)
        beta_c = 10.0 ** rng.uniform(0.0, 3.0)
        beta_e = min(beta_c * 10.0 ** rng.uniform(0.0, 3.0), 1e3)
        d = 10.0 ** rng.uniform(-3.0, 0.0)
        clearance = rng.uniform(0.3, 0.6)
        belt = rng.uniform(0.05, 0.5)
        k_e0 = k_c0 * 10.0 ** rng.uniform(-1.3, 0.0)
        out.append((belt, HystereticStop(clearance, k_c0, k_e0, limit_overlap=d, beta_c=beta_c,
                                         beta_e=beta_e, law=law)))
    return out


def scene(seed):
    rng = np.random.default_rng(seed)
    mu_k = rng.uniform(0.1, 0.4)
    osc = Oscillator(mu_s=mu_k * rng.uniform(1.05, 2.0), mu_k=mu_k,
                     belt_speed=rng.uniform(0.02, 0.4))
    k_c0, ratio = 10 ** rng.uniform(2, 4), 10 ** rng.uniform(-1.5, 0)
    beta_c = 10 ** rng.uniform(0, 3)
    beta_e = beta_c * rng.uniform(1, 5)
    stop = HystereticStop(clearance=osc.a * rng.uniform(0.3, 1.5), k_c0=k_c0, k_e0=k_c0 * ratio,
                          limit_overlap=10 ** rng.uniform(-3, -1), beta_c=beta_c, beta_e=beta_e,
                          law="passive")
    return osc, stop


def digest(tag, res):
    e = res.energy
    info = {k: v for k, v in sorted(res.info.items()) if not k.startswith("time")}
    print(tag, res.status, repr(float(res.x[-1])), repr(float(res.v[-1])), repr(float(res.x_max)),
          len(res.transitions), h(res.t), h(res.x), h(res.v), h(e.stop_loss), h(e.friction_work),
          "|", res.steady.describe(), "|", info, flush=True)
    tt = np.linspace(res.t[0], res.t[-1], 997)
    x, v = res.evaluate(tt)
    print("   evaluate", h(x), h(v), flush=True)


def main():
    pre = {"rtol": 1e-8, "atol": 1e-11}
    for law in ("paper", "passive"):
        seven = [k for k in range(16) if k not in (12, 13)]
        for seed, ks, horizons in ((7, seven, (400.0, 1600.0)), (11, [1, 2, 3, 14], (400.0,))):
            ds = draws(seed, 16, law)
            for k in ks:
                belt, stop = ds[k]
                osc = Oscillator(mu_s=0.45, mu_k=0.30, belt_speed=belt, u_s=2.0)
                t_end = horizons[k % len(horizons)]
                try:
                    digest(f"{law} s{seed} k{k} t{t_end}", simulate(osc, stop, t_end, **pre))
                except Exception as exc:  # a failure is part of the digest
                    print(f"{law} s{seed} k{k} EXC {exc!r}")
    for seed in range(12):
        osc, stop = scene(seed)
        for method in ("exact", "event", "switch"):
            try:
                digest(f"scene {seed} {method}", simulate(osc, stop, 30.0, method=method, rtol=1e-8,
                                                          atol=1e-11, n_samples=2000))
            except Exception as exc:  # a failure is part of the digest
                print(f"scene {seed} {method} EXC {exc!r}")
if __name__ == "__main__":
    main()
