"""Pinned runs: earlier parameter sets kept on the plots as muted ghosts beside the current run.

A pin stores the run's *parameters* (scene and solve values, and the mass and stiffness of
its SI units: :class:`PinSpec`), never its samples: it is solved again in the worker pool
(:class:`app.solve.runner.SolveRunner`), so a permalink that names the pins (:func:`encode_pins`,
:func:`decode_pins`) redraws them on load. Ghost renderers are added to a figure the first
time a pin is drawn on it (:class:`Compare`); a page with no pin holds no model of this
module. The ``*_columns``, label and table functions are pure and
tested without a browser.

Examples
--------
>>> from app.state import scene_values
>>> decode_pins(encode_pins([PinSpec("7c", scene_values("7c"))]))[0].scene
'7c'
>>> pin_label("7c", scene_values("7c"), scene_values("10"))
'7c: stop rigid, r 0.3, t_end 60'
"""

from __future__ import annotations

import html
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from app.export import NAMED, SI_PARAMETERS
from app.glyphs import add_glyph
from app.pins import (  # noqa: F401 - the pins' codec, used with them
    ITEM_SEP,
    MASS,
    MAX_PINS,
    PIN_SEP,
    STIFFNESS,
    URL_KEY,
    PinSpec,
    decode_pins,
    encode_pins,
)
from app.plots import (
    FORCE_TITLE,
    MODE_NAMES,
    force_columns,
    force_quantity,
    loop_columns,
    phase_columns,
    trajectory_columns,
)
from app.readout import restitution_first_last
from app.solve.runner import SolveRunner
from app.solve.solution import Solution
from app.state import (
    DIMENSIONLESS,
    SI_NAMES,
    URL_KEYS,
    Scales,
    si_scales,
)
from app.teach.glossary import BETAS, PLAIN
from core import TransitionKind

#: The pins' colours, in pin order: a violet (the mode bands are chosen so that none,
#: darkened on the black curve's edge, comes near it: app.plots.style), Okabe and Ito's
#: bluish green, a dark grey. CIEDE2000 at least 12.6 from each other and from the modes'
#: blue, orange and red to normal, deuteranope and protanope vision
#: (app.plots.colour_vision); the lilac, teal and tan before were 10.3 apart to a protanope.
PIN_COLORS = ("#8e7cc3", "#009e73", "#555555")
#: Each pin's dash (by its colour): the pins differ in line too, not in colour only.
PIN_DASHES: Mapping[str, str] = dict(zip(PIN_COLORS, ("dashed", "dotdash", "dotted"),
                                         strict=True))
#: Bokeh's named dashes as SVG dash arrays (the legend's and the table's swatches).
SVG_DASHES: Mapping[str, str] = {"dashed": "6 4", "dotdash": "2 3 6 3", "dotted": "2 3"}
#: How a ghost is drawn: its pin's colour and dash, a little thinner than the current run
#: (which stays on top).
GHOST_STYLE: Mapping[str, Any] = {"line_width": 2.0, "line_alpha": 1.0}
#: Parameters named at most in a pin's label (the rest are summed up as "…").
LABEL_ITEMS = 3
#: Names of the parameters in a pin's label, as the page's boxes name them: parameter ->
#: (dimensionless name, SI name); the SI units and factors come from
#: :data:`app.export.SI_PARAMETERS`.
LABEL_NAMES: Mapping[str, tuple[str, str]] = {
    "belt_speed": (PLAIN["v"], SI_NAMES["belt_speed"][1].split()[-1]),
    "u_s": (PLAIN["u_s"], PLAIN["F_N"]), "contact_law": ("law", "law"),
    "k_c0": (f"{PLAIN['k_c0']}/k", PLAIN["k_c0"]), "k_e0": (f"{PLAIN['k_e0']}/k", PLAIN["k_e0"]),
    "beta_c": (BETAS[0],) * 2, "beta_e": (BETAS[1],) * 2,
    **{name: (PLAIN[key],) * 2 for name, key in (
        ("clearance", "x_bar"), ("restitution", "r"), ("mu_s", "mu_s"), ("mu_k", "mu_k"),
        ("limit_overlap", "D"), ("x0", "x0"), ("v0", "v0"), ("t_end", "t_end"))},
}
#: Relative difference below which a label calls two SI values the same (each is the
#: product of a state value and its own unit's factor: equal runs may differ in the last
#: bits).
SAME_RTOL = 1e-9
#: Ghost sources and the figures that draw them: source -> (figure, x column, y column).
GHOSTS: Mapping[str, tuple[tuple[str, str, str], ...]] = {
    "phase": (("phase", "x", "v"),),
    "traj": (("time_x", "t", "x"), ("time_v", "t", "v")),
    "force": (("force", "t", "f"),),
    "loop": (("loop", "d", "phi"),),
}
#: Transition kinds counted as impacts (a deformable stop's contacts count once, at their start).
IMPACT_KINDS = {TransitionKind.IMPACT.value, TransitionKind.STICK_IMPACT.value,
                TransitionKind.CONTACT.value}
#: Preset comparisons of the paper: label -> (scene loaded, scene pinned); ``None``: the
#: current scene with r = 1 loaded and its r < 1 pinned (or the reverse).
PRESETS: Mapping[str, tuple[str, str] | None] = {
    "7c vs 10: rigid stop vs its equivalent deformable stop": ("10", "7c"),
    "7d vs 11: slow belt, mass pressed on a rigid vs a deformable stop": ("11", "7d"),
    "r = 1 vs r < 1 of this scene": None,
}
#: The restitution pinned against an elastic scene by the "r = 1 vs r < 1" preset (the
#: paper's inelastic scenes use 0.3 and 0.7).
R_INELASTIC_PRESET = 0.7


def _f32(a: Any) -> np.ndarray:
    return np.asarray(a, dtype=np.float32)


# --- what a pin shows ----------------------------------------------------------------------

def pin_label(scene: str, values: Mapping[str, Any], current: Mapping[str, Any],
              scales: Scales = DIMENSIONLESS, pin_scales: Scales | None = None) -> str:
    """A short label: the pin's scene and the parameters in which it differs from the
    current run (those its stop type uses), at most :data:`LABEL_ITEMS` of them, named as
    the page's boxes name them. In SI units (``scales``: the current run's,
    ``pin_scales``: the pin's own, :meth:`Pin.scales`) the physical values are compared,
    the mass and stiffness first.

    >>> from app.state import scene_values, si_scales
    >>> pin_label("5b", scene_values("5b"), scene_values("5b"))
    '5b: same parameters'
    >>> si = si_scales(2.0, 50.0, 1.0)
    >>> pin_label("5a", scene_values("5a"), {**scene_values("5a"), "belt_speed": 0.3}, si)
    '5a: v_dr 0.5 m/s'
    >>> pin_label("6b", scene_values("6b"), scene_values("5a"), si)
    '6b: v_dr 1.5 m/s, x̄ 100 mm, r 0.7'
    >>> pin_label("5a", scene_values("5a"), scene_values("5a"), si, si_scales(1.0, 50.0, 1.0))
    '5a: m 1 kg, v_dr 0.7071 m/s, t_end 8.485 s'
    """
    pin_scales = scales if pin_scales is None else pin_scales
    stop = str(values["stop_type"])
    names = ("stop_type", *(("mass", "stiffness") if scales.si else ()),
             *NAMED.get(stop, NAMED["none"]), "program")
    diff = [" ".join(part for part in pair if part)
            for pair in differences(values, current, scales, pin_scales, names)]
    if not diff:
        diff = ["same parameters"]
    more = ", …" if len(diff) > LABEL_ITEMS else ""
    return f"{scene}: {', '.join(diff[:LABEL_ITEMS])}{more}"


def differences(values: Mapping[str, Any], current: Mapping[str, Any],
                scales: Scales = DIMENSIONLESS, own_scales: Scales | None = None,
                names: Sequence[str] | None = None) -> list[tuple[str, str]]:
    """The parameters of ``values`` (in ``own_scales``) that differ from ``current`` (in
    ``scales``), as the page's boxes name them: ``(name, value with its unit)`` pairs, of
    ``names`` (by default those the stop type of ``values`` uses).

    >>> from app.state import scene_values
    >>> differences({**scene_values("5a"), "restitution": 0.42}, scene_values("5a"))
    [('r', '0.42')]
    """
    own_scales = scales if own_scales is None else own_scales
    if names is None:
        names = NAMED.get(str(values["stop_type"]), NAMED["none"])
    diff = []
    for name in names:
        mine, text = _shown(name, values, own_scales)
        theirs, _ = _shown(name, current, scales)
        if not _same(mine, theirs):
            diff.append(text)
    return diff


def _shown(name: str, values: Mapping[str, Any],
           scales: Scales) -> tuple[Any, tuple[str, str]]:
    """A parameter of a run as its label shows it: its value in the units of ``scales``
    and ``(name, value unit)`` (SI units and factors: :data:`app.export.SI_PARAMETERS`)."""
    if name in ("mass", "stiffness"):
        value = getattr(scales, name)
        unit = "kg" if name == "mass" else "N/m"
        return value, (URL_KEYS[name], f"{_short(value)} {unit}")
    value = values.get(name)
    if name == "stop_type":
        return value, ("stop", str(value))
    if name == "program":
        return bool(value), ("overlap program" if value else "no overlap program", "")
    dimensionless, si_name = LABEL_NAMES[name]
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value, (dimensionless, str(value))
    value = float(value)
    if not scales.si:
        return value, (dimensionless, _short(value))
    _, factor, unit = SI_PARAMETERS.get(name, (si_name, None, ""))
    value *= getattr(scales, factor) if factor else 1.0
    return value, (si_name, f"{_short(value)}{' ' + unit if unit else ''}")


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return math.isclose(a, b, rel_tol=SAME_RTOL)
    return a == b


def _short(value: Any) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def ghost_columns(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, dict]:
    """The columns of a pin's ghosts: the phase path (one line, the modes joined), the
    time histories, the contact force (a rigid stop's impulses as stems of one broken
    line) and the hysteresis loop."""
    empty = {"x": _f32([]), "v": _f32([])}
    out: dict[str, dict] = {"phase": empty, "traj": {"t": _f32([]), **empty},
                            "force": {"t": _f32([]), "f": _f32([])},
                            "loop": {"d": _f32([]), "phi": _f32([])}}
    if sol.result is not None:
        phase = phase_columns(sol, scales)
        xs, vs = [], []
        for name in MODE_NAMES.values():
            if len(phase[name]["x"]):
                xs += [phase[name]["x"], [np.nan]]
                vs += [phase[name]["v"], [np.nan]]
        if xs:
            out["phase"] = {"x": _f32(np.concatenate(xs)), "v": _f32(np.concatenate(vs))}
        traj = trajectory_columns(sol, scales)
        out["traj"] = {k: traj[k] for k in ("t", "x", "v")}
    force = force_columns(sol, scales)
    stems = force["stems"]
    if len(stems["t"]):
        n = len(stems["t"])
        t = np.column_stack([stems["t"], stems["t"], np.full(n, np.nan)]).ravel()
        f = np.column_stack([np.zeros(n), stems["j"], np.full(n, np.nan)]).ravel()
        out["force"] = {"t": _f32(t), "f": _f32(f)}
    elif len(force["line"]["t"]):
        out["force"] = {"t": force["line"]["t"], "f": force["line"]["phi"]}
    out["loop"] = dict(loop_columns(sol, scales)["loop"])
    return out


def ghost_extents(cols: Mapping[str, Mapping[str, Any]]
                  ) -> dict[tuple[str, str], tuple[float, float]]:
    """What a pin's ghosts (:func:`ghost_columns`) span on each figure's axes:
    ``(figure, "x" or "y") -> (min, max)``, finite values only (the time histories' two
    figures share their time axis, the phase portrait fits its own in the browser).

    >>> ghost_extents({"traj": {"t": [0.0, 2.0], "x": [1.0, np.nan], "v": []}})
    {('time_x', 'x'): (0.0, 2.0), ('time_x', 'y'): (1.0, 1.0), ('time_v', 'x'): (0.0, 2.0)}
    """
    out: dict[tuple[str, str], tuple[float, float]] = {}
    for source, targets in GHOSTS.items():
        if source not in cols:
            continue
        for fig, *columns in targets:
            for axis, column in zip("xy", columns, strict=True):
                a = np.asarray(cols[source][column], dtype=float)
                a = a[np.isfinite(a)]
                if len(a):
                    out[(fig, axis)] = (float(a.min()), float(a.max()))
    return out


def summary(sol: Solution, scales: Scales = DIMENSIONLESS) -> dict[str, str]:
    """What the comparison table shows of a run: steady state, period, x_max, impacts per
    period and the restitution measured (rebound over approach speed) at the first and the
    last impact or contact, one number where they agree to the digits shown.

    >>> from app.state import scene_values
    >>> from app.solve.pool import solve
    >>> summary(solve(scene_values("10")))["restitution"]
    '0.399 / 0.969'
    """
    res = sol.result
    if res is None:
        return {"steady": "overlap program", "period": "—", "x_max": "—", "impacts": "—",
                "restitution": "—"}
    steady = res.steady
    unit = " s" if scales.si else ""
    period = (f"{steady.period * scales.time:.4g}{unit}"
              if steady.kind.value == "periodic" and math.isfinite(steady.period) else "—")
    impacts = (str(sum(k in IMPACT_KINDS for k in steady.sequence))
               if steady.kind.value == "periodic" else "—")
    ends = restitution_first_last(sol)
    restitution = "—"
    if ends is not None:
        first, last = (f"{r:.3g}" for r in ends)
        restitution = first if first == last else f"{first} / {last}"
    return {"steady": steady.kind.value.replace("_", " "), "period": period,
            "x_max": f"{res.x_max * scales.length:.4g}{scales.length_unit_text}",
            "impacts": impacts,
            "restitution": restitution}


#: Rows of the comparison table: summary key -> row label.
TABLE_ROWS = (("steady", "steady state"), ("period", "period"), ("x_max", "x_max"),
              ("impacts", "impacts / period"),
              ("restitution", "restitution, first / last contact"))


def swatch(color: str) -> str:
    """A line in a pin's ``color`` and dash (:data:`PIN_DASHES`): how its ghost is drawn."""
    dash = SVG_DASHES[PIN_DASHES.get(color, "dashed")]
    return (f'<svg width="26" height="10" aria-hidden="true" style="vertical-align:0">'
            f'<line x1="1" y1="5" x2="25" y2="5" stroke="{color}" stroke-width="2.5" '
            f'stroke-dasharray="{dash}"/></svg>')


def comparison_html(current: Solution,
                    pinned: Sequence[tuple[str, str, Solution | None, Scales]],
                    scales: Scales = DIMENSIONLESS) -> str:
    """The current run and each pin side by side (one column each); ``pinned`` holds
    ``(label, colour, solution or None while it is solved, the pin's own units)``."""
    cols = [("this run", "", summary(current, scales))]
    for label, color, sol, own in pinned:
        cols.append((label, color, summary(sol, own) if sol is not None else None))
    head = "".join(f"<th class='fie-pin-head'>{swatch(c) if c else ''}{html.escape(lab)}</th>"
                   for lab, c, _ in cols)
    body = ""
    for key, row in TABLE_ROWS:
        cells = "".join(f"<td>{html.escape(s[key]) if s else 'solving…'}</td>"
                        for _, _, s in cols)
        body += f"<tr><th>{row}</th>{cells}</tr>"
    return (f"<table class='fie-readout fie-compare'><tr><th>compared</th>{head}</tr>"
            f"{body}</table>")


# --- the session's pins --------------------------------------------------------------------

@dataclass
class Pin:
    """One pinned run: its scene and solve values, the mass m [kg] and stiffness k [N/m]
    it was pinned with (:class:`PinSpec`), its colour, and its solution once solved."""

    scene: str
    values: dict[str, Any]
    mass: float
    stiffness: float
    color: str
    solution: Solution | None = None
    runner: SolveRunner | None = field(default=None, repr=False)

    @property
    def spec(self) -> PinSpec:
        return PinSpec(self.scene, self.values, self.mass, self.stiffness)

    def scales(self, page: Scales) -> Scales:
        """The pin's own units on a page in ``page``'s: SI with its own m and k (its
        seconds, m/s and newtons are those of the run pinned) and the page's length unit,
        or dimensionless."""
        return (si_scales(self.mass, self.stiffness, page.length_unit) if page.si
                else DIMENSIONLESS)


class Compare:
    """The pinned runs of one session and their ghost renderers.

    Parameters
    ----------
    plots : PlotSet
        The session's figures (ghosts are added to those built, when first needed).
    on_change : callable()
        Called on the event loop when a pin's solution arrives or a pin goes (the page
        redraws the table, the legend and the permalink).
    on_failed : callable(Exception)
        A pin's solve failed (its message is shown; the pin is dropped).
    """

    def __init__(self, plots: Any, on_change: Callable[[], None],
                 on_failed: Callable[[Exception], None]) -> None:
        self.plots = plots
        self.on_change = on_change
        self.on_failed = on_failed
        self.pins: list[Pin] = []
        #: Per pin slot: source name -> ColumnDataSource (made on the slot's first use).
        self._sources: list[dict[str, Any]] = []
        #: (slot, figure name) pairs that have their ghost renderer.
        self._drawn: set[tuple[int, str]] = set()
        self._renderers: dict[tuple[int, str], Any] = {}
        self._scales: Scales = DIMENSIONLESS
        #: Per pin slot: what its ghosts span, ``(figure, "x" or "y") -> (min, max)``.
        self._extents: list[dict[tuple[str, str], tuple[float, float]]] = []
        #: What the contact-force plot says of the pins it does not draw.
        self.force_note = ""

    @property
    def full(self) -> bool:
        return len(self.pins) >= MAX_PINS

    def pin(self, scene: str, values: Mapping[str, Any], mass: float,
            stiffness: float) -> None:
        """Pin a run: its scene, solve values, and the page's mass m [kg] and stiffness k
        [N/m] (the oldest pin goes when :data:`MAX_PINS` are pinned)."""
        if self.full:
            self.pins.pop(0)
        used = {p.color for p in self.pins}
        color = next(c for c in PIN_COLORS if c not in used)
        pin = Pin(scene, dict(values), float(mass), float(stiffness), color)
        self.pins.append(pin)
        self._solve(pin)

    def set_pins(self, pins: Sequence[PinSpec]) -> None:
        """Replace every pin (a permalink, a preset)."""
        for pin in self.pins:
            if pin.runner is not None:
                pin.runner.cancel()
        self.pins = []
        for spec in pins[-MAX_PINS:]:
            self.pin(*spec)
        if not pins:
            self.on_change()

    def unpin(self, index: int | None = None) -> None:
        """Drop pin ``index`` (0-based), or all pins."""
        drop = list(range(len(self.pins))) if index is None else [index]
        for i in sorted(drop, reverse=True):
            if 0 <= i < len(self.pins):
                pin = self.pins.pop(i)
                if pin.runner is not None:
                    pin.runner.cancel()
        self.on_change()

    def resolve(self, accuracy: str, method: str) -> None:
        """Solve every pin again with the page's accuracy and method (when they change)."""
        for pin in self.pins:
            if (pin.values["accuracy"], pin.values["method"]) != (accuracy, method):
                pin.values.update(accuracy=accuracy, method=method)
                self._solve(pin)

    def _solve(self, pin: Pin) -> None:
        def failed(exc: Exception) -> None:
            if pin in self.pins:
                self.pins.remove(pin)
            self.on_failed(exc)
            self.on_change()

        def solved(sol: Solution) -> None:
            if pin in self.pins:
                pin.solution = sol
                self.on_change()

        pin.solution = None
        pin.runner = SolveRunner(failed)
        pin.runner.request(pin.values, solved)

    # --- drawing ---------------------------------------------------------------------------

    def labels(self, current: Mapping[str, Any], scales: Scales | None = None) -> list[str]:
        """Each pin's label against the current values (in the units last drawn in)."""
        scales = self._scales if scales is None else scales
        return [pin_label(p.scene, p.values, current, scales, p.scales(scales))
                for p in self.pins]

    def legend_entries(self, current: Mapping[str, Any]) -> list[tuple[str, str, str]]:
        """Entries for an HTML legend (:func:`app.plots.legend_html`)."""
        return [(f"pinned {label}", swatch(p.color),
                 "a pinned run, solved again from its parameters")
                for label, p in zip(self.labels(current), self.pins, strict=True)]

    def table(self, current: Solution, scales: Scales) -> str:
        """The comparison table, or '' with no pin."""
        if not self.pins:
            return ""
        rows = [(label, p.color, p.solution, p.scales(scales))
                for label, p in zip(self.labels(current.values, scales), self.pins,
                                    strict=True)]
        return comparison_html(current, rows, scales)

    def draw(self, current: Solution, scales: Scales) -> None:
        """Put every pin's ghosts, in its own units (:meth:`Pin.scales`), on the built
        figures and blank the unused slots (call under ``pn.io.hold``). Adds renderers only
        where a pin is drawn. A pin whose contact-force plot shows another quantity than
        the ``current`` run's (:func:`app.plots.force_quantity`: impulses, a force) is not
        drawn there; the plot says so."""
        from app.plots import assign  # one rule for "assign only what changed"

        self._scales = scales
        notes = []
        shown = force_quantity(current)
        for slot in range(max(len(self.pins), len(self._sources))):
            pin = self.pins[slot] if slot < len(self.pins) else None
            cols = None
            if pin is not None and pin.solution is not None:
                cols = ghost_columns(pin.solution, pin.scales(scales))
                own = force_quantity(pin.solution)
                if own != shown and len(cols["force"]["t"]):
                    notes.append(f"{pin.scene}: {own}, not comparable with {shown}: "
                                 "not drawn")
                    cols["force"] = {k: _f32([]) for k in cols["force"]}
            if cols is None and slot >= len(self._sources):
                continue
            sources = self._slot_sources(slot)
            for name, source in sources.items():
                assign(source, cols[name] if cols is not None
                        else {k: [] for k in source.data})
            self._extents[slot] = ghost_extents(cols) if cols is not None else {}
            if pin is not None:
                self._attach(slot, pin.color)
        self.force_note = "\n".join(notes)
        self._show_note()

    def _show_note(self) -> None:
        """The contact-force plot's note on the pins it does not draw: a second line of
        its title (a title added to a figure on screen is laid out by BokehJS before its
        view exists)."""
        fig = self.plots.figures.get("force")
        if fig is None:
            return
        text = FORCE_TITLE + (f"\n{self.force_note}" if self.force_note else "")
        if fig.title.text != text:
            fig.title.text = text

    def extents(self) -> dict[tuple[str, str], list[float]]:
        """What the drawn ghosts span, for the axes (:attr:`app.plots.PlotSet.more_extents`):
        ``(figure, "x" or "y") -> [min, max, min, max, ...]`` over the pins."""
        out: dict[tuple[str, str], list[float]] = {}
        for slot in range(min(len(self.pins), len(self._extents))):
            for key, bounds in self._extents[slot].items():
                out.setdefault(key, []).extend(bounds)
        return out

    def attach_all(self) -> None:
        """Give figures built since the last draw the ghosts of the current pins."""
        for slot, pin in enumerate(self.pins):
            if slot < len(self._sources):
                self._attach(slot, pin.color)
        self._show_note()

    def _slot_sources(self, slot: int) -> dict[str, Any]:
        while len(self._sources) <= slot:
            self._extents.append({})
            source = self.plots.shared.source
            self._sources.append({
                "phase": source({"x": [], "v": []}),
                "traj": source({"t": [], "x": [], "v": []}),
                "force": source({"t": [], "f": []}),
                "loop": source({"d": [], "phi": []}),
            })
        return self._sources[slot]

    def _attach(self, slot: int, color: str) -> None:
        figs = self.plots.figures
        for source, targets in GHOSTS.items():
            for fig_name, x, y in targets:
                key = (slot, fig_name)
                if fig_name not in figs:
                    continue
                if key not in self._drawn:
                    fig = figs[fig_name]
                    r = add_glyph(fig, "line", x, y, source=self._sources[slot][source],
                                  line_color=color, line_dash=PIN_DASHES[color],
                                  **GHOST_STYLE)
                    # Drawn under the current run, over the mode bands and references.
                    fig.renderers = _under_current(fig.renderers, r, self.plots.sources)
                    r.view.filter = self.plots.shared.filter
                    if fig_name == "phase":
                        # The portrait's equal-aspect ranges are fitted in the browser to
                        # the renderers they list: a far-off pin is not clipped.
                        for rng in (fig.x_range, fig.y_range):
                            if getattr(rng, "renderers", None):
                                rng.renderers = [*rng.renderers, r]
                    self._drawn.add(key)
                    self._renderers[key] = r
                elif self._renderers[key].glyph.line_color != color:
                    self._renderers[key].glyph.update(line_color=color,
                                                      line_dash=PIN_DASHES[color])

    def ghost_source(self, slot: int, name: str) -> Any:
        """The source of pin slot ``slot``'s ghost ``name`` (a key of :data:`GHOSTS`)."""
        return self._sources[slot][name]

    def ghost_renderer(self, slot: int, figure: str) -> Any:
        """The renderer of pin slot ``slot``'s ghost on ``figure`` (None if not drawn)."""
        return self._renderers.get((slot, figure))

    @property
    def renderer_count(self) -> int:
        """Ghost renderers built so far (none on a page never pinned)."""
        return len(self._renderers)


# --- the page's menu -----------------------------------------------------------------------

#: The menu's button label (its main part pins the run on screen).
PIN_LABEL = "Pin this run"


def _under_current(renderers: list, ghost: Any, sources: Mapping[str, Any]) -> list:
    """``renderers`` with ``ghost`` (the last) moved before the first that draws the
    current run (its path, time histories, force or loop)."""
    current = {id(sources[n]) for n in (*(f"path_{m}" for m in MODE_NAMES.values()),
                                        "traj", "stems", "force", "loop")}
    rest = [r for r in renderers if r is not ghost]
    for i, r in enumerate(rest):
        if id(getattr(r, "data_source", None)) in current:
            return [*rest[:i], ghost, *rest[i:]]
    return [*rest, ghost]
