"""The permalink: the page's state in its address, and back.

A link naming only a scene loads that scene; parameters given beside it override the scene's
values (README, "Links"). The address is read as text (:mod:`app.links`): no value can fail
in Panel's parser, and a value the page cannot take is named with its allowed range. The
address is rewritten :data:`URL_DELAY_MS` after the state was last changed, so that its round
trip (the browser echoes the new address) does not delay the repaint of a slider release.

:meth:`Permalink.apply_query` and :attr:`Permalink.query` are the page's whole state as a
query string, both ways: what drives a page from outside (a lesson) uses them.
"""

from __future__ import annotations

import json
import math
import urllib.parse
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import panel as pn
import param
from panel.io.location import Location

from app import links, presentation
from app.commit_rules import differs
from app.compare import URL_KEY as PINS_KEY
from app.deferred import Deferred, later
from app.lessons.driver import LESSON_KEYS
from app.scenes import CUSTOM, SCENES
from app.state import (
    LEGACY_LENGTH_UNIT,
    URL_KEYS,
    URL_SI_PARAMS,
    ExplorerState,
    scene_values,
    si_bound_error,
    si_range,
    si_units,
)

#: Delay [ms] of the URL rewrite after the last change of the state.
URL_DELAY_MS = 400
#: Query keys the page reads besides the state's (:data:`URL_KEYS`, by key or by name): the
#: pinned runs, the presentation mode and slide format, and the switch of the browser-side
#: paint shortcuts (static/perf/), and the lesson step (app.lessons).
OTHER_URL_KEYS = frozenset({PINS_KEY, presentation.URL_KEY, presentation.SLIDES_KEY,
                            "paint_shortcuts", *LESSON_KEYS})
#: A state value by its permalink key or its own name.
NAMES: Mapping[str, str] = {**{name: name for name in URL_KEYS},
                            **{key: name for name, key in URL_KEYS.items()}}


class Permalink(pn.viewable.Viewer):
    """The address of one page, kept in step with its state.

    Parameters
    ----------
    notices : app.notices.Notices
        Where refused values are said.
    menu : app.compare_menu.CompareMenu
        The pins and the presentation mode (their own keys of the address).
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, notices: Any, menu: Any, **params: Any) -> None:
        super().__init__(**params)
        self.notices = notices
        self.menu = menu
        #: The page's address (:meth:`sync_url`), or None.
        self.location: Location | None = None
        self._timer: Deferred | None = None

    def __panel__(self) -> pn.viewable.Viewable:
        # No view of its own: the address bar is the browser's.
        return pn.Column()

    # --- address -> state -----------------------------------------------------------------

    def sync_url(self, location: Location | None = None,
                 then: Callable[[Location], None] | None = None) -> None:
        """Load the page from the address of ``location`` (default: the session's,
        :func:`app.links.session_location`), call ``then`` with it (what else the address
        opens, such as a lesson step, over the state it gave), then keep the address in
        step."""
        self.location = loc = location if location is not None else links.session_location()
        if loc is None:
            return
        self.apply_query(loc.search)
        if then is not None:
            then(loc)
        self.state.param.watch(self.url_changed, [*URL_KEYS, "pinned", "present"])
        self.state.param.watch(self._slides_changed, "slides")
        pn.state.onload(self.write_url)

    def apply_query(self, query: str) -> list[str]:
        """Load a page state from a permalink's query string (``scene=7c&r=1``, with or
        without its ``?``): the scene first, then the values given, the pins and the
        presentation. Values the page cannot take are refused and said in the page's
        alert, which stays while the run drawn is the one loaded; returns those messages
        (empty if everything applied)."""
        texts, repeated = links.once(links.query_pairs(query))
        scene = texts.get("scene")
        if scene in SCENES and scene != self.state.scene:
            self.state.load_scene(scene)
        errors, unknown = self._apply_values(texts, repeated)
        errors += self.menu.apply_query(texts)
        if unknown:
            errors.append(links.unknown_message(unknown, URL_KEYS.values()))
        if errors:
            self.notices.show("Some URL parameters could not be applied: " + "; ".join(errors))
            self.notices.keep_while(self.state.values())
        return errors

    def _apply_values(self, texts: Mapping[str, str], repeated: Mapping[str, Sequence[str]]
                      ) -> tuple[list[str], list[str]]:
        """Set the state from the address's values in one batch; return the messages of
        the values refused and the unknown keys."""
        given, values, unparsed, errors, unknown = self._read(texts, repeated)
        good, bad = _checked(values)
        si = good.get("units", self.state.units) == "SI"
        if texts.get("units") == "SI" and "length_unit" not in given:
            # An SI link written before the page had a length unit read its lengths, speeds
            # and forces in metres: it opens the same run, lengths shown in mm.
            good["length_unit"] = LEGACY_LENGTH_UNIT
        errors.extend(self._unparsed_messages(unparsed, good, si))
        if si:
            errors.extend(self._si_values(good, bad))
        good = {name: value for name, value in good.items()
                if value != getattr(self.state, name)}
        # A scene's values changed by the address are no longer that scene: its title and
        # caption would describe another motion (the reset button still returns to it).
        scene = good.get("scene", self.state.scene)
        if scene in SCENES and differs({**self.state.values(), **good}, scene_values(
                scene, accuracy=self.state.accuracy, method=self.state.method)):
            good["scene"] = CUSTOM
        if texts.get("scene") in SCENES or good.get("scene", self.state.scene) != CUSTOM:
            # The figure is that of a custom run: a paper scene named is its own (loaded
            # first, it is the figure a changed value leaves).
            good.pop("figure", None)
        try:
            self.state.param.update(**good)
        except Exception:  # noqa: BLE001 - a combination the state refuses
            bad.update(good)
        refused = [links.refused_message(name, self.state.param[name], given[name])
                   for name in bad if name in given]
        return refused + errors, unknown

    def _read(self, texts: Mapping[str, str], repeated: Mapping[str, Sequence[str]]):
        """The address's keys sorted: ``(given texts, parsed values, unparsed texts,
        messages of repeated keys, unknown keys)``."""
        given, values, unparsed, errors, unknown = {}, {}, {}, [], []
        for key, texts_of_key in repeated.items():
            if key in NAMES or key in OTHER_URL_KEYS:
                errors.append(links.repeated_message(key, NAMES.get(key), texts_of_key))
            else:
                unknown.append(key)
        for key, text in texts.items():
            name = NAMES.get(key)
            if name is None:
                if key not in OTHER_URL_KEYS:
                    unknown.append(key)
                continue
            given[name] = text
            try:
                values[name] = links.parse_value(self.state.param[name], text)
            except ValueError:
                unparsed[name] = text
        return given, values, unparsed, errors, unknown

    def _unparsed_messages(self, unparsed: Mapping[str, str], good: Mapping[str, Any],
                           si: bool) -> list[str]:
        """The messages of values that are no value at all (``tend=true``): in an SI
        address those of :data:`URL_SI_PARAMS` with their SI range."""
        units = _units(good, self.state)
        return [f"{URL_KEYS[name]}: {si_units(*units)[name][0]} must be a number "
                f"in {si_range(name, *units)}; got {links.shown(text)}"
                if si and name in URL_SI_PARAMS
                else links.refused_message(name, self.state.param[name], text)
                for name, text in unparsed.items()]

    def _si_values(self, good: dict[str, Any], bad: dict[str, Any]) -> list[str]:
        """Turn the SI values of an SI address (:data:`URL_SI_PARAMS` in ``good`` and
        ``bad``) into the state's, in place; return the messages of those out of range
        (checked after conversion: their bounds depend on ``m`` and ``k``)."""
        units = _units(good, self.state)
        factors, errors = si_units(*units), []
        for name in URL_SI_PARAMS:
            raw = good.pop(name, bad.get(name))
            if raw is None:
                continue
            bad.pop(name, None)
            value = raw / factors[name][2]
            message = si_bound_error(name, value, *units)
            if message:
                errors.append(f"{URL_KEYS[name]}: {message}")
            elif not math.isclose(value, getattr(self.state, name), rel_tol=1e-11):
                # Within 1e-11 the address is the state's own, written with 12 digits.
                good[name] = value
        return errors

    # --- state -> address -----------------------------------------------------------------

    @property
    def query(self) -> str:
        """The page's state as a permalink's query string (no ``?``): every state value
        (the figure only of a custom run: the one its reset button returns to), and the
        pins and presentation where used."""
        return urllib.parse.urlencode(self._values({}))

    def _values(self, current: Mapping[str, str]) -> dict[str, str | None]:
        """The address's values of the state, beside an address holding ``current``
        (``None``: a key of ``current`` to remove)."""
        st, out = self.state, {}
        si = si_units(st.mass, st.stiffness, st.length_unit) if st.units == "SI" else {}
        for name, key in URL_KEYS.items():
            value = getattr(st, name)
            if name in URL_SI_PARAMS and si:
                # In SI the address says what the boxes say (12 digits: no rounding tail).
                value = float(f"{value * si[name][2]:.12g}")
            value = st.param[name].serialize(value)
            out[key] = value if isinstance(value, str) else json.dumps(value)
        if st.scene != CUSTOM:
            # A paper scene is its own figure: its link has no ``fig`` (one left from a
            # custom run goes).
            fig = URL_KEYS["figure"]
            out.pop(fig)
            if fig in current:
                out[fig] = None
        out.update(self.menu.query(current))
        return out

    def url_changed(self, *events: param.parameterized.Event) -> None:
        """Rewrite the address once the state has been still for :data:`URL_DELAY_MS`."""
        if self._timer is not None:
            self._timer.cancel()
        self._timer = later(self.write_url, URL_DELAY_MS)

    def write_url(self, *events: param.parameterized.Event) -> None:
        """Write the state into the address now (the keys the page does not read stay as
        they came)."""
        self._timer = None
        loc = self.location if self.location is not None else pn.state.location
        if loc is None:
            return
        loc.search = links.merged_search(
            loc.search, self._values(dict(links.query_pairs(loc.search))))

    def _slides_changed(self, event: param.parameterized.Event) -> None:
        if (event.new == "svg") != (event.old == "svg") and self.location is not None:
            # BokehJS picks a figure's drawing backend when it makes its view: the page
            # loads its own permalink again (pins, presentation and all).
            self.location.reload = True
            self.write_url()
            return
        self.url_changed()


def _units(good: Mapping[str, Any], state: ExplorerState) -> tuple[float, float, float]:
    """The mass, stiffness and length unit an address's SI values are read with: its own
    where it gives them (and the state takes them), else the page's."""
    return tuple(good.get(name, getattr(state, name))
                 for name in ("mass", "stiffness", "length_unit"))


def _checked(values: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """``values`` split into those the state takes and those it refuses, each checked on
    its own so that one bad value does not drop the others."""
    good, bad = {}, {}
    for name, value in values.items():
        try:
            ExplorerState(**{name: value})
        except Exception:  # noqa: BLE001 - any rejected value: say which
            bad[name] = value
        else:
            good[name] = value
    return good, bad
