"""The readout: the regime in words, the characteristic numbers, the steady state found.

:func:`readout_rows` returns ``(label, text)`` pairs (tested without a browser);
:func:`readout_html` renders them as the small table the page shows.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import panel as pn
import param

from app.deferred import later
from app.scenes import CUSTOM, SCENES
from app.solve.measure import integrates, reference_name
from app.solve.presets import ACCURACY
from app.solve.solution import Solution
from app.state import DIMENSIONLESS, ExplorerState, Scales
from app.teach.glossary import GLOSSARY
from app.widgets import set_changed
from core import (
    HystereticStop,
    Mode,
    Status,
    Steady,
    SteadyKind,
    TransitionKind,
    rest_swing_of,
)

#: What the page says of each reading of the contact law (docs/contact-law.md).
CONTACT_LAW_TEXT = {
    "paper": "the paper's reading of Eqs. 12-13 (reproduces Fig. 2b); not passive: some "
             "closed overlap programs return energy",
    "passive": "the passive reading of Eqs. 12-13: no closed overlap program returns energy",
}

#: Significant digits of the numbers shown.
DIGITS = 4
#: Significant digits of a duration in seconds (a solve's time varies more than that).
DURATION_DIGITS = 3
#: The house stylesheet (panes render in shadow DOMs: each that uses its classes links it).
STYLESHEET = "assets/explorer.css"
#: Height [px] of one line of the readout (``explorer.css``) and the room kept below it.
READOUT_ROW_PX, READOUT_PAD_PX = 20, 8
#: Lines the readout reserves beyond its rows (one long row that wraps at the page's width,
#: or the note of a drag's preview).
READOUT_SPARE_LINES = 1
#: Delay [ms] after a release before the readout says that its run is not shown yet: a
#: run drawn sooner clears the drag's note in its own message, and the readout changes
#: once per drag (its text sent at every step and again at the release held the release's
#: picture up by some 20 ms, paired in one browser).
SOLVING_NOTE_DELAY_MS = 300
#: The readout while its rows are not the sliders' run: greyed, under a line that says why.
PENDING_CSS = """
.fie-pending table { opacity: 0.45; }
.fie-pending-note { font-size: 13px; line-height: 18px; font-style: italic; color: #1f3f7a; }
"""


def _num(x: float, unit: str = "") -> str:
    if x is None or not math.isfinite(x):
        return "—" if x is None or math.isnan(x) else ("∞" if x > 0 else "-∞")
    return f"{x:.{DIGITS}g}{unit}"


def duration_text(seconds: float) -> str:
    """A wall-clock duration as a person reads it: milliseconds below a second, seconds
    (three significant digits) from one on ("19.4 s", not "1.942e+04 ms").

    >>> duration_text(0.0123), duration_text(19.42)
    ('12.3 ms', '19.4 s')
    """
    ms = float(f"{seconds * 1e3:.{DIGITS}g}")
    if ms < 1e3:
        return f"{ms:g} ms"
    return f"{seconds:.{DURATION_DIGITS}g} s"


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
    >>> from app.solve.pool import solve
    >>> rows = dict(readout_rows(solve(scene_values("5b"))))
    >>> rows["Belt"].startswith("slow")
    True
    """
    if sol.program is not None:
        return _program_rows(sol, scales)
    rows = _theory_rows(sol, scales) if sol.theory is not None else []
    if sol.result is not None:
        rows += _run_rows(sol, scales)
    rows.append(("Solve", f"{sol.method}, {duration_text(sol.solve_time)}; "
                          f"accuracy {accuracy_text(sol, scales)}"))
    return rows


def _program_rows(sol: Solution, scales: Scales) -> list[tuple[str, str]]:
    """The stop alone, driven by the overlap program of Fig. 2b."""
    stop = sol.stop
    len_unit, length = scales.length_unit_text, scales.length
    stiffness = (f"k_c0 = {_num(stop.k_c0 * scales.stiffness)} N/m, "
                 f"k_e0 = {_num(stop.k_e0 * scales.stiffness)} N/m" if scales.si else
                 f"k_c0/k = {_num(stop.k_c0)}, k_e0/k = {_num(stop.k_e0)}")
    area = float(np.trapezoid(sol.program.force, sol.program.overlap))
    return [
        ("Scene", "the stop alone, driven by a prescribed overlap (Fig. 2b)"),
        ("Stop", f"{stiffness}, D = {_num(stop.limit_overlap * length)}{len_unit}, beta_c = "
                 f"{_num(stop.beta_c)}, beta_e = {_num(stop.beta_e)}"),
        ("Contact law", CONTACT_LAW_TEXT[stop.law]),
        ("Energy lost", f"{_num(area * scales.energy)}{' J' if scales.si else ' (per unit k)'} "
                        "over the program (loop area)"),
    ]


def _theory_rows(sol: Solution, scales: Scales) -> list[tuple[str, str]]:
    """The paper's closed forms: the regime, the belt against the critical speed, x_max
    without impact, x* (Eqs. 25, 35)."""
    th = sol.theory
    vel_unit = " m/s" if scales.si else ""
    len_unit, length = scales.length_unit_text, scales.length
    equivalent = (" (the theory of the equivalent rigid stop, r_eq = sqrt(k_e0/k_c0), "
                  "Eq. 16)" if isinstance(sol.stop, HystereticStop) else "")
    rows = [("Regime", th.regime.description + equivalent)]
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
                             f"v = v_dr/omega = {_num(v * length, len_unit)} and v* = "
                             f"{_num(th.critical_speed * length, len_unit)} (the paper's "
                             "time t = omega tau)"))
    else:
        rows.append(("Belt", f"{belt}: v = {_num(v)} {rel} "
                             f"v* = {_num(th.critical_speed)} (critical speed, Eq. 25)"))
    rows.append(("x_max impactless", _num(th.x_max_impactless * length, len_unit)))
    if sol.stop is not None and th.restitution < 1.0 and not th.fast:
        rows.append(("x*", f"{_num(th.x_star * length, len_unit)} (Eq. 35 rederived, "
                           f"r = {_ratio(th.restitution)})"))
    return rows


def _run_rows(sol: Solution, scales: Scales) -> list[tuple[str, str]]:
    """What the run found: x_max, the steady state, the restitutions, its status."""
    res = sol.result
    rows = [("x_max simulated", _num(res.x_max * scales.length, scales.length_unit_text))]
    rows += _steady_rows(sol, scales)
    if len(sol.restitution_measured):
        rows.append(("Restitution", _restitution_text(sol)))
    if isinstance(sol.stop, HystereticStop):
        rows.append(("Contact law", CONTACT_LAW_TEXT[sol.stop.law]))
    if res.status is not Status.SUCCESS:
        rows.append(("Status", res.status.message))
    if res.truncated:
        rows.append(("Transitions", f"{res.n_transitions} ({len(res.transitions)} "
                                    "stored: the first ones, then only a reduced "
                                    "model's start, rest or a failed stop)"))
    return rows


def _restitution_text(sol: Solution) -> str:
    """A deformable stop's measured restitutions, first and last, against Eq. 16's."""
    res, th = sol.result, sol.theory
    r_eq = _ratio(th.restitution) if th is not None else "—"
    first, last = restitution_first_last(sol)
    total = contact_count(res, len(sol.restitution_measured))
    # A run that ends on the stop has a last contact without a rebound yet: the
    # restitutions are those of the contacts that ended.
    on_stop = len(res.mode) > 0 and int(res.mode[-1]) == int(Mode.CONTACT)
    ended = total - 1 if on_stop else total
    spread = (f"{_ratio(first)} at the first contact, {_ratio(last)} at the "
              f"last of {ended}" if ended > 1 else f"{_ratio(first)} (one contact)")
    if on_stop:
        spread += (f"{' that ended' if ended > 1 else ''}; contact {total} has not "
                   "ended (the mass stays on the stop)")
    return (f"{spread}; Eq. 16's r_eq = sqrt(k_e0/k_c0) = {r_eq} "
            "holds only for beta * overlap / D >> 1")


def _steady_rows(sol: Solution, scales: Scales) -> list[tuple[str, str]]:
    """The rows of the steady state found: the run's, the force on a rigid stop that holds
    the mass, the transition sequence, and where they differ, the exact method's verdict
    over the same span and the theory's."""
    res = sol.result
    units = _units(scales)
    rows: list[tuple[str, str]] = [("Steady state found", _steady_text(sol, scales))]
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
                     f"{ref.describe(*units)} (over the same span; the {sol.method} method "
                     "finds the steady state above)"))
    return rows + _theory_expects(sol)


def _units(scales: Scales) -> tuple[float, str, float, str, str, float]:
    """The arguments of :meth:`core.Steady.describe` for ``scales``."""
    si = scales.si
    return (scales.time, " s" if si else "", scales.velocity, " m/s" if si else "",
            scales.length_unit_text, scales.length)


def _steady_text(sol: Solution, scales: Scales) -> str:
    """The steady state the run found; a modelled rest's time with its stated bound."""
    res = sol.result
    rest_error = res.info.get("rest_time_error")
    if res.steady.kind is SteadyKind.REST and rest_error is not None:
        # A modelled rest's time is known to its stated bound, not to six digits.
        time_unit = " s" if scales.si else ""
        return (f"rest at the stop (from t = {_num(res.steady.t_reached * scales.time)}"
                f" ± {_num(rest_error * scales.time, time_unit)}, by a reduced model)")
    return res.steady.describe(*_units(scales))


def _theory_expects(sol: Solution) -> list[tuple[str, str]]:
    """The theory's steady state, where it is not the one the run found."""
    th = sol.theory
    if th is None or th.regime.expected_steady == sol.result.steady.kind.value:
        return []
    rigid = ("the equivalent rigid stop" if isinstance(sol.stop, HystereticStop)
             else "this stop")
    return [("Theory expects", f"{th.regime.expected_steady} (the paper's closed forms for "
                               f"{rigid}, which reach it from the natural path, Sec. 4.5)")]


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


#: Transitions at which a rigid stop gives the mass an impulse (Newton's law).
RIGID_IMPACTS = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)


def restitution_first_last(sol: Solution) -> tuple[float, float] | None:
    """Rebound over approach speed at the run's first and last impact or contact, or
    ``None`` without one: a deformable stop's measured ones (its last the core's: the
    stored transitions may end long before the run does, a capped log, a train laid out by
    its map), a rigid stop's from its impacts (Newton's r, Eq. 8).

    >>> from app.state import scene_values
    >>> from app.solve.pool import solve
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
    """What the run's accuracy is, as far as it is known: rounding for a closed form, else
    the error measured for this run against the exact solution, or that it was not
    measured and why. No preset's figure is quoted in its place: none holds on random
    scenes (:data:`app.solve.presets.ACCURACY`). Where a reduced model took over, when (in the
    page's units): its error is in the measured one."""
    if not integrates(sol.method, sol.stop):
        return "closed form, rounding only"
    if sol.error_measured:
        text = (f"{_num(sol.error_estimate)} relative, measured against "
                f"{reference_name(sol.stop)} ({sol.values['accuracy']})")
    elif sol.preview:
        text = "preview, not measured"
    elif sol.measure_skipped:
        text = (f"not measured for this run ({sol.values['accuracy']}): the exact solve it is "
                "measured against would have made the answer late; 'Measure the trade' "
                "measures it")
    else:  # a run with no motion to compare (it stopped at its start)
        text = f"not measured for this run ({sol.values['accuracy']})"
    return text + _reduced_text(sol, scales)


def _reduced_text(sol: Solution, scales: Scales) -> str:
    """Where a reduced model took over a deformable stop's run, and its time of rest."""
    res = sol.result
    if res is None:
        return ""
    reduced = [t.t for t in res.transitions if t.kind is TransitionKind.REDUCED]
    if not reduced:
        return ""
    time_unit = " s" if scales.si else ""
    text = f"; from t = {_num(reduced[0] * scales.time, time_unit)} a reduced model"
    rest_error = res.info.get("rest_time_error")
    if rest_error is not None:
        text += f"; its time of rest within ±{_num(rest_error * scales.time, time_unit)}"
    return text


def pending_text(preview: Mapping[str, Any] | None, values: Mapping[str, Any],
                 shown: Mapping[str, Any], scales: Scales = DIMENSIONLESS) -> str | None:
    """What the readout says above rows that are not those of the values on the sliders:
    a drag's ``preview`` (the phase portrait draws its draft), or committed ``values``
    whose run is being solved, against the values of the run ``shown``; None when the
    rows are the sliders' run. A preview names the parameters dragged, not their values
    (the slider's handle shows its value as it moves): one note for the whole drag.

    >>> from app.state import scene_values
    >>> five_a = scene_values("5a")
    >>> pending_text({**five_a, "restitution": 0.42}, five_a, five_a)
    'Preview of r — release to solve'
    >>> pending_text(None, {**five_a, "restitution": 0.42}, five_a)
    'Not shown yet: r = 0.42 — the rows below are the run before'
    >>> pending_text(None, five_a, five_a) is None
    True
    """
    # The pins' labels name values as the page's boxes do (and app.compare reads the
    # readout's restitutions: imported here, not at the top).
    from app.compare import differences

    if preview is not None and _differ(preview, shown):
        changed = differences(preview, shown, scales) or [("new values", "")]
        return f"Preview of {_named([(name, '') for name, _ in changed])} — release to solve"
    if _differ(values, shown):
        # Said alike while the run is solved and after it failed (the alert says why):
        # either way the rows are the run before.
        changed = differences(values, shown, scales) or [("new values", "")]
        return f"Not shown yet: {_named(changed)} — the rows below are the run before"
    return None


def _differ(values: Mapping[str, Any], shown: Mapping[str, Any]) -> bool:
    return any(shown.get(name) != value for name, value in values.items())


def _named(pairs: list[tuple[str, str]]) -> str:
    return ", ".join(f"{name} = {value}" if value else name for name, value in pairs)


#: The core's plain-text mathematics as a reader sees it in print (the page shows the
#: symbols of its sliders and of the model card; the core's texts stay ASCII).
PRINTED_SYMBOLS = (("<=", "≤"), (">=", "≥"), ("x_bar", GLOSSARY["x_bar"].plain),
                   ("r^h", "rʰ"), ("sqrt(", "√("), ("mu_s", GLOSSARY["mu_s"].plain),
                   ("mu_k", GLOSSARY["mu_k"].plain), ("omega", "ω"))


def printed(text: str) -> str:
    """``text`` with the core's ASCII mathematics in printed symbols.

    >>> printed("a <= x_bar < x*: impact speeds fall as r^h; r_eq = sqrt(k_e0/k_c0)")
    'a ≤ x̄ < x*: impact speeds fall as rʰ; r_eq = √(k_e0/k_c0)'
    """
    for ascii_text, symbol in PRINTED_SYMBOLS:
        text = text.replace(ascii_text, symbol)
    return text


def readout_html(sol: Solution, scales: Scales = DIMENSIONLESS) -> str:
    """The rows as an HTML table (escaped, their mathematics in printed symbols); a long
    row wraps."""
    rows = ((html.escape(k), html.escape(printed(v))) for k, v in readout_rows(sol, scales))
    body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    return f'<table class="fie-readout">{body}</table>'


class Readout(pn.viewable.Viewer):
    """The scene's title and caption, and the readout of the run on screen with the
    comparison of the pinned runs (hidden in the presentation mode, whose plots take its
    room).

    Parameters
    ----------
    compare : app.compare.Compare
        The page's pinned runs (their table follows the readout).
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, compare: Any, **params: Any) -> None:
        super().__init__(**params)
        self.compare = compare
        self.caption = pn.pane.HTML("", sizing_mode="stretch_width",
                                    css_classes=["fie-caption"], stylesheets=[STYLESHEET])
        # Sized to its content, its rows wrapped, never cut; the space it reserves grows
        # with its rows within a scene and is set again only by a new scene: a readout
        # that grew or shrank on a release made BokehJS lay out every figure again (about
        # 60 ms before the new picture showed).
        self.readout = pn.pane.HTML("", sizing_mode="stretch_width",
                                    css_classes=["fie-readout-pane"],
                                    stylesheets=[STYLESHEET, PENDING_CSS])
        self._reserved_for: str | None = None
        #: The rows of the run on screen (the note of a drag or a solve goes above them).
        self._rows = ""
        # After the plots' draw (one message all the same: the page waits for its figures).
        self.state.param.watch(self._show, ["solution", "pinned"], precedence=1)
        self.state.param.watch(self._preview_changed, "preview", precedence=1)
        self.state.param.watch(self._presented, "present")

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Column(self.caption, self.readout, sizing_mode="stretch_width", margin=0)

    def _show(self, *events: param.parameterized.Event) -> None:
        sol = self.state.solution
        if sol is None:
            return
        scales = self.state.scales()
        self._rows = readout_html(sol, scales) + self.compare.table(sol, scales)
        self._pending()
        self._reserve(self._rows.count("<tr>"))
        self.caption.object = caption_html(self.state.scene)

    def _preview_changed(self, event: param.parameterized.Event) -> None:
        """A drag moved or ended. At a release (the values left the run on screen) the
        drag's note stays until the run arrives, which clears it with the new rows, or
        until :data:`SOLVING_NOTE_DELAY_MS` have passed, when it says the run is not shown
        yet."""
        st, sol = self.state, self.state.solution
        if event.new is None and sol is not None and _differ(st.values(), sol.values):
            later(self._pending, SOLVING_NOTE_DELAY_MS)
        else:
            self._pending()

    def _pending(self, *events: param.parameterized.Event) -> None:
        """Mark the rows (greyed, a line above them) while they are not the run of the
        sliders' values: a drag's draft is drawn, or a release's run is being solved (or
        failed). The
        note takes the line the readout keeps spare (:data:`READOUT_SPARE_LINES`)."""
        st, sol = self.state, self.state.solution
        if sol is None:
            return
        note = pending_text(st.preview, st.values(), sol.values, st.scales())
        text = self._rows
        if note is not None:
            # Greyed inside the pane's text: a change of the pane's own classes restyled
            # it and laid the page out again, its figures repainted, at every release.
            text = (f"<div class='fie-pending'><div class='fie-pending-note' role='status'>"
                    f"{html.escape(note)}</div>{text}</div>")
        if self.readout.object != text:
            self.readout.object = text

    def _reserve(self, rows: int) -> None:
        """Keep room for ``rows`` rows (and a wrapped line) below the caption: more rows
        grow the room; a new scene sets it afresh."""
        height = (rows + READOUT_SPARE_LINES) * READOUT_ROW_PX + READOUT_PAD_PX
        scene = self.state.scene
        if scene != self._reserved_for and scene != CUSTOM:
            self._reserved_for = scene
        elif self.readout.min_height is not None and height <= self.readout.min_height:
            return
        set_changed(self.readout, min_height=height)

    def _presented(self, event: param.parameterized.Event) -> None:
        # The readout (and the comparison table in it) gives its room to the plots.
        set_changed(self.readout, visible=not event.new)


def caption_html(scene: str) -> str:
    """The scene's title and what to look at, or a word on custom values."""
    info = SCENES.get(scene)
    if info is None:
        return ("<div class='fie-title'>Custom parameters</div><div>Pick a scene to "
                "return to one of the paper's figures.</div>")
    return (f"<div class='fie-title'>{html.escape(info.title)}</div>"
            f"<div class='fie-look'>{html.escape(info.caption)}</div>")
