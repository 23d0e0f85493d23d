"""A stand-in for :func:`core.simulate` in the server of ``test_trade_ui.py``'s second test.

Each call appends the id of the process it runs in to the file named by
``FIE_TRADE_PIDS``; the first exact solve with the horizon :data:`SLOW_T_END` (a
measurement's reference) first sleeps :data:`SLOW_S`, so that the measurement still runs
when the page is clicked again. A
module-level function, so that the server's solver processes (``app/solve/process.py``)
receive it by reference.
"""

from __future__ import annotations

import os
import time

from core import simulate as real_simulate

#: Horizon of the slow reference, and how long it sleeps [s]: long enough for the test to
#: click again while the measurement runs, within the reference's budget (15 s).
SLOW_T_END = 79.0
SLOW_S = 4.0


def simulate(osc, stop, t_end, *args, **kwargs):
    with open(os.environ["FIE_TRADE_PIDS"], "a") as f:
        f.write(f"{os.getpid()}\n")
    slept = os.environ["FIE_TRADE_PIDS"] + ".slept"
    if t_end == SLOW_T_END and kwargs.get("method") == "exact" and not os.path.exists(slept):
        time.sleep(SLOW_S)
        open(slept, "w").close()
    return real_simulate(osc, stop, t_end, *args, **kwargs)
