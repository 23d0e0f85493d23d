"""The regime map's legend: colour swatches naming the regimes, and what their words mean."""

from __future__ import annotations

import html

from app.plots import MAP_PALETTE

#: What the words of the regime map's legend mean (shown under it, for the words used).
MAP_TERMS = {
    "slow": "slow / fast belt: v below / above the critical speed v* (Eq. 25)",
    "no impact": "no impact: the motion stays short of the stop",
    "elastic": "elastic / inelastic / plastic: restitution r = 1 / 0 < r < 1 / r = 0",
    "case": "case a / b / c: where the stick phase meets the stop (Sec. 4.2-4.4, Eq. 35)",
    "grazing": "grazing: impacts fade towards a slip circle touching the stop",
    "rest": "rest: the impacts accumulate and the mass stays pressed on the stop",
}


def map_legend_html(labels: list[str], covered: bool = False) -> str:
    """Colour swatches naming the regimes of the map, and what their words mean; with
    ``covered``, first that the simulated layer hides them."""
    items = "".join(
        f"<span class='fie-swatch'><i style='background:{MAP_PALETTE[i % len(MAP_PALETTE)]}'>"
        f"</i>{html.escape(label)}</span>"
        for i, label in enumerate(labels)
    )
    words = " ".join(labels)
    terms = [text for word, text in MAP_TERMS.items()
             if word in words or (word == "slow" and "fast" in words)
             or (word == "elastic" and ("inelastic" in words or "plastic" in words))]
    notes = "".join(f"<div class='fie-look'>{html.escape(t)}</div>" for t in terms)
    head = ("<div class='fie-look fie-map-covered'>The simulated steady states cover the "
            "map (their colours are in the sweep card); the theory's regimes below show "
            "where that layer is off.</div>" if covered else "")
    return f"<div class='fie-legend'>{head}{items}{notes}</div>"
