"""A stand-in for :func:`core.simulate` in the server of ``test_perf_isolation.py``.

A solve with the horizon :data:`SLOW_T_END` first spends :data:`SLOW_S` of CPU time in
Python (holding its process's interpreter lock, as long integrations do), then writes the
file named by ``FIE_SLOW_DONE_FILE``. It is a module-level function so that the server's
child processes (``app/solve/process.py``) receive it by reference.
"""

from __future__ import annotations

import os
import time

from core import simulate as real_simulate

#: Horizon that makes a solve slow, and how long it computes [s of CPU time]: long enough
#: for the other session's three releases measured during it (each a drag and its reply,
#: 0.5-1 s on the test machine; with 3 s only two fitted once).
SLOW_T_END = 77.0
SLOW_S = 5.0


def simulate(osc, stop, t_end, *args, **kwargs):
    if t_end == SLOW_T_END:
        end = time.thread_time() + SLOW_S
        while time.thread_time() < end:
            pass
        with open(os.environ["FIE_SLOW_DONE_FILE"], "w"):
            pass
    return real_simulate(osc, stop, t_end, *args, **kwargs)
