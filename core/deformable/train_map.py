"""A train of contacts of a pressed mass advanced by its contact-to-contact map.

With the belt pressing the mass on the stop (``x_bar < a``) and no stick, every contact
of a train starts at the stop's face with the law's state fresh (first loading, paper
Eq. 13 from the origin) and slip towards the stop, and every flight is a slip circle about
``(a, 0)`` through the face, which returns to it at the speed it left with (paper Eqs.
3-6). So all that happens from one contact's start to the next is a function of one number,
the approach speed ``w``: the train is the return map ``w -> P(w) = w - L(w)``, its period
``T(w) = d(w) + 2 atan(P(w) / (a - x_bar))`` with ``d`` the contact's duration.

Trains whose contacts turn elastic as they shrink (a peak overlap ``r`` with ``r (D - r)
<= D^2 / beta`` unloads along the compression envelope) lose less per contact than any
power of ``w - w_inf``: they never repeat to a fixed point, and a fitted decay law does not
hold their phase. Here the loss ``L`` and the duration ``d`` are solved for one contact
each at the Chebyshev nodes of the range of ``w`` the train visits, at a tight tolerance
(:data:`NODE_RTOL`; below ``s+``, in closed form and by quadrature,
:mod:`core.deformable.node`), and the interpolants are iterated a block of contacts at a time
(:func:`iterate_block`): a fraction of a microsecond per contact instead of a contact integrated
step by step (~1 ms).

The model refuses (the solve goes on step by step) where a node's contact is not one
reversal between its start and its separation (stick, a second reversal, the limit: the
map has a kink in the range), and where its error per contact is above the solve's
``rtol`` (it must be at least as accurate as the contacts it replaces). It hands back to
the step-by-step solve at the start of the last contact before the horizon (so the end
state is integrated), or earlier where the iterate leaves the last range it could build.

Error: the interpolants' errors ``e_L``, ``e_d`` are the larger of their Chebyshev tails
(the last :data:`TAIL_TERMS` coefficients) and their misses at contacts solved halfway
between nodes (:data:`CHECK_INTERVALS`), doubled, plus the nodes' own tolerance; an error
``dw_k`` in the speed grows as ``dw_(k+1) <= g dw_k + e_L`` with ``g = max |P'|``, and the
time of contact ``k`` is off by ``dt_k = sum (e_d + T'_max dw_j + e_L 2 / (a - x_bar))``
(the phase of ``k`` contacts: ``~ k^2 e_L / (a - x_bar)``). The state where the model hands
back is off by at most ``2 dw + max(|x''|, w) dt``, and whatever the phase by at most the
train's band (positions) and ``2 w`` (velocities), the smaller of the two being stated.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.polynomial import chebyshev as cheb
from numpy.polynomial import polynomial as poly

from core.deformable import hermite
from core.deformable.contact import run_contact
from core.deformable.law import FIRST_LOADING, elastic_limit
from core.deformable.node import node_contact
from core.deformable.reduced_train import contact_at, record_last_restitution
from core.deformable.state import MAP_CONTACTS_PER_STEP, TRAIN, Solve, State
from core.result import TransitionKind

#: Points of each node contact's profile kept for drawing the model's contacts.
PROFILE_POINTS = 129
#: Degree of the interpolants (nodes: one more): solving a node costs ~3 contacts of the
#: standard preset.
DEGREE = 16
#: Relative tolerance of the nodes' contacts (absolute: this times the length scale
#: times 1e-3).
NODE_RTOL = 1e-12
#: Node intervals (first, middle, last) at whose midpoints a contact is solved to check
#: the interpolants.
CHECK_INTERVALS = [0, DEGREE // 2, DEGREE - 1]
#: Trailing Chebyshev coefficients whose doubled sum bounds an interpolant's error.
TAIL_TERMS = 3
#: Regular contacts (one reversal each) seen step by step before the map is tried.
MIN_CONTACTS = 16
#: The map is tried only when at least this many contacts per node are left before the
#: horizon: otherwise following them step by step costs less than the nodes.
MIN_GAIN = 8
#: Contacts of the model's end stored as transitions (the steady-state label reads the
#: last ones); the others are counted.
LOGGED = 16
#: Lower ends of the interpolated ranges, as fractions of the way from ``w_inf`` to the
#: speed at the switch (each next one built if the iteration leaves the one before).
RANGE_FRACTIONS = (0.1, 0.01, 0.001, 0.0)
#: Contacts of the first block iterated at once, the most of one block, the sweeps a
#: block may take to settle, and the relative change (of the speed) below which it has.
FIRST_BLOCK, MAX_BLOCK, MAX_SWEEPS, SWEEP_RTOL = 64, 16_384, 24, 1e-15
#: Largest loss of approach speed per contact, relative, at which the map is tried.
MAX_LOSS = 0.01
#: Ranges built at most per train (each costs DEGREE + 1 contacts solved).
MAX_BUILDS = 6
#: Width kept when a range's interpolants miss the accuracy (towards the switch's speed).
NARROWING = 0.25
#: The sequence of one regular contact in the log: contact, reversal, separation.
REGULAR = ("contact", "reversal", "separation")



class ContactMap(NamedTuple):
    """Interpolants of the loss ``L(w)``, duration ``d(w)`` and peak position over
    ``[lo, hi]`` as power series in ``u = (w - mid) / half``, with their error bounds."""

    lo: float
    hi: float
    loss: tuple[float, ...]
    dur: tuple[float, ...]
    peak: tuple[float, ...]
    err_loss: float
    err_dur: float
    gain: float  # max |P'(w)| over the range
    dur_slope: float  # max |d'(w)|
    accel: float  # largest |x''| of the node contacts
    overlap: float  # largest peak overlap of the node contacts
    nodes: np.ndarray  # approach speeds of the nodes
    profiles: np.ndarray  # (node, overlap / velocity, PROFILE_POINTS): the solved contacts

    def evaluate(self, series, w):
        u = (np.asarray(w, dtype=float) - 0.5 * (self.lo + self.hi)) / (0.5 * (self.hi - self.lo))
        return _horner(series, u)


def _horner(series, u):
    """``polyval(u, series)`` in place: the same operations in the same order (so the same
    bits), without two temporaries per coefficient (the sweeps of :func:`iterate_block` evaluate
    millions of contacts)."""
    y = u * 0.0
    y += series[-1]
    for c in series[-2::-1]:
        y *= u
        y += c
    return y


def solve_contact(sv: Solve, w: float, profile: bool = True):
    """One contact from the face at approach speed ``w`` with the law's state fresh:
    ``(separation speed, duration, peak x, largest |x''|, kinds, profile)``. In closed form
    and by quadrature where it is one regular contact below ``s+``
    (:func:`core.deformable.node.node_contact`), else integrated step by step at
    :data:`NODE_RTOL`."""
    closed = node_contact(sv, w, PROFILE_POINTS if profile else None)
    if closed is not None:
        w_out, dur, peak, accel, prof = closed
        return w_out, dur, peak, accel, REGULAR, prof
    rtol = min(NODE_RTOL, sv.rtol)
    # every row a Hermite step (no arcs): the profile below reads them
    one = Solve(sv.osc, sv.stop, math.inf, rtol, 1e-3 * rtol * sv.scale(), 16,
                use_arcs=False, use_reduced=False)
    st = State(0.0, sv.xb, w, (0.0, 0.0, 0.0))
    outcome = run_contact(one, st, stick=False)
    kinds = tuple(tr.kind.value for tr in one.log.stored)
    if outcome != "separated":
        kinds += (outcome,)
    if kinds != REGULAR:
        return -st.v, st.t, one.x_max, 0.0, kinds, None
    peak = one.x_max
    # |x''| = |a - x - phi| is largest at the peak, where the stop's force is (the last
    # branch starts at the reversal point).
    accel = abs(sv.a - peak - one.contact.branches[-1].phi_r)
    return -st.v, st.t, peak, accel, kinds, _profile(one, st.t)


def _profile(one: Solve, dur: float) -> np.ndarray:
    """Overlap and velocity of a solved contact at :data:`PROFILE_POINTS` times spread
    evenly over its duration (rows of the contact's Hermite steps, evaluated at once)."""
    c = one.contact
    times = np.linspace(0.0, dur, PROFILE_POINTS)
    t0 = np.array(c.t0)
    rows = np.clip(np.searchsorted(t0, times, side="right") - 1, 0, len(t0) - 1)
    data = np.array([c.data[r][:7] for r in rows])
    h = data[:, 6]
    th = (times - t0[rows]) / h
    coeffs = data[:, :6].T  # each row a coefficient over the points: poly takes arrays
    out = np.empty((2, PROFILE_POINTS))
    out[0] = hermite.poly(coeffs, th) - one.xb
    out[1] = hermite.dpoly(coeffs, th) / h
    out[0, -1] = 0.0  # the separation
    return out


def _series(values: np.ndarray) -> tuple[tuple[float, ...], float]:
    """Power series in ``u`` of the Chebyshev interpolant through ``values`` at the
    Chebyshev-Lobatto points (descending ``u``), and its tail bound."""
    coef = cheb.chebfit(np.cos(np.pi * np.arange(DEGREE + 1) / DEGREE), values, DEGREE)
    tail = 2.0 * float(np.abs(coef[-TAIL_TERMS:]).sum())
    return tuple(float(c) for c in cheb.cheb2poly(coef)), tail


def build_map(sv: Solve, lo: float, hi: float) -> ContactMap | None:
    """The map over ``[lo, hi]`` from contacts solved at the nodes, or ``None`` if one of
    them is not a regular contact (a kink of the map in the range)."""
    u = np.cos(np.pi * np.arange(DEGREE + 1) / DEGREE)
    ws = 0.5 * (lo + hi) + 0.5 * (hi - lo) * u
    rows, profiles = [], []
    for w in ws:
        w_out, dur, peak, accel, kinds, profile = solve_contact(sv, float(w))
        if kinds != REGULAR:
            return None
        rows.append((w - w_out, dur, peak, accel))
        profiles.append(profile)
    loss, dur, peak, accel = (np.array(c) for c in zip(*rows, strict=True))
    # The nodes' own error: the contact integrated to NODE_RTOL, relative to the speed.
    node = 10.0 * min(NODE_RTOL, sv.rtol) * hi
    loss_s, e_loss = _series(loss)
    dur_s, e_dur = _series(dur)
    # The tail misjudges a loss whose onset (the elastic speed) lies near the range: the
    # interpolants are also checked against contacts solved halfway between nodes, at
    # both ends and in the middle, and their error taken as the larger, doubled.
    half_u = 0.5 * (u[:-1] + u[1:])[CHECK_INTERVALS]
    for uc in half_u:
        w = 0.5 * (lo + hi) + 0.5 * (hi - lo) * float(uc)
        w_out, d_c, _, _, kinds, _ = solve_contact(sv, w, profile=False)
        if kinds != REGULAR:
            return None
        e_loss = max(e_loss, 2.0 * abs(poly.polyval(uc, loss_s) - (w - w_out)))
        e_dur = max(e_dur, 2.0 * abs(poly.polyval(uc, dur_s) - d_c))
    e_loss += node
    peak_s, _ = _series(peak)
    grid = np.linspace(-1.0, 1.0, 257)
    half = 0.5 * (hi - lo)
    dl = poly.polyval(grid, poly.polyder(loss_s)) / half
    dd = poly.polyval(grid, poly.polyder(dur_s)) / half
    return ContactMap(lo, hi, loss_s, dur_s, peak_s, e_loss, e_dur + node * dur.max(),
                      float(np.abs(1.0 - dl).max()), float(np.abs(dd).max()),
                      float(accel.max()), float(peak.max() - sv.xb), ws, np.array(profiles))


class MapTrain(NamedTuple):
    """The contacts laid out by the map, as a function of time (the solve's dense output).

    Contact ``k`` starts ``start[k]`` after the switch at approach speed ``w[k]`` and lasts
    ``dur[k]``; inside it the overlap and velocity are the profile of the node contact
    nearest in speed, over the contact's own duration, scaled by the ratio of the speeds
    (nodes lie within a few percent of each contact's speed); each flight is the exact slip
    circle about ``(a, 0)`` leaving the face at ``-w[k + 1]``.
    """

    a: float
    xb: float
    start: np.ndarray
    w: np.ndarray  # one more than start: the speed of the contact handed back
    dur: np.ndarray
    nodes: np.ndarray
    profiles: np.ndarray

    @property
    def amp0(self) -> float:
        return float(self.w[0])

    def _nearest(self, w: np.ndarray) -> np.ndarray:
        """Index of the node contact nearest in speed to each of ``w`` (the first of equals,
        as ``argmin``), by a search in the sorted nodes: a train has ~1e4 samples."""
        order = np.argsort(self.nodes, kind="stable")
        sorted_nodes = self.nodes[order]
        right = np.clip(np.searchsorted(sorted_nodes, w), 1, len(order) - 1)
        left = right - 1
        d_left = np.abs(sorted_nodes[left] - w)
        d_right = np.abs(sorted_nodes[right] - w)
        # Duplicate nodes sit next to each other in the stable order: the leftmost of a
        # run of equal nodes is the first in the original order.
        first = np.searchsorted(sorted_nodes, sorted_nodes, side="left")
        pick = np.where((d_right < d_left) | ((d_right == d_left) & (order[first[right]]
                                                                    < order[first[left]])),
                        right, left)
        return order[first[pick]]

    def energy(self, w):
        """Energy of the train above its touching limit at approach speed ``w``: the
        flight's ``((x - a)^2 + x'^2) / 2`` less its value at ``w = 0``."""
        return 0.5 * np.asarray(w, dtype=float) ** 2

    def state(self, tau):
        """Position, velocity and the train's speed ``tau`` after the switch: the
        approach speed of the contact under way, in a flight the one it returns at
        (the stop is unloaded there: a contact's loss counts from its separation)."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        j = self._nearest(w_in)
        pos = np.clip(s / d, 0.0, 1.0) * (PROFILE_POINTS - 1)
        i0 = np.minimum(pos.astype(int), PROFILE_POINTS - 2)
        f = pos - i0
        ratio = w_in / self.nodes[j]
        prof = self.profiles
        delta = ratio * ((1.0 - f) * prof[j, 0, i0] + f * prof[j, 0, i0 + 1])
        v_c = ratio * ((1.0 - f) * prof[j, 1, i0] + f * prof[j, 1, i0 + 1])
        sig = np.where(inside, 0.0, s - d)
        gap = self.xb - self.a
        x_f = self.a + gap * np.cos(sig) - w_out * np.sin(sig)
        v_f = -gap * np.sin(sig) - w_out * np.cos(sig)
        return (np.where(inside, self.xb + delta, x_f), np.where(inside, v_c, v_f),
                np.where(inside, w_in, w_out))

    def peak(self, tau):
        """Peak overlap of the contact under way ``tau`` after the switch (0 in a flight):
        the drawn node profile's, scaled as in :meth:`state`."""
        tau, s, d, w_in, w_out, inside = contact_at(self.start, self.w, self.dur, tau)
        j = self._nearest(w_in)
        return np.where(inside, w_in / self.nodes[j] * self.profiles[:, 0].max(axis=1)[j], 0.0)


class MapRun(NamedTuple):
    """The contacts the map laid out: ``start`` (after the switch), approach speeds
    ``w`` (one more: the speed of the contact handed back), durations ``dur``, and the
    error bounds where it hands back."""

    start: np.ndarray
    w: np.ndarray
    dur: np.ndarray
    t_last: float
    err_speed: float
    err_time: float
    reason: str  # "horizon", "bound", "range" or "limit" (the work limit)


def iterate_block(cmap: ContactMap, w0: float, m: int) -> np.ndarray | None:
    """The next ``m`` speeds from ``w0``, ``w_(k+1) = w_k - L(w_k)``, all at once: the
    sums ``w_k = w0 - sum_(j<k) L(w_j)`` are swept over the block (from the first iterate
    that still changed) until they no longer change (to rounding), which makes them the
    sequential iterates; ``None`` if
    that takes more than :data:`MAX_SWEEPS` sweeps (the block is too long for the loss's
    slope: each sweep fixes at least one more iterate, the error falls like
    ``(m L')^j / j!``)."""
    loss0 = float(cmap.evaluate(cmap.loss, w0))
    w = w0 - loss0 * np.arange(m + 1, dtype=float)
    new = np.empty(m + 1)
    new[0] = w0
    sums = np.empty(m + 1)  # sums[k] = sum_(j<k) L(w_j)
    sums[0] = 0.0
    p = 0  # w[:p + 1] no longer changes: nor do their losses, nor sums[:p + 2]
    for _ in range(MAX_SWEEPS):
        with np.errstate(over="ignore", invalid="ignore"):  # a sweep running away
            # The sums continue from sums[p], one addition after the other, as a cumsum
            # over the whole block does: the same bits, for the part that still changes.
            tail = cmap.evaluate(cmap.loss, w[p:-1])
            tail[0] += sums[p]
            np.cumsum(tail, out=sums[p + 1:])
            new[p + 1:] = w0 - sums[p + 1:]
            diff = np.abs(new[p:] - w[p:])
            change = np.max(diff)
        if not np.isfinite(change):
            return None
        if change <= SWEEP_RTOL * w0:
            return new
        # new[p] == w[p] always; the first change is at p + agree: the next sweep starts
        # at the last point that agrees (both buffers hold the same bits up to there).
        agree = int(np.argmax(diff > 0.0))
        p += max(agree - 1, 0)
        w, new = new, w
    return None


def iterate(cmap: ContactMap, w0: float, horizon: float, gap: float, t0: float = 0.0,
            dw0: float = 0.0, dt0: float = 0.0, max_contacts: int | None = None) -> MapRun:
    """Iterate the map from a contact at ``w0`` starting ``t0`` after the switch (with the
    bounds ``dw0``, ``dt0`` so far) until the next contact would start past ``horizon``,
    ``w`` leaves the range or ``max_contacts`` are laid out, in blocks of contacts
    (:func:`iterate_block`; a block that does not settle is halved, one that settles fast
    doubled)."""
    g, e_l, e_d = cmap.gain, cmap.err_loss, cmap.err_dur
    t_slope = cmap.dur_slope + 2.0 / gap
    dt_flight = 2.0 * e_l / gap
    starts, speeds, durs = [], [np.array([w0])], []
    t, w, dw, dt = t0, w0, dw0, dt0
    m = FIRST_BLOCK
    left = math.inf if max_contacts is None else max_contacts
    while True:
        m = int(min(m, max(left, 1)))
        ws = iterate_block(cmap, w, m)
        if ws is None:
            m = max(1, m // 2)
            continue
        d = cmap.evaluate(cmap.dur, ws[:-1])
        ends = t + np.cumsum(d + 2.0 * np.arctan(ws[1:] / gap))
        # dw_(k+1) = g dw_k + e_L; dt_(k+1) = dt_k + e_d + T'_max dw_k + 2 e_L / gap
        k = np.arange(m + 1, dtype=float)
        if g == 1.0:
            dws = dw + e_l * k
        else:
            gk = g**k
            dws = gk * dw + e_l * (1.0 - gk) / (1.0 - g)
        dts = dt + np.concatenate(([0.0], np.cumsum(e_d + t_slope * dws[:-1] + dt_flight)))
        stop = m
        reason = None
        past = np.nonzero(ends > horizon)[0]
        if len(past):
            stop, reason = int(past[0]), "horizon"
        out = np.nonzero(ws[1:stop + 1] < cmap.lo)[0]
        if len(out):
            stop, reason = int(out[0]), "range"
        if stop > left or (stop == left and reason is None):
            stop, reason = int(left), "limit"
        left -= stop
        begins = np.concatenate(([t], ends[:-1]))
        starts.append(begins[:stop])
        durs.append(d[:stop])
        speeds.append(ws[1:stop + 1])
        if stop > 0:
            t, w, dw, dt = float(ends[stop - 1]), float(ws[stop]), float(dws[stop]), float(
                dts[stop])
        if reason is not None:
            return MapRun(np.concatenate(starts), np.concatenate(speeds), np.concatenate(durs),
                          t, dw, dt, reason)
        m = min(2 * m, MAX_BLOCK)


def elastic_speed(sv: Solve) -> float:
    """Approach speed ``w_inf`` of the contact whose peak overlap ``r`` just stays elastic,
    ``r (D - r) = D^2 / beta_e`` (:func:`core.deformable.law.elastic_limit`). A train of the
    paper's law tends to it from above and never passes it (slower contacts are elastic:
    ``P(w) = w``); ``nan`` when every contact is elastic (``beta_e <= 4``) or none is."""
    w_inf = elastic_limit(sv.a, sv.xb, sv.stop).w_inf
    return w_inf if 0.0 < w_inf < math.inf else math.nan


def map_train(sv: Solve, st: State, train: list) -> bool:
    """Advance a regular train of contacts by its contact-to-contact map from the start
    of a contact (``st``) to the start of a later one, where the step-by-step solve takes
    over again (see the module's docstring); ``False`` (nothing done) while the train is
    not regular, too short, or close enough to the horizon that the nodes cost more than
    they save, or if the map has a kink in the range.

    ``train`` holds ``(t, approach speed, peak x, transitions so far)`` of the contacts;
    the last entry is the contact just started. Energy: as
    :func:`core.deformable.reduced_train.advance_train` (each flight conserves the slip
    circle's energy, so the stop takes what the approach speed loses).
    """
    ready = _ready(sv, st, train)
    if ready is None:
        return False
    period, w_inf = ready
    sv.mark_map_tried()
    gap = sv.a - sv.xb
    runs, maps = _runs(sv, st, st.v, w_inf, period, gap)
    if not runs or sum(len(r.start) for r in runs) == 0:
        return False
    t, dw, dt = runs[-1].t_last, runs[-1].err_speed, runs[-1].err_time
    run = MapRun(np.concatenate([r.start for r in runs]),
                 np.concatenate([runs[0].w[:1]] + [r.w[1:] for r in runs]),
                 np.concatenate([r.dur for r in runs]), t, dw, dt, runs[-1].reason)
    cmap = maps[-1]._replace(accel=max(m.accel for m in maps),
                            overlap=max(m.overlap for m in maps),
                            nodes=np.concatenate([m.nodes for m in maps]),
                            profiles=np.concatenate([m.profiles for m in maps]))
    _advance(sv, st, run, cmap, gap)
    return True


def _ready(sv: Solve, st: State, train: list) -> tuple[float, float] | None:
    """``(period, w_inf)`` of a train the map may take over from ``st``, or ``None``: not
    regular, too short, too near the horizon for the nodes to pay, still losing much per
    contact, or not above its elastic speed (see :func:`map_train`)."""
    if not (sv.use_reduced and sv.pressed()) or sv.map_tried:
        return None
    if len(train) < MIN_CONTACTS + 1:
        return None
    gap = sv.a - sv.xb
    w_now = st.v
    # Regular: one reversal per contact, no stick in contact (x' <= w < v) nor in flight
    # (the slip circle's speed stays below the belt's).
    window = train[-(MIN_CONTACTS + 1):]
    if any(n1 - n0 != len(REGULAR) for (_, _, _, n0), (_, _, _, n1)
           in zip(window[:-1], window[1:], strict=True)):
        return None
    if not math.hypot(gap, w_now) < sv.vb or not 0.0 < w_now:
        return None
    period = window[-1][0] - window[-2][0]
    if (sv.t_end - st.t) / period < MIN_GAIN * (DEGREE + 1):
        return None
    # A train that still loses much per contact crosses a range in a few contacts: the
    # nodes would cost more than they save. It is tried again at a later contact.
    if window[-2][1] - w_now > MAX_LOSS * w_now:
        return None
    w_inf = elastic_speed(sv)
    if not w_inf < w_now:
        return None
    return period, w_inf


def _runs(sv: Solve, st: State, w_now: float, w_inf: float, period: float, gap: float
          ) -> tuple[list[MapRun], list[ContactMap]]:
    """The map's ranges from ``w_now`` towards ``w_inf``, each built when the iteration
    leaves the one before and iterated (the runs and their maps)."""
    # the contacts it may lay out within the work limit (what is left of it)
    budget = max(0, sv.max_steps - sv.work_steps()) * MAP_CONTACTS_PER_STEP
    runs, maps = [], []
    t, w, dw, dt = 0.0, w_now, 0.0, 0.0
    # The train tends to w_inf ever more slowly: one interpolated range after another,
    # each down to a tenth of the way left to w_inf (the last to w_inf itself, where the
    # map is the identity), built when the iteration leaves the one before; a range whose
    # interpolants are not accurate enough is narrowed (a quarter, towards w) and rebuilt.
    targets = [w_inf + f * (w_now - w_inf) for f in RANGE_FRACTIONS]
    narrow, floor = 1.0, w_now
    for _ in range(MAX_BUILDS):
        lo = next((x for x in targets if x < floor), None)
        if lo is None:
            break
        cmap = build_map(sv, w - narrow * (w - lo), w)
        if cmap is None:
            break  # a kink: hand back where the last range ends
        # The map replaces contacts integrated to rtol: it must be at least as accurate
        # per contact, in the speed and in the duration.
        if cmap.err_loss > sv.rtol * cmap.lo or cmap.err_dur > sv.rtol * period:
            narrow *= NARROWING
            continue
        narrow = 1.0
        run = iterate(cmap, w, sv.t_end - st.t, gap, t, dw, dt,
                      max_contacts=max(0, budget - sum(len(r.start) for r in runs)))
        runs.append(run)
        maps.append(cmap)
        t, w, dw, dt = run.t_last, float(run.w[-1]), run.err_speed, run.err_time
        floor = cmap.lo  # the iterate left this range: the next one reaches lower
        if run.reason != "range":
            break
    return runs, maps


def _advance(sv: Solve, st: State, run: MapRun, cmap: ContactMap, gap: float) -> None:
    """Lay the map's contacts into the solve (a row of :class:`Train`) and move ``st`` to
    the start of the contact handed back."""
    sv.record(TransitionKind.REDUCED, st, st.v)
    k = len(run.start)
    model = MapTrain(sv.a, sv.xb, run.start, run.w, run.dur, cmap.nodes, cmap.profiles)
    x_s, m_s, loss_s = st.x, 0.5 * (st.x * st.x + st.v * st.v), st.work[2]
    sv.new_branch(FIRST_LOADING, 0.0, st.work[2])
    sv.add_row(TRAIN, st.t, st.t + run.t_last, (model, x_s, m_s, loss_s), sv.a, st.work)
    w1 = float(run.w[-1])
    wf, wb, ws = st.work
    dm = 0.5 * (w1 * w1 - st.v * st.v)
    st.work = (wf, wb + sv.a * sv.vb * run.t_last, ws - dm)
    t_s = st.t
    # The last contacts as transitions (the steady state is read off them), the others
    # counted; the contact handed back is recorded by the caller.
    first = max(0, k - LOGGED)
    for j in range(k):
        if j < first:
            continue
        t0, w, d = t_s + float(run.start[j]), float(run.w[j]), float(run.dur[j])
        if j > 0:
            sv.add_transition(TransitionKind.CONTACT, t0, sv.xb, w, w)
        peak = float(cmap.evaluate(cmap.peak, w))
        t_peak = t0 + 0.5 * d
        sv.add_transition(TransitionKind.REVERSAL, t_peak, peak, 0.0, 0.0)
        sv.add_transition(TransitionKind.SEPARATION, t0 + d, sv.xb, -float(run.w[j + 1]),
                   -float(run.w[j + 1]))
    for kind in REGULAR:
        n = k - first - (1 if kind == "contact" and first == 0 else 0)
        sv.count_transitions(TransitionKind(kind), (k - 1 if kind == "contact" else k) - n)
    sv.count_laid_out(k - 1, k)
    record_last_restitution(sv, run.w)
    st.t, st.x, st.v = t_s + run.t_last, sv.xb, w1
    err = 2.0 * run.err_speed + max(cmap.accel, run.w[0]) * run.err_time
    # Whatever the phase, both motions stay in the train's band: positions within the
    # contacts' overlap and the flights' depth below the face, speeds within +-w.
    w0 = float(run.w[0])
    envelope = max(2.0 * w0, cmap.overlap + math.hypot(gap, w0) - gap)
    sv.bound(error=min(err, envelope), band=cmap.overlap)
