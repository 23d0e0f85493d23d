"""Every value of a link opens a working page that names what it refused (app.links).

Panel guessed each query value's type: ``?tend=true`` became a bool, which a slider
refused while the page was built (a white page), and ``?r=true`` silently became 1; a
value of more than 4,300 digits failed in Panel's address parsing (Python's int-string
limit) before the page could say anything. The page now reads the text of each value by
the type of the parameter it sets.
"""

from __future__ import annotations

import html

import panel as pn
import pytest
from panel.io.location import Location

from app import links
from app.compare import decode_pins
from app.explorer import Explorer
from app.state import URL_KEYS, ExplorerState, scene_values

#: Values no number, choice or switch of the page takes: bool words and JSON's other
#: literals, lists and dicts in JSON form, NaN and infinities, numerals whose value
#: overflows, numerals past Python's 4,300-digit int-string limit, the empty text,
#: unicode and Python's numeric spellings that are no decimal numerals.
HOSTILE = ["true", "false", "True", "null", "[1, 2]", '{"a": 1}', "NaN", "nan", "inf",
           "-Infinity", "1e999", "9" * 4400, "", "ünï😀", "1_000", "0x10", "1/2"]
#: Parameters that take a switch: "true" and "false" are theirs.
SWITCHES = {"program", "show_all"}


def _open(search: str, monkeypatch) -> Explorer:
    loc = Location(search=search)
    monkeypatch.setattr(pn.state, "_location", loc)
    ex = Explorer()
    ex.sync_url()
    return ex


@pytest.mark.parametrize("text", HOSTILE, ids=[t[:12] or "empty" for t in HOSTILE])
def test_a_value_of_the_wrong_type_is_refused_by_name(monkeypatch, text):
    """Every key the page reads (README, "Links") given ``text``: each is named with what
    it allows, and none is applied."""
    keys = {name: key for name, key in URL_KEYS.items()
            if not (name in SWITCHES and text.lower() in ("true", "false"))}
    ex = _open(links.merged_search("", dict.fromkeys(keys.values(), text)), monkeypatch)
    shown = html.unescape(ex.alert.object)
    assert ex.alert.visible
    for name, key in keys.items():
        assert f"{key} ({name}) must be {links.allowed(ex.state.param[name])}; got " in shown
    default = ExplorerState()
    for name in URL_KEYS:
        assert getattr(ex.state, name) == getattr(default, name), name  # nothing applied


def test_switches_take_true_and_false_in_any_case(monkeypatch):
    ex = _open("?scene=5a&all=TRUE&prog=false", monkeypatch)
    assert ex.state.show_all is True and ex.state.program is False
    assert not ex.alert.visible


def test_a_repeated_key_is_refused_by_name(monkeypatch):
    """``?r=0.5&r=0.7``: Panel kept the last; which one the link meant is not known."""
    ex = _open("?scene=7c&r=0.5&r=0.7&pins=5a&pins=5b&v=0.05", monkeypatch)
    shown = html.unescape(ex.alert.object)
    assert "r (restitution) must be given once; got 2 values: '0.5', '0.7'" in shown
    assert "pins must be given once" in shown
    assert ex.state.restitution == scene_values("7c")["restitution"]
    assert ex.state.belt_speed == 0.05 and not ex.compare.pins


def test_a_number_past_the_int_digit_limit_does_not_stop_the_location():
    """Panel parses the address whenever the location's ``search`` changes (the browser
    reports it): a 4,400-digit value raised there, on the plain Location."""
    huge = "9" * 4400
    plain = Location()
    with pytest.raises(ValueError, match="4300"):
        plain.search = f"?tend={huge}"
    loc = links.PageLocation()
    loc.search = f"?tend={huge}&v=0.5&x=true"
    assert loc.query_params == {"tend": huge, "v": 0.5, "x": True}


def test_a_huge_value_is_named_and_left_out_of_the_address(monkeypatch):
    """The page reads a 4,400-digit value as text, names it, and writes its own address
    without it (the page of a served session: tests/ui/test_hostile_links.py)."""
    huge = "9" * 4400
    loc = links.PageLocation(search=f"?scene=7c&tend={huge}&present={huge}")
    ex = Explorer()
    ex.sync_url(loc)
    shown = html.unescape(ex.alert.object)
    assert "tend (t_end) must be a number in [0.1, 5000]; got '999" in shown
    assert "(4400 characters)" in shown and "present must be one of" in shown
    assert ex.state.scene == "7c" and ex.state.t_end == scene_values("7c")["t_end"]
    ex.permalink.write_url()
    assert huge not in loc.search and "tend=60.0" in loc.search and "present=0" in loc.search


@pytest.mark.parametrize(("raw", "words"), [
    ("5a,prog=yes", "prog (program) must be true or false; got 'yes'"),
    ("5a,prog=1", "prog (program) must be true or false; got '1'"),
    ("5a,r=nan", "r (restitution) must be a number in [0, 1]; got 'nan'"),
    ("5a,tend=1_000", "tend (t_end) must be a number in [0.1, 5000]; got '1_000'"),
    ("5a,tend=1e999", "got '1e999'"),
    ("5a,tend=" + "9" * 4400, "(4400 characters)"),
    ("5a,r=0.5,r=0.7", "r (restitution) must be given once"),
    ("5a,stop=true", "stop (stop_type) must be one of 'none', 'rigid', 'hysteretic'"),
    ("5a,r=[1]", "got '[1]'"),
    ("5a,r=", "got ''"),
])
def test_the_pin_codec_refuses_what_a_link_refuses(raw, words):
    """A pin's values are read as the link's: ``prog=yes`` silently read as false, and
    ``1_000`` (a Python numeral, no decimal one) as 1000."""
    with pytest.raises(ValueError, match="pin 1") as info:
        decode_pins(raw)
    message = str(info.value)
    assert words in message
    assert len(message) < 400  # a long pin is cut in the message, not echoed whole


def test_the_pin_codec_takes_switches_in_any_case():
    assert decode_pins("5a,stop=hysteretic,prog=TRUE")[0].values["program"] is True


def test_the_refusal_stays_until_the_page_shows_other_values(monkeypatch):
    """A served page's first solution arrives after the address was read, and every
    drawing hid the alert: the refusal flashed and was gone. It stays while the picture is
    of the values the page opened with."""
    ex = _open("?scene=7c&tend=true", monkeypatch)
    ex.host.redraw()  # the first solution, drawn after the address was read
    assert ex.alert.visible and "tend (t_end)" in html.unescape(ex.alert.object)
    ex.controls.commit({"restitution": 0.5})  # the user's own change: its drawing hides it
    assert ex.solution.values["restitution"] == 0.5
    assert not ex.alert.visible
