"""Work-precision of the numerical methods on rigid and hysteretic scenes (issue 3).

For each scene and each method, over a tolerance sweep (``rtol`` 1e-3 ... 1e-12,
``atol = rtol / 100``) and, for the switch model, an ``eta`` sweep at a tight tolerance, this
measures the median CPU time of a whole solve (``t_end = 100``, 2,000 samples) and its error
against a reference:

* rigid scenes: the exact solver (``core.simulate``, method ``exact``);
* hysteretic scenes: ``core.simulate`` if it offers the deformable stop, else the event
  method with DOP853 at ``rtol = 1e-13`` (the best method at a tight tolerance).

Error measures: the state at ``t_end`` (``max(|dx|, |dx'|)``), the maximum displacement, and
the transition times (largest difference over the first transitions, as long as both
sequences have the same kinds; ``seq`` when they part).

It then picks, per scene class and accuracy level (draft 1e-3, standard 1e-6, precise 1e-9
on the largest of the three errors), the fastest setting that meets the level on every
scene of the class, and prints the result as ``ACCURACY_PRESETS``. matplotlib, if
installed, draws the work-precision diagram to ``work_precision.png``.

The headline comes first: on the rigid scenes, at ``t_end = 100`` and ``1000``, the time of
the fastest ``solve_ivp`` run (event location, RK45 or DOP853, over the ``rtol`` sweep) whose
error against the exact answer is within 1e-6 and 1e-9, divided by the exact solver's time
(whose own error is rounding: ~1e-12 or less against the closed forms).

    python benchmarks/work_precision.py            # about two minutes on two cores
    python benchmarks/work_precision.py --quick    # a coarser sweep
    python benchmarks/work_precision.py --headline # only the headline table
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, RigidStop, Status, TransitionKind  # noqa: E402
from core.event_method import simulate_event  # noqa: E402
from core.switch import simulate_switch  # noqa: E402

T_END = 100.0
N_SAMPLES = 2000
RTOLS = [1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
RTOLS_QUICK = [1e-3, 1e-6, 1e-9, 1e-12]
#: Stick-band half-widths of the switch model relative to the belt speed (at rtol 1e-12).
ETA_RELS = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
#: absolute tolerance = rtol * ATOL_PER_RTOL (the states are of order 0.1)
ATOL_PER_RTOL = 1e-2
#: Reference tolerance of the event method where no exact answer exists.
REF_RTOL = 1e-13
#: Accuracy levels: the largest admissible error (a length or a time) of each measure.
LEVELS = {"draft": 1e-3, "standard": 1e-6, "precise": 1e-9}
#: A run slower than this (s) ends its method's sweep to tighter tolerances.
SLOW_RUN = 1.0
#: Compared transitions (the first ones: later ones drift apart on long horizons).
N_TRANSITIONS = 30

SLOW = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
FAST = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.5)
SCENES = {
    "rigid": {
        "elastic fast (c=0.3, r=1)": (FAST, RigidStop(0.3, 1.0)),
        "slow case b (c=0.28, r=0.7)": (SLOW, RigidStop(0.28, 0.7)),
        "slow Zeno (c=0.15, r=0.7)": (SLOW, RigidStop(0.15, 0.7)),
    },
    "hysteretic": {
        "Fig.10-like (c=0.25)": (SLOW, HystereticStop(0.25)),
        "stiff sharp (c=0.25, k=1e5, beta=50)": (
            SLOW,
            HystereticStop(
                0.25, k_c0=1e5, k_e0=0.49e5, limit_overlap=0.01, beta_c=50.0, beta_e=50.0
            ),
        ),
    },
}


def _methods(rtols):
    from core import simulate

    out = []
    for rtol in rtols:
        atol = rtol * ATOL_PER_RTOL
        # The exact method: closed form for the rigid stop (rtol unused), integrated contact
        # phase at this tolerance for the deformable stop.
        out.append(
            (
                "exact",
                rtol,
                None,
                lambda o, s, r=rtol, a=atol: simulate(
                    o, s, T_END, n_samples=N_SAMPLES,
                    **({"rtol": r, "atol": a} if isinstance(s, HystereticStop) else {}),
                ),
            )
        )
        for solver in ("RK45", "DOP853", "Radau", "LSODA"):
            out.append(
                (
                    f"event {solver}",
                    rtol,
                    None,
                    lambda o, s, r=rtol, a=atol, m=solver: simulate_event(
                        o, s, T_END, rtol=r, atol=a, solver=m, n_samples=N_SAMPLES
                    ),
                )
            )
        out.append(
            (
                "switch",
                rtol,
                None,
                lambda o, s, r=rtol, a=atol: simulate_switch(
                    o, s, T_END, rtol=r, atol=a, n_samples=N_SAMPLES
                ),
            )
        )
    for eta_rel in ETA_RELS:
        out.append(
            (
                "switch eta",
                1e-12,
                eta_rel,
                lambda o, s, e=eta_rel: simulate_switch(
                    o, s, T_END, rtol=1e-12, atol=1e-14, eta=e * o.v, n_samples=N_SAMPLES
                ),
            )
        )
    return out


def exact_solver(stop):
    """``core.simulate(method='exact')`` for this kind of stop, or None."""
    try:
        from core import simulate
    except ImportError:
        return None

    def run(osc, s):
        return simulate(osc, s, T_END, n_samples=N_SAMPLES, method="exact")

    try:
        run(SLOW, stop)
    except (ImportError, NotImplementedError, ValueError):
        return None
    return run


def timed(fn, budget: float) -> tuple[float, object]:
    """Median time of repeated runs (more repeats for fast runs), and the answer."""
    t0 = time.perf_counter()
    out = fn()
    first = time.perf_counter() - t0
    repeats = 1 if first > 0.2 * budget else (3 if first > 0.05 else 7)
    times = [first]
    for _ in range(repeats - 1):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def errors(res, ref) -> dict[str, float]:
    e_state = max(abs(res.x[-1] - ref.x[-1]), abs(res.v[-1] - ref.v[-1]))
    e_xmax = abs(res.x_max - ref.x_max)
    if res.status is not Status.SUCCESS:
        return {"state": math.inf, "xmax": math.inf, "trans": math.inf}
    # Zeno: the numerical methods stop bouncing below a rest speed, so compare the impacts
    # both sequences hold and then the accumulation times
    ends = (TransitionKind.ACCUMULATION, TransitionKind.REST)
    p_seq = [tr for tr in res.transitions if tr.kind not in ends]
    q_seq = [tr for tr in ref.transitions if tr.kind not in ends]
    n = min(len(p_seq), len(q_seq), N_TRANSITIONS)
    e_tr = 0.0
    for p, q in zip(p_seq[:n], q_seq[:n], strict=True):
        if p.kind is not q.kind:
            e_tr = math.inf
            break
        e_tr = max(e_tr, abs(p.t - q.t))
    if (len(p_seq) == 0) != (len(q_seq) == 0):
        e_tr = math.inf
    acc = [
        [tr.t for tr in seq if tr.kind is TransitionKind.ACCUMULATION]
        for seq in (res.transitions, ref.transitions)
    ]
    if acc[0] and acc[1]:
        e_tr = max(e_tr, abs(acc[0][0] - acc[1][0]))
    elif acc[0] or acc[1]:
        e_tr = math.inf
    return {"state": e_state, "xmax": e_xmax, "trans": e_tr}


#: Horizons and accuracy levels of the headline.
HEADLINE_T_ENDS = (100.0, 1000.0)
HEADLINE_LEVELS = (1e-6, 1e-9)
#: A headline run slower than this (s) ends that solver's sweep to tighter tolerances.
HEADLINE_SLOW = 3.0
#: Runs of the exact solver whose median is its headline time.
HEADLINE_EXACT_REPEATS = 41


def _once(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def headline(rtols) -> None:
    """Speed ratio solve_ivp / exact at equal accuracy on the rigid scenes."""
    from core import simulate

    print(
        "Headline: time of the fastest solve_ivp run (event location, RK45 or DOP853, rtol "
        "sweep, atol = rtol/100) whose error against the exact answer (largest of: state at "
        "t_end, x_max, transition times) is within the level, over the exact solver's time; "
        f"{N_SAMPLES} samples. '>' : no run met the level, ratio to the slowest run tried."
    )
    print(
        f"{'t_end':>6s} {'scene':30s} {'exact ms':>9s} {'level':>6s} {'solve_ivp':>16s} "
        f"{'ms':>9s} {'ratio':>8s}"
    )
    summary: dict[tuple[float, float], list[str]] = {}
    for t_end in HEADLINE_T_ENDS:
        for scene, (osc, stop) in SCENES["rigid"].items():
            # The exact solve takes a millisecond: the median of many runs, so that a spike
            # of the machine's load does not set the ratio.
            ref = simulate(osc, stop, t_end, n_samples=N_SAMPLES)
            t_ex = statistics.median(
                _once(lambda o=osc, s=stop, t=t_end: simulate(o, s, t, n_samples=N_SAMPLES))
                for _ in range(HEADLINE_EXACT_REPEATS)
            )
            runs = []
            for solver in ("RK45", "DOP853"):
                for rtol in rtols:
                    secs, res = timed(
                        lambda o=osc, s=stop, t=t_end, r=rtol, m=solver: simulate_event(
                            o, s, t, rtol=r, atol=r * ATOL_PER_RTOL, solver=m,
                            n_samples=N_SAMPLES,
                        ),
                        HEADLINE_SLOW,
                    )
                    runs.append((secs, max(errors(res, ref).values()), f"{solver} {rtol:.0e}"))
                    if secs > HEADLINE_SLOW:
                        break
            for level in HEADLINE_LEVELS:
                ok = [run for run in runs if run[1] <= level]
                if ok:
                    secs, _, name = min(ok)
                    ratio = f"{secs / t_ex:.0f}"
                else:
                    secs, _, name = max(runs)
                    ratio = f">{secs / t_ex:.0f}"
                summary.setdefault((t_end, level), []).append(ratio.strip())
                print(
                    f"{t_end:6g} {scene:30s} {t_ex * 1e3:9.3f} {level:6.0e} {name:>16s} "
                    f"{secs * 1e3:9.1f} {ratio:>8s}"
                )
    for (t_end, level), ratios in summary.items():
        print(
            f"t_end = {t_end:g}, error <= {level:.0e}: solve_ivp / exact = "
            f"{', '.join(r + 'x' for r in ratios)} ({', '.join(SCENES['rigid'])})"
        )
    print()


def fmt(e: float) -> str:
    """``seq``: the transition sequences part (or the solve failed)."""
    return "    seq" if math.isinf(e) else f"{e:7.1e}"


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser tolerance sweep")
    ap.add_argument("--plot", default="work_precision.png", help="PNG file of the diagram")
    ap.add_argument("--headline", action="store_true", help="only the headline table")
    args = ap.parse_args(argv)
    headline(RTOLS_QUICK if args.quick else RTOLS)
    if args.headline:
        return
    methods = _methods(RTOLS_QUICK if args.quick else RTOLS)
    rows = []  # (class, scene, method, rtol, eta_rel, seconds, errors)
    for cls, scenes in SCENES.items():
        for scene, (osc, stop) in scenes.items():
            exact = exact_solver(stop) if not isinstance(stop, HystereticStop) else None
            if exact is not None:
                t_ref, ref = timed(lambda o=osc, s=stop, f=exact: f(o, s), SLOW_RUN)
                ref_name = "exact"
                rows.append(
                    (
                        cls,
                        scene,
                        "exact",
                        math.nan,
                        None,
                        t_ref,
                        {"state": 0.0, "xmax": 0.0, "trans": 0.0},
                    )
                )
            else:
                # Deformable stop: the exact method's contact phase at a tolerance tighter
                # than any in the sweep (checked against event DOP853 at REF_RTOL below).
                from core import simulate

                ref = simulate(
                    osc, stop, T_END, rtol=REF_RTOL, atol=REF_RTOL * 1e-2, n_samples=N_SAMPLES
                )
                ref_name = f"exact, contact at rtol {REF_RTOL:g}"
                check = simulate_event(
                    osc, stop, T_END, rtol=REF_RTOL, atol=REF_RTOL * 1e-2, solver="DOP853",
                    n_samples=N_SAMPLES,
                )
                agree = errors(check, ref)
                ref_name += (
                    f"; event DOP853 at the same rtol differs by {fmt(agree['state'])} "
                    f"(state), {fmt(agree['trans'])} (transition times)"
                )
            print(
                f"\n== {cls}: {scene}  (reference: {ref_name}; {ref.n_transitions} "
                f"transitions; steady {ref.steady.kind.value})"
            )
            print(
                f"{'method':14s} {'rtol':>7s} {'eta/v':>7s} {'ms':>9s} "
                f"{'err t_end':>9s} {'err xmax':>9s} {'err trans':>9s}"
            )
            given_up: set[str] = set()
            for name, rtol, eta_rel, fn in methods:
                if name in given_up:
                    continue
                secs, res = timed(lambda f=fn, o=osc, s=stop: f(o, s), SLOW_RUN)
                if secs > SLOW_RUN:
                    given_up.add(name)
                err = errors(res, ref)
                rows.append((cls, scene, name, rtol, eta_rel, secs, err))
                eta_txt = "default" if eta_rel is None else f"{eta_rel:7.0e}"
                eta_txt = "" if name.startswith("event") else eta_txt
                print(
                    f"{name:14s} {rtol:7.0e} {eta_txt:>7s} {secs * 1e3:9.1f} "
                    f"{fmt(err['state'])}   {fmt(err['xmax'])}   {fmt(err['trans'])}"
                )
            if exact is not None:
                print(f"{'exact':14s} {'':>7s} {'':>7s} {t_ref * 1e3:9.3f} {'(reference)':>9s}")

    presets = recommend(rows)
    print(
        "\nFastest setting meeting each accuracy level on every scene of the class "
        "(error = largest of the three measures):"
    )
    print("ACCURACY_PRESETS = {")
    for cls, levels in presets.items():
        print(f"    {cls!r}: {{")
        for level, choice in levels.items():
            print(f"        {level!r}: {choice!r},")
        print("    },")
    print("}")
    plot(rows, args.plot)


def recommend(rows) -> dict[str, dict[str, dict]]:
    """Per class and level, the setting with the least total time that meets the level."""
    presets: dict[str, dict[str, dict]] = {}
    for cls in SCENES:
        n_scenes = len(SCENES[cls])
        settings: dict[tuple, list] = {}
        for c, _scene, name, rtol, eta_rel, secs, err in rows:
            if c == cls:
                settings.setdefault((name, rtol, eta_rel), []).append((secs, max(err.values())))
        presets[cls] = {}
        for level, tol in LEVELS.items():
            best = None
            for (name, rtol, eta_rel), runs in settings.items():
                if len(runs) < n_scenes or any(e > tol for _, e in runs):
                    continue
                total = sum(s for s, _ in runs)
                if best is None or total < best[0]:
                    best = (total, name, rtol, eta_rel)
            if best is None:
                presets[cls][level] = {"method": None, "note": "no setting met this level"}
                continue
            total, name, rtol, eta_rel = best
            choice: dict = {"method": name.split()[0]}
            if name.startswith("event"):
                choice["solver"] = name.split()[1]
            if not math.isnan(rtol):
                choice["rtol"] = rtol
                choice["atol"] = rtol * ATOL_PER_RTOL
            if eta_rel is not None:
                choice["eta_rel"] = eta_rel
            choice["ms_per_scene"] = round(total / n_scenes * 1e3, 2)
            presets[cls][level] = choice
    return presets


def plot(rows, path: str) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\nmatplotlib is not installed: no plot written (the tables above hold the data).")
        return
    scenes = sorted({(r[0], r[1]) for r in rows})
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.5 * len(scenes), 4), squeeze=False)
    for ax, (cls, scene) in zip(axes[0], scenes, strict=True):
        for name in sorted({r[2] for r in rows if r[1] == scene}):
            pts = [(r[5], max(r[6].values())) for r in rows if r[1] == scene and r[2] == name]
            pts = [(s, max(e, 1e-16)) for s, e in pts if math.isfinite(e)]
            if pts:
                ax.loglog([p[0] * 1e3 for p in pts], [p[1] for p in pts], "o-", label=name)
        ax.set_title(f"{cls}: {scene}", fontsize=8)
        ax.set_xlabel("median CPU time [ms]")
        ax.set_ylabel("error")
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"\nplot written to {path}")


if __name__ == "__main__":
    main()
