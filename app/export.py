"""CSV exports of the current run: the trajectory (full resolution, not the decimated plot
data) and its transitions, each file standing alone: a comment line with every parameter,
units in the column names, and a file name that says which run it is.

Examples
--------
>>> from app.state import scene_values
>>> from app.solve.pool import solve
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
from app.scenes import SCENES
from app.solve.solution import Solution
from app.state import DIMENSIONLESS, MM_PER_M, SI_CONVERSIONS, URL_KEYS, Scales
from core import TransitionKind

#: Significant digits of the SI values in a header: a value on a slider's step grid (the
#: finest step is 5e-4, app.control_specs) reads back to 1e-12 relative up to 1e8 steps,
#: while the last bits a unit conversion adds (0.07 * 10 = 0.7000000000000001) go.
SI_HEADER_DIGITS = 12
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


#: Parameters shown in other units in SI mode: the state's name -> (SI name, the factor of
#: :class:`app.state.Scales` from the core's number, unit), the factors and units those of
#: :data:`app.state.SI_CONVERSIONS` (lengths in mm, 1e3 L times the core's number).
SI_PARAMETERS: Mapping[str, tuple[str, str | None, str]] = {
    name: (si_name, SI_CONVERSIONS[name][1], SI_CONVERSIONS[name][0])
    for name, si_name in (("belt_speed", "v_dr"), ("v0", "v0"), ("t_end", "t_end"),
                          ("u_s", "F_N"), ("k_c0", "k_c0"), ("k_e0", "k_e0"),
                          ("clearance", "clearance"), ("x0", "x0"), ("limit_overlap", "D"))
}


def csv_number(value: float) -> str:
    """A CSV cell: the shortest digits that read back to the same double (the float's
    repr), so 0.07 is written "0.07", not "0.070000000000000007".

    >>> csv_number(np.float64(0.07)), csv_number(1 / 3), csv_number(float("nan"))
    ('0.07', '0.3333333333333333', 'nan')
    """
    return repr(float(value))


def si_header_number(value: float) -> str:
    """An SI value of a header with :data:`SI_HEADER_DIGITS` significant digits.

    >>> si_header_number(0.07 * 10.0), si_header_number(100.0), si_header_number(0.1 / 3)
    ('0.7', '100', '0.0333333333333')
    """
    return f"{float(value):.{SI_HEADER_DIGITS}g}"


def si_values(values: Mapping[str, Any], scales: Scales) -> list[tuple[str, Any, str]]:
    """The run's parameters as the SI page shows them: ``(name, value, unit)``, first the
    mass, stiffness and length unit ``L`` (a dimensionless 1, in mm) that fix the units.

    >>> from app.state import ExplorerState, scene_values
    >>> rows = si_values(scene_values("5a"), ExplorerState(
    ...     units="SI", mass=2.0, stiffness=50.0, length_unit=0.5).scales())
    >>> [r for r in rows if r[0] in ("m", "L", "v_dr", "clearance")]
    [('m', 2.0, 'kg'), ('L', 500.0, 'mm'), ('v_dr', 0.25, 'm/s'), ('clearance', 160.0, 'mm')]
    """
    m, k = scales.mass, scales.stiffness
    out: list[tuple[str, Any, str]] = [("m", m, "kg"), ("k", k, "N/m"),
                                       ("omega", (k / m) ** 0.5, "rad/s"),
                                       ("L", scales.length_unit * MM_PER_M, "mm")]
    for name, value in values.items():
        if name in SI_PARAMETERS and isinstance(value, int | float):
            si_name, factor, unit = SI_PARAMETERS[name]
            out.append((si_name, float(value) * (getattr(scales, factor) if factor else 1.0),
                        unit))
        else:
            out.append((name, value, ""))
    return out


def _units(scales: Scales) -> dict[str, str]:
    """Column units: SI (lengths in mm), or the core's (time in 1/omega, lengths in the unit
    of u_s)."""
    if scales.si:
        return {"t": "s", "x": "mm", "v": "m/s", "force": "N", "impulse": "N s"}
    return {"t": "1/omega", "x": "length", "v": "length", "force": "phi/k: length",
            "impulse": "m omega length"}


#: The deformable stop's values.
DEFORMABLE_VALUES = ("k_c0", "k_e0", "limit_overlap", "beta_c", "beta_e", "contact_law",
                     "program")
#: State values a stop type does not use: the page keeps them for the other stop types.
UNUSED_BY_STOP: Mapping[str, tuple[str, ...]] = {
    "none": ("clearance", "restitution", *DEFORMABLE_VALUES),
    "rigid": DEFORMABLE_VALUES,
    "hysteretic": ("restitution",),
}


def _header(sol: Solution, what: str, scales: Scales) -> str:
    unused = UNUSED_BY_STOP.get(sol.values.get("stop_type"), ())
    used = {k: v for k, v in sol.values.items() if k not in unused}
    params = ", ".join(f"{k}={v}" for k, v in used.items())
    kept = ", ".join(f"{k}={sol.values[k]}" for k in unused if k in sol.values)
    if kept:
        params += f"; kept by the page, not used with this stop: {kept}"
    if scales.si:
        # The SI values the page showed, then the core's own (a permalink's) numbers.
        shown = ", ".join(f"{name}={si_header_number(value)} {unit}" if unit
                          else f"{name}={value}"
                          for name, value, unit in si_values(used, scales))
        head = f"units: SI; {shown}; the core's dimensionless values: {params}"
    else:
        head = f"units: dimensionless (t = omega tau; lengths in the unit of u_s); {params}"
    return (f"# Friction-Impact Explorer {what}; {head}\n"
            "# overlap = max(x - clearance, 0): how far the mass is inside the stop "
            "(0 without a stop, and for a rigid stop, which it never enters)\n")


def trajectory_csv(sol: Solution, scales: Scales = DIMENSIONLESS) -> io.StringIO:
    """The trajectory as CSV: two comment lines (parameters, units, what ``overlap`` is),
    then the columns with their units.

    In SI mode time is in seconds, ``x`` and ``overlap`` in mm, ``xdot`` in m/s and the
    contact force in newtons; in dimensionless mode the core's units (``contact_force`` is
    ``phi/k``, a length).
    """
    u = _units(scales)
    buf = io.StringIO()
    buf.write(_header(sol, "trajectory", scales))
    res = sol.result
    if res is None:  # the overlap program of Fig. 2b
        buf.write(f"s,overlap [{u['x']}],contact_force [{u['force']}]\n")
        prog = sol.program
        for row in zip(prog.s, prog.overlap * scales.length, prog.force * scales.force,
                       strict=True):
            buf.write(",".join(csv_number(v) for v in row) + "\n")
        return _rewound(buf)
    buf.write(f"t [{u['t']}],x [{u['x']}],xdot [{u['v']}],mode,"
              f"contact_force [{u['force']}],overlap [{u['x']}]\n")
    t = np.asarray(res.t) * scales.time
    x = np.asarray(res.x) * scales.length
    v = np.asarray(res.v) * scales.velocity
    phi = np.asarray(res.contact_force) * scales.force
    overlap = _overlap(sol, np.asarray(res.x)) * scales.length
    for i in range(len(t)):
        buf.write(
            f"{csv_number(t[i])},{csv_number(x[i])},{csv_number(v[i])},"
            f"{MODE_NAMES[int(res.mode[i])]},{csv_number(phi[i])},"
            f"{csv_number(overlap[i])}\n"
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
        cells = [csv_number(tr.t * scales.time), tr.kind.value,
                 csv_number(tr.x * scales.length),
                 csv_number(tr.v * scales.velocity), csv_number(tr.v_after * scales.velocity),
                 csv_number(_overlap(sol, np.array([tr.x]))[0] * scales.length),
                 "" if impulse is None else csv_number(impulse)]
        buf.write(",".join(cells) + "\n")
    return _rewound(buf)


def file_name(values: Mapping[str, Any], scene: str, what: str,
              scales: Scales = DIMENSIONLESS) -> str:
    """A file name naming the scene and the run's parameters (``key-value`` with the
    permalink's keys; in SI mode ``SI``, the mass and stiffness, and the values converted
    to the page's units under their SI names), of safe characters only (letters, digits,
    ``.``, ``-``, ``_``).

    >>> from app.state import ExplorerState, scene_values
    >>> name = file_name(scene_values("5a"), "5a", "trajectory",
    ...                  ExplorerState(units="SI", mass=2.0, stiffness=50.0,
    ...                                length_unit=0.5).scales())
    >>> name[:58], name[-29:]
    ('fie_5a_trajectory_SI_m-2_k-50_L-500mm_stop-rigid_v_dr-0.25', 'F_N-25_x0-0_v0-0_t_end-12.csv')
    """
    stop = str(values.get("stop_type", "none"))
    parts = ["fie", scene, what, f"stop-{stop}"]
    if scales.si:
        parts[3:3] = ["SI", f"m-{scales.mass:.6g}", f"k-{scales.stiffness:.6g}",
                      f"L-{scales.length_unit * MM_PER_M:.6g}mm"]
    for name in NAMED.get(stop, NAMED["none"]):
        value = values.get(name)
        if isinstance(value, str):
            parts.append(f"{URL_KEYS[name]}-{value}")
        elif value is not None:
            key = URL_KEYS[name]
            if scales.si and name in SI_PARAMETERS and SI_PARAMETERS[name][1]:
                key, factor, _ = SI_PARAMETERS[name]
                value = value * getattr(scales, factor)
            parts.append(f"{key}-{value:.6g}")
    return re.sub(r"[^A-Za-z0-9._-]", "-", "_".join(parts)) + ".csv"


def _overlap(sol: Solution, x: np.ndarray) -> np.ndarray:
    """How far the mass is inside the stop, ``max(x - clearance, 0)`` (0 without one)."""
    if sol.stop is None:
        return np.zeros_like(x, dtype=float)
    return np.maximum(x - sol.stop.clearance, 0.0)


def _rewound(buf: io.StringIO) -> io.StringIO:
    buf.seek(0)
    return buf


class Downloads:
    """The page's two download buttons: the run on screen as CSV files named after it
    (the state's ``solution``; the widgets are built with the page, the files on demand).

    Parameters
    ----------
    state : ExplorerState
        The page's state.
    width : int
        The buttons' width [px].
    """

    def __init__(self, state: Any, width: int) -> None:
        import panel as pn  # the functions above stand without a page

        self.state = state
        self.trajectory = pn.widgets.FileDownload(
            callback=self.trajectory_file, filename="trajectory.csv",
            label="Download trajectory (CSV)", color="default", width=width,
            css_classes=["fie-download"])
        self.transitions = pn.widgets.FileDownload(
            callback=self.transitions_file, filename="transitions.csv",
            label="Download transitions (CSV)", color="default", width=width,
            css_classes=["fie-download-transitions"])

    def trajectory_file(self) -> io.StringIO | None:
        """The trajectory file; its name (set before the transfer) names the run."""
        sol = self.state.solution
        if sol is None:
            return None
        self.trajectory.filename = self._name("trajectory")
        return trajectory_csv(sol, self.state.scales())

    def transitions_file(self) -> io.StringIO | None:
        """One row per transition (impacts with speeds before and after, impulses)."""
        sol = self.state.solution
        if sol is None:
            return None
        self.transitions.filename = self._name("transitions")
        return transitions_csv(sol, self.state.scales())

    def _name(self, what: str) -> str:
        st = self.state
        scene = st.scene if st.scene in SCENES else f"custom-from-{st.figure}"
        return file_name(st.solution.values, scene, what, st.scales())
