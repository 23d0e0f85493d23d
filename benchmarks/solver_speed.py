"""Speed and error of the exact solver against solve_ivp with events (issue 2).

For a set of paper scenes (no stop, fast and slow belt; rigid elastic stop, fast belt; slow
belt cases a/b/c; inelastic impact accumulation) this times

* ``core.simulate`` (method ``exact``, ``t_end = 100``, 2,000 samples: one slider update),
* ``core.event_method.simulate_event`` (``solve_ivp`` RK45 and DOP853 with event location on
  the non-smooth model) at ``rtol = 1e-6`` and ``1e-10`` (``atol = rtol / 100``),
* the switch model (``core.switch``, RKF 4(5)) at ``rtol = 1e-6`` for reference,

and prints medians (``time.perf_counter``, repeated) with each numerical answer's error
against the exact one: the state at ``t_end`` (``max(|dx|, |dx'|)``) and ``x_max``.
Targets: exact >= 100x faster than RK45 at ``rtol = 1e-6``; a whole solve < 2 ms median.

    python benchmarks/solver_speed.py            # about a minute on two cores
    python benchmarks/solver_speed.py --quick    # fewer repeats
    python benchmarks/solver_speed.py --against /work/main   # exact solver: this tree vs another

``--against TREE`` times only the exact solver, paired in one run: one worker process on
this tree and one on ``TREE`` (another checkout, e.g. the main branch) take turns, round
by round and alternating which goes first, at solving the same scene 20 times; the table
gives each side's median and the median of the paired ratios, so that the load of a
shared machine falls on both sides alike.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import Oscillator, RigidStop  # noqa: E402
from core.event_method import simulate_event  # noqa: E402
from core.switch import simulate_switch  # noqa: E402

T_END = 100.0
N_SAMPLES = 2000
#: Target ratio of RK45 (rtol 1e-6) time to exact time, and the exact solve's budget (ms).
TARGET_RATIO = 100.0
TARGET_EXACT_MS = 2.0

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)  # a = 0.2, b = 0.3, v = 0.1 < a
FAST = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)  # v > v* = a
#: x* = a + v sqrt(1 - r^2) = 0.271 for r = 0.7 (core.theory.x_star)
SCENES = {
    "no stop, fast belt": (FAST, None),
    "no stop, slow belt": (SLOW, None),
    "rigid elastic, fast (c=0.3)": (FAST, RigidStop(0.3, 1.0)),
    "slow case a (c=0.32>=b, r=0.7)": (SLOW, RigidStop(0.32, 0.7)),
    "slow case b (x*<=c=0.28<b)": (SLOW, RigidStop(0.28, 0.7)),
    "slow case c (a<c=0.25<x*)": (SLOW, RigidStop(0.25, 0.7)),
    "inelastic Zeno (c=0.15<a)": (SLOW, RigidStop(0.15, 0.7)),
}
NUMERICAL = [
    ("RK45 1e-6", lambda o, s: simulate_event(o, s, T_END, rtol=1e-6, atol=1e-8)),
    ("RK45 1e-10", lambda o, s: simulate_event(o, s, T_END, rtol=1e-10, atol=1e-12)),
    (
        "DOP853 1e-6",
        lambda o, s: simulate_event(o, s, T_END, rtol=1e-6, atol=1e-8, solver="DOP853"),
    ),
    (
        "DOP853 1e-10",
        lambda o, s: simulate_event(o, s, T_END, rtol=1e-10, atol=1e-12, solver="DOP853"),
    ),
    ("switch 1e-6", lambda o, s: simulate_switch(o, s, T_END, rtol=1e-6, atol=1e-8)),
]


def exact_solver():
    """``core.simulate`` with the exact method, or None while it is not available."""
    try:
        from core import simulate
    except ImportError:
        return None

    def run(osc, stop):
        return simulate(osc, stop, T_END, n_samples=N_SAMPLES, method="exact")

    try:
        run(FAST, None)
    except (ImportError, NotImplementedError):
        return None
    return run


def median_time(fn, repeats: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def errors(res, ref) -> tuple[float, float]:
    state = max(abs(res.x[-1] - ref.x[-1]), abs(res.v[-1] - ref.v[-1]))
    return state, abs(res.x_max - ref.x_max)


#: Program run in a persistent subprocess on one tree: for each request (a scene index and a
#: count on stdin) it solves that scene that many times and answers with the time taken.
_WORKER = """
import json, sys, time
from core import Oscillator, RigidStop, simulate
scenes = json.loads(sys.argv[1]); t_end, n = float(sys.argv[2]), int(sys.argv[3])
built = [(Oscillator(*o), RigidStop(*s) if s else None) for o, s in scenes]
for o, s in built:
    simulate(o, s, t_end, n_samples=n, method="exact")
print("ready", flush=True)
for line in sys.stdin:
    i, count = map(int, line.split())
    o, s = built[i]
    t0 = time.perf_counter()
    for _ in range(count):
        simulate(o, s, t_end, n_samples=n, method="exact")
    print(time.perf_counter() - t0, flush=True)
"""


def _worker(tree: Path) -> subprocess.Popen:
    scenes = [
        ((o.mu_s, o.mu_k, o.belt_speed, o.u_s),
         (s.clearance, s.restitution) if s is not None else None)
        for o, s in SCENES.values()
    ]
    proc = subprocess.Popen(
        [sys.executable, "-c", _WORKER, json.dumps(scenes), str(T_END), str(N_SAMPLES)],
        env=dict(os.environ, PYTHONPATH=str(tree)), cwd=tree, text=True,
        stdin=subprocess.PIPE, stdout=subprocess.PIPE,
    )
    assert proc.stdout.readline().strip() == "ready"
    return proc


def _ask(proc: subprocess.Popen, scene: int, count: int) -> float:
    proc.stdin.write(f"{scene} {count}\n")
    proc.stdin.flush()
    return float(proc.stdout.readline()) / count


def paired(other: Path, rounds: int, count: int) -> None:
    """Exact solve times of this tree and ``other``: one worker process per tree, asked in
    turn (alternating which goes first) for ``count`` solves of a scene, ``rounds`` times
    per scene; the median over rounds of each side, and the median of the paired ratios."""
    here = Path(__file__).resolve().parents[1]
    workers = {"this": _worker(here), "other": _worker(other)}
    print(f"exact solver, t_end = {T_END:g}, {N_SAMPLES} samples; {rounds} paired rounds of "
          f"{count} solves per scene (other = {other})")
    print(f"{'scene':32s} {'this ms':>9s} {'other ms':>9s} {'paired ratio':>12s}")
    medians = []
    try:
        for k, name in enumerate(SCENES):
            times: dict[str, list[float]] = {"this": [], "other": []}
            for r in range(rounds):
                order = ["this", "other"] if r % 2 == 0 else ["other", "this"]
                for side in order:
                    times[side].append(_ask(workers[side], k, count))
            ratio = statistics.median(
                a / b for a, b in zip(times["this"], times["other"], strict=True)
            )
            medians.append(ratio)
            print(f"{name:32s} {statistics.median(times['this']) * 1e3:9.3f} "
                  f"{statistics.median(times['other']) * 1e3:9.3f} {ratio:12.3f}")
    finally:
        for proc in workers.values():
            proc.stdin.close()
            proc.wait()
    print(f"median over scenes of the paired ratio this/other: {statistics.median(medians):.3f}")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--against", type=Path, help="time the exact solver against this tree")
    ap.add_argument("--rounds", type=int, default=60, help="paired rounds for --against")
    args = ap.parse_args(argv)
    if args.against is not None:
        paired(args.against.resolve(), args.rounds, 5 if args.quick else 20)
        return
    rep_exact, rep_num = (20, 1) if args.quick else (101, 3)
    exact = exact_solver()
    if exact is None:
        print("core.simulate(method='exact') is not available yet: nothing to compare against.")
        return

    print(
        f"t_end = {T_END:g}, {N_SAMPLES} samples; medians of {rep_exact} (exact) and "
        f"{rep_num} (numerical) runs; error = max(|dx|,|dx'|) at t_end / |d x_max|\n"
    )
    head = f"{'scene':32s} {'exact ms':>9s}"
    for name, _ in NUMERICAL:
        head += f" | {name + ' ms':>15s} {'err t_end':>9s} {'err xmax':>9s}"
    head += f" | {'RK45-6/exact':>12s}"
    print(head)
    print("-" * len(head))
    worst_ratio, worst_exact = float("inf"), 0.0
    for scene, (osc, stop) in SCENES.items():
        t_ex, ref = median_time(lambda o=osc, s=stop: exact(o, s), rep_exact)
        row = f"{scene:32s} {t_ex * 1e3:9.3f}"
        t_rk = None
        for name, fn in NUMERICAL:
            t_num, res = median_time(lambda f=fn, o=osc, s=stop: f(o, s), rep_num)
            e_state, e_xmax = errors(res, ref)
            row += f" | {t_num * 1e3:15.1f} {e_state:9.1e} {e_xmax:9.1e}"
            if name == "RK45 1e-6":
                t_rk = t_num
        ratio = t_rk / t_ex
        worst_ratio = min(worst_ratio, ratio)
        worst_exact = max(worst_exact, t_ex * 1e3)
        row += f" | {ratio:12.0f}"
        print(row)
    print()
    print(
        f"smallest speed ratio RK45(rtol 1e-6) / exact: {worst_ratio:.0f}x "
        f"(target >= {TARGET_RATIO:.0f}x): {'met' if worst_ratio >= TARGET_RATIO else 'NOT met'}"
    )
    print(
        f"slowest exact solve (median): {worst_exact:.3f} ms "
        f"(target < {TARGET_EXACT_MS:g} ms): "
        f"{'met' if worst_exact < TARGET_EXACT_MS else 'NOT met'}"
    )


if __name__ == "__main__":
    main()
