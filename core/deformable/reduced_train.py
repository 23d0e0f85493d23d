"""The reduced contact train: a shrinking train of contacts of a pressed mass, fitted to a
loss law per contact and laid out contact by contact to the horizon or to rest.

A train of ever smaller contacts (paper Fig. 10's kind, a mass pressed on the stop) costs,
step by step, as many contact integrations as it has contacts. Once its band (from the
bottom of a flight to the peak of a contact) is below :data:`TRAIN_PER_RTOL` ``rtol`` of
the length scale (and below :data:`TRAIN_MAX_BAND`), the loss of approach speed per contact
is fitted over its last :data:`TRAIN_FIT` contacts (:func:`fit_train_decay`) and the train
is laid out from that law (:class:`Train`): each contact drawn as a Hermite arc of its
duration, each flight as the slip circle's arc. Its error in the position is within the
band whatever the phase; at the horizon the velocity's is up to twice the approach speed.
A regular train is first handed to its contact-to-contact map
(:mod:`core.deformable.train_map`), which keeps the phase.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from core.deformable.law import FIRST_LOADING
from core.deformable.rest import DECAY_SPREAD, rest_amplitude, rest_at_stop, train_band
from core.deformable.state import TRAIN, Solve, State
from core.result import TransitionKind

#: Contacts the loss law of a train is fitted to (a train that nears its elastic limit
#: changes its approach speed by 1e-4 per contact: six contacts do not tell the law).
TRAIN_FIT = 32
#: Contacts laid out per block while the model is advanced to the horizon.
TRAIN_BLOCK = 65_536
#: Most contacts the model lays out (memory: three float arrays of this length).
TRAIN_MAX_CONTACTS = 20_000_000


def contact_at(start: np.ndarray, w: np.ndarray, dur: np.ndarray, tau):
    """Where times ``tau`` after the switch fall in a train laid out as contacts starting at
    ``start[k]`` with approach speed ``w[k]``, lasting ``dur[k]`` and leaving at
    ``w[k + 1]``: ``(tau, s, dur, w_in, w_out, inside)``, ``s`` the time since the contact's
    start and ``inside`` whether it is still on (else in the flight after it)."""
    tau = np.atleast_1d(np.asarray(tau, dtype=float))
    k = np.clip(np.searchsorted(start, tau, side="right") - 1, 0, len(start) - 1)
    s = tau - start[k]
    return tau, s, dur[k], w[k], w[k + 1], s < dur[k]


def _hermite_overlap(d, w_in, w_out, th):
    """Overlap of a contact of duration ``d`` drawn as the cubic Hermite curve from the face
    at speed ``w_in`` back to it at ``-w_out``, at the fraction ``th`` of its duration."""
    return d * (w_in * (th - 2.0 * th * th + th**3) - w_out * (th**3 - th * th))


class Train(NamedTuple):
    """A train of contacts of a pressed mass advanced by its contact-to-contact map.

    Contact ``k`` (``k = 0`` at the switch) starts ``start[k]`` after the switch with the
    approach speed ``w[k]`` (the fitted loss law, :class:`TrainDecay`) and lasts
    ``dur[k]`` (linear in ``w``, fitted over the same contacts). It ends with the
    separation speed ``w[k + 1]``: the flight between two contacts is a slip circle about
    ``(a, 0)`` through the stop, so it returns at the speed it left with, and lasts
    ``2 atan(w[k + 1] / (a - x_bar))`` exactly (paper Eqs. 3-6). Inside a contact the
    overlap is the cubic Hermite curve through its ends. The position error is bounded by
    the band of the train at the switch (both motions stay in it), the velocity error by
    twice the approach speed (the phase of a long train, not resolved step by step either).
    """

    a: float
    xb: float
    start: np.ndarray
    w: np.ndarray  # one more than start: the last separation speed
    dur: np.ndarray
    band: float
    t_last: float  # end of the model after the switch (the horizon, or rest)
    settled: bool  # the train ends at rest on the stop

    @property
    def amp0(self) -> float:
        return float(self.w[0])

    @property
    def error_bound(self) -> float:
        return self.band

    def state(self, tau):
        """Position, velocity and the train's speed ``tau`` after the switch: the
        approach speed of the contact under way, in a flight the one it returns at
        (the stop is unloaded there: a contact's loss counts from its separation)."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        th = np.where(inside, s / np.where(d > 0.0, d, 1.0), 0.0)
        delta = _hermite_overlap(d, w_in, w_out, th)
        v_c = w_in * (3.0 * th * th - 4.0 * th + 1.0) - w_out * (3.0 * th * th - 2.0 * th)
        sig = np.where(inside, 0.0, s - d)
        gap = self.xb - self.a
        x_f = self.a + gap * np.cos(sig) - w_out * np.sin(sig)
        v_f = -gap * np.sin(sig) - w_out * np.cos(sig)
        x = np.where(inside, self.xb + delta, x_f)
        v = np.where(inside, v_c, v_f)
        return x, v, np.where(inside, w_in, w_out)

    def peak(self, tau):
        """Peak overlap of the contact under way ``tau`` after the switch (0 in a flight):
        the cubic's, where its velocity ``v_c`` of :meth:`state` vanishes (the smaller root
        of ``3 (w_in - w_out) th^2 - (4 w_in - 2 w_out) th + w_in``, in the stable form)."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        b = 4.0 * w_in - 2.0 * w_out
        th = 2.0 * w_in / (b + np.sqrt(np.maximum(b * b - 12.0 * (w_in - w_out) * w_in, 0.0)))
        delta = _hermite_overlap(d, w_in, w_out, th)
        return np.where(inside, delta, 0.0)

    def energy(self, w) -> float:
        """Energy of the train above its touching limit at approach speed ``w``: the
        flight's ``((x - a)^2 + x'^2) / 2`` less its value at ``w = 0``."""
        return 0.5 * np.asarray(w, dtype=float) ** 2


class TrainDecay(NamedTuple):
    """Loss of approach speed per contact of a shrinking train, ``w_k - w_{k+1} = c (w_k -
    w_inf)^n``, advanced in closed form as ``dw/dk = -c (w - w_inf)^n``.

    It covers the geometric decay (``n = 1``), the ``1/k`` decay of contacts that lose
    energy like the cube of their size (``n = 2``, ``w_inf = 0``) and trains whose contacts
    turn elastic as their overlap falls below ``D / beta`` (Eq. 13): their loss vanishes
    as ``w`` nears a limit ``w_inf > 0``, with a large ``n`` (slow algebraic approach).
    """

    c: float
    n: float
    limit: float

    def speed(self, w0: float, k):
        """Approach speed ``k`` contacts after one at ``w0``."""
        k = np.asarray(k, dtype=float)
        u0 = w0 - self.limit
        if abs(self.n - 1.0) < 1e-6:
            return self.limit + u0 * (1.0 - self.c) ** k
        base = u0 ** (1.0 - self.n) + (self.n - 1.0) * self.c * k
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            u = np.where(base > 0.0, np.abs(base) ** (1.0 / (1.0 - self.n)), 0.0)
        return self.limit + u


def _fit_losses(w, loss, limits):
    """Least-squares ``n`` and ``log c`` of ``log loss = log c + n log(w - w_inf)`` for each
    limit ``w_inf``, and the largest relative miss of the fitted losses."""
    u = np.maximum(w[None, :-1] - limits[:, None], 1e-300)
    x, y = np.log(u), np.log(loss)[None, :]
    xm, ym = x.mean(axis=1, keepdims=True), y.mean(axis=1, keepdims=True)
    n = ((x - xm) * (y - ym)).sum(axis=1) / ((x - xm) ** 2).sum(axis=1)
    logc = ym[:, 0] - n * xm[:, 0]
    with np.errstate(over="ignore"):
        miss = np.abs(np.expm1(logc[:, None] + n[:, None] * x - y)).max(axis=1)
    return n, logc, miss


def fit_train_decay(ws) -> TrainDecay | None:
    """The loss law of :class:`TrainDecay` fitted to consecutive approach speeds ``ws``
    (least squares on ``log(w_k - w_{k+1})`` against ``log(w_k - w_inf)`` for a grid of
    ``w_inf``), or ``None`` if they do not shrink or the best fit misses a loss by more
    than :data:`DECAY_SPREAD`.

    Examples
    --------
    >>> law = fit_train_decay(0.9 ** np.arange(32))  # geometric: loses 10 % per contact
    >>> round(law.n, 6), law.limit, round(law.c, 6)
    (1.0, 0.0, 0.1)
    """
    w = np.asarray(ws, dtype=float)
    loss = w[:-1] - w[1:]
    if len(w) < 8 or np.any(loss <= 0.0):
        return None
    limits = np.concatenate(([0.0], w[-1] * (1.0 - np.geomspace(1e-6, 1.0, 48)[:-1])))
    n, logc, miss = _fit_losses(w, loss, limits)
    best = int(np.argmin(miss))
    # A finer grid between the neighbours of the best limit (the coarse one is 34 % apart
    # in w - w_inf).
    lo, hi = limits[max(best - 1, 0)], limits[min(best + 1, len(limits) - 1)]
    limits = np.linspace(min(lo, hi), max(lo, hi), 49)
    n, logc, miss = _fit_losses(w, loss, limits)
    best = int(np.argmin(miss))
    if miss[best] > DECAY_SPREAD or not 0.5 <= n[best] <= 200.0:
        return None
    return TrainDecay(float(np.exp(logc[best])), float(n[best]), float(limits[best]))


def fit_train(sv: Solve, train: list) -> Train | None:
    """The reduced model of a shrinking train from its last :data:`TRAIN_FIT` contacts,
    or ``None`` while the train is too wide, could stick in flight, or is not regular
    (another transition than one reversal per contact, a loss law that does not fit).

    ``train`` holds ``(t, approach speed, peak x, transitions so far)`` of the contacts;
    the last entry is the contact just started.
    """
    if not (sv.use_reduced and sv.pressed()) or len(train) < TRAIN_FIT + 1:
        return None
    gap = sv.a - sv.xb
    w_now = train[-1][1]
    band = train[-2][2] - (sv.a - math.hypot(gap, w_now))
    if not band <= train_band(sv) or w_now >= sv.vb:
        return None
    window = train[-(TRAIN_FIT + 1):]
    if any(n1 - n0 != 3 for (_, _, _, n0), (_, _, _, n1) in zip(window[:-1], window[1:],
                                                                   strict=True)):
        return None
    w_arr = np.array([w for _, w, _, _ in window])
    decay = fit_train_decay(w_arr)
    if decay is None:
        return None
    times = np.array([t for t, _, _, _ in window])
    durs = np.diff(times) - 2.0 * np.arctan(w_arr[1:] / gap)
    if np.any(durs <= 0.0):
        return None
    slope, icpt = np.polyfit(w_arr[:-1], durs, 1)
    return _lay_out(sv, decay, w_now, float(slope), float(icpt), band, train[-1][0])


def _lay_out(sv, decay: TrainDecay, w0: float, slope: float, icpt: float, band: float,
             t_s: float) -> Train | None:
    """Contacts from the switch to the horizon, or up to the first whose band is below the
    rest amplitude (the train has settled on the stop: the model ends at its start)."""
    gap = sv.a - sv.xb
    rest = rest_amplitude(sv)
    horizon = sv.t_end - t_s
    starts, speeds, durs = [], [], []
    t_next, k0 = 0.0, 0
    while True:
        w = decay.speed(w0, np.arange(k0, k0 + TRAIN_BLOCK + 1, dtype=float))
        d = icpt + slope * w[:-1]
        if np.any(d <= 0.0) or k0 > TRAIN_MAX_CONTACTS:
            return None
        step = d + 2.0 * np.arctan(w[1:] / gap)
        ends = t_next + np.cumsum(step)
        begins = np.concatenate(([t_next], ends[:-1]))
        n, settled, done = TRAIN_BLOCK, False, False
        # Band of a contact and its flight: the flight's depth below the stop and the
        # Hermite overlap's peak (about d w / 3).
        # Settled once the band is within the rest error, and the approach speed within
        # half of it, as loops on the stop rest (a swing of four reversals, twice their
        # amplitude, within the rest amplitude: their speed within half the rest error).
        band_k = np.hypot(gap, w[:-1]) - gap + 0.5 * d * w[:-1]
        small = np.nonzero(np.maximum(band_k, 2.0 * w[:-1]) <= rest)[0]
        if len(small):
            n, settled, done = int(small[0]), True, True
        over = np.nonzero(ends > horizon)[0]
        if len(over) and int(over[0]) + 1 <= n:
            n, settled, done = int(over[0]) + 1, False, True
        starts.append(begins[:n])
        speeds.append(w[:n])
        durs.append(d[:n])
        if done:
            speeds.append(w[n:n + 1])
            t_last = float(begins[n]) if settled else horizon
            break
        t_next, k0 = float(ends[-1]), k0 + TRAIN_BLOCK
    start = np.concatenate(starts)
    if len(start) == 0:  # settled at the switch
        start, dur = np.zeros(1), np.zeros(1)
    else:
        dur = np.concatenate(durs)
    w_all = np.concatenate(speeds)
    if len(w_all) < len(start) + 1:
        w_all = np.append(w_all, w_all[-1])
    return Train(sv.a, sv.xb, start, w_all, dur, band, t_last, settled)


def record_last_restitution(sv: Solve, w: np.ndarray) -> None:
    """The restitution of the last contact a train's model lays out (rebound over approach
    speed, ``w[-1] / w[-2]``): the run's last contact, which ``info`` reports."""
    if len(w) >= 2 and w[-2] > 0.0:
        sv.add_restitution(float(w[-1] / w[-2]))


def advance_train(sv: Solve, st: State, model: Train) -> str:
    """Advance a shrinking train by its reduced model from the start of a contact
    (``st``) to the horizon, or to rest at the equilibrium on the compression envelope
    once its band is below the rest amplitude.

    Energy: friction and belt work follow the model's motion (slip towards the stop
    throughout, ``x' < v``); the stop takes the rest of the balance and its loss grows by
    the train's energy ``w^2 / 2`` as the approach speed ``w`` falls, so ``stop_loss``
    never falls.
    """
    sv.record(TransitionKind.REDUCED, st, st.v)
    t1 = min(st.t + model.t_last, sv.t_end)
    x_s, m_s, loss_s = st.x, 0.5 * (st.x * st.x + st.v * st.v), st.work[2]
    sv.new_branch(FIRST_LOADING, 0.0, st.work[2])
    sv.add_row(TRAIN, st.t, t1, (model, x_s, m_s, loss_s), sv.a, st.work)
    x1, v1, _ = (float(q[0]) for q in model.state(t1 - st.t))
    wf, wb, ws = st.work
    dwf = sv.a * (x1 - x_s)
    dm = 0.5 * (x1 * x1 + v1 * v1) - m_s
    st.work = (wf + dwf, wb + sv.a * sv.vb * (t1 - st.t), ws + dwf - dm)
    st.t, st.x, st.v = t1, x1, v1
    laid_out = len(model.start) - 1
    sv.count_laid_out(laid_out)
    for kind in (TransitionKind.CONTACT, TransitionKind.REVERSAL, TransitionKind.SEPARATION):
        sv.count_transitions(kind, laid_out)  # counted, not stored (the map logs its last ones)
    record_last_restitution(sv, model.w)
    sv.bound(error=model.error_bound, band=model.error_bound)
    if not model.settled or t1 >= sv.t_end:
        # At the horizon the phase of the contacts is not kept: both speeds lie within the
        # approach speed of the train, so the velocity may be off by twice it.
        sv.bound(error=2.0 * float(model.w[0]))
        return "horizon"
    st.x = sv.xb
    return rest_at_stop(sv, st, FIRST_LOADING, 1)

