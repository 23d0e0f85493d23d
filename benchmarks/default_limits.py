"""Wall time and status of a default call of the numerical methods at long horizons.

``simulate(..., method=m, t_end=T)`` with no ``max_steps`` nor ``time_budget``: each method
stops at its own default step limit (``core.switch.DEFAULT_MAX_STEPS``,
``core.event_method.DEFAULT_MAX_STEPS``), which should come within a few seconds whatever
the horizon. Scenes: 5a (``Oscillator(0.3, 0.2, 0.1)``, ``RigidStop(0.32, 1.0)``) and 10
(the page's deformable stop, ``Oscillator(0.3, 0.2, 0.07)``, x_bar = 0.24).

Columns: the scene, method and horizon; the wall time; the status; the time reached
(``t[-1]``); accepted + rejected steps.

    PYTHONPATH=. .venv/bin/python benchmarks/default_limits.py
"""

from __future__ import annotations

import datetime
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core import HystereticStop, Oscillator, RigidStop, simulate  # noqa: E402
from core.event_method import DEFAULT_MAX_STEPS as EVENT_STEPS  # noqa: E402
from core.switch import DEFAULT_MAX_STEPS as SWITCH_STEPS  # noqa: E402

SCENES = {
    "5a rigid": (Oscillator(0.3, 0.2, 0.1), RigidStop(clearance=0.32, restitution=1.0)),
    "10 deformable": (
        Oscillator(0.3, 0.2, 0.07),
        HystereticStop(clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.01,
                       beta_c=300.0, beta_e=300.0),
    ),
}
HORIZONS = (1e3, 1e4, 1e5, 1e6, 1e7)


def main() -> None:
    print(f"# {datetime.date.today()} {platform.node()} python {platform.python_version()} "
          f"numpy {np.__version__} scipy {scipy.__version__}; default max_steps: "
          f"switch {SWITCH_STEPS}, event {EVENT_STEPS}")
    print(f"{'scene':<14} {'method':<7} {'t_end':>7} {'wall [s]':>9} {'status':<11} "
          f"{'t reached':>10} {'steps':>8}")
    for name, (osc, stop) in SCENES.items():
        for method in ("switch", "event"):
            for t_end in HORIZONS:
                start = time.perf_counter()
                res = simulate(osc, stop, t_end=t_end, method=method)
                wall = time.perf_counter() - start
                steps = res.stats["steps"] + res.stats["rejected"]
                print(f"{name:<14} {method:<7} {t_end:7.0e} {wall:9.2f} {res.status.value:<11} "
                      f"{float(res.t[-1]):10.4g} {steps:8d}", flush=True)


if __name__ == "__main__":
    main()
