"""The control strip of the presentation mode: one slim row above the plots to drive the page
from the lectern.

Left to right: the open lesson's step with its Back and Next buttons (a lesson open,
:mod:`app.lessons.stepper`), the scene picker, the two or three sliders that matter for the
scene's stop (:data:`STRIP_SLIDERS`), the layout (one, two, three or four plots), a
fullscreen toggle (the browser's Fullscreen API, run in the browser by the button's own
script), the exit and the keyboard's help under "?". Every widget is a copy linked to the page's
:class:`~app.state.ExplorerState`: a release commits through the page's own commit (its
constraints and notes), and the state's changes move the copies; the sidebar's widgets stay
where they are, hidden while presenting.

The strip is built the first time the page presents (a page that never presents carries none
of it). A lesson's step is its player's: the strip's buttons, like the player's own and its
←/→ keys (:mod:`app.lessons.keys`), ask the player to step, and show the step it shows.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import panel as pn

from app.control_specs import MU_S_MIN, SLIDERS
from app.lessons.stepper import StripStepper
from app.scenes import CUSTOM, SCENES
from app.teach.glossary import PLAIN, SLIDER_SYMBOLS
from app.widgets import on_click, set_changed

#: The sliders of the strip by stop type: the belt speed (a slow or a fast belt, Eq. 25),
#: and the stop's place and restitution (a rigid stop) or limit overlap (a deformable one);
#: without a stop, the static friction and the static deflection u_s = F_N / k.
STRIP_SLIDERS: Mapping[str, tuple[str, ...]] = {
    "none": ("belt_speed", "mu_s", "u_s"),
    "rigid": ("belt_speed", "clearance", "restitution"),
    "hysteretic": ("belt_speed", "clearance", "limit_overlap"),
}
#: Font of the strip's widgets [px]: read by the lecturer a step from the screen and, on the
#: projector, by the room (the figures' tick labels are 18 px in the one-plot layout).
STRIP_FONT_PX = 18
#: Height [px] the strip takes above the plots, its margins included (kept in step with the
#: plots' heights, :data:`app.presentation.STRIP_PX`).
STRIP_HEIGHT_PX = 50
#: The sliders' labels: the paper's symbols, printed as on the sidebar's sliders (the strip
#: holds three on a 1024 px screen; the sidebar's tooltips say what each means).
SYMBOLS: Mapping[str, str] = {
    name: PLAIN[SLIDER_SYMBOLS[name]]
    for name in ("belt_speed", "clearance", "restitution", "mu_s", "u_s", "limit_overlap")}
#: The browser toggles fullscreen (a button's click is the user's gesture the API needs).
FULLSCREEN_JS = """
if (document.fullscreenElement) { document.exitFullscreen() }
else if (document.documentElement.requestFullscreen) {
  document.documentElement.requestFullscreen().catch(() => {})
}
"""
#: The keyboard's shortcuts (static/present.js), in the help under "?".
KEYS_HELP = (
    ("P", "present / leave"), ("1–4", "one, two, three or four plots"),
    ("F", "fullscreen on / off"), ("← →", "lesson steps (a lesson open)"),
    ("?", "this help"),
)
#: The strip's widgets in its font, buttons of a touch's height.
STYLESHEET = f""":host {{ --font-size: {STRIP_FONT_PX}px; font-size: {STRIP_FONT_PX}px; }}
.bk-input, .bk-btn, label, .bk-slider-title {{ font-size: {STRIP_FONT_PX}px !important; }}
.bk-input, .bk-btn {{ min-height: 36px; }}
"""


def help_html() -> str:
    """The keyboard's help: a "?" that opens a short table (a native ``<details>``, reached
    and opened by the keyboard like any button)."""
    rows = "".join(f"<tr><th><kbd>{key}</kbd></th><td>{what}</td></tr>"
                   for key, what in KEYS_HELP)
    return (f'<details class="fie-present-keys" style="font-size:{STRIP_FONT_PX}px">'
            '<summary aria-label="Keyboard shortcuts" title="Keyboard shortcuts" '
            'style="cursor:pointer;font-weight:bold;padding:4px 10px;border:1px solid #888;'
            'border-radius:6px;list-style:none">?</summary>'
            '<table style="position:absolute;right:8px;z-index:10;background:#fff;'
            'white-space:nowrap;width:max-content;border-spacing:8px 4px;'
            'border:1px solid #444;padding:8px;box-shadow:0 2px 8px #0004">'
            f"{rows}</table></details>")


class PresentStrip:
    """The strip of one page (see the module's docstring).

    Parameters
    ----------
    state : ExplorerState
        The page's state.
    commit : callable(dict)
        Commits a user's values (the page's controls' commit).
    set_mode : callable(str)
        Switches the presentation's layout (``""``: leave).
    modes : mapping
        The layouts: key -> what it shows.
    lesson : LessonsMount, optional
        The page's lessons (their ``position`` and ``step``): the strip steps the open one.

    The sliders move the core's dimensionless values, in SI units too (the sidebar's SI
    boxes convert).
    """

    def __init__(self, state: Any, commit: Callable[[Mapping[str, Any]], None],
                 set_mode: Callable[[str], None], modes: Mapping[str, str],
                 lesson: Any = None) -> None:
        self.state, self._commit, self._set_mode = state, commit, set_mode
        st = state
        self.stepper = (StripStepper(lesson.position, lesson.step) if lesson is not None
                        else None)
        self.scene = pn.widgets.Select(
            options={**{SCENES[k].title: k for k in SCENES}, "custom": CUSTOM},
            value=st.scene, sizing_mode="stretch_width", min_width=90, max_width=440,
            margin=(6, 6), stylesheets=[STYLESHEET], css_classes=["fie-present-scene"])
        self.scene.param.watch(self._scene_picked, "value")
        self.sliders = {name: self._slider(name) for name in dict.fromkeys(
            n for names in STRIP_SLIDERS.values() for n in names)}
        self.layouts = pn.widgets.RadioButtonGroup(
            options={k: k for k in modes}, value=st.present or "1", margin=(6, 6),
            stylesheets=[STYLESHEET], css_classes=["fie-present-layouts"],
            description="Plots shown: " + ", ".join(f"{k}: {v}" for k, v in modes.items())
                        + " (keys 1-4)")
        self.layouts.param.watch(self._layout_picked, "value")
        self.fullscreen = pn.widgets.Button(
            label="Fullscreen", margin=(6, 6), stylesheets=[STYLESHEET],
            css_classes=["fie-present-fullscreen"])
        self.fullscreen.js_on_click(code=FULLSCREEN_JS)
        self.exit = pn.widgets.Button(
            label="Exit", margin=(6, 6), color="primary",
            stylesheets=[STYLESHEET], css_classes=["fie-present-exit"])
        on_click(self.exit, lambda event: set_mode(""))
        self.help = pn.pane.HTML(help_html(), margin=(9, 6), css_classes=["fie-present-help"])
        lesson_step = [self.stepper.layout] if self.stepper else []
        self.layout = pn.Row(
            *lesson_step, self.scene, *self.sliders.values(), self.layouts, self.fullscreen,
            self.exit, self.help,
            sizing_mode="stretch_width", height=STRIP_HEIGHT_PX, margin=0,
            css_classes=["fie-present-strip"], styles={"flex": "1 1 100%"})
        st.param.watch(lambda *events: self.show(), ["scene", "present", "stop_type",
                                              *self.sliders])
        self.show()

    def _slider(self, name: str) -> pn.widgets.FloatSlider:
        st = self.state
        p = st.param[name]
        low, high = p.softbounds or p.bounds
        if name == "mu_s":
            low = MU_S_MIN
        value = getattr(st, name)
        step = SLIDERS[name][1]
        slider = pn.widgets.FloatSlider(
            label=SYMBOLS[name], start=min(low, value), end=max(high, value), step=step,
            value=value, sizing_mode="stretch_width", min_width=110, max_width=280,
            margin=(2, 6), stylesheets=[STYLESHEET],
            css_classes=["fie-present-slider", f"fie-present-w-{name}"])
        slider.param.watch(lambda e, n=name: self._released(n, e.new), "value_throttled")
        return slider

    def _released(self, name: str, value: float) -> None:
        if value is not None and value != getattr(self.state, name):
            self._commit({name: value})

    def _layout_picked(self, event: Any) -> None:
        if event.new != self.state.present:
            self._set_mode(event.new)

    def _scene_picked(self, event: Any) -> None:
        if event.new in SCENES and event.new != self.state.scene:
            self.state.load_scene(event.new)

    def show(self) -> None:
        """Show the state: its scene, the sliders of its stop at its values, its layout."""
        st = self.state
        set_changed(self.scene, value=st.scene)
        if st.present:
            set_changed(self.layouts, value=st.present)
        wanted = STRIP_SLIDERS[st.stop_type]
        for name, slider in self.sliders.items():
            value = getattr(st, name)
            if name in wanted and not slider.start <= value <= slider.end:
                slider.param.update(start=min(slider.start, value),
                                    end=max(slider.end, value))
            set_changed(slider, visible=name in wanted, value=value)
        set_changed(self.layout, visible=bool(st.present))
