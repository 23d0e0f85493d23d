"""CSV export of the current trajectory (full resolution, not the decimated plot data).

Examples
--------
>>> from app.state import scene_values
>>> from app.solver import solve
>>> text = trajectory_csv(solve(scene_values("5b"))).getvalue()
>>> text.splitlines()[1]
't,x,xdot,mode,contact_force,overlap'
"""

from __future__ import annotations

import io

import numpy as np

from app.plots import MODE_NAMES
from app.solver import Solution
from app.state import DIMENSIONLESS, Scales

#: Significant digits written (double precision round-trips with 17).
CSV_DIGITS = 17


def trajectory_csv(sol: Solution, scales: Scales = DIMENSIONLESS) -> io.StringIO:
    """The trajectory as CSV: one header comment with the parameters, then the columns.

    In SI mode time is in seconds, ``xdot`` in m/s and the contact force in newtons; in
    dimensionless mode the core's units (``contact_force`` is ``phi/k``, a length).
    """
    buf = io.StringIO()
    params = ", ".join(f"{k}={v}" for k, v in sol.values.items())
    buf.write(f"# Friction-Impact Explorer trajectory; {params}\n")
    res = sol.result
    if res is None:  # the overlap program of Fig. 2b
        buf.write("s,overlap,contact_force\n")
        prog = sol.program
        for row in zip(prog.s, prog.overlap, prog.force * scales.force, strict=True):
            buf.write(",".join(f"{v:.{CSV_DIGITS}g}" for v in row) + "\n")
        return _rewound(buf)
    buf.write("t,x,xdot,mode,contact_force,overlap\n")
    t = np.asarray(res.t) * scales.time
    v = np.asarray(res.v) * scales.velocity
    phi = np.asarray(res.contact_force) * scales.force
    for i in range(len(t)):
        buf.write(
            f"{t[i]:.{CSV_DIGITS}g},{res.x[i]:.{CSV_DIGITS}g},{v[i]:.{CSV_DIGITS}g},"
            f"{MODE_NAMES[int(res.mode[i])]},{phi[i]:.{CSV_DIGITS}g},"
            f"{res.overlap[i]:.{CSV_DIGITS}g}\n"
        )
    return _rewound(buf)


def _rewound(buf: io.StringIO) -> io.StringIO:
    buf.seek(0)
    return buf
