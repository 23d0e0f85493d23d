r"""The model card's text: the mechanism drawn and labelled, the equations of motion in slip,
stick and contact, the friction law, Newton's impact law, the hysteretic contact law, the
glossary and the details a student needs (the closed-form results of the paper, Secs. 3-5).

HTML with TeX between ``\(`` ``\)`` (inline) and ``$$`` (displayed), typeset in the browser
by Bokeh's MathJax. Pure functions of nothing: the text is the same for every session.

Examples
--------
>>> "x'' + x" in model_html()
True
"""

from __future__ import annotations

import functools
import html

from app.teach.glossary import GLOSSARY

#: Colours of the drawing: the page's slip blue, the belt grey, the stop black.
_MASS, _BELT, _STOP = "#1f5fbf", "#8a8f98", "#222222"


def mechanism_svg() -> str:
    """The mechanism of the explorer's "Mechanism" plot as a labelled SVG drawing: the wall
    and spring ``k``, the mass ``m`` on the belt running at ``v_dr`` with friction
    ``mu_s``, ``mu_k``, the normal force ``F_N``, and the stop at the clearance ``x_bar``
    from the unstretched position."""
    coils = " ".join(f"{70 + 9 * i},{92 + (-14 if i % 2 else 14)}" for i in range(1, 14))
    text = "font-family='serif' font-style='italic' font-size='17'"
    return f"""<svg class="fie-mechanism" viewBox="0 0 560 210" width="560" height="210"
 role="img" aria-label="The mechanism: wall, spring, mass on a moving belt, stop">
<defs><marker id="fie-arr" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7"
 markerHeight="7" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#333"/>
</marker></defs>
<rect x="40" y="40" width="14" height="100" fill="#bbb" stroke="{_STOP}"/>
<polyline points="54,92 70,92 {coils} 196,92 212,92" fill="none" stroke="#333"
 stroke-width="2"/>
<text x="124" y="72" {text}>k</text>
<rect x="212" y="58" width="92" height="70" rx="3" fill="{_MASS}" fill-opacity="0.85"
 stroke="#000"/>
<text x="250" y="99" {text} fill="#fff">m</text>
<line x1="258" y1="18" x2="258" y2="54" stroke="#333" stroke-width="2"
 marker-end="url(#fie-arr)"/>
<text x="266" y="30" {text}>F<tspan font-size="12" dy="4">N</tspan></text>
<rect x="30" y="130" width="480" height="16" fill="{_BELT}"/>
<circle cx="38" cy="138" r="11" fill="#ccc" stroke="#555"/>
<circle cx="502" cy="138" r="11" fill="#ccc" stroke="#555"/>
<line x1="46" y1="168" x2="96" y2="168" stroke="#333" stroke-width="2"
 marker-end="url(#fie-arr)"/>
<text x="100" y="173" {text}>v<tspan font-size="12" dy="4">dr</tspan></text>
<text x="150" y="173" font-family="sans-serif" font-size="13">belt, friction
 <tspan {text}>μ</tspan><tspan font-size="10" dy="4">s</tspan><tspan dy="-4">,</tspan>
 <tspan {text}>μ</tspan><tspan font-size="10" dy="4">k</tspan></text>
<rect x="440" y="40" width="14" height="88" fill="{_STOP}"/>
<text x="462" y="60" font-family="sans-serif" font-size="13">stop</text>
<line x1="304" y1="200" x2="304" y2="130" stroke="#777" stroke-dasharray="3,3"/>
<line x1="304" y1="190" x2="438" y2="190" stroke="#333" stroke-width="1.5"
 marker-start="url(#fie-arr)" marker-end="url(#fie-arr)"/>
<text x="366" y="184" {text}>x&#772;</text>
<text x="296" y="206" text-anchor="end" font-family="sans-serif" font-size="12">mass at
 x = 0: spring unstretched</text>
</svg>"""


#: Each law as (heading, HTML with TeX).
LAWS = (
    ("Units", r"""Time is measured in units of \(1/\omega\), \(\omega = \sqrt{k/m}\):
\(t = \omega\tau\), and a prime is \(\mathrm{d}/\mathrm{d}t\). Forces are divided by \(k\),
which makes them lengths: the friction forces become \(a = \mu_k u_s\) and
\(b = \mu_s u_s\) with \(u_s = F_N/k\), and the belt speed is \(v = v_{dr}/\omega\)."""),
    ("Slip", r"""While the block slides on the belt, friction has the size \(a\) and opposes
the relative velocity \(u_r = v - x'\):
$$x'' + x = s\,a, \qquad s = \operatorname{sign}(v - x').$$
In the phase plane \((x, x')\) the motion runs clockwise round a circle about
\((s\,a, 0)\)."""),
    ("Stick", r"""While the block rides with the belt it moves at the belt's speed, as long
as friction can hold the spring:
$$x' = v, \qquad |x| \le b.$$
At \(x = b\) the spring wins and the block slips back."""),
    ("Friction law (Coulomb)", r"""The friction force over \(k\) is
$$f = \begin{cases} a\,\operatorname{sign}(u_r), & u_r \ne 0 \ \text{(slip)},\\
-b \le f \le b, & u_r = 0 \ \text{(stick)},\end{cases}\qquad a = \mu_k u_s \le b = \mu_s u_s.$$
"""),
    ("Impact on a rigid stop (Newton)", r"""When the block reaches the stop,
\(x = \bar x\) with \(x' \gt 0\), its velocity is reversed and scaled by the coefficient of
restitution \(r\):
$$x'(+) = -r\,x'(-), \qquad 0 \le r \le 1.$$
The impact takes the kinetic energy \(\tfrac{1}{2}(1 - r^2)\,x'(-)^2\) (per unit mass)."""),
    ("Contact with a deformable stop", r"""A deformable stop pushes back with the force
\(\varphi\) (over \(k\)) of the overlap \(\delta = x - \bar x \gt 0\); in contact
$$x'' + x = s\,a - \varphi, \qquad \text{or stick while } |x + \varphi| \le b.$$"""),
    ("Hysteretic contact law", r"""On first loading the force follows the compression
envelope, and it always stays between the two envelopes
$$\varphi_C(\delta) = \frac{k_{c0}\,D\,\delta}{D - \delta}, \qquad
\varphi_E(\delta) = \frac{k_{e0}\,D\,\delta}{D - \delta}, \qquad k_{e0} \le k_{c0},$$
which grow without bound as \(\delta\) nears the limit overlap \(D\). After the overlap turns
at \((\delta_r, \varphi_r)\), the force moves exponentially towards the envelope of the new
direction:
$$\text{unloading: } \varphi = \varphi_E + (\varphi_r - \varphi_E(\delta_r))\,
e^{-\beta_e(\delta_r - \delta)/D},$$
$$\text{reloading: } \varphi = \varphi_C - (\varphi_C(\delta_r) - \varphi_r)\,
e^{-\beta_c(\delta - \delta_r)/D}.$$
The area of a loop of \(\varphi\) against \(\delta\) is the energy the stop takes. A stiff stop
with a sharp turn (large \(\beta\)) acts like a rigid stop with
\(r_{eq} = \sqrt{k_{e0}/k_{c0}}\)."""),
)

#: What a student needs beyond the laws: the paper's closed-form results (HTML with TeX).
DETAILS = r"""<p><b>Critical speed.</b> From the start \((x_0, x_0')\) the belt is
<i>fast</i> if \(v \gt v^* = \sqrt{(x_0 - a)^2 + x_0'^2}\) (from rest \(v^* = a\)): the
block slides for ever on the circle about \((a, 0)\) through the start. A <i>slow</i> belt,
\(v \le v^*\), settles on the stick&ndash;slip cycle: stick from \(2a - b\) to \(b\), then a
slip arc of radius \(R = \sqrt{(b - a)^2 + v^2}\) back to the belt speed; the farthest point
is \(x_{\max} = a + R\).</p>
<p><b>Slow belt with a stop</b> (start at rest). Case a, \(b \le \bar x \lt x_{\max}\):
stick, slip, impact, slip back. Case b, \(x^* \le \bar x \lt b\): the stick runs into the
stop. Case c, \(\bar x \lt x^*\): the rebound never reaches the belt speed again. The
boundary is \(x^* = a + v\sqrt{1 - r^2}\): after the rebound at \((\bar x, -r v)\) the slip
circle about \((a, 0)\) has the radius \(\sqrt{(\bar x - a)^2 + r^2 v^2}\), which reaches
the belt speed exactly when it is at least \(v\). (The paper prints
\(a + v/\sqrt{1 - r^2}\); the geometry and every solver give the form above.)</p>
<p><b>Grazing and accumulation.</b> With \(0 \lt r \lt 1\) and no stick, each arc about
\((a, 0)\) brings the block back to the stop at the speed it left with, so the impact speeds
fall as \(w_h = r^h w_0\). If \(\bar x \ge a\) the impacts never stop and the motion tends
to the circle that touches the stop (grazing). If \(\bar x \lt a\) each arc lasts
\(2\arctan(w_h/(a - \bar x))\), the durations shrink geometrically and the impacts end at
the finite time \(t_{acc}\); then the belt presses the block on the stop with the force
\(k\,(a - \bar x)\).</p>
<p><b>What the page computes.</b> Slip arcs and stick segments are exact, so a rigid stop's
whole response is a chain of closed forms; the contact with a deformable stop is integrated
numerically. The two readings of the contact law: the paper's reproduces its Fig. 2b but
some closed overlap programs give back more energy than they took; the passive one never
does (every loop inside the envelopes is elastic, the loss happens on the compression
envelope). A small contact, with overlap below about \(D/\beta_e\), never leaves
\(\varphi_C\) and is elastic under both, so a train of small contacts tends to a small
steady impact speed rather than to zero.</p>"""


def glossary_html() -> str:
    """The glossary as a table: symbol, meaning, dimensionless definition."""
    rows = []
    for s in GLOSSARY.values():
        rows.append(f"<tr id='fie-gl-{s.key}'><td>\\({s.tex}\\)</td>"
                    f"<td>{html.escape(s.meaning)}</td><td>\\({s.definition}\\)</td></tr>")
    return ("<table class='fie-glossary'><tr><th>symbol</th><th>meaning</th>"
            "<th>definition</th></tr>" + "".join(rows) + "</table>")


@functools.cache
def model_html() -> str:
    """The whole model card: drawing, laws, glossary and details (built once per
    process, on the first page that opens it)."""
    laws = "".join(f"<div class='fie-law'><h4>{html.escape(head)}</h4>{body}</div>"
                   for head, body in LAWS)
    return (f"<div class='fie-model'>{mechanism_svg()}<div class='fie-laws'>{laws}</div>"
            f"<h4>Symbols</h4>{glossary_html()}"
            f"<details class='fie-details'><summary>Details: what the theory predicts"
            f"</summary>{DETAILS}</details></div>")
