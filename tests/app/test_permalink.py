"""The permalink's public surface: a page's state as a query string and back
(:meth:`app.permalink.Permalink.apply_query`, :attr:`~app.permalink.Permalink.query`), what
drives a page from outside."""

from __future__ import annotations

import html
import urllib.parse

import pytest
from panel.io.location import Location

from app import links
from app.control_specs import reset_label
from app.explorer import Explorer
from app.scenes import CUSTOM, DEFAULT_SCENE, SCENES
from app.state import SOLVE_PARAMS, VIEW_PARAMS


def test_a_page_s_query_loads_the_same_page_elsewhere():
    """A page in SI units with custom values, a pin and the presentation mode: its query,
    applied to a new page, gives the same state, pins and mode; and that page's own query
    is the same text (the reference: the first page)."""
    first = Explorer()
    first.permalink.apply_query("scene=7c&units=SI&m=2&k=50")
    first.controls.commit({"belt_speed": 0.123})
    first.menu.choose(None)  # pin the run on screen
    first.menu.choose("present:4")
    query = first.permalink.query
    other = Explorer()
    assert other.permalink.apply_query(query) == []
    for name in (*SOLVE_PARAMS, *VIEW_PARAMS, "scene", "present"):
        assert getattr(other.state, name) == getattr(first.state, name), name
    assert [p.spec for p in other.compare.pins] == [p.spec for p in first.compare.pins]
    assert other.permalink.query == query
    assert not other.alert.visible


def test_a_query_s_bad_values_and_keys_are_refused_with_the_page_s_messages():
    ex = Explorer()
    said = ex.permalink.apply_query("?scene=7c&r=2&zz=1&tend=5&tend=6")
    assert ex.state.scene == "7c" and ex.state.restitution == 0.3  # the scene's, kept
    assert len(said) == 3
    assert said[0] == "r (restitution) must be a number in [0, 1]; got '2'"
    assert said[1] == "tend (t_end) must be given once; got 2 values: '5', '6'"
    assert said[2].startswith("unknown key 'zz'")
    shown = html.unescape(ex.alert.object)
    assert ex.alert.visible and all(text in shown for text in said)


def test_the_query_names_every_state_value_by_its_permalink_key():
    ex = Explorer()
    keys = dict(urllib.parse.parse_qsl(ex.permalink.query))
    assert keys["scene"] == ex.state.scene and float(keys["v"]) == ex.state.belt_speed
    assert "pins" not in keys and "present" not in keys  # written only when used


def _reloaded(search: str) -> Explorer:
    """A new page opened at address ``search`` (a reload, or a server restart)."""
    ex = Explorer()
    ex.sync_url(Location(search=search))
    return ex


def test_a_custom_run_s_link_reopens_the_figure_it_came_from():
    """Fig. 7c with a value changed, reloaded from its address: the address did not say
    which figure the custom run came from, and the reset button and captions named the
    default figure (Fig. 5a) instead of the one loaded (the reference: 7c, loaded here)."""
    first = Explorer()
    loc = Location(search="?scene=5b")
    first.sync_url(loc)
    first.state.load_scene("7c")
    first.controls.commit({"belt_speed": 0.123})
    assert first.state.scene == CUSTOM and first.state.figure == "7c"
    first.permalink.write_url()
    other = _reloaded(loc.search)
    assert other.state.scene == CUSTOM and other.state.figure == "7c"
    assert other.state.belt_speed == first.state.belt_speed
    assert other.controls.reset_button.label == reset_label("7c") == "Reset to Fig. 7c"
    assert "custom parameters (from Fig. 7c)" in other.host.presentation.caption()
    assert not other.alert.visible
    assert other.permalink.query == first.permalink.query
    assert dict(links.query_pairs(loc.search))["fig"] == "7c"


def test_a_scene_s_link_carries_no_figure_and_drops_one_left_by_a_custom_run():
    """A paper scene is its own figure: ``fig`` is written beside ``scene=custom`` only,
    and a scene named beside a ``fig`` is the figure (its reset returns to it)."""
    ex = Explorer()
    loc = Location(search="?scene=custom&fig=7c&r=0.5")
    ex.sync_url(loc)
    assert ex.state.figure == "7c"
    ex.state.load_scene("9a")
    ex.permalink.write_url()
    keys = dict(links.query_pairs(loc.search))
    assert keys["scene"] == "9a" and "fig" not in keys
    assert "fig" not in dict(links.query_pairs(Explorer().permalink.query))
    named = _reloaded("?scene=5b&fig=7c&r=0.5")
    assert named.state.scene == CUSTOM and named.state.figure == "5b"
    assert not named.alert.visible


@pytest.mark.parametrize("text", ["8z", "custom", "7C", "", "<b>7c</b>", "7c" * 100])
def test_a_figure_that_is_no_paper_scene_is_refused_by_name(text):
    """``fig`` takes a paper scene's label, nothing else: the page says so with the labels
    allowed and keeps the figure it had; the rest of the link applies."""
    ex = Explorer()
    said = ex.permalink.apply_query(
        "scene=custom&" + urllib.parse.urlencode({"v": "0.2", "fig": text}))
    allowed = "one of " + ", ".join(repr(key) for key in SCENES)
    assert said == [f"fig (figure) must be {allowed}; got {links.shown(text)}"]
    assert ex.alert.visible and said[0] in html.unescape(ex.alert.object)
    assert ex.state.figure == DEFAULT_SCENE and ex.state.belt_speed == 0.2
    assert ex.controls.reset_button.label == reset_label(DEFAULT_SCENE)


def test_a_custom_run_s_link_without_a_figure_still_opens():
    """A link written before it carried the figure opens its run, with the default
    figure (what it opened with then), and says nothing."""
    first = Explorer()
    first.state.load_scene("7c")
    first.controls.commit({"belt_speed": 0.123})
    old = [(k, v) for k, v in urllib.parse.parse_qsl(first.permalink.query) if k != "fig"]
    other = _reloaded("?" + urllib.parse.urlencode(old))
    assert other.state.scene == CUSTOM and other.state.figure == DEFAULT_SCENE
    for name in (*SOLVE_PARAMS, *VIEW_PARAMS):
        assert getattr(other.state, name) == getattr(first.state, name), name
    assert not other.alert.visible
