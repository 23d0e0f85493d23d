"""A stand-in for :func:`core.simulate` in the server of ``test_perf_isolation.py``.

A solve with the horizon :data:`SLOW_T_END` computes in Python (holding its process's
interpreter lock, as long integrations do) until the file named by ``FIE_SLOW_GO_FILE``
exists (the test has measured what it needs while the solve ran) or :data:`SLOW_MAX_S` of
CPU time have passed, then writes the file named by ``FIE_SLOW_DONE_FILE``. It is a
module-level function so that the server's child processes (``app/solve/process.py``)
receive it by reference.
"""

from __future__ import annotations

import os
import time

from core import simulate as real_simulate

#: Horizon that makes a solve slow.
SLOW_T_END = 77.0
#: Longest it computes [s of CPU time] when the test never says go: a fixed length let only
#: two of the other session's releases fit on a slow machine (each a drag and its reply,
#: 0.5-1.5 s), so the test decides when the solve ends.
SLOW_MAX_S = 120.0
#: How often [s of CPU time] the solve looks for the test's go.
LOOK_S = 0.01


def simulate(osc, stop, t_end, *args, **kwargs):
    if t_end == SLOW_T_END:
        go = os.environ["FIE_SLOW_GO_FILE"]
        start = time.thread_time()
        look = start + LOOK_S
        while time.thread_time() < start + SLOW_MAX_S:
            if time.thread_time() >= look:
                if os.path.exists(go):
                    break
                look = time.thread_time() + LOOK_S
        with open(os.environ["FIE_SLOW_DONE_FILE"], "w"):
            pass
    return real_simulate(osc, stop, t_end, *args, **kwargs)
