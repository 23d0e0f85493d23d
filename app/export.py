"""CSV exports of the current run: the trajectory (full resolution, not the decimated plot
data) and its transitions, each file standing alone: a comment line with every parameter,
units in the column names, and a file name that says which run it is.

Examples
--------
>>> from app.state import scene_values
>>> from app.solver import solve
>>> sol = solve(scene_values("5b"))
>>> trajectory_csv(sol).getvalue().splitlines()[2]
't [1/omega],x [length],xdot [length],mode,contact_force [phi/k: length],overlap [length]'
>>> transitions_csv(sol).getvalue().splitlines()[2].split(",")[:3]
['t [1/omega]', 'kind', 'x [length]']
>>> file_name(sol.values, "5b", "trajectory")
'fie_5b_trajectory_stop-rigid_v-0.1_xbar-0.25_r-1_mus-0.3_muk-0.2_us-1_x0-0_v0-0_tend-60.csv'
"""

from __future__ import annotations

import io
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from app.plots import MODE_NAMES
from app.solver import Solution
from app.state import DIMENSIONLESS, URL_KEYS, Scales
from core import TransitionKind

#: Significant digits written (double precision round-trips with 17).
CSV_DIGITS = 17
#: Transition kinds at which the stop gives the mass an impulse (Newton's law).
IMPACT_KINDS = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
#: Parameters named in a file name, by stop type (the URL's short keys).
NAMED = {
    "none": ("belt_speed", "mu_s", "mu_k", "u_s", "x0", "v0", "t_end"),
    "rigid": ("belt_speed", "clearance", "restitution", "mu_s", "mu_k", "u_s", "x0", "v0",
              "t_end"),
    "hysteretic": ("belt_speed", "clearance", "k_c0", "k_e0", "limit_overlap", "beta_c",
                   "beta_e", "contact_law", "mu_s", "mu_k", "u_s", "x0", "v0", "t_end"),
}


def _units(scales: Scales) -> dict[str, str]:
    """Column units: SI, or the core's (time in 1/omega, lengths in the unit of u_s)."""
    if scales.si:
        return {"t": "s", "x": "m", "v": "m/s", "force": "N", "impulse": "N s"}
    return {"t": "1/omega", "x": "length", "v": "length", "force": "phi/k: length",
            "impulse": "m omega length"}


def _header(sol: Solution, what: str, scales: Scales) -> str:
    params = ", ".join(f"{k}={v}" for k, v in sol.values.items())
    units = "SI" if scales.si else "dimensionless (t = omega tau; lengths in the unit of u_s)"
    return (f"# Friction-Impact Explorer {what}; units: {units}; {params}\n"
            "# overlap = max(x - clearance, 0): how far the mass is inside the stop "
            "(0 without a stop, and for a rigid stop, which it never enters)\n")


def trajectory_csv(sol: Solution, scales: Scales = DIMENSIONLESS) -> io.StringIO:
    """The trajectory as CSV: two comment lines (parameters, units, what ``overlap`` is),
    then the columns with their units.

    In SI mode time is in seconds, ``xdot`` in m/s and the contact force in newtons; in
    dimensionless mode the core's units (``contact_force`` is ``phi/k``, a length).
    """
    u = _units(scales)
    buf = io.StringIO()
    buf.write(_header(sol, "trajectory", scales))
    res = sol.result
    if res is None:  # the overlap program of Fig. 2b
        buf.write(f"s,overlap [{u['x']}],contact_force [{u['force']}]\n")
        prog = sol.program
        for row in zip(prog.s, prog.overlap, prog.force * scales.force, strict=True):
            buf.write(",".join(f"{v:.{CSV_DIGITS}g}" for v in row) + "\n")
        return _rewound(buf)
    buf.write(f"t [{u['t']}],x [{u['x']}],xdot [{u['v']}],mode,"
              f"contact_force [{u['force']}],overlap [{u['x']}]\n")
    t = np.asarray(res.t) * scales.time
    v = np.asarray(res.v) * scales.velocity
    phi = np.asarray(res.contact_force) * scales.force
    overlap = _overlap(sol, np.asarray(res.x))
    for i in range(len(t)):
        buf.write(
            f"{t[i]:.{CSV_DIGITS}g},{res.x[i]:.{CSV_DIGITS}g},{v[i]:.{CSV_DIGITS}g},"
            f"{MODE_NAMES[int(res.mode[i])]},{phi[i]:.{CSV_DIGITS}g},"
            f"{overlap[i]:.{CSV_DIGITS}g}\n"
        )
    return _rewound(buf)


def transitions_csv(sol: Solution, scales: Scales = DIMENSIONLESS) -> io.StringIO:
    """One row per stored transition: time, kind, position, velocity just before and just
    after, and at an impact the impulse of the stop on the mass (``m (v_before - v_after)``,
    Newton's law, Eq. 8), with the same header lines as :func:`trajectory_csv`."""
    u = _units(scales)
    buf = io.StringIO()
    buf.write(_header(sol, "transitions", scales))
    buf.write(f"t [{u['t']}],kind,x [{u['x']}],v_before [{u['v']}],v_after [{u['v']}],"
              f"overlap [{u['x']}],impulse [{u['impulse']}]\n")
    res = sol.result
    if res is None:
        return _rewound(buf)
    if res.truncated:
        buf.write(f"# {len(res.transitions)} of {res.n_transitions} transitions are stored: "
                  "the first ones, then only a reduced model's start, rest or a failed stop\n")
    for tr in res.transitions:
        impulse = ((tr.v - tr.v_after) * scales.impulse if tr.kind in IMPACT_KINDS else None)
        cells = [f"{tr.t * scales.time:.{CSV_DIGITS}g}", tr.kind.value,
                 f"{tr.x:.{CSV_DIGITS}g}", f"{tr.v * scales.velocity:.{CSV_DIGITS}g}",
                 f"{tr.v_after * scales.velocity:.{CSV_DIGITS}g}",
                 f"{float(_overlap(sol, np.array([tr.x]))[0]):.{CSV_DIGITS}g}",
                 "" if impulse is None else f"{impulse:.{CSV_DIGITS}g}"]
        buf.write(",".join(cells) + "\n")
    return _rewound(buf)


def file_name(values: Mapping[str, Any], scene: str, what: str) -> str:
    """A file name naming the scene and the run's parameters (``key-value`` with the
    permalink's keys), of safe characters only (letters, digits, ``.``, ``-``, ``_``)."""
    stop = str(values.get("stop_type", "none"))
    parts = ["fie", scene, what, f"stop-{stop}"]
    for name in NAMED.get(stop, NAMED["none"]):
        value = values.get(name)
        if isinstance(value, str):
            parts.append(f"{URL_KEYS[name]}-{value}")
        elif value is not None:
            parts.append(f"{URL_KEYS[name]}-{value:.6g}")
    return re.sub(r"[^A-Za-z0-9._-]", "-", "_".join(parts)) + ".csv"


def _overlap(sol: Solution, x: np.ndarray) -> np.ndarray:
    """How far the mass is inside the stop, ``max(x - clearance, 0)`` (0 without one)."""
    if sol.stop is None:
        return np.zeros_like(x, dtype=float)
    return np.maximum(x - sol.stop.clearance, 0.0)


def _rewound(buf: io.StringIO) -> io.StringIO:
    buf.seek(0)
    return buf
