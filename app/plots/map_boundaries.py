"""The theory's boundaries over the regime map, in closed form: where its regimes' words change.

In the plane of belt speed ``v`` and clearance ``x_bar`` (docs/physics.md): the critical
speed ``v*`` (Eq. 25) between slow and fast belts; the impactless ``x_max(v)`` (Sec. 3.2)
above which the stop is never reached; and, for a slow belt that sticks before it reaches
the stop, ``x_bar = b`` between cases a and b and ``x* = a + v sqrt(1 - r^2)`` (Eq. 35)
between cases b and c. A deformable stop has the equivalent rigid stop's (Eq. 16).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from app.state import core_inputs
from core import equivalent_rigid, theory

#: Belt speeds at which the curved boundaries are sampled across the map.
BOUNDARY_SAMPLES = 241
#: Columns of the boundaries' source: a line each (``xs``, ``ys``, NaN between pieces), and
#: its label at ``(lx, ly)``, anchored there by its corner ``align``, ``baseline`` and off
#: it by ``dx``, ``dy`` [px].
BOUNDARY_COLUMNS = ("xs", "ys", "text", "lx", "ly", "align", "baseline", "dx", "dy")
#: Where a line's label goes, at the line's last point in view: the corner of the label
#: there, so that it stays in the frame (the vertical v* ends at the top; the others end
#: at the right edge or at v*) and the labels of b and x* (which end together at v*) lie
#: on opposite sides of their lines.
LABEL_CORNERS: dict[str, tuple[str, str]] = {
    "v*": ("left", "top"), "x_max (no impact above)": ("right", "top"),
    "b": ("right", "bottom"), "x*": ("right", "top"),
}
#: Distance [px] of a label's corner from its line's end, sideways and up or down.
LABEL_GAP_PX = 3


def _line(v: np.ndarray, x: np.ndarray, text: str) -> tuple[list, list, str] | None:
    """A boundary through the finite points ``(v, x)``, or None if it has none."""
    if not np.isfinite(x).any():
        return None
    return v.tolist(), x.tolist(), text


def boundary_lines(values: Mapping[str, Any], frame: tuple[float, float, float]
                   ) -> list[tuple[list[float], list[float], str]]:
    """The boundaries over the map of the scene ``values`` on ``frame`` ``(v_hi, x_lo,
    x_hi)``: ``(v, x_bar, label)`` per line (dimensionless; NaN breaks a line).

    >>> from app.state import scene_values
    >>> [text for _, _, text in boundary_lines(scene_values("5a"), (0.4, 0.0, 0.5))]
    ['v*', 'x_max (no impact above)', 'b', 'x*']
    """
    v_hi = frame[0]
    osc, stop, x0, v0, _ = core_inputs({**values, "t_end": 1.0, "program": False})
    vc = theory.critical_speed(osc, x0, v0)
    lines = []
    if 0.0 < vc < v_hi:
        lines.append(([vc, vc], [frame[1], frame[2]], "v*"))
    if stop is None:
        return lines
    v = np.linspace(0.0, v_hi, BOUNDARY_SAMPLES)
    v = np.unique(np.r_[v, [vc] if 0.0 < vc < v_hi else []])
    oscs = [dataclasses.replace(osc, belt_speed=float(s)) for s in v]
    x_max = np.array([theory.x_max_impactless(o, x0, v0) if s > 0 else math.nan
                      for o, s in zip(oscs, v, strict=True)])
    # x_max jumps at v* (the limit cycle's reach, then the circle through the start): the
    # two pieces are not joined.
    cut = np.searchsorted(v, vc, side="right")
    lines.append(_line(np.r_[v[:cut], math.nan, v[cut:]],
                       np.r_[x_max[:cut], math.nan, x_max[cut:]], "x_max (no impact above)"))
    r = equivalent_rigid(stop).restitution
    slow = (v > 0.0) & (v <= vc)
    # Cases a, b, c: a slow belt whose motion sticks before it reaches the stop (from a
    # natural start, past its first stick point).
    natural = x0 == 0.0 and v0 == 0.0
    first = np.array([(theory.first_stick_point(o) or (math.inf,))[0] if natural else -math.inf
                      for o in oscs])
    b = np.where(slow & (osc.b >= first), osc.b, math.nan)
    x_star = osc.a + v * math.sqrt((1.0 - r) * (1.0 + r))
    x_star = np.where(slow & (x_star <= osc.b) & (x_star >= first), x_star, math.nan)
    lines += [_line(v, b, "b"), _line(v, x_star, "x*")]
    return [line for line in lines if line is not None]


def boundary_columns(values: Mapping[str, Any], frame: tuple[float, float, float],
                     velocity: float = 1.0, length: float = 1.0) -> dict[str, list]:
    """The source columns (:data:`BOUNDARY_COLUMNS`) of :func:`boundary_lines`, belt speeds
    times ``velocity`` and clearances times ``length`` (the page's units); each label at
    its line's last point in view. No lines where the theory does not cover the scene (a
    stop behind the start)."""
    try:
        lines = boundary_lines(values, frame)
    except ValueError:
        lines = []
    cols: dict[str, list] = {k: [] for k in BOUNDARY_COLUMNS}
    for v, x, text in lines:
        vs, xs = np.asarray(v, float) * velocity, np.asarray(x, float)
        inside = np.isfinite(xs) & (xs >= frame[1]) & (xs <= frame[2])
        if not inside.any():
            continue
        last = int(np.flatnonzero(inside)[-1])
        align, baseline = LABEL_CORNERS[text]
        cols["xs"].append(vs.tolist())
        cols["ys"].append((xs * length).tolist())
        cols["text"].append(text)
        cols["lx"].append(float(vs[last]))
        cols["ly"].append(float(xs[last] * length))
        cols["align"].append(align)
        cols["baseline"].append(baseline)
        cols["dx"].append(LABEL_GAP_PX if align == "left" else -LABEL_GAP_PX)
        cols["dy"].append(LABEL_GAP_PX if baseline == "bottom" else -LABEL_GAP_PX)
    return cols
