"""The sidebar's controls: one widget per value of :class:`~app.state.ExplorerState`, the SI
boxes that convert to them, and the rules a value meets on its way in.

Data flow: a slider's ``value`` (while dragging) sets the state's ``preview`` (a draft is
drawn, :mod:`app.plots_host`); its release (or a typed entry) is committed
(:meth:`Controls.commit`): through the constraints (:mod:`app.commit_rules`) into the state
in one batch, which the page's views watch. The controls watch the state in turn and show
what it holds (a scene loaded, a permalink, a tap, a clamp).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import panel as pn
import param

from app import commit_rules
from app.commit_rules import Note, constrained
from app.control_specs import (
    CONSTRAINTS,
    CONTACT_LAW_TIPS,
    HYSTERETIC_SLIDERS,
    METHOD_TIPS,
    MU_S_MIN,
    SHOWN_LATER,
    SI_BOX_SLIDERS,
    SI_SLIDERS,
    SI_SOFT_SPAN,
    SI_START_SLIDERS,
    SI_STATE_NAME,
    SI_TWINS,
    SLIDERS,
    TOOLTIPS,
    WIDGET_WIDTH,
    accuracy_tip,
    reset_label,
)
from app.plot_choice import applicable_plots, show_all_label, visible_plots
from app.scenes import CUSTOM, SCENES
from app.state import (
    ACCURACIES,
    CONTACT_LAWS,
    METHODS,
    MM_PER_M,
    SOLVE_PARAMS,
    STOP_TYPES,
    UNITS,
    VIEW_PARAMS,
    ExplorerState,
    scene_values,
    si_units,
)
from app.teach.glossary import PLAIN
from app.widgets import (
    Checkbox,
    RadioButtonGroup,
    Select,
    ShownLater,
    TypedSlider,
    format_number,
    on_click,
    set_changed,
)

#: The choice widgets and the state value each shows.
CHOICES = ("stop_type", "units", "accuracy", "method", "show_all", "program", "contact_law")
#: The SI names of the mass and stiffness boxes (:meth:`ExplorerState.from_physical`).
SI_OWN = {"mass": "m", "stiffness": "k"}


class Controls(pn.viewable.Viewer):
    """The controls of one page, watching its state."""

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, notices: Any, **params: Any) -> None:
        super().__init__(**params)
        self.notices = notices
        self.sliders: dict[str, TypedSlider] = {}
        self._build_sliders()
        self._build_si_sliders()
        self._build_choices()
        self.state.param.watch(self._show_state, ["scene", "figure", *SOLVE_PARAMS,
                                                  *VIEW_PARAMS])
        self._show_state()

    # --- building ------------------------------------------------------------------------

    def _slider(self, key: str, label: str, value: float, step: float, soft: tuple,
                bounds: tuple, **calls: Any) -> None:
        higher = dict(CONSTRAINTS).get(key)  # the value that bounds this one from above
        self.sliders[key] = TypedSlider(
            label, value, step, soft, bounds, on_release=self._release_arrived,
            width=WIDGET_WIDTH, css_class=f"fie-w-{key}", tooltip=TOOLTIPS[key],
            lazy=key in SHOWN_LATER, ceiling=SLIDERS[higher][0] if higher else "", **calls)

    def _build_sliders(self) -> None:
        st = self.state
        for name, (label, step) in SLIDERS.items():
            p = st.param[name]
            bounds, soft = p.bounds, p.softbounds or p.bounds
            if name == "mu_s":
                bounds, soft = (MU_S_MIN, bounds[1]), (MU_S_MIN, soft[1])
            on_commit = ((lambda v, k=SI_OWN[name]: self.commit_si({k: v}))
                         if name in SI_OWN else (lambda v, n=name: self.commit({n: v})))
            self._slider(name, label, getattr(st, name), step, soft, bounds, name=name,
                         on_drag=lambda v, n=name: self._dragged({n: v}), on_commit=on_commit,
                         validate=lambda v, n=name: commit_rules.refusal(
                             self.state, n, v, self.sliders[n].bounds))

    def _build_si_sliders(self) -> None:
        st = self.state
        phys = st.physical()
        factors = si_units(st.mass, st.stiffness, st.length_unit)
        for name, (label, step, key) in SI_SLIDERS.items():
            value = phys[key]
            state_name = SI_STATE_NAME[key]
            # The state's bounds in SI (moved with m, k and L by _show_si).
            bounds = tuple(b * factors[state_name][2] for b in st.param[state_name].bounds)
            soft = (0.0, max(SI_SOFT_SPAN * value, step))
            if name in SI_TWINS:
                twin = SI_TWINS[name]
                soft = tuple(factors[twin][2] * b for b in st.param[twin].softbounds)
            self._slider(name, label, value, step, soft, bounds, name=label.split(" (")[0],
                         on_drag=lambda v, k=key: self._dragged_si(k, v),
                         on_commit=lambda v, k=key: self.commit_si({k: v}),
                         validate=lambda v, n=name, k=key: commit_rules.refusal_si(
                             self.state, k, v, self.sliders[n].name,
                             self.sliders[n].bounds[0]))

    def _build_choices(self) -> None:
        st = self.state
        self.scene_select = Select(
            label="Scene (paper figure)", value=st.scene, width=WIDGET_WIDTH,
            options={**{SCENES[k].title: k for k in SCENES}, "custom": CUSTOM},
            css_classes=["fie-scene"])
        self.scene_select.param.watch(self._scene_picked, "value")
        self.stop_type = RadioButtonGroup(
            label="Stop", options=list(STOP_TYPES), value=st.stop_type, width=WIDGET_WIDTH,
            color="default", css_classes=["fie-stop-type"])
        self.units = RadioButtonGroup(
            label="Units", options=list(UNITS), value=st.units, width=WIDGET_WIDTH,
            description=si_default_tip())
        self.accuracy = RadioButtonGroup(
            label="Accuracy", options=list(ACCURACIES), value=st.accuracy, width=WIDGET_WIDTH,
            description=accuracy_tip(), css_classes=["fie-accuracy"])
        self.method = Select(
            label="Method", options=list(METHODS), value=st.method, width=WIDGET_WIDTH,
            description="; ".join(f"{k}: {v}" for k, v in METHOD_TIPS.items()) + ".",
            css_classes=["fie-method"])
        self.program = Checkbox(
            label="overlap program (Fig. 2b): the stop alone", value=st.program,
            css_classes=["fie-program"])
        self.reset_button = pn.widgets.Button(
            label=reset_label(st.figure), width=WIDGET_WIDTH, css_classes=["fie-reset"],
            description="Put back every value of the figure last loaded.")
        on_click(self.reset_button, lambda event: self.reset())
        self.show_all = Checkbox(label="show all plots", value=st.show_all)
        # First in the deformable stop's group, and like it in the page once first shown.
        self.contact_law = Select(
            label="Contact law", options=list(CONTACT_LAWS), value=st.contact_law,
            width=WIDGET_WIDTH, css_classes=["fie-contact-law"],
            description="; ".join(f"{k}: {v}" for k, v in CONTACT_LAW_TIPS.items())
                        + ".")
        for name in CHOICES:
            getattr(self, name).param.watch(lambda e, n=name: self._chosen(n, e.new), "value")
        # Groups shown only in some states join the page when first shown (their sliders'
        # widgets are made then).
        self.hysteretic_box = ShownLater(
            self.contact_law, *(self.sliders[n] for n in HYSTERETIC_SLIDERS))
        self.si_box = ShownLater(*(self.sliders[n] for n in SI_BOX_SLIDERS))
        #: The SI twins outside those groups, each in a column of its own.
        self.si_start = {n: ShownLater(self.sliders[n]) for n in SI_START_SLIDERS}

    def sidebar(self) -> list[Any]:
        """The controls, top to bottom, down to the solver's method."""
        w = {name: slider.layout for name, slider in self.sliders.items()
             if name not in SHOWN_LATER}

        def head(text: str) -> pn.pane.HTML:
            return pn.pane.HTML(text, margin=(8, 10, 0, 10))

        return [
            self.scene_select, self.reset_button,
            head("<b>Stop</b>"), self.stop_type, self.program,
            w["clearance"], self.si_start["clearance_si"], w["restitution"],
            self.hysteretic_box,
            head("<b>Belt and friction</b>"), w["belt_speed"], w["mu_s"], w["mu_k"], w["u_s"],
            head("<b>Units</b>"), self.units, self.si_box,
            head("<b>Start and horizon</b> (or click the phase portrait)"),
            w["x0"], self.si_start["x0_si"], w["v0"], self.si_start["v0_si"], w["t_end"],
            self.si_start["t_end_si"],
            head("<b>Solver</b>"), self.accuracy, self.method,
        ]

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Column(*self.sidebar(), self.show_all, width=WIDGET_WIDTH + 30)

    # --- widgets -> state ----------------------------------------------------------------

    def commit(self, changes: Mapping[str, Any]) -> None:
        """A user's final value(s): into the state in one batch (one solve), through the
        constraints (:func:`app.commit_rules.commit_changes`). A commit that changes
        nothing ends a drag's draft (the full run shows again)."""
        changed, notes = commit_rules.commit_changes(self.state, changes)
        for slider in self.sliders.values():  # a note is about the last change only
            if slider.noting and not slider.invalid:
                slider.note("")
        if changed:
            self.state.param.update(preview=None, **changed)
        else:
            self.state.preview = None
        for note in notes:
            self._coupled_note(note)

    def commit_si(self, si: Mapping[str, float]) -> None:
        """A user's final SI value(s): converted, then committed as the state's values."""
        try:
            values = self.state.from_physical(**si)
        except ValueError as exc:
            self.state.param.trigger("stale")
            self.notices.show(str(exc))
            return
        self.commit(values)

    def reset(self) -> None:
        """Every value of the figure last loaded, whatever was typed or refused since."""
        for slider in self.sliders.values():
            slider.clear()
        st = self.state
        if st.scene == st.figure and st.values() == scene_values(
                st.figure, accuracy=st.accuracy, method=st.method):
            self._show_state()
            return
        st.load_scene(st.figure)

    def _chosen(self, name: str, value: Any) -> None:
        if value != getattr(self.state, name):  # not the state's own value shown
            self.commit({name: value})

    def _scene_picked(self, event: param.parameterized.Event) -> None:
        if event.new in SCENES and event.new != self.state.scene:
            self.state.load_scene(event.new)

    def _coupled_note(self, note: Note) -> None:
        """Say that ``note.low`` followed ``note.high`` down, next to the box shown."""
        twin_of = {twin: name for name, twin in SI_TWINS.items()}
        shown = twin_of.get(note.low, note.low) if self.state.units == "SI" else note.low
        slider = self.sliders[shown]
        scale = slider.value / note.now if shown != note.low and note.now else 1.0
        slider.note(f"{slider.name} lowered from {format_number(note.was * scale)} to "
                    f"{format_number(note.now * scale)} to stay ≤ {note.high}")

    def _release_arrived(self) -> None:
        """A slider's release has arrived and will be committed: a draft whose drawing is
        still pending is stale."""
        self.state.param.trigger("stale")

    def _dragged(self, changes: Mapping[str, Any]) -> None:
        """While dragging: the values to draw a draft of (the full run, back at the
        committed values)."""
        changes = {k: v for k, v in changes.items() if k in SOLVE_PARAMS}
        if not changes:
            return
        values = constrained({**self.state.values(), **changes})
        if values.get("program"):
            return
        self.state.preview = None if values == self.state.values() else values

    def _dragged_si(self, key: str, value: float) -> None:
        try:
            values = self.state.from_physical(**{key: value})
        except ValueError:
            return
        self._dragged(values)

    # --- state -> widgets ----------------------------------------------------------------

    def _show_state(self, *events: param.parameterized.Event) -> None:
        """Show the state in the widgets (after a scene, a URL, a tap or a clamp)."""
        self._show_sliders()
        st = self.state
        if st.units == "SI":  # hidden SI boxes catch up when the units change (this runs)
            self._show_si()
        for name in CHOICES:
            set_changed(getattr(self, name), value=getattr(st, name))
        set_changed(self.scene_select, value=st.scene)
        set_changed(self.reset_button, label=reset_label(st.figure))
        set_changed(self.show_all, name=show_all_label(visible_plots(st), applicable_plots(st)))
        self._show_groups()

    def _show_sliders(self) -> None:
        st = self.state
        bounded = {low: getattr(st, high) for low, high in CONSTRAINTS}
        for name, w in self.sliders.items():
            if name in SI_SLIDERS or w.moved_on_from(getattr(st, name)):
                continue
            if name in bounded:  # the lower slider of a constraint ends at the higher value
                top = bounded[name]
                w.set(getattr(st, name), hard_end=top,
                      soft_end=min(st.param[name].softbounds[1], top))
            elif w.value != getattr(st, name):
                w.set(getattr(st, name))

    def _show_si(self) -> None:
        st = self.state
        try:
            phys = st.physical()
        except ValueError:
            return
        twin_of = {twin: name for name, twin in SI_TWINS.items()}
        si_bounded = {twin_of[low]: phys[high] for low, high in CONSTRAINTS
                      if low in twin_of and high in twin_of}
        factors = si_units(st.mass, st.stiffness, st.length_unit)
        for name, (_, step, key) in SI_SLIDERS.items():
            w, value = self.sliders[name], phys[key]
            state_name = SI_STATE_NAME[key]
            low, high = (b * factors[state_name][2] for b in st.param[state_name].bounds)
            if name in si_bounded:  # as in _show_sliders, in SI
                top = si_bounded[name]
                w.set_bounds((low, top))
                w.set(value, soft_end=top)
                continue
            w.set_bounds((low, high))
            if name in SI_TWINS:  # the twin's range in the units of the new m, k, L
                soft_low, soft_high = (factors[SI_TWINS[name]][2] * b
                                       for b in st.param[SI_TWINS[name]].softbounds)
                if math.isclose(w.value, value, rel_tol=1e-12, abs_tol=1e-15):
                    value = w.value  # the box keeps what was typed, not its round trip
                w.set(value, soft_start=soft_low, soft_end=max(soft_high, step))
            elif not math.isclose(w.value, value, rel_tol=1e-12, abs_tol=1e-15):
                w.set(value, soft_end=max(w.end, SI_SOFT_SPAN * value, step))

    def _show_groups(self) -> None:
        """Which widgets the state needs: SI or dimensionless boxes, the stop's."""
        st = self.state
        si = st.units == "SI"
        self.si_box.show(si)
        stop = st.stop_type != "none"
        for name, twin in SI_TWINS.items():
            self.sliders[name].visible = si
            self.sliders[twin].visible = not si
        for name, box in self.si_start.items():
            box.show(si and (stop or name != "clearance_si"))
        self.sliders["u_s"].visible = not si
        self.sliders["belt_speed"].visible = not si
        self.sliders["clearance"].visible = stop and not si
        self.sliders["restitution"].visible = st.stop_type == "rigid"
        self.hysteretic_box.show(st.stop_type == "hysteretic")
        set_changed(self.program, visible=st.stop_type == "hysteretic")


def si_default_tip() -> str:
    """The units' tooltip: what SI shows and its default mass, stiffness and length unit
    (those of :class:`~app.state.ExplorerState`), with the numbers they give a scene.

    >>> si_default_tip()[:66]
    'SI: the scene in seconds, newtons and millimetres, with m = 0.5 kg'
    """
    m, k, length_unit = (ExplorerState.param[name].default
                         for name in ("mass", "stiffness", "length_unit"))
    omega = math.sqrt(k / m)
    mm = length_unit * MM_PER_M
    u_s, f_n = PLAIN["u_s"], PLAIN["F_N"]
    return (f"SI: the scene in seconds, newtons and millimetres, with m = {m:g} kg, "
            f"k = {k:g} N/m and a length unit L = {mm:g} mm by default (a bench rig: "
            f"ω = {omega:.3g} rad/s, a period of {2 * math.pi / omega:.2g} s). A "
            f"dimensionless length of 1 is L: the scenes' {u_s} = 1 is a static deflection of "
            f"{mm:g} mm, a normal force {f_n} = k L {u_s} = {k * length_unit:g} N, and a belt "
            f"speed v = 0.1 is v_dr = ω L v = {omega * length_unit * 0.1:.3g} m/s. "
            "Change m, k and L in the boxes below: a new L resizes the rig, the scene's "
            "dimensionless numbers stay.")
