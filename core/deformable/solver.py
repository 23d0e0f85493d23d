"""The deformable stop's solve: the event loop over exact free flight and integrated
contacts, and the reduced models of a train of contacts tried at each contact's start.

Away from the stop the motion is the closed form of :mod:`core.flight` (slip circles and stick
lines, paper Eqs. 3-6). Only the contact phase ``x > clearance`` is integrated numerically
(paper Eqs. 14-15 with the law of :mod:`core.deformable.law`, Eqs. 11-13;
:mod:`core.deformable.contact`). A train of contacts of a pressed mass is handed to its
contact-to-contact map (:mod:`core.deformable.train_map`) or its fitted loss law
(:mod:`core.deformable.reduced_train`) at the start of a contact. The state of the solve is
one :class:`~core.deformable.state.Solve`; the result is read off it by
:mod:`core.deformable.samples`.

Energy (per unit ``k``): the work done on the stop is the path integral of the force along
the branches (:func:`core.deformable.law.branch_work`, closed form), friction work is
``s*a`` times the displacement in slip and ``int (x + phi) dx`` in stick: all are functions
of the integrated states, so the balance ``mechanical - mechanical[0] = friction_work -
stop_loss - stop_stored`` checks the integration itself.
"""

from __future__ import annotations

import numpy as np

from core.deformable.contact import run_contact, start_plain
from core.deformable.law import force_and_slope, start_branch
from core.deformable.reduced_train import advance_train, fit_train
from core.deformable.rest import rest_in_place
from core.deformable.samples import assemble
from core.deformable.state import DEFAULT_MAX_STEPS, Solve, State
from core.deformable.train_map import map_train
from core.flight import after_event, free_flight, start_motion
from core.numerics.limits import COUNT_MAX
from core.params import HystereticStop
from core.result import Mode, Result, Status, TransitionKind
from core.solve_inputs import SolveInputs, solve_entry
from core.validation import check_integer


def start_train(sv: Solve, st: State) -> str | None:
    """Record a contact's start (:func:`~core.deformable.contact.start_plain`), and hand a
    shrinking train to its reduced model from here: its contact-to-contact map
    (:func:`core.deformable.train_map.map_train`), which moves ``st`` to the start of a
    later contact and returns ``None``, or its fitted loss law
    (:func:`core.deformable.reduced_train.fit_train`), which runs to the horizon
    (``"horizon"``) or rest (``"rest"``). A train whose contacts turn elastic tends to the
    elastic speed without reaching it: it is never tiled as periodic."""
    started = start_plain(sv, st)
    if started:
        return started
    if map_train(sv, st, sv.train):
        # st is now the start of a later contact, handed back to the integration
        sv.contact_starts(st, st.v)
        sv.add_train_contact(st)
        return None
    model = fit_train(sv, sv.train)
    if model is None:
        return None
    return advance_train(sv, st, model)


def solve_hysteretic(
    inputs: SolveInputs,
    *,
    rtol: float = 1e-9,
    atol: float = 1e-12,
    arcs: bool = True,
    reduce: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> Result:
    """Response with a hysteretic stop: exact free flight and integrated contact phases.

    :func:`simulate_hysteretic` takes the scene, horizon, start and sampling as
    :func:`core.simulate` does (:class:`~core.solve_inputs.SolveInputs`); the stop must be
    a :class:`~core.params.HystereticStop` (paper Eqs. 9-13, docs/contact-law.md).

    Parameters
    ----------
    inputs : SolveInputs
        The checked scene, horizon, start and sampling.
    rtol, atol : float
        Tolerances of the contact integration (position and velocity).
    arcs : bool
        Take the slip between two reversals of a contact semi-analytically where that is
        exact (:func:`core.deformable.arcs.arc`); ``False`` integrates every contact step
        by step (the reference of the tests and ``benchmarks/hysteretic_speed.py``).
    max_steps : int
        Work limit (``>= 1``; default :data:`DEFAULT_MAX_STEPS`, which returns within a few
        seconds whatever the horizon): contact steps, arcs, transitions solved and the
        contacts a map lays out (one per eight), counted in ``info["work_steps"]``. At the
        first transition past it the result ends there (``t[-1]``) with
        ``Status.STEP_LIMIT``.
    reduce : bool
        Advance the small motion of a mass pressed on the stop by a reduced model
        (:mod:`core.deformable.oscillation`, :mod:`core.deformable.reduced_train`) once it
        is below the tolerance; ``False`` follows every loop and contact (the reference of
        the error columns of the benchmark).

    Returns
    -------
    Result
        ``contact_force`` (``phi/k``) and ``overlap`` at the samples; the transitions include
        ``contact``, ``separation``, ``reversal`` and ``reduced`` (the switch into a
        reduced model). ``stats`` holds the counts of :func:`core.result.make_stats`;
        ``info`` holds ``n_contacts``, the effective restitution (rebound over approach
        speed) of the first and the last contact (``effective_restitution_first``,
        ``effective_restitution``; :func:`effective_restitutions` lists all), ``law``, and
        when they apply ``rest_force`` (``phi/k`` at rest), ``reduced_error`` (bound of
        a reduced model's error in the state where it ends, the horizon or rest: for a
        train fitted to a loss law that runs to the horizon, twice its approach speed at
        least, the velocity's bound) and ``reduced_band`` (bound of the
        position's error while the model runs), both absolute, with ``length_scale``
        (``max(a, b, v, |x_bar|, D)``, the scale the tolerances are relative to), and
        ``rest_time_error`` (bound of the error of a rest time a reduced oscillation
        gives).

    Examples
    --------
    >>> from core import HystereticStop, Oscillator
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    >>> stop = HystereticStop(clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.02,
    ...                       beta_c=40.0, beta_e=40.0)
    >>> res = simulate_hysteretic(osc, stop, 80.0, 0.0, 0.0)
    >>> res.status.value, res.info["n_contacts"] > 0
    ('success', True)
    """
    osc, stop, t_end, x0, v0 = inputs.osc, inputs.stop, inputs.t_end, inputs.x0, inputs.v0
    if not isinstance(stop, HystereticStop):
        raise TypeError(f"stop must be a HystereticStop; got {type(stop).__name__}")
    transition_cap, n_samples, t_eval = inputs.transition_cap, inputs.n_samples, inputs.t_eval
    # the arcs' closed forms are the paper's
    sv = Solve(osc, stop, t_end, rtol, atol, transition_cap,
               max_steps=check_integer("max_steps", max_steps, 1, COUNT_MAX),
               use_arcs=arcs and stop.law == "paper", use_reduced=reduce)
    st = State(0.0, x0, v0, (0.0, 0.0, 0.0))
    motion = start_motion(osc, x0, v0)
    # Each pass records a transition, or moves to a contact that records one: twice the
    # limit bounds the passes should a pass record none.
    for _ in range(2 * sv.max_steps + 2):
        if st.t >= t_end or sv.steady is not None or sv.status is not Status.SUCCESS:
            break
        motion = _one_pass(sv, st, motion, x0, v0)
        if motion is None:
            break
    else:
        sv.fail(Status.STEP_LIMIT)
    return assemble(sv, osc, stop, t_end, x0, v0, n_samples, t_eval)


def _one_pass(sv: Solve, st: State, motion, x0: float, v0: float):
    """One pass of the event loop from ``st``: a contact to its end, or a free flight to its
    event. Returns the motion after it, or ``None`` where the solve ends."""
    osc, xb = sv.osc, sv.xb
    if st.t == 0.0 and x0 > xb:
        return _start_inside(sv, st, motion, x0, v0)
    into_stop = st.x >= xb and (
        st.v > 0.0 or (st.v == 0.0 and motion.mode is Mode.SLIP and motion.s * osc.a > xb)
    )
    if into_stop:
        outcome = run_contact(sv, st, stick=motion.mode is Mode.STICK and st.v == osc.v,
                              start=start_train)
        return start_motion(osc, st.x, st.v) if outcome == "separated" else None
    return _fly(sv, st, motion)


def _start_inside(sv: Solve, st: State, motion, x0: float, v0: float):
    """A start inside the stop at ``(x0, v0)``: held there for ever, or the contact it
    starts."""
    osc, stop = sv.osc, sv.stop
    inside = start_branch(x0 - sv.xb, v0, motion.s * osc.a - x0, stop)
    phi0 = force_and_slope(x0 - sv.xb, inside, stop)[0]
    held = v0 == osc.v and abs(x0 + phi0) <= osc.b
    if held and osc.v == 0.0:  # held for ever where it starts
        rest_in_place(sv, st, inside)
        return None
    outcome = run_contact(sv, st, stick=held, inside=inside, start=start_train)
    return start_motion(osc, st.x, st.v) if outcome == "separated" else None


def _fly(sv: Solve, st: State, motion):
    """Free flight (exact, :mod:`core.flight`) from ``st`` to its event or the horizon."""
    osc, t_end = sv.osc, sv.t_end
    seg, ev = free_flight(osc, st.t, st.x, st.v, motion, sv.xb)
    if ev is None or ev.t >= t_end:
        sv.add_free(seg, t_end, st)
        st.x, st.v = seg.state_at(min(t_end, seg.t1) if ev is not None else t_end)
        st.t = t_end
        if ev is None:
            sv.end_free(seg)
        return None
    sv.add_free(seg, ev.t, st)
    st.t, st.x, st.v = ev.t, ev.x, ev.v
    if ev.kind is TransitionKind.IMPACT:
        if motion.mode is Mode.STICK:
            st.v = osc.v
        return motion
    sv.record(ev.kind, st, ev.v)
    return after_event(osc, ev, motion)


#: :func:`solve_hysteretic` with the inputs of :func:`core.simulate`.
simulate_hysteretic = solve_entry(solve_hysteretic)


def effective_restitutions(res: Result) -> np.ndarray:
    """Rebound speed over approach speed of each stored contact that separated.

    The measured restitution of the deformable stop (docs/contact-law.md), to compare with the
    equivalent rigid stop's ``sqrt(k_e0/k_c0)`` (paper Eq. 16).
    """
    out = []
    w_in = None
    for tr in res.transitions:
        if tr.kind is TransitionKind.CONTACT:
            w_in = tr.v
        elif tr.kind is TransitionKind.SEPARATION and w_in:
            out.append(-tr.v / w_in)
            w_in = None
    return np.array(out, dtype=float)
