"""The readout: the regime in words, the characteristic numbers, the steady state found.

:func:`readout_rows` returns ``(label, text)`` pairs (tested without a browser);
:func:`readout_html` renders them as the small table the page shows.
"""

from __future__ import annotations

import html
import math

import numpy as np

from app.solver import ACCURACY, Solution, reference_name
from app.state import DIMENSIONLESS, Scales
from core import HystereticStop, Mode, Status, Steady, SteadyKind, TransitionKind
from core.hysteretic_reduced import rest_swing_of

#: What the page says of each reading of the contact law (docs/contact-law.md).
CONTACT_LAW_TEXT = {
    "paper": "the paper's reading of Eqs. 12-13 (reproduces Fig. 2b); not passive: some "
             "closed overlap programs return energy (docs/contact-law.md)",
    "passive": "the passive reading of Eqs. 12-13: no closed overlap program returns energy",
}

#: Significant digits of the numbers shown.
DIGITS = 4


def _num(x: float, unit: str = "") -> str:
    if x is None or not math.isfinite(x):
        return "—" if x is None or math.isnan(x) else ("∞" if x > 0 else "-∞")
    return f"{x:.{DIGITS}g}{unit}"


def _ratio(r: float) -> str:
    """A restitution with the digits that tell it from 0 and 1: 0.999999 is an inelastic
    impact, and "1" beside "inelastic impact" said otherwise.

    >>> _ratio(0.999999), _ratio(0.3), _ratio(1.0), _ratio(1e-9)
    ('0.999999', '0.3', '1', '1e-09')
    """
    text = _num(r)
    if r is not None and math.isfinite(r) and float(text) in (0.0, 1.0) and r != float(text):
        text = f"{r:.12g}"
    return text


def readout_rows(sol: Solution, scales: Scales = DIMENSIONLESS) -> list[tuple[str, str]]:
    """The readout as ``(label, text)`` rows.

    >>> from app.state import scene_values
    >>> from app.solver import solve
    >>> rows = dict(readout_rows(solve(scene_values("5b"))))
    >>> rows["Belt"].startswith("slow")
    True
    """
    rows: list[tuple[str, str]] = []
    th, res = sol.theory, sol.result
    vel_unit = " m/s" if scales.si else ""
    len_unit = " m" if scales.si else ""
    if sol.program is not None:
        stop = sol.stop
        rows.append(("Scene", "the stop alone, driven by a prescribed overlap (Fig. 2b)"))
        stiffness = (f"k_c0 = {_num(stop.k_c0 * scales.force)} N/m, "
                     f"k_e0 = {_num(stop.k_e0 * scales.force)} N/m" if scales.si else
                     f"k_c0/k = {_num(stop.k_c0)}, k_e0/k = {_num(stop.k_e0)}")
        rows.append(("Stop", f"{stiffness}, "
                             f"D = {_num(stop.limit_overlap)}{len_unit}, beta_c = "
                             f"{_num(stop.beta_c)}, beta_e = {_num(stop.beta_e)}"))
        rows.append(("Contact law", CONTACT_LAW_TEXT[stop.law]))
        area = float(np.trapezoid(sol.program.force, sol.program.overlap))
        rows.append(("Energy lost", f"{_num(area * scales.energy)}"
                                    f"{' J' if scales.si else ' (per unit k)'} "
                                    "over the program (loop area)"))
        return rows
    if th is not None:
        equivalent = (" (the theory of the equivalent rigid stop, r_eq = sqrt(k_e0/k_c0), "
                      "Eq. 16)" if isinstance(sol.stop, HystereticStop) else "")
        rows.append(("Regime", th.regime.description + equivalent))
        v = sol.osc.v
        belt = "fast" if th.fast else "slow"
        rel = ">" if th.fast else "<="
        if scales.si:
            # The regime's relations (x_max = a + v*, ...) are the paper's, in its time
            # omega tau, where a speed is a length: v = v_dr / omega.
            rows.append(("Belt", f"{belt}: v_dr = {_num(v * scales.velocity, vel_unit)} "
                                 f"{rel} v*_dr = "
                                 f"{_num(th.critical_speed * scales.velocity, vel_unit)} "
                                 "(critical speed, Eq. 25); in the Regime row's relations "
                                 f"v = v_dr/omega = {_num(v)} m and v* = "
                                 f"{_num(th.critical_speed)} m (the paper's time "
                                 "t = omega tau)"))
        else:
            rows.append(("Belt", f"{belt}: v = {_num(v)} {rel} "
                                 f"v* = {_num(th.critical_speed)} (critical speed, Eq. 25)"))
        rows.append(("x_max impactless", _num(th.x_max_impactless, len_unit)))
        if sol.stop is not None and th.restitution < 1.0 and not th.fast:
            rows.append(("x*", f"{_num(th.x_star, len_unit)} (Eq. 35 rederived, "
                               f"r = {_ratio(th.restitution)})"))
    if res is not None:
        rows.append(("x_max simulated", _num(res.x_max, len_unit)))
        rows += _steady_rows(sol, scales)
        measured = sol.restitution_measured
        if len(measured):
            r_eq = _ratio(th.restitution) if th is not None else "—"
            first, last = restitution_first_last(sol)
            total = contact_count(res, len(measured))
            # A run that ends on the stop has a last contact without a rebound yet: the
            # restitutions are those of the contacts that ended.
            on_stop = len(res.mode) > 0 and int(res.mode[-1]) == int(Mode.CONTACT)
            ended = total - 1 if on_stop else total
            spread = (f"{_ratio(first)} at the first contact, {_ratio(last)} at the "
                      f"last of {ended}" if ended > 1
                      else f"{_ratio(first)} (one contact)")
            if on_stop:
                spread += (f"{' that ended' if ended > 1 else ''}; contact {total} has not "
                           "ended (the mass stays on the stop)")
            rows.append(("Restitution", f"{spread}; Eq. 16's r_eq = sqrt(k_e0/k_c0) = {r_eq} "
                         "holds only for beta * overlap / D >> 1"))
        if isinstance(sol.stop, HystereticStop):
            rows.append(("Contact law", CONTACT_LAW_TEXT[sol.stop.law]))
        if res.status is not Status.SUCCESS:
            rows.append(("Status", res.status.message))
        if res.truncated:
            rows.append(("Transitions", f"{res.n_transitions} ({len(res.transitions)} "
                                        "stored: the first ones, then only a reduced "
                                        "model's start, rest or a failed stop)"))
    rows.append(("Solve", f"{sol.method}, {_num(sol.solve_time * 1e3)} ms; "
                          f"accuracy {accuracy_text(sol, scales)}"))
    return rows


def _steady_rows(sol: Solution, scales: Scales) -> list[tuple[str, str]]:
    """The rows of the steady state found: the run's, the force on a rigid stop that holds
    the mass, the transition sequence, and where they differ, the exact method's verdict
    over the same span and the theory's."""
    rows: list[tuple[str, str]] = []
    th, res = sol.theory, sol.result
    vel_unit = " m/s" if scales.si else ""
    time_unit = " s" if scales.si else ""
    len_unit = " m" if scales.si else ""
    steady = res.steady.describe(scales.time, time_unit, scales.velocity, vel_unit, len_unit)
    rest_error = res.info.get("rest_time_error")
    if res.steady.kind is SteadyKind.REST and rest_error is not None:
        # A modelled rest's time is known to its stated bound, not to six digits.
        steady = (f"rest at the stop (from t = {_num(res.steady.t_reached * scales.time)}"
                  f" ± {_num(rest_error * scales.time, time_unit)}, by a reduced model)")
    rows.append(("Steady state found", steady))
    pressed = np.asarray(res.mode) == int(Mode.CONTACT)
    if sol.values["stop_type"] == "rigid" and pressed.any():
        force = float(np.asarray(res.contact_force)[pressed][-1]) * scales.force
        rows.append(("Force on the stop", f"{_num(force, ' N' if scales.si else '')}"
                     f"{'' if scales.si else ' (per unit k)'} = k (a - x_bar): the belt "
                     "holds the mass on the stop"))
    if res.steady.sequence:
        rows.append(("Sequence", " -> ".join(res.steady.sequence)))
    ref = sol.reference_steady
    if ref is not None and ref.kind is not res.steady.kind and not _at_rest_alike(sol, ref):
        # A method can change the verdict: said beside it, not left to the trade table.
        rows.append(("The exact method finds",
                     f"{ref.describe(scales.time, time_unit, scales.velocity, vel_unit, len_unit)}"
                     f" (over the same span; the {sol.method} method finds the steady "
                     "state above)"))
    if th is not None and th.regime.expected_steady != res.steady.kind.value:
        rigid = "the equivalent rigid stop" if isinstance(sol.stop, HystereticStop) else (
            "this stop")
        rows.append(("Theory expects", f"{th.regime.expected_steady} (the paper's "
                                       f"closed forms for {rigid}, which reach it from "
                                       "the natural path, Sec. 4.5)"))
    return rows


def _at_rest_alike(sol: Solution, ref: Steady) -> bool:
    """A run at rest on a deformable stop whose reference (at a tighter ``rtol``, whose rule
    for rest is tighter too) finds loops still swinging there, within the run's own rule:
    the same verdict at the run's accuracy (docs/contact-law.md)."""
    if sol.result.steady.kind is not SteadyKind.REST or not isinstance(sol.stop, HystereticStop):
        return False
    preset = ACCURACY.get(sol.values.get("accuracy"), {})
    if "rtol" not in preset:
        return False
    return ref.at_rest_within(*rest_swing_of(sol.osc, sol.stop, preset["rtol"],
                                             preset.get("atol", 0.0)))


#: Contacts (and loops on the stop) past which the readout says what a deformable stop's
#: error over them was measured to be: the preset's figure is per contact (the paper's
#: scenes, tens of contacts); over a long train each contact's small error in its timing
#: adds to the next, and so does each loop's over hundreds of loops inside one contact
#: (docs/contact-law.md).
MANY_CONTACTS = 50
#: The largest error measured against a tight reference, over the scale, at t_end = 100 and
#: the standard preset, where no reduced model took over (a model's own bound is stated
#: beside it) and the mass does not rest, on the 80 pressed stops of
#: benchmarks/hysteretic_speed.py: 6.3e-9 under either law (k_c0 = 100, beta = 100, D = 1;
#: benchmarks/results/hysteretic_speed_2026-11-27g.txt), 3.8e-9 on Fig. 10's train by
#: t = 1000. It was 1.1e-4 (the phase of hundreds of contacts) before the contacts of a
#: train were kept on their first integral (core/hysteretic_contact.py), and 3.5e-6 under
#: the passive law until its contacts were kept there too.
MANY_CONTACTS_ERROR = 1e-8
#: The same for runs that end at rest on the stop with no reduced model: the rule for rest
#: (core.hysteretic.REST_AMPLITUDE_PER_RTOL) declares it once the loops left swing within
#: 10 rtol of the scale in the position and 100 rtol in the velocity, and they die out
#: from there: 1e-6 at standard. Measured 2.2e-8 to 1.9e-7 at horizons 0.05 to 3 past the
#: rest of k_c0 = 100, beta = 1000, D = 0.01 (t ~ 199). (When rest was read on the
#: position alone, loops on stiff stops were left swinging at omega times 10 rtol in the
#: velocity: 4.6e-6 of the scale one time unit past a rest at k_c0 = 1e4, where 4e-7, the
#: figure measured at t = 100 only, was quoted.)
MANY_CONTACTS_REST_ERROR = 1e-6
#: The horizon of that measurement (dimensionless time).
MANY_CONTACTS_T_END = 100.0


#: Transitions at which a rigid stop gives the mass an impulse (Newton's law).
RIGID_IMPACTS = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)


def restitution_first_last(sol: Solution) -> tuple[float, float] | None:
    """Rebound over approach speed at the run's first and last impact or contact, or
    ``None`` without one: a deformable stop's measured ones (its last the core's: the
    stored transitions may end long before the run does, a capped log, a train laid out by
    its map), a rigid stop's from its impacts (Newton's r, Eq. 8).

    >>> from app.state import scene_values
    >>> from app.solver import solve
    >>> [round(r, 6) for r in restitution_first_last(solve(scene_values("7c")))]
    [0.3, 0.3]
    """
    measured = np.asarray(sol.restitution_measured)
    res = sol.result
    if res is None:
        return None
    if len(measured):
        last = float(res.info.get("effective_restitution", math.nan))
        return float(measured[0]), last if math.isfinite(last) else float(measured[-1])
    ratios = [-tr.v_after / tr.v for tr in res.transitions
              if tr.kind in RIGID_IMPACTS and tr.v > 0]
    return (ratios[0], ratios[-1]) if ratios else None


def contact_count(res, measured: int) -> int:
    """The contacts of the whole run: ``info['n_contacts']`` counts those integrated and
    those a reduced model laid out, ``transition_counts`` every one logged (a periodic tail
    tiled from one period included, past the stored ones), ``measured`` the restitutions
    of the stored ones."""
    return max(int(res.info.get("n_contacts", 0)), _logged(res, TransitionKind.CONTACT),
               measured)


def _logged(res, kind: TransitionKind) -> int:
    return int(res.transition_counts.get(kind.value, 0))


def accuracy_text(sol: Solution, scales: Scales = DIMENSIONLESS) -> str:
    """What the run's accuracy is, as far as it is known: rounding for a closed form; for a
    numerical method the preset's measured error, and for a deformable stop how it grows
    with the contacts and what a reduced model's stated bound is (times in the page's
    units)."""
    time_unit = " s" if scales.si else ""
    if sol.method == "exact" and (sol.stop is None or sol.values["stop_type"] == "rigid"):
        return "closed form, rounding only"
    if sol.error_measured:
        return (f"{_num(sol.error_estimate)} relative, measured against "
                f"{reference_name(sol.stop)} ({sol.values['accuracy']})")
    text = f"~{_num(sol.error_estimate)} relative ({sol.values['accuracy']})"
    if sol.measure_skipped:
        return (f"{text}, the preset's expected error: not measured for this run (the exact "
                "solve it is measured against would have made the answer late; 'Measure the "
                "trade' measures it)")
    res = sol.result
    if res is None or not isinstance(sol.stop, HystereticStop):
        return text
    contacts = contact_count(res, len(sol.restitution_measured))
    # Loops on the stop: the reversals beyond each contact's one, two per loop.
    loops = max(_logged(res, TransitionKind.REVERSAL) - _logged(res, TransitionKind.CONTACT),
                0) // 2
    if contacts + loops > MANY_CONTACTS:
        what = (f"{contacts} contacts" if loops <= MANY_CONTACTS else
                f"{contacts} contact{'s' if contacts != 1 else ''} and {loops} loops on the "
                "stop")
        # A rest the rule declared (a REST transition), not loops still dying at the horizon.
        at_rest = any(t.kind is TransitionKind.REST for t in res.transitions[-2:])
        if at_rest:
            text += (f" per contact; over {what} within {_num(MANY_CONTACTS_REST_ERROR)} of "
                     "the scale at standard (at rest: the rule for rest leaves loops within "
                     "it)")
        else:
            text += (f" per contact; over {what} measured within "
                     f"{_num(MANY_CONTACTS_ERROR)} of the scale by t = "
                     f"{_num(MANY_CONTACTS_T_END * scales.time, time_unit)} at standard "
                     "(their timing errors add up over longer runs)")
    reduced = [t.t for t in res.transitions if t.kind is TransitionKind.REDUCED]
    if reduced:
        # The core states the bound as a length: over its scale, as the preset's error is.
        bound = res.info.get("reduced_error", math.nan) / res.info.get("length_scale", math.nan)
        text += (f"; from t = {_num(reduced[0] * scales.time, time_unit)} a reduced model, "
                 "its stated error "
                 f"<= {_num(bound)} of the scale")
        rest_error = res.info.get("rest_time_error")
        if rest_error is not None:
            text += f"; its time of rest within ±{_num(rest_error * scales.time, time_unit)}"
    return text


def readout_html(sol: Solution, scales: Scales = DIMENSIONLESS) -> str:
    """The rows as an HTML table (escaped); a long row wraps."""
    rows = ((html.escape(k), html.escape(v)) for k, v in readout_rows(sol, scales))
    body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    return f'<table class="fie-readout">{body}</table>'
