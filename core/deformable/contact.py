"""One contact with the deformable stop, from its start to its end: the law's branches and
their reversals, slip and stick on each (:mod:`core.deformable.stepper`), the semi-analytic
arcs between reversals (:mod:`core.deformable.arcs`), and the end of the loops of a pressed
mass in rest (:mod:`core.deformable.rest`) or in a reduced oscillation
(:mod:`core.deformable.oscillation`).

A contact starts on the first loading (the compression envelope, paper Eq. 11) at the face,
or on the branch of a start inside the stop. At each reversal of the overlap rate the law's
new branch starts from the stored reversal point (Eq. 13). Energy: the work done on the
stop is the path integral of the force along the branches
(:func:`core.deformable.law.branch_work`, closed form), closed at each branch's end.
"""

from __future__ import annotations

import math

from core.deformable.arcs import arc
from core.deformable.decay import creep_end
from core.deformable.law import (
    FIRST_LOADING,
    Branch,
    branch_work,
    force_and_slope,
    on_compression,
    reverse,
)
from core.deformable.oscillation import reduce_oscillation
from core.deformable.rest import (
    reduce_extent,
    rest_amplitude,
    rest_at_stop,
    rest_rule,
    rest_swing_factor,
)
from core.deformable.state import Solve, State
from core.deformable.stepper import slip, stick_line
from core.deformable.train_contact import TrainContact
from core.result import Status, TransitionKind

#: Reversals between two tries of the reduced oscillation: a try fits the decay of the last
#: cycles (35 % of a soft stop's solve when made at every reversal, k_c0 = 100, t_end = 1e4),
#: and a switch two cycles later changes nothing the model's bounds do not state.
REDUCE_EVERY = 4


def start_plain(sv: Solve, st: State) -> str | None:
    """Record a contact's start at the face: ``"periodic"`` if the motion is periodic from
    here (a fixed point of the friction-impact map), else ``None`` (integrate it), the
    contact added to the train."""
    sv.contact_starts(st, st.v)
    if sv.steady is not None:
        return "periodic"
    sv.add_train_contact(st)
    return None


def run_contact(sv: Solve, st: State, stick: bool, inside: Branch | None = None,
                start=start_plain) -> str:
    """Integrate one contact from ``st`` (at the face, moving in) until it ends; with
    ``inside``, from a start inside the stop on that branch
    (:func:`~core.deformable.law.start_branch`).

    Returns ``"separated"``, ``"rest"``, ``"failed"``, ``"limit"``, ``"periodic"`` or
    ``"horizon"``.
    """
    xb = sv.xb
    opened = open_contact(sv, st, inside, start)
    if isinstance(opened, str):
        return opened
    branch, s = opened
    d_branch0 = st.x - xb
    w_in = st.v if inside is None else math.nan
    reversal_x: list[tuple[float, float, int]] = []  # (t, x, transitions) of reversals
    # a contact of a train is kept on its first integral (core/deformable/train_contact.py)
    train = TrainContact(sv, st.x, w_in, s, stick)
    while True:
        if stick:
            outcome = stick_line(sv, st, branch)
            if outcome != "slip":
                close_branch(sv, branch, d_branch0, st.x - xb, st)
                return outcome
            stick, s = False, 1
            continue
        # a semi-analytic arc from the reversal the branch starts from
        phi = (arc(sv, st, s, branch)
               if sv.use_arcs and st.v == 0.0 and branch.delta_r == st.x - xb else None)
        if phi is not None:
            train.regular = False  # a second reversal
            branch, ended = _reverse(sv, st, branch, phi, reversal_x, s)
            d_branch0 = st.x - xb
            if ended:
                return ended
            continue
        outcome, s_new = slip(sv, st, s, branch, train.kinks(), train.tight(len(reversal_x)))
        if outcome == "separated":
            return _separate(sv, st, train, branch, d_branch0, w_in, len(reversal_x))
        if outcome == "reversal":
            branch, d_branch0, ended = _reverse_at_peak(sv, st, train, branch, d_branch0,
                                                       reversal_x, s)
            if ended:
                return ended
            continue
        if outcome == "friction":
            train.regular = False
            stick, s, branch, d_branch0 = belt_speed_reached(sv, st, s, s_new, branch,
                                                             d_branch0)
            continue
        # "failed", "limit" or "horizon"
        close_branch(sv, branch, d_branch0, st.x - xb, st)
        return outcome


def _reverse(sv: Solve, st: State, branch: Branch, phi: float, reversal_x, s: int
             ) -> tuple[Branch, str | None]:
    """:func:`reversal`, and ``"failed"`` if the solve failed there (the work limit)."""
    branch, ended = reversal(sv, st, branch, phi, reversal_x, s)
    if not ended and sv.status is not Status.SUCCESS:
        ended = "failed"
    return branch, ended


def _reverse_at_peak(sv: Solve, st: State, train: TrainContact, branch: Branch,
                     d_branch0: float, reversal_x, s: int
                     ) -> tuple[Branch, float, str | None]:
    """A reversal the steps found: its peak projected (a train's contact, a retraced
    curve), the branch closed and the next one started. Returns the new branch, its start
    overlap and how the contact ended, if it did."""
    delta = st.x - sv.xb
    st.x = sv.xb + retraced_top(sv, train.peak(delta, len(reversal_x)), branch)
    delta = st.x - sv.xb
    phi, _ = force_and_slope(delta, branch, sv.stop)
    close_branch(sv, branch, d_branch0, delta, st)
    branch, ended = reversal(sv, st, branch, phi, reversal_x, s)
    train.unloading(branch)
    if not ended and sv.status is not Status.SUCCESS:
        ended = "failed"
    return branch, delta, ended


def _separate(sv: Solve, st: State, train: TrainContact, branch: Branch, d_branch0: float,
              w_in: float, reversals: int) -> str:
    """The contact ends at the face: its separation speed (projected for a train's
    contact), the branch closed, the restitution and the transition recorded."""
    st.v = train.separation(st.v, branch, reversals)
    close_branch(sv, branch, d_branch0, 0.0, st)
    st.x = sv.xb
    sv.add_restitution(-st.v / w_in if w_in > 0 else math.nan)
    sv.record(TransitionKind.SEPARATION, st, st.v)
    return "separated"


def open_contact(sv: Solve, st: State, inside: Branch | None, start=start_plain
                 ) -> str | tuple[Branch, int]:
    """The branch and friction sign a contact starts with, or how it ended at once (see
    :func:`start_plain`, or the ``start`` given). From the face (``inside`` None) on the
    first loading; from a start inside the stop on ``inside``: not a contact of a train (no
    entry speed)."""
    if inside is None:
        started = start(sv, st)
        if started:
            return started
        # a train's map may have moved st to the start of a later contact
        branch = FIRST_LOADING
    else:
        sv.contact_starts(st, st.v)
        branch = inside
    delta = st.x - sv.xb
    sv.new_branch(branch, delta, st.work[2])
    if st.v != sv.vb:
        return branch, 1 if st.v < sv.vb else -1
    # at the belt's speed and not held: friction gives way to the net force
    return branch, 1 if st.x + force_and_slope(delta, branch, sv.stop)[0] > 0.0 else -1


def belt_speed_reached(sv: Solve, st: State, s: int, s_new: int, branch: Branch,
                       d_branch0: float):
    """The mass reaches the belt speed inside contact: it sticks if static friction
    holds the stop's force, ``|x + phi| <= b``, else friction changes sign. Returns
    ``(stick, s, branch, start overlap of the branch)``."""
    delta = st.x - sv.xb
    phi, _ = force_and_slope(delta, branch, sv.stop)
    if not (abs(st.x + phi) <= sv.b and sv.vb > 0.0):
        sv.record(TransitionKind.SIGN_CHANGE, st, st.v)
        return False, s_new, branch, d_branch0
    st.v = sv.vb
    sv.record(TransitionKind.SLIP_STICK, st, st.v)
    if not branch.loading:  # x' = v > 0: the overlap grows again
        close_branch(sv, branch, d_branch0, delta, st)
        branch = reverse(delta, phi, branch, sv.stop)
        d_branch0 = delta
        sv.new_branch(branch, delta, st.work[2])
    return True, s, branch, d_branch0


def close_branch(sv: Solve, branch: Branch, d0: float, d1: float, st: State) -> None:
    wf, wb, ws = st.work
    st.work = (wf, wb, ws + branch_work(d0, d1, branch, sv.stop))


def reversal(
    sv: Solve, st: State, branch: Branch, phi: float, reversal_x: list[tuple[float, float]],
    s: int,
) -> tuple[Branch, str | None]:
    """The overlap rate changes sign at ``st``: the new branch starts from the stored
    reversal point (Eq. 13). Returns it, and ``"periodic"`` or ``"rest"`` when the
    contact ends here (a fixed point, or the reversals have died out)."""
    delta = st.x - sv.xb
    branch = reverse(delta, phi, branch, sv.stop)
    sv.new_branch(branch, delta, st.work[2])
    sv.record(TransitionKind.REVERSAL, st, 0.0, phi=phi)
    if sv.steady is not None:
        return branch, "periodic"
    reversal_x.append((st.t, st.x, sv.log.total))
    if len(reversal_x) == 1:
        sv.set_train_peak(st.x)
    rule, error = settled(sv, reversal_x)
    if rule == "model" and not sv.use_reduced:
        rule = "follow"  # a solve without reduced models follows the creeping loops
    if rule == "follow":
        # Rest would be a model stating more than the tolerance, and the loops to the
        # horizon are few: they are followed, and no reduced model is tried on them.
        sv.defer_reduction(sv.t_end)
    elif rule is not None:
        if rule == "model":
            # Rest is then a model of loops still creeping: its error is stated, the
            # velocity's too (the loops left move at omega times their amplitude).
            sv.record(TransitionKind.REDUCED, st, 0.0)
            sv.bound(error=error)
        return branch, rest_at_stop(sv, st, branch, s, creep_end(sv, reversal_x, s))
    if len(reversal_x) % REDUCE_EVERY or st.t < sv.reduce_after:
        return branch, None
    return branch, reduce_oscillation(sv, st, branch, reversal_x, s)


def settled(sv: Solve, reversal_x: list[tuple[float, float, int]]) -> tuple[str | None, float]:
    """The rule for rest on the reversals of this contact (:func:`rest_rule`)."""
    if len(reversal_x) < 4:
        return None, 0.0
    # fixed for the solve; this runs at every reversal
    rest, tol = sv.rest_tolerances(lambda sv: (rest_amplitude(sv), reduce_extent(sv)))
    # the rule's first test without building lists (loops followed on the stop: a tenth
    # of their time went here)
    x0, x1, x2, x3 = reversal_x[-1][1], reversal_x[-2][1], reversal_x[-3][1], reversal_x[-4][1]
    factor = rest_swing_factor(reversal_x[-1][0] - reversal_x[-3][0])
    if (max(x0, x1, x2, x3) - min(x0, x1, x2, x3)) * factor > rest:
        return None, 0.0
    tail = reversal_x[-5:]
    return rest_rule([t for t, _, _ in tail], [x for _, x, _ in tail], sv.t_end, rest,
                     tol)


def retraced_top(sv: Solve, delta: float, branch: Branch) -> float:
    """The overlap of a reversal ending a loading of the passive law along the curve
    through its anchor: the anchor itself when the integration overshot it onto
    ``phi_C`` by less than its tolerance.

    Such a loading is the exactly conservative motion back up the curve the mass came
    down from the anchor, so its reversal is the anchor. An overshoot reverses from a
    new point of ``phi_C``, a new curve a little higher at every loop: at rtol 1e-5
    (k_c0 = 1e4, beta = 1000, D = 0.01) the loops then never retraced one curve and
    were followed one by one to the horizon (3,000 reversals, 0.6 s)."""
    anchor = branch.anchor
    if sv.stop.law != "passive" or not branch.loading or anchor is None:
        return delta
    d_a, p_a = anchor
    if (on_compression(d_a, p_a, sv.stop)
            and 0.0 < delta - d_a <= max(sv.rtol * sv.scale(), sv.atol)):
        return d_a
    return delta
