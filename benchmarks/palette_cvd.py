"""Least CIEDE2000 difference between the classes of the page's palettes, for normal vision
and simulated protanopia and deuteranopia (:mod:`app.plots.colour_vision`).

    PYTHONPATH=. python benchmarks/palette_cvd.py

Palettes: the regime map's categories (all, and the first six, which most maps use), the
mode bands behind the time histories, and the steady states of the simulated map.
"""

from __future__ import annotations

from app.bifurcation import LABEL_COLORS
from app.plots import BAND_COLORS, MAP_PALETTE
from app.plots.colour_vision import CVD_MATRICES, min_difference


def main() -> None:
    palettes = {
        f"regime map ({len(MAP_PALETTE)})": list(MAP_PALETTE),
        "regime map, first 6": list(MAP_PALETTE[:6]),
        "mode bands (3)": list(BAND_COLORS.values()),
        f"steady states ({len(LABEL_COLORS)})": list(LABEL_COLORS.values()),
    }
    visions = list(CVD_MATRICES)
    print("| palette | " + " | ".join(f"min dE00 {v}" for v in visions) + " |")
    print("|---|" + "---|" * len(visions))
    for name, colours in palettes.items():
        row = " | ".join(f"{min_difference(colours, v):.2f}" for v in visions)
        print(f"| {name} | {row} |")


if __name__ == "__main__":
    main()
