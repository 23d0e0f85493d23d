"""app.glyphs makes the renderer that Bokeh's glyph methods make, minus the glyph copies."""

from __future__ import annotations

import pytest
from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

from app.glyphs import add_glyph

#: Calls as the explorer makes them (app.plots, app.animation): positional fields, the
#: ``color``/``alpha`` shorthands, fields as colours and markers, renderer arguments.
CALLS = [
    ("line", ("x", "v"), {"line_color": "#777777", "line_dash": "dashed", "line_width": 1}),
    ("line", ("t", "f"), {"y_range_name": "rest", "line_width": 2, "line_dash": "dashed"}),
    ("scatter", ("x", "v"), {"marker": "marker", "color": "color", "size": 7,
                             "fill_alpha": 0.6}),
    ("scatter", ("x", "v"), {"size": 0, "alpha": 0.0}),
    ("scatter", ("v", "x"), {"marker": "circle_cross", "size": 14, "fill_color": "#ffffff",
                             "line_color": "#000000", "line_width": 2, "level": "overlay"}),
    ("segment", ("t", 0.0, "t", "j"), {"line_color": "#d62728", "line_width": 1.5}),
    ("quad", (), {"left": "left", "right": "right", "bottom": -1e3, "top": 1e3,
                  "fill_color": "color", "line_color": None}),
    ("quad", (), {"left": "left", "right": "right", "bottom": "b", "top": "t",
                  "color": "color"}),
    ("image", (), {"image": "image", "x": "x", "y": "y", "dw": "dw", "dh": "dh"}),
]


def _values(model):
    """A model's set properties, other models by type (their ids differ)."""
    return {k: (type(v).__name__ if hasattr(v, "properties_with_values") else v)
            for k, v in model.properties_with_values(include_defaults=False).items()}


@pytest.mark.parametrize(("method", "args", "kw"), CALLS)
def test_same_renderer_as_the_glyph_method(method, args, kw):
    source = ColumnDataSource({})
    reference = figure()
    reference.extra_y_ranges = {"rest": reference.y_range.clone()}
    old = getattr(reference, method)(*args, source=source, **kw)
    fig = figure()
    fig.extra_y_ranges = {"rest": fig.y_range.clone()}
    new = add_glyph(fig, method, *args, source=source, **kw)
    assert fig.renderers == [new]
    assert type(new.glyph) is type(old.glyph)
    # Every visual default the glyph method sets (its palette's first colour, opaque,
    # black hatch and text) is set here too.
    assert _values(new.glyph) == _values(old.glyph)
    assert new.data_source is source
    assert new.nonselection_glyph == "auto" and new.muted_glyph == "auto"
    for name in ("level", "y_range_name", "x_range_name", "visible"):
        assert getattr(new, name) == getattr(old, name)


def test_unknown_property_is_refused():
    with pytest.raises(TypeError, match="Line has no properties.*'size'"):
        add_glyph(figure(), "line", "x", "y", source=ColumnDataSource({}), size=3)
