"""The permalink's public surface: a page's state as a query string and back
(:meth:`app.permalink.Permalink.apply_query`, :attr:`~app.permalink.Permalink.query`), what
drives a page from outside."""

from __future__ import annotations

import html
import urllib.parse

from app.explorer import Explorer
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
