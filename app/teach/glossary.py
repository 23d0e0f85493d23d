"""One glossary of every symbol the page shows on a slider, an axis or in its texts.

Each entry gives the symbol in TeX (typeset on the page), its meaning in words and its
definition in the dimensionless units the page computes in: time ``t = omega tau`` with
``omega = sqrt(k/m)``, lengths in any unit (forces divided by ``k`` are lengths).

Examples
--------
>>> GLOSSARY["x_bar"].meaning.split(":")[0]
'clearance'
>>> SLIDER_SYMBOLS["clearance"]
'x_bar'
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

#: Unicode's subscript characters: it has them for the digits and some lower-case letters
#: only (no c, d, q, N, ...).
SUBSCRIPTS = MappingProxyType(dict(zip("0123456789aehijklmnoprstuvx",
                                       "₀₁₂₃₄₅₆₇₈₉ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ", strict=True)))


def subscripted(base: str, sub: str, family: tuple[str, ...] = ()) -> str:
    """``base`` with subscript ``sub`` as printed in plain text: in Unicode's subscript
    characters where it has one for each character of ``sub`` and of every subscript of
    the ``family`` shown beside it, else as ``base_sub`` (so a pair such as k_c0, k_e0 reads
    alike, not as k_c0 beside kₑ₀).

    >>> subscripted("μ", "s", ("s", "k")), subscripted("x", "0")
    ('μₛ', 'x₀')
    >>> subscripted("k", "e0", _KE), subscripted("v", "dr"), subscripted("F", "N")
    ('k_e0', 'v_dr', 'F_N')
    """
    if all(c in SUBSCRIPTS for part in (sub, *family) for c in part):
        return base + "".join(SUBSCRIPTS[c] for c in sub)
    return f"{base}_{sub}"


@dataclass(frozen=True)
class Symbol:
    """A glossary entry.

    Attributes
    ----------
    key : str
        Its anchor on the page (``fie-gl-<key>``).
    tex : str
        The symbol in TeX, without delimiters.
    plain : str
        The symbol in plain text (tooltips).
    meaning : str
        What it is, in words (plain text).
    definition : str
        Its dimensionless definition in TeX, without delimiters.
    """

    key: str
    tex: str
    plain: str
    meaning: str
    definition: str


#: The subscripts printed side by side: the friction coefficients', the stop's stiffnesses'.
_MU, _KE = ("s", "k"), ("c0", "e0")
#: The deformable stop's rates beta_c, beta_e as printed (Unicode has no subscript c).
BETAS = tuple(subscripted("β", sub, ("c", "e")) for sub in ("c", "e"))

_ENTRIES = (
    Symbol("t", "t", "t", "time: the page's clock, one unit is 1/ω of a second "
           "(a free swing of the spring lasts 2π)", r"t = \omega\tau,\ \ \omega = \sqrt{k/m}"),
    Symbol("x", "x", "x", "displacement of the mass from where the spring is unstretched",
           r"\text{a length; lengths keep their unit}"),
    Symbol("xdot", "x'", "x'", "velocity of the mass: the rate of change of x in the page's "
           "time", r"x' = \mathrm{d}x/\mathrm{d}t"),
    Symbol("m", "m", "m", "mass of the block [kg]; only the SI view uses it",
           r"\omega = \sqrt{k/m}"),
    Symbol("k", "k", "k", "stiffness of the spring [N/m]; every force on the page is "
           "divided by it, which makes it a length", r"\text{force}/k = \text{a length}"),
    Symbol("F_N", "F_N", subscripted("F", "N"), "normal force pressing the block on the "
           "belt [N]", r"u_s = F_N/k"),
    Symbol("v", "v", "v", "belt speed: how fast the belt runs forward",
           r"v = v_{dr}/\omega"),
    Symbol("mu_s", r"\mu_s", subscripted("μ", "s", _MU), "static friction coefficient: how "
           "hard the belt can hold the block before it slips (a pure number)",
           r"b = \mu_s u_s"),
    Symbol("mu_k", r"\mu_k", subscripted("μ", "k", _MU), "kinetic friction coefficient: the "
           "friction while the block slides on the belt (a pure number, μₖ ≤ μₛ)",
           r"a = \mu_k u_s"),
    Symbol("u_s", "u_s", subscripted("u", "s"), "static deflection: how far the normal force "
           "would stretch the spring", r"u_s = F_N / k"),
    Symbol("a", "a", "a", "kinetic friction force over k: while slipping, the block swings "
           "about x = a", r"a = \mu_k u_s"),
    Symbol("b", "b", "b", "largest static friction force over k: the block rides with the "
           "belt while the spring pull |x| stays below b", r"b = \mu_s u_s"),
    Symbol("u_r", "u_r", "u_r", "velocity of the belt relative to the block; its sign "
           "gives the direction of friction", r"u_r = v - x'"),
    Symbol("x_bar", r"\bar x", "x̄", "clearance: position of the stop, measured from where "
           "the spring is unstretched (a length)", r"\text{impact at } x = \bar x"),
    Symbol("r", "r", "r", "coefficient of restitution of the rigid stop: rebound speed over "
           "impact speed (1 elastic, below 1 inelastic, 0 plastic)",
           r"x'(+) = -r\,x'(-)"),
    Symbol("v_star", "v^*", "v*", "critical belt speed: above it the block slips for ever, "
           "below it it sticks (Eq. 25); from rest v* = a",
           r"v^* = \sqrt{(x_0 - a)^2 + x_0'^2}"),
    Symbol("x_max", r"x_{\max}", "x_max", "farthest point of the motion without a stop, on "
           "the slow belt's stick-slip cycle (Eq. 23)",
           r"x_{\max} = a + \sqrt{(b - a)^2 + v^2}"),
    Symbol("x_star", "x^*", "x*", "critical clearance of the slow belt: above it the "
           "rebound from the stop reaches the belt speed again (Eq. 35)",
           r"x^* = a + v\sqrt{1 - r^2}"),
    Symbol("w", "w_h", "w_h", "speed of the h-th impact on the stop", r"w_h = r^h w_0"),
    Symbol("t_acc", r"t_{acc}", "t_acc", "accumulation time: when infinitely many ever "
           "shorter bounces end and the mass rests on the stop",
           r"t_{acc} = t_0 + \sum_{h \ge 1} 2\arctan\frac{r^h w_0}{a - \bar x}"),
    Symbol("x0", "x_0", subscripted("x", "0"), "initial displacement of the mass",
           r"x(0) = x_0"),
    Symbol("v0", "x_0'", subscripted("x", "0") + "'", "initial velocity of the mass",
           r"x'(0) = x_0'"),
    Symbol("t_end", r"t_{end}", subscripted("t", "end"), "length of the simulated run, in the "
           "page's time", r"0 \le t \le t_{end}"),
    Symbol("delta", r"\delta", "δ", "overlap: how far the mass has pushed into the "
           "deformable stop", r"\delta = x - \bar x"),
    Symbol("phi", r"\varphi", "φ", "force of the deformable stop over k (a length); on the "
           "force plot also the impulse of a rigid stop's impact", r"\varphi = F_{stop}/k"),
    Symbol("D", "D", "D", "limit overlap: the stop's force grows without bound as δ nears "
           "D, so it cannot be pushed farther (a length)", r"0 \lt \delta \lt D"),
    Symbol("k_c0", "k_{c0}", subscripted("k", "c0", _KE), "stiffness of the compression "
           "envelope at zero overlap, over k: the stop's slope while it is loaded",
           r"\varphi_C'(0) = k_{c0}"),
    Symbol("k_e0", "k_{e0}", subscripted("k", "e0", _KE), "stiffness of the expansion "
           "envelope at zero overlap, over k: the stop's slope while it springs back "
           "(k_e0 ≤ k_c0)",
           r"\varphi_E'(0) = k_{e0}"),
    Symbol("beta", r"\beta_c,\ \beta_e", ", ".join(BETAS), "how fast the stop's force moves "
           "towards the compression (β_c) or expansion (β_e) envelope after the overlap "
           "turns, per limit overlap D (Eq. 13)", r"e^{-\beta\,|\delta - \delta_r|/D}"),
    Symbol("r_eq", r"r_{eq}", "r_eq", "restitution of a rigid stop that a stiff, sharp "
           "deformable stop resembles (Eq. 16)", r"r_{eq} = \sqrt{k_{e0}/k_{c0}}"),
    Symbol("E", "E", "E", "energy per unit k (a length squared): kinetic plus spring",
           r"E = \tfrac{1}{2}(x'^2 + x^2)"),
)

#: Every entry by key, in reading order.
GLOSSARY = MappingProxyType({s.key: s for s in _ENTRIES})
#: Every symbol as printed in plain text (slider labels, tooltips, messages), by key.
PLAIN = MappingProxyType({s.key: s.plain for s in _ENTRIES})

#: The glossary entry of each slider's symbol (state parameter name -> entry key).
SLIDER_SYMBOLS = MappingProxyType({
    "belt_speed": "v", "clearance": "x_bar", "restitution": "r", "mu_s": "mu_s",
    "mu_k": "mu_k", "u_s": "u_s", "k_c0": "k_c0", "k_e0": "k_e0", "limit_overlap": "D",
    "beta_c": "beta", "beta_e": "beta", "x0": "x0", "v0": "v0", "t_end": "t_end",
    "mass": "m", "stiffness": "k",
})

#: The glossary entries of the plots' axes (axis label -> entry keys).
AXIS_SYMBOLS = MappingProxyType({
    "x": ("x",), "x'": ("xdot",), "t": ("t",), "impulse / force": ("phi",),
    "overlap x - x_bar": ("delta",), "phi / k": ("phi",),
    "relative velocity u_r = v - x'": ("u_r",), "friction force / k": ("a", "b"),
    "energy / k": ("E",), "belt speed v": ("v",), "clearance x_bar": ("x_bar",),
})


#: Class of the buttons of the story and the model (the glossary link finds them by it).
TEACH_BUTTONS = "fie-teach-buttons"
#: A link in a tooltip that presses the model card's button (the second), whose text holds
#: the glossary (the buttons found among BokehJS's ``Document.all_models`` by their class).
GLOSSARY_LINK = (
    "<a href=\"#\" class=\"fie-glossary-link\" onclick=\"const d = window.Bokeh && "
    "Bokeh.documents[0]; const m = d && [...d.all_models].find(x => (x.css_classes || "
    f"[]).includes('{TEACH_BUTTONS}')); if (m && !m.active.includes(1)) {{{{ m.active = "
    "[...m.active, 1]; }} return false;\">{label}</a>")


def tooltip(name: str, text: str) -> str:
    """The tooltip of slider ``name``: ``text`` and a link that opens the glossary, where
    its symbol has its entry (the model card above the plots)."""
    if name not in SLIDER_SYMBOLS:
        return text
    label = f"{GLOSSARY[SLIDER_SYMBOLS[name]].plain} and every other symbol: the glossary"
    return f"{text} {GLOSSARY_LINK.format(label=label)}."
