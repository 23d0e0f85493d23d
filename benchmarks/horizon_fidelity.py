"""How faithfully the exact method solves long horizons: the error of late samples against
a reference at the same double ``t`` whose phase is reduced in exact arithmetic.

A time near ``t`` is only known to the spacing of doubles there, ``ulp(t) ~ 2.2e-16 t``, so
a sample's ``x`` can be no better than its speed times that. This table shows how the
solvers' error follows ``ulp(t)`` and where the phase becomes meaningless; it is the
measurement behind ``core.validation.MAX_T_END``. Horizons past the bound are solved with
the bound lifted (``--past``), to show what the bound refuses.

* rigid: the elastic fast-belt cycle of paper §4.1 (a = 0.2, x_bar = 0.3, r = 1, v = 0.5),
  on which the mass is from rest: ``x = a (1 - cos th)``, period ``4 pi / 3``, the phase
  reduced with pi to 60 digits. Error of ``Result.evaluate`` at four late times and of the
  last 50 samples.
* deformable: the page's Fig. 10 stop at x_bar = 0.285 (a tiled cycle). Error of
  ``Result.evaluate`` at four late times against the same solution at those times reduced
  into its first cycle exactly (this measures the tiling's rounding, not the contact
  integration's own error).

    PYTHONPATH=. .venv/bin/python benchmarks/horizon_fidelity.py [--past]
"""

from __future__ import annotations

import argparse
import datetime
import math
import platform
import sys
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import core.validation  # noqa: E402
from core import HystereticStop, Oscillator, RigidStop, simulate  # noqa: E402

PI = Fraction("3.14159265358979323846264338327950288419716939937510582097494")


def rigid_error(t_end: float) -> tuple[float, float]:
    res = simulate(Oscillator(0.3, 0.2, 0.5), RigidStop(0.3, 1.0), t_end=t_end)

    def ref(t: float) -> float:
        r = Fraction(t) + 2 * PI / 3
        r -= math.floor(r / (4 * PI / 3)) * (4 * PI / 3)
        return 0.2 * (1.0 - math.cos(float(r - 2 * PI / 3)))

    times = np.minimum(t_end * np.array([0.5, 0.7, 0.9, 1.0]) + [0.1, 0.3, 0.7, 0.0], t_end)
    x, _ = res.evaluate(times)
    e_eval = max(abs(xi - ref(ti)) for xi, ti in zip(x, times, strict=True))
    e_samp = max(abs(xi - ref(ti)) for xi, ti in zip(res.x[-50:], res.t[-50:], strict=True))
    return e_eval, e_samp


def soft_error(t_end: float) -> float:
    stop = HystereticStop(clearance=0.285, k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                          beta_c=300.0, beta_e=300.0)
    res = simulate(Oscillator(0.3, 0.2, 0.07), stop, t_end=t_end)
    t1, period = Fraction(res.steady.t_reached), Fraction(res.steady.period)
    late = np.minimum(t_end * np.array([0.5, 0.7, 0.9, 1.0]) + [0.1, 0.3, 0.7, 0.0], t_end)
    early = np.array([float(t1 + (Fraction(t) - t1) % period) for t in late])
    return float(np.max(np.abs(res.evaluate(late)[0] - res.evaluate(early)[0])))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--past", action="store_true", help="lift MAX_T_END to 1e20")
    args = parser.parse_args()
    top = 20 if args.past else int(math.log10(core.validation.MAX_T_END))
    if args.past:  # the bound is read at call time through check_horizon
        core.validation.MAX_T_END = 1e20
    print(f"# {datetime.date.today()} {platform.node()} python {platform.python_version()} "
          f"numpy {np.__version__}; MAX_T_END = {core.validation.MAX_T_END:g}")
    print(f"{'t_end':>7} {'ulp(t_end)':>10} {'rigid eval':>10} {'rigid samp':>10} "
          f"{'soft eval':>10}")
    for e in range(2, top + 1):
        t_end = 10.0**e
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                r_eval, r_samp = rigid_error(t_end)
                s_eval = f"{soft_error(t_end):10.1e}"
            except (ValueError, FloatingPointError) as exc:
                print(f"{t_end:7.0e} {type(exc).__name__}: {exc}")
                continue
        print(f"{t_end:7.0e} {math.ulp(t_end):10.1e} {r_eval:10.1e} {r_samp:10.1e} {s_eval}")


if __name__ == "__main__":
    main()
