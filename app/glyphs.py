"""Glyph renderers made with the one glyph they draw.

``figure.line(...)`` and the other glyph methods of ``bokeh.plotting`` build three glyph
models per renderer (the glyph, a non-selection copy and a muted copy); the explorer has no
selection tools and no muting legend, so the copies were thrown away at once
(:meth:`app.plots.sources.SharedModels.lighten` sets them to ``"auto"``, derived in the browser).
Building them cost a new session's page ~1 ms per renderer (26 renderers on the default
page). :func:`add_glyph` makes the same renderer from the public models, with the same visual
defaults as the glyph methods (colour ``#1f77b4``, alpha 1, black text and hatch) and the
same ``color``/``alpha`` shorthands, so that what the browser receives does not change.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from bokeh.models import GlyphRenderer, Image, Line, MultiLine, Quad, Scatter, Segment

#: Glyph methods the explorer uses: the glyph class and its positional arguments.
GLYPHS: Mapping[str, tuple[type, tuple[str, ...]]] = {
    "line": (Line, ("x", "y")),
    "multi_line": (MultiLine, ("xs", "ys")),
    "scatter": (Scatter, ("x", "y")),
    "segment": (Segment, ("x0", "y0", "x1", "y1")),
    "quad": (Quad, ("left", "right", "top", "bottom")),
    "image": (Image, ("image", "x", "y", "dw", "dh")),
}
#: Arguments that belong to the renderer, not to its glyph (as in ``bokeh.plotting``).
RENDERER_ARGS = ("name", "x_range_name", "y_range_name", "level", "visible", "view")
#: Features of a glyph's visual properties (``line_color``: feature ``line``).
VISUAL_FEATURES = ("line", "fill", "hatch", "text", "global")
#: Values of visual properties that nothing sets: those of ``bokeh.plotting``'s glyph
#: methods (their first palette colour, opaque, black text and hatch).
TRAIT_DEFAULTS: Mapping[str, Any] = {"color": "#1f77b4", "alpha": 1.0}
PROP_DEFAULTS: Mapping[str, Any] = {"text_color": "black", "hatch_color": "black"}


def glyph_props(glyph_class: type, kw: dict[str, Any]) -> dict[str, Any]:
    """The properties of a ``glyph_class`` glyph from glyph-method keywords ``kw``.

    Every visual property is set, as the glyph methods do: from ``kw`` itself, else from a
    trait shorthand (``color`` sets ``line_color``, ``fill_color`` and ``hatch_color``
    unless the glyph has a property of that name), else from :data:`PROP_DEFAULTS` and
    :data:`TRAIT_DEFAULTS`.
    """
    names = set(glyph_class.properties())
    props = {k: v for k, v in kw.items() if k in names}
    shorthands = set()
    for name in names:
        feature, _, trait = name.partition("_")
        if feature not in VISUAL_FEATURES or not trait:
            continue
        if trait not in names:
            shorthands.add(trait)
        if name in props:
            continue
        if trait not in names and trait in kw:
            props[name] = kw[trait]
        elif name in PROP_DEFAULTS:
            props[name] = PROP_DEFAULTS[name]
        elif trait in TRAIT_DEFAULTS:
            props[name] = TRAIT_DEFAULTS[trait]
    unknown = set(kw) - names - shorthands
    if unknown:
        raise TypeError(f"{glyph_class.__name__} has no properties {sorted(unknown)}")
    return props


def add_glyph(fig: Any, method: str, *args: Any, source: Any, **kw: Any) -> GlyphRenderer:
    """Add to ``fig`` the renderer that ``fig.<method>(*args, source=source, **kw)`` adds,
    without the non-selection and muted copies of its glyph (``"auto"`` instead).

    Examples
    --------
    >>> from bokeh.models import ColumnDataSource
    >>> from bokeh.plotting import figure
    >>> fig, src = figure(), ColumnDataSource({"x": [0, 1], "v": [1, 0]})
    >>> r = add_glyph(fig, "line", "x", "v", source=src, line_color="#777777", line_width=1)
    >>> r.glyph.line_color, r.nonselection_glyph
    ('#777777', 'auto')
    """
    glyph_class, positional = GLYPHS[method]
    if len(args) > len(positional):
        raise TypeError(f"{method} takes at most {len(positional)} positional arguments")
    kw = {**dict(zip(positional, args, strict=False)), **kw}
    if method == "scatter":
        kw.setdefault("marker", "circle")  # set, as ``figure.scatter`` sets it
    renderer_kw = {k: kw.pop(k) for k in RENDERER_ARGS if k in kw}
    glyph = glyph_class(**glyph_props(glyph_class, kw))
    return fig.add_glyph(source, glyph, nonselection_glyph="auto", muted_glyph="auto",
                         **renderer_kw)
