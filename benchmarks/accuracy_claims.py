"""Validation of every accuracy figure the page can quote, on random scenes.

The page quotes an error figure for a run only where :data:`app.solve.presets.ACCURACY`'s
``error`` holds one and this script validated it (no failure on >= :data:`MIN_SCENES`
random scenes); otherwise a run that integrates has its error measured against the exact
solution (:func:`app.solve.measure.measure_run`) or says "not measured". The script also checks
the figures the page quoted before (:data:`FORMER`): the presets' table, the switch rule
``max(figure, 20 eta/v)`` and the readout's many-contacts and rest figures of a deformable
stop. It draws random scenes over the sliders' ranges (app/state.py), solves them as the
page does (its presets, options and samples: :func:`app.solve.presets.preset_options`,
:func:`app.sampling.samples_for`) and takes the page's own error
(:func:`app.solve.measure.reference_error`: the largest distance of the positions from the exact
solution at the run's sample times, over its amplitude).

Families (``--family``):

* ``rigid``, ``none``: ``event`` and ``switch`` at each preset against the closed form.
* ``contact``: the exact method on a deformable stop at each preset against the exact
  method at rtol 1e-12. A run's allowance is the figure plus the stated bound of a reduced
  model where one took over.

Scenes mix uniform draws with grazing stops (the clearance within 1e-6 ... 1e-2 of the
impactless excursion), Zeno (a small restitution, the stop near the belt's equilibrium),
stick-slip (mu_s well above mu_k) and slow belts (v down to 1e-3). Records are appended
to a JSON-lines file per family (resumable: seeds already there are skipped; each run
stops at ``--budget-s``).

    nice .venv/bin/python benchmarks/accuracy_claims.py run --family rigid \
        --seeds 0:1200 --t-end 100 --budget-s 2400     # and --family none, contact
    .venv/bin/python benchmarks/accuracy_claims.py table [--write]

``table`` prints, per figure, the scenes, failures, the worst error and the 99.9th
percentile; ``--write`` writes benchmarks/results/accuracy_claims.json (and .md), which
tests/app/test_accuracy_figures.py holds the page's table to: a figure of ACCURACY is
quoted only with 0 failures on >= MIN_SCENES scenes of every family.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy

from app.sampling import samples_for
from app.solve.measure import reference_error, reference_options
from app.solve.presets import ACCURACY, MAX_SOLVE_BUDGET_S, preset_options
from app.state import ACCURACIES, core_inputs
from core import HystereticStop, TransitionKind, method_options, simulate, theory

RESULTS = Path(__file__).parent / "results"
RECORDS = RESULTS / "accuracy_claims"
SUMMARY = RESULTS / "accuracy_claims.json"
#: Methods measured per family.
FAMILY_METHODS = {"rigid": ("event", "switch"), "none": ("event", "switch"),
                  "contact": ("exact",)}
#: Wall-time budget [s] of one numerical solve (the core stops it there; a run cut short
#: is measured over what it has, as the page does).
RUN_BUDGET_S = 20.0
#: Wall time [s] of one scene's solves: the page's largest budget
#: (:data:`app.solve.presets.MAX_SOLVE_BUDGET_S`, a retry's) for each.
SCENE_TIMEOUT_S = 4 * MAX_SOLVE_BUDGET_S


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(10 ** rng.uniform(math.log10(lo), math.log10(hi)))


def _friction(rng: np.random.Generator, kind: str) -> dict:
    mu_s = float(rng.uniform(0.02, 1.0))
    ratio = rng.uniform(0.2, 0.7) if kind == "stick-slip" else rng.uniform(0.0, 1.0)
    v = (_log_uniform(rng, 1e-3, 0.05) if kind == "slow" or rng.random() < 0.25
         else float(rng.uniform(0.0, 0.6)))
    return {"mu_s": mu_s, "mu_k": float(mu_s * ratio), "u_s": float(rng.uniform(0.05, 3.0)),
            "belt_speed": v, "x0": float(rng.uniform(-1.5, 1.5)),
            "v0": float(rng.uniform(-1.5, 1.5)) if rng.random() < 0.7 else 0.0}


def draw(family: str, seed: int, t_end: float) -> tuple[str, dict]:
    """The scene of ``seed``: its kind and its state values (app/state.py)."""
    rng = np.random.default_rng([seed, {"rigid": 1, "none": 2, "contact": 3}[family]])
    kind = str(rng.choice(["uniform", "grazing", "zeno", "stick-slip", "slow"],
                          p=[0.4, 0.2, 0.15, 0.15, 0.1]))
    values = _friction(rng, kind)
    values.update(t_end=t_end, method="auto", accuracy="standard", program=False,
                  stop_type={"contact": "hysteretic"}.get(family, family),
                  contact_law=str(rng.choice(["paper", "passive"])),
                  restitution=float(rng.uniform(0.0, 1.0)), clearance=0.0,
                  k_c0=1.0, k_e0=1.0, limit_overlap=0.01, beta_c=1.0, beta_e=1.0)
    a = values["mu_k"] * values["u_s"]
    x_start = values["x0"]
    if kind == "grazing" and values["belt_speed"] > 0:
        osc = core_inputs({**values, "stop_type": "none"})[0]
        graze = theory.x_max_impactless(osc, values["x0"], values["v0"])
        clearance = graze * (1 + float(rng.choice([-1, 1])) * _log_uniform(rng, 1e-6, 1e-2))
    elif kind == "zeno":
        values["restitution"] = float(rng.uniform(0.0, 0.4))
        clearance = a + abs(a) * float(rng.uniform(-0.3, 0.3)) + 1e-3
    elif family == "contact" and values["belt_speed"] > 0 and rng.random() < 0.8:
        # Mostly a stop within the impactless excursion: a run with contacts.
        osc = core_inputs({**values, "stop_type": "none"})[0]
        graze = theory.x_max_impactless(osc, values["x0"], values["v0"])
        clearance = float(rng.uniform(x_start, max(graze, x_start + 1e-3)))
    else:
        clearance = float(rng.uniform(-0.2, 0.8))
    # The stop lies ahead of the start (the core refuses one behind it).
    values["clearance"] = max(clearance, x_start + float(rng.uniform(1e-3, 0.2)))
    k_c0 = _log_uniform(rng, 1.0, 2000.0)
    values.update(k_c0=k_c0, k_e0=k_c0 * float(rng.uniform(0.001, 1.0)) if kind != "zeno"
                  else k_c0 * float(rng.uniform(0.001, 0.2)),
                  limit_overlap=_log_uniform(rng, 1e-3, 0.2),
                  beta_c=_log_uniform(rng, 0.5, 1000.0))
    values["beta_e"] = _log_uniform(rng, values["beta_c"], 1000.0)  # beta_c <= beta_e
    values["k_e0"] = max(values["k_e0"], 1.0)
    values["k_c0"] = max(values["k_c0"], values["k_e0"])
    return kind, values


def _contacts(res) -> tuple[int, int, bool]:
    """Contacts, loops on the stop and whether a rest was declared (app.readout's count)."""
    counts = res.transition_counts
    contacts = max(int(res.info.get("n_contacts", 0)),
                   int(counts.get(TransitionKind.CONTACT.value, 0)))
    loops = max(int(counts.get(TransitionKind.REVERSAL.value, 0))
                - int(counts.get(TransitionKind.CONTACT.value, 0)), 0) // 2
    rest = any(t.kind is TransitionKind.REST for t in res.transitions[-2:])
    return contacts, loops, rest


def _rest_time(res) -> float | None:
    """When the run comes to rest on the stop, or ``None``."""
    steady = res.steady
    if steady.kind.value != "rest" or not math.isfinite(steady.t_reached):
        return None
    return float(steady.t_reached)


def solve_scene(family: str, values: dict) -> dict:
    """Each method of the family at each preset, as the page solves a full run."""
    osc, stop, x0, v0, t_end = core_inputs(values)
    start = time.perf_counter()
    ref = simulate(osc, stop, t_end, x0, v0, n_samples=2, method="exact",
                   **reference_options(stop))
    runs: dict = {"ref_seconds": time.perf_counter() - start}
    x_ref_amp = None
    for method in FAMILY_METHODS[family]:
        for preset in ACCURACIES:
            acc = ACCURACY[preset]
            used = method_options(method, stop)
            options = preset_options(acc, used, osc)
            if "time_budget" in used:
                options["time_budget"] = RUN_BUDGET_S
            start = time.perf_counter()
            try:
                res = simulate(osc, stop, t_end, x0, v0, method=method,
                               n_samples=samples_for(t_end, acc["n_samples"]), **options)
            except Exception as exc:  # noqa: BLE001 - a failed solve is a record too
                runs[f"{method}/{preset}"] = {"failed": repr(exc)}
                continue
            seconds = time.perf_counter() - start
            error = reference_error(res, ref)
            row = {"error": error, "seconds": seconds, "status": res.status.name,
                   "t_last": float(res.t[-1]) if len(res.t) else 0.0,
                   "eta": options.get("eta")}
            if isinstance(stop, HystereticStop):
                if x_ref_amp is None:
                    # past the reference's end its last position, as reference_error
                    x, _ = ref.evaluate(np.minimum(np.asarray(res.t, float), ref.t[-1]))
                    x_ref_amp = float(np.max(np.abs(x - np.mean(x))))
                contacts, loops, rest = _contacts(res)
                bound = float(res.info.get("reduced_error", 0.0) or 0.0)
                row.update(contacts=contacts, loops=loops, rest=rest,
                           reduced=any(t.kind is TransitionKind.REDUCED
                                       for t in res.transitions),
                           reduced_over_amplitude=bound / max(x_ref_amp, 1e-300),
                           periodic=res.steady.kind.value == "periodic",
                           rest_time_error=res.info.get("rest_time_error"),
                           t_rest=_rest_time(res), t_rest_ref=_rest_time(ref))
            runs[f"{method}/{preset}"] = row
    return runs


def _seeds(spec: str) -> list[int]:
    lo, hi = (int(p) for p in spec.split(":"))
    return list(range(lo, hi))


def _solve_in(pool, family: str, values: dict):
    """:func:`solve_scene` in the worker ``pool``, and the pool to use next. The exact
    method on a deformable stop takes no time budget: a scene is given the page's largest
    budget (a retry's) for each solve; past it the page shows no run."""
    try:
        return pool.apply_async(solve_scene, (family, values)).get(SCENE_TIMEOUT_S), pool
    except multiprocessing.TimeoutError:
        pool.terminate()
        return ({"refused": f"over {SCENE_TIMEOUT_S:g} s"},
                multiprocessing.get_context("fork").Pool(1))
    except Exception as exc:  # noqa: BLE001 - the benchmark's own failure, counted
        return {"raised": repr(exc)}, pool


def run(family: str, seeds: list[int], t_end: float, budget_s: float, part: str = "") -> None:
    """Append the records of ``seeds`` not yet in the family's files to its file (``part``
    names another file, for a second process)."""
    RECORDS.mkdir(parents=True, exist_ok=True)
    path = RECORDS / f"{family}_t{t_end:g}{part and '.' + part}.jsonl"
    done = {json.loads(line)["seed"] for other in RECORDS.glob(f"{family}_t{t_end:g}*.jsonl")
            for line in other.read_text().splitlines() if line}
    start = time.monotonic()
    pool = multiprocessing.get_context("fork").Pool(1)
    with path.open("a") as out:
        for seed in seeds:
            if seed in done:
                continue
            if time.monotonic() - start > budget_s:
                print(f"budget of {budget_s:g} s spent; resume with the same command")
                break
            try:
                kind, values = draw(family, seed, t_end)
                core_inputs(values)
            except ValueError as exc:  # refused inputs: not a scene of the page
                kind, values, runs = "refused", {}, {"refused": str(exc)}
            else:
                runs, pool = _solve_in(pool, family, values)
            out.write(json.dumps({"seed": seed, "kind": kind, "values": values,
                                  "runs": runs}) + "\n")
            out.flush()
    pool.terminate()


#: The figures the page quoted before this validation (app.solve.presets.ACCURACY's ``error``, the
#: readout's many-contacts and rest figures): candidates, checked as the page stated them.
FORMER = {
    "draft": {"contact": 1e-3, "event": 1e-3, "switch": 3e-2},
    "standard": {"contact": 1e-6, "event": 1e-6, "switch": 3e-3},
    "precise": {"contact": 1e-8, "event": 1e-8, "switch": 1e-4},
}
#: The switch model's former rule: at least 20 eta / v.
SWITCH_PER_BAND = 20.0
MANY_CONTACTS, MANY_CONTACTS_ERROR, REST_ERROR = 50, 1e-8, 1e-6
#: The runs behind benchmarks/results/accuracy_claims.md (two processes for ``none``).
RUN_COMMANDS = "\n".join(
    f"    nice -n 10 env PYTHONPATH=. .venv/bin/python benchmarks/accuracy_claims.py run "
    f"--family {family} --seeds {seeds} --t-end 100 {extra}".rstrip()
    for family, seeds, extra in (("rigid", "0:1200", ""), ("contact", "0:1200", ""),
                                 ("none", "0:600", ""), ("none", "600:1200", "--part b")))
#: Scenes a figure needs, with no failure, to be quoted.
MIN_SCENES = 1000


def _key(method: str) -> str:
    return "contact" if method == "exact" else method


def _checks(family: str):
    """(figure, run key, stated figure, allowance of a run row or None where the figure
    does not apply to it) for each figure the page may quote, or quoted, on this family."""
    for method in FAMILY_METHODS[family]:
        for preset in ACCURACIES:
            key, run_key = _key(method), f"{method}/{preset}"
            stated = ACCURACY[preset]["error"].get(key)
            if stated is not None:
                yield f"{key}/{preset}", run_key, stated, lambda row, f=stated: (
                    f + row.get("reduced_over_amplitude", 0.0))
            former = FORMER[preset][key]
            yield f"former {key}/{preset}", run_key, former, lambda row, f=former: (
                f + row.get("reduced_over_amplitude", 0.0))
            if method == "switch":
                yield (f"former switch/{preset} rule max(fig, 20 eta/v)", run_key, former,
                       lambda row, f=former: max(f, SWITCH_PER_BAND * row["eta"] / row["v"])
                       if row.get("v") else None)
    if family == "contact":
        for preset in ACCURACIES:
            run_key = f"exact/{preset}"
            yield (f"former many contacts/{preset}", run_key, MANY_CONTACTS_ERROR,
                   lambda row: MANY_CONTACTS_ERROR
                   if row["contacts"] + row["loops"] > MANY_CONTACTS and not row["rest"]
                   and not row["reduced"] else None)
            yield (f"former rest/{preset}", run_key, REST_ERROR,
                   lambda row: REST_ERROR if row["rest"] and not row["reduced"]
                   and row["contacts"] + row["loops"] > MANY_CONTACTS else None)


def _records(family: str, t_end: float) -> tuple[list[dict], int]:
    """The family's scenes the page solves, and how many took longer than it waits."""
    seen: dict[int, dict] = {}
    for path in sorted(RECORDS.glob(f"{family}_t{t_end:g}*.jsonl")):
        for line in path.read_text().splitlines():
            record = json.loads(line)
            seen.setdefault(record["seed"], record)  # parts run side by side may overlap
    records = list(seen.values())
    slow = sum(str(r["runs"].get("refused", "")).startswith("over ") for r in records)
    return [r for r in records if "refused" not in r["runs"]], slow


def summarize(t_end_by_family: dict[str, float]) -> list[dict]:
    """One row per figure and family: scenes it applies to, failures, worst, 99.9th
    percentile of the error, solves that raised, runs whose error is ``nan`` and scenes
    past :data:`SCENE_TIMEOUT_S` (the page shows no run of those)."""
    rows = []
    for family, t_end in t_end_by_family.items():
        records, too_slow = _records(family, t_end)
        for name, run_key, stated, allowance in _checks(family):
            errors, seeds, failures, raised, unmeasured = [], [], 0, 0, 0
            for rec in records:
                row = dict(rec["runs"].get(run_key, {}), v=rec["values"]["belt_speed"])
                if "failed" in row or "raised" in rec["runs"]:
                    raised += 1
                    continue
                allowed = allowance(row)
                if allowed is None:
                    continue
                error = row["error"]
                if error is None or not math.isfinite(error):
                    unmeasured += 1  # the page says "not measured": no figure quoted
                    continue
                errors.append(error)
                seeds.append(rec["seed"])
                failures += error > allowed
            arr = np.asarray(errors)
            rows.append({
                "figure": name, "family": family, "t_end": t_end, "stated": stated,
                "scenes": len(errors), "failures": int(failures), "raised": raised,
                "unmeasured": unmeasured, "too_slow": too_slow,
                "failure_rate": failures / len(errors) if len(errors) else math.nan,
                "worst": float(arr.max()) if len(arr) else math.nan,
                "p999": float(np.quantile(arr, 0.999)) if len(arr) else math.nan,
                "worst_seeds": [seeds[i] for i in np.argsort(arr)[::-1][:3]],
            })
    return rows


def validated(rows: list[dict]) -> dict[str, dict[str, float]]:
    """The figures the page may quote: per preset, each of ACCURACY's that holds with 0
    failures on >= MIN_SCENES scenes of every family it was checked on."""
    out: dict[str, dict[str, float]] = {preset: {} for preset in ACCURACIES}
    for preset in ACCURACIES:
        for key in ("contact", "event", "switch"):
            mine = [r for r in rows if r["figure"] == f"{key}/{preset}"]
            if mine and all(r["scenes"] >= MIN_SCENES and r["failures"] == 0 for r in mine):
                out[preset][key] = mine[0]["stated"]
    return out


def table(rows: list[dict]) -> str:
    lines = [f"| {'figure':<46} | family  | t_end | stated | scenes | failures | worst    "
             "| 99.9th   | worst seeds |", "|" + "---|" * 9]
    for r in rows:
        lines.append(f"| {r['figure']:<46} | {r['family']:<7} | {r['t_end']:>5g} | "
                     f"{r['stated']:.0e} | {r['scenes']:>6} | {r['failures']:>8} | "
                     f"{r['worst']:.2e} | {r['p999']:.2e} | "
                     f"{' '.join(map(str, r['worst_seeds']))} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("--family", choices=tuple(FAMILY_METHODS), required=True)
    r.add_argument("--seeds", default="0:1000")
    r.add_argument("--t-end", type=float, default=100.0)
    r.add_argument("--budget-s", type=float, default=3000.0)
    r.add_argument("--part", default="", help="another file, for a second process")
    t = sub.add_parser("table")
    t.add_argument("--t-end", action="append", default=[],
                   help="family=t_end (default 100 for each)")
    t.add_argument("--write", action="store_true")
    args = parser.parse_args()
    if args.command == "run":
        run(args.family, _seeds(args.seeds), args.t_end, args.budget_s, args.part)
        return
    horizons = {"rigid": 100.0, "none": 100.0, "contact": 100.0}
    horizons.update({k: float(v) for k, v in (s.split("=") for s in args.t_end)})
    rows = summarize(horizons)
    print(table(rows))
    print(f"validated (0 failures on >= {MIN_SCENES} scenes): {validated(rows)}")
    if args.write:
        SUMMARY.write_text(json.dumps({
            "command": " ".join(sys.argv), "python": platform.python_version(),
            "numpy": np.__version__, "scipy": scipy.__version__,
            "machine": f"{platform.machine()}, {os.cpu_count()} cpus",
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "min_scenes": MIN_SCENES, "validated": validated(rows),
            "figures": rows}, indent=1) + "\n")
        SUMMARY.with_suffix(".md").write_text(
            f"# Accuracy figures on random scenes ({time.strftime('%Y-%m-%d', time.gmtime())})"
            f"\n\n{RUN_COMMANDS}\n\nthen `{' '.join(sys.argv)}`; Python "
            f"{platform.python_version()}, NumPy {np.__version__}, SciPy {scipy.__version__}, "
            f"{platform.machine()}, {os.cpu_count()} cpus shared. Error: the page's "
            "(app.solve.measure.reference_error). A failure: a scene beyond the figure (plus a "
            "reduced model's stated bound where one took over).\n\n"
            f"{table(rows)}\n\nValidated (0 failures on >= {MIN_SCENES} scenes): "
            f"{validated(rows)}. 'former': a figure the page quoted before; the page now "
            "quotes none of them: it measures a run that integrates, or says it did not."
            "\n")


if __name__ == "__main__":
    main()
