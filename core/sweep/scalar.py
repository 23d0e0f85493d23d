"""Sweep lanes one by one with :func:`core.simulate`: any stop, any method.

This is the reference the vectorised closed form is tested against, the fallback for the
few lanes it does not cover, and the work of a deformable-stop sweep (run in parallel by
:mod:`core.sweep.distributed`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from core.deformable.law import phi_compression
from core.params import HystereticStop
from core.result import Result, SteadyKind, TransitionKind
from core.simulate import simulate
from core.sweep.lanes import Lanes
from core.sweep.result import KIND_CODE, LABEL_CODE, LaneRecords

#: Transitions stored per solve: enough for the transient of every regime and the cycle
#: that closes it at ``t_end`` of a few thousand (a stored cycle is needed for its samples).
TRANSITION_CAP = 1_000_000


def steady_cycle(res: Result, stop=None) -> list:
    """Transitions of the steady period of ``res``: the ``transitions_per_period`` stored
    transitions after ``steady.t_reached`` (empty unless periodic). A grazing motion gets
    its limit: on a rigid stop one impact of speed 0; on a deformable ``stop`` whose law
    turns slow contacts elastic, the contact at the elastic speed ``steady.impact_speed``
    (its approach, its peak at ``steady.x_max`` and its separation with the compression
    envelope's force there, :func:`core.steady.train_steady`)."""
    steady = res.steady
    if steady.kind is SteadyKind.GRAZING and isinstance(stop, HystereticStop) and (
            steady.impact_speed > 0.0 and math.isfinite(steady.x_max)):
        w, c, peak = steady.impact_speed, stop.clearance, steady.x_max
        force = float(phi_compression(peak - c, stop))
        return [(KIND_CODE[TransitionKind.CONTACT], c, w, w, np.nan),
                (KIND_CODE[TransitionKind.REVERSAL], peak, 0.0, 0.0, np.nan),
                (KIND_CODE[TransitionKind.SEPARATION], c, -w, -w, force)]
    if steady.kind is SteadyKind.GRAZING:
        return [(KIND_CODE[TransitionKind.IMPACT], float(steady.x_max), 0.0, 0.0, np.nan)]
    if steady.kind is not SteadyKind.PERIODIC:
        return []
    stored = res.transitions
    times = np.fromiter((tr.t for tr in stored), float, len(stored))
    i0 = int(np.searchsorted(times, steady.t_reached, side="right"))
    cycle = stored[i0 : i0 + steady.transitions_per_period]
    force = _force_peaks(res, cycle)
    return [
        (KIND_CODE[tr.kind], tr.x, tr.v, tr.v_after, f)
        for tr, f in zip(cycle, force, strict=True)
    ]


def _force_peaks(res: Result, cycle) -> list[float]:
    """Peak contact force over ``k`` of the contact each separation ends, from the samples
    (which hold every transition point, so a reversal, where the compression force peaks,
    is one of them); ``nan`` for other transitions."""
    out = [np.nan] * len(cycle)
    starts = [tr.t for tr in res.transitions if tr.kind is TransitionKind.CONTACT]
    for j, tr in enumerate(cycle):
        if tr.kind is not TransitionKind.SEPARATION:
            continue
        began = max((t for t in starts if t <= tr.t), default=0.0)
        inside = (res.t >= began) & (res.t <= tr.t)
        if np.any(inside):
            out[j] = float(np.max(res.contact_force[inside]))
    return out


def solve_lanes(
    lanes: Lanes,
    t_end: float,
    x0: float,
    v0: float,
    method: str,
    options: dict | None = None,
) -> LaneRecords:
    """Each lane's steady state from :func:`core.simulate` (all lanes are flagged
    ``fallback``)."""
    n = len(lanes)
    rec = LaneRecords.empty(n)
    rec.fallback[:] = True
    sequences = []
    cycles = []
    for i in range(n):
        osc, stop = lanes.scene(i)
        res = simulate(
            osc, stop, t_end, x0, v0, method=method, n_samples=2,
            transition_cap=TRANSITION_CAP, **(options or {}),
        )
        steady = res.steady
        rec.label[i] = LABEL_CODE[steady.kind]
        rec.period[i] = steady.period
        rec.transitions_per_period[i] = steady.transitions_per_period
        rec.x_max[i] = steady.x_max
        rec.impact_speed[i] = steady.impact_speed
        sequences.append(tuple(KIND_CODE[TransitionKind(k)] for k in steady.sequence))
        cycles.append(steady_cycle(res, stop))
    flat = [row for cycle in cycles for row in cycle]
    rec = dataclasses.replace(
        rec,
        sequence=sequences,
        offsets=np.concatenate(([0], np.cumsum([len(c) for c in cycles]))).astype(np.int64),
    )
    if flat:
        kind, x, v, v_after, force = (np.array(col) for col in zip(*flat, strict=True))
        rec = dataclasses.replace(
            rec,
            cycle_kind=kind.astype(np.int8),
            cycle_x=x.astype(float),
            cycle_v=v.astype(float),
            cycle_v_after=v_after.astype(float),
            cycle_force=force.astype(float),
        )
    return rec
