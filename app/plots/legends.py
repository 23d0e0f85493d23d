"""The HTML legends below the figures: swatches of styles and the phase portrait's entries."""

from __future__ import annotations

import html
from collections.abc import Iterable, Mapping
from typing import Any

import panel as pn

from app.plots.style import (
    BAND_COLORS,
    MODE_NAMES,
    PHASE_LABELS,
    PHASE_STYLE,
    TRANSITION_LABELS,
    TRANSITION_STYLE,
)
from core import Mode

#: An entry of an HTML legend: its label, its swatch (inline SVG) and its explanation.
Entry = tuple[str, str, str]


def swatch(marker: str = "line", **style: Any) -> str:
    """A small inline SVG of a line style or a marker, for an HTML legend."""
    color = style.get("line_color", style.get("color", "#000000"))
    fill = style.get("fill_color", style.get("color", color))
    width = style.get("line_width", 1.5)
    if marker == "line":
        dash = {"dashed": "4 3", "dotted": "1 2", "dotdash": "1 2 4 2"}.get(
            style.get("line_dash", ""), "")
        shape = (f'<line x1="1" y1="6" x2="17" y2="6" stroke="{color}" '
                 f'stroke-width="{width}" stroke-dasharray="{dash}"/>')
    else:
        shape = {
            "triangle": '<polygon points="9,1 15,11 3,11"',
            "inverted_triangle": '<polygon points="3,1 15,1 9,11"',
            "diamond": '<polygon points="9,0 15,6 9,12 3,6"',
            "square": '<rect x="4" y="2" width="9" height="9"',
            "square_pin": '<rect x="4" y="2" width="9" height="9"',
        }.get(marker, '<circle cx="9" cy="6" r="4.5"')
        shape += f' fill="{fill}" stroke="{color}" stroke-width="{min(width, 2)}"/>'
    return (f'<svg width="18" height="12" viewBox="0 0 18 12" aria-hidden="true" '
            f'style="vertical-align:-1px;margin-right:4px">{shape}</svg>')


def legend_html(entries: list[Entry]) -> str:
    """An HTML legend: each entry's swatch and label, its explanation as a tooltip.

    >>> legend_html([("slip", "<svg/>", "")])
    '<span style="display:inline-block;margin-right:12px;white-space:nowrap"><svg/>slip</span>'
    """
    parts = []
    for label, swatch, note in entries:
        title = f' title="{html.escape(note)}"' if note else ""
        parts.append(f'<span style="display:inline-block;margin-right:12px;'
                     f'white-space:nowrap"{title}>{swatch}{html.escape(label)}</span>')
    return "".join(parts)


#: Lines of an HTML legend's height kept free (20 px each): entries that come and go
#: with the state do not move the plots below on every release.
LEGEND_LINES = 3
#: Height [px] of a legend's line, and the legend's margin below it.
LEGEND_LINE_PX, LEGEND_MARGIN_PX = 20, 4


def legend_pane(text: str = "", lines: int = LEGEND_LINES) -> pn.pane.HTML:
    """An HTML legend below a figure, ``lines`` high at least. A Panel HTML pane, not a
    Bokeh ``Div``: BokehJS answers any change of a ``Div`` by laying out the whole page
    again, which resizes and repaints every figure (28-48 ms in Chromium on each release
    whose legend changed, e.g. the count of a cycle's repeats); the pane only replaces its
    inner HTML."""
    return pn.pane.HTML(text, sizing_mode="stretch_width",
                        margin=(0, 10, LEGEND_MARGIN_PX, 50),
                        min_height=LEGEND_LINE_PX * lines,
                        styles={"font-size": "12px", "line-height": f"{LEGEND_LINE_PX}px"})


#: What each mode band behind the time histories means (tooltips): a rigid stop holds
#: the mass at rest in contact (docs/physics.md, "Rest at the stop"), the belt at rest
#: in stick.
BAND_NOTES: Mapping[int, tuple[str, str]] = {
    int(Mode.SLIP): ("slip", "the mass slides on the belt (Eq. 7)"),
    int(Mode.STICK): ("stick / rest on the belt", "the mass moves with the belt (x′ = v)"),
    int(Mode.CONTACT): ("contact / rest on the stop",
                        "the mass touches the stop: a deformable stop's contact, or rest "
                        "pressed on a rigid stop"),
}


def band_entries() -> list[Entry]:
    """Entries of the mode bands behind the time histories, in :data:`BAND_COLORS`.

    >>> [label for label, _, _ in band_entries()]
    ['slip', 'stick / rest on the belt', 'contact / rest on the stop']
    """
    return [(label, swatch("square", fill_color=BAND_COLORS[m], line_color="#999999",
                           line_width=1), note)
            for m, (label, note) in BAND_NOTES.items()]


def phase_entries(data: Mapping[str, Mapping[str, Any]], kinds: Iterable[str]) -> list[Entry]:
    """Entries of what the phase portrait draws, from its sources' ``data`` (by source
    name) and the transition ``kinds`` listed: the references, the modes, the transitions,
    the theory points, the closing of a cycle (with its count of repeats) and the start."""
    out = []
    for key in ("gamma0", "cycle", "removed"):
        if len(data[key]["x"]):
            label, note = PHASE_LABELS[key]
            out.append((label, swatch("line", **PHASE_STYLE[key]), note))
    for name in MODE_NAMES.values():
        if len(data[f"path_{name}"]["x"]):
            out.append((name, swatch("line", **PHASE_STYLE[name]), ""))
    kinds = set(kinds)
    for kind, (marker, color) in TRANSITION_STYLE.items():
        if kind in kinds:
            out.append((TRANSITION_LABELS.get(kind, kind),
                        swatch(marker, fill_color=color, line_color=color), ""))
    for key in ("points", "repeat", "start"):
        if len(data[key]["x"]):
            label, note = PHASE_LABELS[key]
            if key == "repeat":  # with the count of repeats
                label = f"{label} ({data[key]['text'][0]})"
            out.append((label, swatch(**PHASE_STYLE[key]), note))
    return out
