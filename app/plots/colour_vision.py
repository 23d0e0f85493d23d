"""How far apart the page's colours look, to normal and to red-green colour-blind vision.

A colour is simulated as a protanope or deuteranope sees it with the matrices of Machado,
Oliveira and Fernandes (2009, severity 1: dichromacy), applied to linear sRGB; the
distance of two colours is CIEDE2000 (Sharma, Wu and Dalal 2005) in CIELAB under D65. The
palettes of the regime map and of the mode bands are chosen so that their classes stay
apart for all three viewers (``benchmarks/palette_cvd.py`` prints the distances).

>>> round(float(delta_e2000([50.0, 2.6772, -79.7751], [50.0, 0.0, -82.7485])), 4)
2.0425
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from itertools import combinations

import numpy as np

#: Machado et al. (2009) simulation matrices at severity 1 (linear sRGB).
CVD_MATRICES: Mapping[str, np.ndarray] = {
    "normal": np.eye(3),
    "protanopia": np.array([[0.152286, 1.052583, -0.204868],
                            [0.114503, 0.786281, 0.099216],
                            [-0.003882, -0.048116, 1.051998]]),
    "deuteranopia": np.array([[0.367322, 0.860646, -0.227968],
                              [0.280085, 0.672501, 0.047413],
                              [-0.011820, 0.042940, 0.968881]]),
}
#: sRGB (linear) to CIE XYZ, D65 white (IEC 61966-2-1).
SRGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                        [0.2126729, 0.7151522, 0.0721750],
                        [0.0193339, 0.1191920, 0.9503041]])
#: The D65 white point in XYZ (Y = 1).
D65 = SRGB_TO_XYZ.sum(axis=1)


def hex_to_rgb(colour: str) -> np.ndarray:
    """``"#rrggbb"`` as sRGB in [0, 1]."""
    c = colour.lstrip("#")
    return np.array([int(c[i:i + 2], 16) for i in (0, 2, 4)], dtype=float) / 255.0


def to_linear(rgb: np.ndarray) -> np.ndarray:
    """Gamma-encoded sRGB to linear (IEC 61966-2-1)."""
    rgb = np.asarray(rgb, float)
    return np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)


def simulate(colour: str, vision: str) -> np.ndarray:
    """Linear sRGB of ``colour`` as seen with ``vision`` (a key of :data:`CVD_MATRICES`),
    clipped to the gamut."""
    return np.clip(CVD_MATRICES[vision] @ to_linear(hex_to_rgb(colour)), 0.0, 1.0)


def linear_to_lab(rgb: np.ndarray) -> np.ndarray:
    """CIELAB (D65) of a linear sRGB colour."""
    t = (SRGB_TO_XYZ @ np.asarray(rgb, float)) / D65
    eps, kappa = 216 / 24389, 24389 / 27
    f = np.where(t > eps, np.cbrt(t), (kappa * t + 16) / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e2000(lab1, lab2) -> float:
    """CIEDE2000 colour difference of two CIELAB colours (Sharma et al. 2005, Eqs. 1-19)."""
    l1, a1, b1 = (float(v) for v in lab1)
    l2, a2, b2 = (float(v) for v in lab2)
    c_bar = 0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))
    g = 0.5 * (1 - np.sqrt(c_bar**7 / (c_bar**7 + 25.0**7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360 if c1p else 0.0
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360 if c2p else 0.0
    dlp, dcp = l2 - l1, c2p - c1p
    dh = h2p - h1p
    if c1p * c2p == 0:
        dh = 0.0
    elif dh > 180:
        dh -= 360
    elif dh < -180:
        dh += 360
    dhp = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh / 2))
    lbp, cbp = 0.5 * (l1 + l2), 0.5 * (c1p + c2p)
    hbp = h1p + h2p
    if c1p * c2p != 0:
        if abs(h1p - h2p) <= 180:
            hbp = 0.5 * (h1p + h2p)
        else:
            hbp = 0.5 * (h1p + h2p + (360 if h1p + h2p < 360 else -360))
    t = (1 - 0.17 * np.cos(np.radians(hbp - 30)) + 0.24 * np.cos(np.radians(2 * hbp))
         + 0.32 * np.cos(np.radians(3 * hbp + 6)) - 0.20 * np.cos(np.radians(4 * hbp - 63)))
    dtheta = 30 * np.exp(-(((hbp - 275) / 25) ** 2))
    rc = 2 * np.sqrt(cbp**7 / (cbp**7 + 25.0**7))
    sl = 1 + 0.015 * (lbp - 50) ** 2 / np.sqrt(20 + (lbp - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    rt = -np.sin(np.radians(2 * dtheta)) * rc
    return float(np.sqrt((dlp / sl) ** 2 + (dcp / sc) ** 2 + (dhp / sh) ** 2
                         + rt * (dcp / sc) * (dhp / sh)))


def min_difference(colours: Iterable[str], vision: str) -> float:
    """The least CIEDE2000 difference between any two of ``colours`` seen with ``vision``.

    >>> min_difference(["#000000", "#ffffff"], "deuteranopia") > 99
    True
    """
    labs = [linear_to_lab(simulate(c, vision)) for c in colours]
    return min(delta_e2000(p, q) for p, q in combinations(labs, 2))
