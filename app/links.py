"""The page's address, read as text by the page itself: no value of a link can stop the page.

Panel reads an address's query by guessing each value's type (``panel.util.parse_query``):
``true`` becomes a bool, which a ``param.Number`` takes as 1 and a slider refuses; ``[1]``
becomes a list; a value of more than 4,300 digits becomes an ``int``, which Python refuses to
convert (its integer-string limit), and that refusal escaped from the session's
:class:`~panel.io.location.Location` while the page was built, so the page stayed blank.

Here the query is split into its raw text values (:func:`query_pairs`, :func:`once`), and
each value the page reads is parsed by the type of the parameter it sets
(:func:`parse_value`): a number is a decimal numeral with a finite value, a choice one of its
names, a switch ``true`` or ``false``. Anything else is refused with a message naming the
parameter and what it allows. The session's location (:func:`session_location`) is a
:class:`PageLocation`, whose ``query_params`` keep a value they cannot convert as its text,
so that Panel's own reading of the address (when it watches the location) cannot fail
either.

Examples
--------
>>> once(query_pairs("?tend=10&v=0.1&v=0.2&x="))
({'tend': '10', 'x': ''}, {'v': ['0.1', '0.2']})
>>> parse_number("1e3"), parse_number(" 0.5 ")
(1000.0, 0.5)
"""

from __future__ import annotations

import math
import re
import urllib.parse
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import panel as pn
import param
from panel.io.location import Location
from panel.util import parse_query

from app.state import URL_KEYS

#: A decimal numeral (the page writes its numbers so): no ``nan``, ``inf``, ``0x``, ``1_0``.
NUMERAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
#: A switch's words (as Panel and the page write them; any case).
TRUE_WORDS, FALSE_WORDS = ("true",), ("false",)


class PageLocation(Location):
    """The session's location (public :class:`panel.io.location.Location`), whose
    ``query_params`` never fail: a value Panel's parser cannot convert (a numeral of more
    than 4,300 digits) is kept as its text.

    Panel reads ``query_params`` whenever the address changes (it watches the location's
    ``search``), the browser's first report of its address included; on the plain
    ``Location`` such a value raised there, before the page could say anything.
    """

    @property
    def query_params(self) -> dict[str, Any]:
        try:
            return super().query_params
        except ValueError:
            return {key: _panel_value(key, text) for key, text in query_pairs(self.search)}


def _panel_value(key: str, text: str) -> Any:
    """Panel's reading of one value, or its text where Panel's reading fails."""
    try:
        return parse_query("?" + urllib.parse.urlencode({key: text}))[key]
    except (ValueError, KeyError):
        return text


def session_location() -> Location | None:
    """The location of the session being built: a :class:`PageLocation` made from the
    session's request (hand it to ``server_doc(location=...)``), or, outside a served
    session, Panel's (``pn.state.location``)."""
    doc = pn.state.curdoc
    context = doc.session_context if doc is not None else None
    if context is None or getattr(context, "request", None) is None:
        return pn.state.location
    return PageLocation.from_request(context.request)


def query_pairs(search: str) -> list[tuple[str, str]]:
    """The ``(key, text)`` pairs of a query string (``?a=1&b=``), in order, percent-decoded,
    empty values kept.

    >>> query_pairs("?a=1&b=&c=%3Cb%3E&d=x+y")
    [('a', '1'), ('b', ''), ('c', '<b>'), ('d', 'x y')]
    """
    return urllib.parse.parse_qsl(search.removeprefix("?"), keep_blank_values=True)


def once(pairs: Sequence[tuple[str, str]]) -> tuple[dict[str, str], dict[str, list[str]]]:
    """The keys given once with their text, and those given more than once with all of
    theirs (a link gives each key once: which of them it meant is not known)."""
    seen: dict[str, list[str]] = {}
    for key, text in pairs:
        seen.setdefault(key, []).append(text)
    return ({key: texts[0] for key, texts in seen.items() if len(texts) == 1},
            {key: texts for key, texts in seen.items() if len(texts) > 1})


def merged_search(search: str, values: Mapping[str, str | None]) -> str:
    """``search`` with ``values`` set (a key kept in its place, a new one appended, a
    repeated one given once, one set to ``None`` removed); the other keys stay as they
    came.

    >>> merged_search("?a=1&zz=9&a=2&c=0", {"a": "3", "b": "x y", "c": None})
    '?a=3&zz=9&b=x+y'
    """
    merged = dict(query_pairs(search))
    merged.update(values)
    return "?" + urllib.parse.urlencode({k: v for k, v in merged.items() if v is not None})


def parse_number(text: str) -> float:
    """The finite number a decimal numeral ``text`` stands for (surrounding spaces allowed);
    raises ``ValueError`` for anything else (``nan``, ``inf``, ``true``, ``[1]``, a numeral
    whose value overflows).

    >>> parse_number("-2.5e-3")
    -0.0025
    >>> parse_number("1e999")
    Traceback (most recent call last):
    ...
    ValueError: not a finite decimal number
    """
    text = text.strip()
    if NUMERAL.fullmatch(text):
        value = float(text)  # a float, never an int: no digit limit
        if math.isfinite(value):
            return value
    raise ValueError("not a finite decimal number")


def parse_value(p: param.Parameter, text: str) -> Any:
    """The value of parameter ``p`` that a link's ``text`` stands for; raises
    ``ValueError`` if it stands for none (the caller names the parameter and
    :func:`allowed`).

    >>> from app.state import ExplorerState
    >>> parse_value(ExplorerState.param.t_end, "12"), parse_value(ExplorerState.param.units, "SI")
    (12.0, 'SI')
    >>> parse_value(ExplorerState.param.program, "TRUE")
    True
    >>> parse_value(ExplorerState.param.t_end, "true")
    Traceback (most recent call last):
    ...
    ValueError: not a finite decimal number
    """
    if isinstance(p, param.Boolean):
        word = text.strip().lower()
        if word in TRUE_WORDS + FALSE_WORDS:
            return word in TRUE_WORDS
        raise ValueError("not true or false")
    if isinstance(p, param.Number):
        return parse_number(text)
    if isinstance(p, param.Selector):
        if text in [str(o) for o in p.objects]:
            return next(o for o in p.objects if str(o) == text)
        raise ValueError("not one of the choices")
    raise ValueError(f"a link cannot set {p.name}")


def allowed(p: param.Parameter) -> str:
    """What parameter ``p`` accepts, in words.

    >>> from app.state import ExplorerState
    >>> allowed(ExplorerState.param.restitution), allowed(ExplorerState.param.units)
    ('a number in [0, 1]', "one of 'dimensionless', 'SI'")
    """
    if isinstance(p, param.Boolean):
        return "true or false"
    if isinstance(p, param.Number):
        low, high = p.bounds
        return f"a number in [{low:g}, {high:g}]"
    if isinstance(p, param.Selector):
        return "one of " + ", ".join(repr(o) for o in p.objects)
    return "a valid value"


#: Characters of a refused value shown in a message (a long value is cut, and says so).
SHOWN_CHARS = 60
#: Unknown keys named in a message at most (the others are counted).
SHOWN_KEYS = 5


def shown(value: Any) -> str:
    """A received value for a message: its repr, cut to :data:`SHOWN_CHARS` characters.

    >>> shown("x" * 100).endswith("xx… (100 characters)'")
    True
    """
    text = repr(value)
    if len(text) <= SHOWN_CHARS:
        return text
    n = len(value) if isinstance(value, str) else len(text)
    return f"{text[:SHOWN_CHARS]}… ({n} characters)'"


def refused_message(name: str, p: param.Parameter, text: Any) -> str:
    """The page's words for a link's value of parameter ``name`` that it refuses.

    >>> from app.state import ExplorerState
    >>> refused_message("t_end", ExplorerState.param.t_end, "true")
    "tend (t_end) must be a number in [0.1, 5000]; got 'true'"
    """
    return f"{URL_KEYS[name]} ({name}) must be {allowed(p)}; got {shown(text)}"


def repeated_message(key: str, name: str | None, texts: Sequence[str]) -> str:
    """The page's words for a ``key`` the link gives more than once (``name``: the
    parameter it sets, if any).

    >>> repeated_message("r", "restitution", ["0.5", "0.7"])
    "r (restitution) must be given once; got 2 values: '0.5', '0.7'"
    """
    what = f"{key} ({name})" if name else key
    values = ", ".join(shown(t) for t in texts[:SHOWN_KEYS])
    more = f" and {len(texts) - SHOWN_KEYS} more" if len(texts) > SHOWN_KEYS else ""
    return f"{what} must be given once; got {len(texts)} values: {values}{more}"


def unknown_message(unknown: Sequence[str], known: Iterable[str]) -> str:
    """The page's words for the keys it does not know (at most :data:`SHOWN_KEYS` named).

    >>> unknown_message(["colour"], ["v", "r"])
    "unknown key 'colour' (known: v, r, or the parameters' names)"
    """
    keys = ", ".join(shown(k) for k in unknown[:SHOWN_KEYS])
    more = f" and {len(unknown) - SHOWN_KEYS} more" if len(unknown) > SHOWN_KEYS else ""
    return (f"unknown {'keys' if len(unknown) > 1 else 'key'} {keys}{more} (known: "
            f"{', '.join(known)}, or the parameters' names)")
