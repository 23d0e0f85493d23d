"""The work done on a deformable stop along a numerical method's solution, in closed form.

On each branch of the contact law (paper Eqs. 12-13) the force is a function of the overlap,
so the work from the branch's start is its primitive (:class:`core.deformable.law.BranchPrimitive`).
The event method (:mod:`core.event_method`) and the switch model (:mod:`core.switch`) record
the branch each point of their track follows; :func:`core.dense.result_from_dense` takes the
work at the points and at the samples from here instead of the trapezoid rule over the
solver's steps, so the energy balance closes to the states' own error and the loss of a
passive law never falls (docs/contact-law.md).
"""

from __future__ import annotations

import numpy as np

from core.deformable.law import (
    LIMIT_MARGIN,
    Branch,
    BranchPrimitive,
    contact_force,
    stored_energy_many,
)
from core.params import HystereticStop


class StopWork:
    """The work done on a deformable stop along the solution, in closed form: on each
    branch of the law the force is a function of the overlap, so the work from the
    branch's start is its primitive (:class:`core.deformable.law.BranchPrimitive`). Each
    point of the track records its branch (:meth:`add_point`); the work is evaluated at
    the points that need it (:attr:`points`) and at any sample (:meth:`at`), for
    :func:`core.dense.result_from_dense`. With the trapezoid rule over the solver's
    steps the energy balance of scenes 10 and 11 closed to only 2e-6 to 5e-6 of the belt's
    input by the event method and 3e-6 to 2e-5 by the switch model at rtol 1e-8, and the
    passive law's loss dipped by up to 4.8e-7."""

    def __init__(self, stop: HystereticStop, clearance: float) -> None:
        self.stop, self.c = stop, clearance
        #: The branches followed: (branch, its primitive, overlap and work at its start).
        self.entries: list[tuple[Branch, BranchPrimitive, float, float]] = []
        self.current = -1  # the entry followed now; -1 out of contact
        self.work_out = 0.0  # the work done so far, while out of contact
        self.point_entry: list[int] = []
        self.point_x: list[float] = []
        self.point_work: list[float] = []  # out of contact: the work done so far
        self.stuck: list[bool] = []  # stick in contact on the interval after each point

    def work_at(self, x: float) -> float:
        """The work done on the stop up to position ``x`` on the current branch."""
        if self.current < 0:
            return self.work_out
        _, primitive, d0, w0 = self.entries[self.current]
        return w0 + primitive(max(x - self.c, 0.0)) - primitive(d0)

    def follow(self, branch: Branch | None, x: float) -> None:
        """From ``x`` on, follow ``branch`` (``None``: out of contact)."""
        work = self.work_at(x)
        if branch is None:
            self.current, self.work_out = -1, work
            return
        d, d_lim = max(x - self.c, 0.0), self.stop.limit_overlap
        lo, hi = (d, d_lim * (1.0 - LIMIT_MARGIN)) if branch.loading else (0.0, d)
        self.entries.append((branch, BranchPrimitive(branch, self.stop, lo, hi), d, work))
        self.current = len(self.entries) - 1

    def add_point(self, x: float, stuck: bool) -> None:
        """A point of the track at ``x``; the interval after it follows the current branch
        (``stuck``: the mass sticks to the belt there)."""
        self.point_entry.append(self.current)
        self.point_x.append(x)
        self.point_work.append(self.work_out)
        self.stuck.append(stuck and self.current >= 0)

    def retag_last(self, stuck: bool) -> None:
        """The interval after the last point follows the current branch: for a method that
        stores a step's end point before it finds that a contact started, reversed or ended
        there (the switch model)."""
        if not self.point_entry:
            return
        self.point_entry[-1] = self.current
        self.point_work[-1] = self.work_out
        self.stuck[-1] = stuck and self.current >= 0

    @property
    def points(self) -> np.ndarray:
        """The work done at the points where it is needed: out of contact, and at the ends
        of the intervals of stick in contact (the friction's work there is ``x + phi``'s);
        ``nan`` elsewhere (a slip interval's friction is ``s a``, and the samples have
        their own work).
        Evaluated at every point it cost a tenth of scene 11's solve."""
        stuck = np.asarray(self.stuck, dtype=bool)
        entry = np.asarray(self.point_entry, dtype=int)
        ends = stuck.copy()
        ends[1:] |= stuck[:-1]
        # out of contact (free stick too): the work done so far
        out = np.where(entry < 0, np.asarray(self.point_work, dtype=float), np.nan)
        for i in np.flatnonzero(ends & (entry >= 0)):
            _, primitive, d0, w0 = self.entries[entry[i]]
            out[i] = w0 + primitive(max(self.point_x[i] - self.c, 0.0)) - primitive(d0)
        return out

    def at(self, idx: np.ndarray, xs: np.ndarray):
        """Contact force, overlap, work done and energy stored at samples ``xs`` taken in
        the intervals that start at the points ``idx``.

        The stored energy is what the stop gives back on unloading from the law's state:
        while loading, along the unloading branch that would start at the sample (Eq. 12);
        while unloading, along the current branch (not a fresh one from the sample's
        ``(delta, phi)``: the two differ where the branch has been clipped onto the
        compression envelope), as the exact method's samples have it."""
        entry = np.asarray(self.point_entry)[idx]
        overlap = xs - self.c
        force = np.zeros(len(xs))
        work = np.asarray(self.point_work)[idx]  # out of contact: the work done so far
        stored = np.zeros(len(xs))
        fresh = np.zeros(len(xs), dtype=bool)
        for e in np.unique(entry[entry >= 0]):
            sel = np.flatnonzero((entry == e) & (overlap > 0.0))
            if not len(sel):
                continue
            branch, primitive, d0, w0 = self.entries[e]
            d = overlap[sel]
            force[sel] = contact_force(d, branch, self.stop)
            prim = np.array([primitive(dd) for dd in d])
            work[sel] = w0 - primitive(d0) + prim
            if branch.loading:
                fresh[sel] = True
            else:
                stored[sel] = prim - primitive(0.0)
        if fresh.any():
            stored[fresh] = stored_energy_many(overlap[fresh], force[fresh], self.stop)
        inside = (entry >= 0) & (overlap <= 0.0)  # at the face, in contact: from d = 0
        for i in np.flatnonzero(inside):
            _, primitive, d0, w0 = self.entries[entry[i]]
            work[i] = w0 + primitive(0.0) - primitive(d0)
        return force, overlap, work, stored
