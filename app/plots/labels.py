"""The phase portrait's theory points, their names, and the browser's placement of their labels.

Where a label goes is decided once, in the browser (:data:`PLACE_LABELS_JS`): which corner
of a label to anchor at its point depends on the frame's size in pixels, which only the
browser knows (the figure follows the page, and its ranges are fitted to the frame there,
``match_aspect``). Deciding there also keeps a drag fast: a release sends the points and
nothing else, and when only the frame or the font changes (a resize, the presentation
mode) the labels move without a message to the server. The server sends what it alone
knows: the points (coincident ones merged into one marker with a joint label), their names
and the centre of the slip arcs through them, from which the browser tells which side of a
point faces away from its curves (the corner it tries first).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import Any

from bokeh.models import CustomJS, GlyphRenderer, LabelSet, Span

from app.state import Scales

#: The paper's names of the theory's points, after its transitions (Sec. 2): slip->stick
#: (SlSt), stick->slip (StSl), slip->contact (SlC), contact->slip (CSl), stick->contact
#: (StC, a stick segment that ends at the stop); ``lim`` is the point the impacts tend to.
PAPER_NAMES: Mapping[str, str] = {
    "P_stick_start": "P_SlSt", "P_stick_end": "P_StSl", "P_impact_in": "P_SlC",
    "P_impact_out": "P_CSl", "P_limit": "P_lim",
}
#: A stick segment's end on the stop is the stick->contact point.
PAPER_STICK_CONTACT = "P_StC"
#: Points this close (relative, and absolute near zero) are one marker.
SAME_POINT_RTOL, SAME_POINT_ATOL = 1e-9, 1e-12
#: The browser's placement of the theory points' labels (the body of a ``CustomJS``).
PLACE_LABELS_JS = Path(__file__).resolve().parents[2] / "static" / "point_labels.js"
#: Columns of the points' source. ``align``, ``baseline``, ``dx``, ``dy`` are the browser's
#: to write (:data:`PLACE_LABELS_JS`); until it has placed them a label is centred on its
#: point (:data:`UNPLACED`).
POINT_COLUMNS = ("x", "v", "name", "paper", "centre", "align", "baseline", "dx", "dy")
UNPLACED: Mapping[str, Any] = {"align": "center", "baseline": "middle", "dx": 0, "dy": 0}


def merge_points(named: Mapping[str, tuple[float, float]]
                 ) -> list[tuple[float, float, list[str]]]:
    """The points ``named`` with those that coincide (a stick segment that ends at the
    stop: its end is the impact point) merged: ``(x, v, keys)`` in the order first met.

    >>> merge_points({"P_stick_end": (0.25, 0.07), "P_impact_in": (0.25, 0.07 + 1e-15),
    ...               "P_stick_start": (0.1, 0.07)})
    [(0.25, 0.07, ['P_stick_end', 'P_impact_in']), (0.1, 0.07, ['P_stick_start'])]
    """
    merged: list[tuple[float, float, list[str]]] = []
    for key, (x, v) in named.items():
        same = (keys for mx, mv, keys in merged
                if math.isclose(x, mx, rel_tol=SAME_POINT_RTOL, abs_tol=SAME_POINT_ATOL)
                and math.isclose(v, mv, rel_tol=SAME_POINT_RTOL, abs_tol=SAME_POINT_ATOL))
        keys = next(same, None)
        if keys is None:
            merged.append((x, v, [key]))
        else:
            keys.append(key)
    return merged


def label_text(keys: list[str]) -> str:
    """The label of a point that is each of ``keys`` (``P_`` dropped, joined by ``=``).

    >>> label_text(["P_stick_end", "P_impact_in"])
    'stick end = impact in'
    """
    return " = ".join(key.removeprefix("P_").replace("_", " ") for key in keys)


def paper_name(keys: list[str]) -> str:
    """The paper's name of a point that is each of ``keys`` (:data:`PAPER_NAMES`).

    >>> paper_name(["P_stick_end", "P_impact_in"]), paper_name(["P_impact_out"])
    ('P_StC', 'P_CSl')
    """
    if {"P_stick_end", "P_impact_in"} <= set(keys):
        return PAPER_STICK_CONTACT
    return " = ".join(PAPER_NAMES.get(k, k) for k in keys)


def theory_points(named: Mapping[str, tuple[float, float]], scales: Scales,
                  centre: float = math.nan) -> dict[str, list]:
    """The columns of the theory points' source (:data:`POINT_COLUMNS`): one marker per
    distinct point (:func:`merge_points`), its label in words and the paper's name, and
    ``centre``, the displacement ``a`` of the slip arcs' centre ``(a, 0)`` (Eq. 7).

    >>> from app.state import DIMENSIONLESS
    >>> p = theory_points({"P_limit": (0.24, 0.0)}, DIMENSIONLESS, 0.2)
    >>> p["name"], p["paper"], p["centre"], p["align"]
    (['limit'], ['P_lim'], [0.2], ['center'])
    """
    merged = merge_points(named)
    n = len(merged)
    return {"x": [x * scales.length for x, _, _ in merged],
            "v": [v * scales.velocity for _, v, _ in merged],
            "name": [label_text(keys) for _, _, keys in merged],
            "paper": [paper_name(keys) for _, _, keys in merged],
            "centre": [float(centre) * scales.length] * n,
            **{k: [u] * n for k, u in UNPLACED.items()}}


def applicable_points(points: Mapping[str, list], path_stick: Mapping[str, Any],
                      kinds: list[str]) -> dict[str, list]:
    """The theory's points that the drawn motion can have: no stick points when it never
    sticks (``path_stick`` empty: a pure slip orbit), no impact points when it never
    reaches the stop (no impact among the transition ``kinds``)."""
    sticks = len(path_stick["x"]) > 0
    impacts = any(k in ("impact", "stick->impact") for k in kinds)
    keep = [i for i, name in enumerate(points["name"])
            if (sticks or "stick" not in name) and (impacts or "impact" not in name)]
    return {k: [col[i] for i in keep] for k, col in points.items()}


@cache
def place_labels_code() -> str:
    """The text of :data:`PLACE_LABELS_JS`."""
    return PLACE_LABELS_JS.read_text(encoding="utf-8")


def place_labels(fig: Any, labels: LabelSet, stop: Span) -> CustomJS:
    """Let the browser place the theory points' ``labels`` on ``fig``
    (:data:`PLACE_LABELS_JS`) each time the frame, the ranges, the labels' font, the stop
    or what the portrait draws changes (renderers added later are avoided but not watched:
    the animation's marker moves on every frame): one ``CustomJS`` model for the page."""
    place = CustomJS(args={"labels": labels, "fig": fig, "stop": stop},
                     code=place_labels_code())
    watched = [(fig, ("inner_width", "inner_height")),
               (fig.x_range, ("start", "end")), (fig.y_range, ("start", "end")),
               (labels, ("text_font_size", "text_font_style", "text")),
               (stop, ("location", "visible"))]
    sources = {r.data_source for r in fig.renderers if isinstance(r, GlyphRenderer)}
    watched += [(src, ("data",)) for src in sources]
    for model, attrs in watched:
        for attr in attrs:
            model.js_on_change(attr, place)
    return place
