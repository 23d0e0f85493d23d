"""The page's compare menu: one split button whose main part pins the run on screen; its menu
unpins, loads the paper's preset comparisons and switches the presentation mode
(:class:`app.presentation.Presentation`). One Bokeh model whatever it offers; beside it, the
"Present" button (one more) that starts the presentation.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import panel as pn
import param

from app.compare import PIN_LABEL, PRESETS, R_INELASTIC_PRESET, Compare
from app.control_specs import WIDGET_WIDTH
from app.perf.browser_values import say_refused
from app.pins import URL_KEY, PinSpec, decode_pins, encode_pins
from app.state import ExplorerState, scene_values
from app.widgets import on_click

#: The label of the button that starts the presentation (P: its shortcut).
PRESENT_LABEL = "▶ Present (P)"
#: The layout the button starts with.
PRESENT_FIRST = "1"


class CompareMenu(pn.viewable.Viewer):
    """The menu of one page: it pins the state's run into ``compare``.

    Parameters
    ----------
    compare : Compare
        The page's pinned runs.
    presentation : app.presentation.Presentation
        The presentation mode the menu switches.
    notices : app.notices.Notices
        Where a preset that does not apply says why.
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, compare: Compare, presentation: Any, notices: Any,
                 **params: Any) -> None:
        super().__init__(**params)
        self.compare = compare
        self.presentation = presentation
        self.notices = notices
        self.button = pn.widgets.MenuButton(
            label=PIN_LABEL, split=True, items=self._items(), width=WIDGET_WIDTH,
            color="default", css_classes=["fie-compare-menu"])
        on_click(self.button, self._clicked)
        #: Starts the presentation (one large plot; its strip switches the layout).
        self.present = pn.widgets.Button(
            label=PRESENT_LABEL, width=WIDGET_WIDTH, color="primary",
            css_classes=["fie-present-button"])
        on_click(self.present, lambda event: self.presentation.set_mode(PRESENT_FIRST))
        self.state.param.watch(lambda event: self.refresh(), ["pinned", "present", "slides"])

    def __panel__(self) -> pn.viewable.Viewable:
        return self.button

    def _items(self) -> list[tuple[str, str]]:
        items = [(f"Unpin {i + 1}: {label}", f"unpin:{i}")
                 for i, label in enumerate(self.compare.labels(self.state.values()))]
        if items:
            items.append(("Unpin all", "unpin:all"))
        items += [(f"Compare {label}", f"preset:{i}") for i, label in enumerate(PRESETS)]
        items += self.presentation.menu_items()
        return items

    def refresh(self) -> None:
        """The menu's entries for the current pins and mode."""
        items = self._items()
        if items != self.button.items:
            self.button.items = items

    def choose(self, value: str | None) -> None:
        """Do what the menu's entry ``value`` says (``None`` or :data:`PIN_LABEL`: pin the
        run on screen); a value that is no entry of the menu (a script's click) is refused
        in one quiet line."""
        if value not in (PIN_LABEL, None) and value not in dict(self.button.items).values():
            say_refused(f"refused from the browser: menu entry {value!r:.60}")
            return
        st = self.state
        what, _, which = (value or PIN_LABEL).partition(":")
        if value in (PIN_LABEL, None):
            self.compare.pin(st.scene, st.values(), st.mass, st.stiffness)
        elif what == "unpin":
            self.compare.unpin(None if which == "all" else int(which))
        elif what == "preset":
            self.preset(list(PRESETS)[int(which)])
        elif what == "present":
            self.presentation.set_mode(which)
        elif what == "slides":
            self.presentation.set_slides(which)
        self.refresh()

    def _clicked(self, event: Any) -> None:
        self.choose(event.new)

    def preset(self, label: str) -> None:
        """Load a preset comparison: one scene loaded, the other pinned (only it)."""
        st = self.state
        pair = PRESETS[label]
        acc = {"accuracy": st.accuracy, "method": st.method}
        units = (st.mass, st.stiffness)
        if pair is not None:
            loaded, pinned = pair
            st.load_scene(loaded)
            self.compare.set_pins([PinSpec(pinned, scene_values(pinned, **acc), *units)])
            return
        values = st.values()
        if values["stop_type"] != "rigid":
            self.notices.show("r = 1 vs r < 1 compares rigid stops: pick a scene with a "
                              f"rigid stop (this one has stop type {values['stop_type']!r})")
            return
        other = R_INELASTIC_PRESET if values["restitution"] == 1.0 else 1.0
        self.compare.set_pins([PinSpec(st.scene, {**values, "restitution": other}, *units)])

    # --- permalink -------------------------------------------------------------------------

    def apply_query(self, query: Mapping[str, str]) -> list[str]:
        """Pins and presentation mode from the address's text values; returns what was
        refused, in words."""
        st = self.state
        refused = []
        raw = query.get(URL_KEY)
        if raw:
            try:
                pins = decode_pins(raw, st.accuracy, st.method, st.mass, st.stiffness)
            except ValueError as exc:
                refused.append(f"{URL_KEY}: the pinned runs could not be restored: {exc}")
            else:
                self.compare.set_pins(pins)
        refused += self.presentation.apply_query(query)
        self.refresh()
        return refused

    def query(self, current: Mapping[str, Any]) -> dict[str, str]:
        """What the address says of the pins and the presentation (keys only written when
        used, or to clear a value the address holds)."""
        out: dict[str, str] = {}
        if self.compare.pins or URL_KEY in current:
            out[URL_KEY] = encode_pins([p.spec for p in self.compare.pins], self.state.mass,
                                       self.state.stiffness)
        out.update(self.presentation.query(current))
        return out
