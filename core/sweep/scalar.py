"""Sweep lanes one by one with :func:`core.simulate`: any stop, any method.

This is the reference the vectorised closed form is tested against, the fallback for the
few lanes it does not cover, and the work of a deformable-stop sweep (run in parallel by
:mod:`core.sweep.distributed`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from core.deformable.law import phi_compression
from core.result import Result, SteadyKind, TransitionKind
from core.simulate import simulate
from core.steady import cycle_transitions
from core.sweep.lanes import Lanes
from core.sweep.result import KIND_CODE, LABEL_CODE, LaneRecords

#: Transitions stored per solve: enough for the transient of every regime and the cycle
#: that closes it at ``t_end`` of a few thousand (a stored cycle is needed for its samples).
TRANSITION_CAP = 1_000_000


def cycle_rows(res: Result, stop=None) -> list:
    """Rows ``(kind code, x, v, v_after, force)`` of the transitions of the steady period
    of ``res`` (:func:`core.steady.cycle_transitions`: a periodic cycle, or the limit a
    grazing motion approaches). ``force`` is the peak contact force over ``k`` of the
    contact a separation ends: from the samples, and for the elastic contact of a grazing
    limit the compression envelope's force at its peak ``steady.x_max``."""
    cycle = cycle_transitions(res, stop)
    if res.steady.kind is SteadyKind.GRAZING:
        force = [float(phi_compression(res.steady.x_max - stop.clearance, stop))
                 if tr.kind is TransitionKind.SEPARATION else np.nan for tr in cycle]
    else:
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
        cycles.append(cycle_rows(res, stop))
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
