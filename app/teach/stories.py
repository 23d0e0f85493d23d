r"""Each scene's story: what the paper's figure shows, in two to four plain sentences, and
its key formula.

The sentences are HTML with inline TeX between ``\(`` and ``\)``; the formula is TeX for a
displayed equation. The "look for" line is the scene's caption (:attr:`app.scenes.Scene.caption`).
A state that is no scene gets :func:`custom_story`: the regime the closed-form theory
predicts for it (:func:`core.theory.classify`) and the comparisons that decide it.

Examples
--------
>>> STORIES["7b"].formula
'x^* = a + v\\sqrt{1 - r^2} \\le \\bar x \\lt b'
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any


@dataclass(frozen=True)
class Story:
    """What a scene's figure shows (HTML with inline TeX) and its key formula (TeX)."""

    shows: str
    formula: str


_LIMIT_CYCLE = r"x_{\max} = a + \sqrt{(b - a)^2 + v^2}"
_FAST_IMPACT = (r"x' = \pm\sqrt{\bar x\,(2a - \bar x)}\ \text{ at } x = \bar x, \qquad "
                r"T = 2\arccos\left(1 - \frac{\bar x}{a}\right)")
_DECAY = r"w_h = r^h\,w_0 \;\to\; 0"
_ACCUMULATION = (r"t_{acc} = t_0 + \sum_{h \ge 1} 2\arctan\frac{r^h w_0}{a - \bar x}"
                 r"\;\lt\; \infty")
_X_STAR = r"x^* = a + v\sqrt{1 - r^2}"

STORIES: Mapping[str, Story] = MappingProxyType({
    "2b": Story(
        r"The deformable stop alone, pushed in and let out by a prescribed overlap "
        r"\(\delta\) of falling amplitude. Loading follows the upper (compression) envelope "
        r"\(\varphi_C\); after each turn the force moves towards the lower (expansion) "
        r"envelope \(\varphi_E\) at a rate set by \(\beta\). Both envelopes grow without "
        r"bound as \(\delta\) nears the limit overlap \(D\).",
        r"\varphi_C(\delta) = \frac{k_{c0}\,D\,\delta}{D - \delta}, \qquad "
        r"\varphi_E(\delta) = \frac{k_{e0}\,D\,\delta}{D - \delta}, \qquad "
        r"\text{energy lost} = \oint \varphi\,\mathrm{d}\delta"),
    "3a": Story(
        r"No stop and a slow belt (\(v \le v^*\)). Started away from rest, the block "
        r"settles on the stick&ndash;slip limit cycle: it rides with the belt along "
        r"\(x' = v\) from \(x = 2a - b\) to \(x = b\), where the spring beats static "
        r"friction, then slips back round a circle about \((a, 0)\) to the belt speed.",
        _LIMIT_CYCLE),
    "3b": Story(
        r"No stop, a start far to the left. While the block slides, friction has the size "
        r"\(a\) and the sign of the relative velocity \(u_r = v - x'\), so the motion is a "
        r"circle about \((+a, 0)\) or \((-a, 0)\) in the phase plane. Each time \(x'\) "
        r"passes the belt speed the centre changes, until the block first sticks.",
        r"x'' + x = a\,\operatorname{sign}(v - x')"),
    "4a": Story(
        r"A fast belt (\(v \gt v^* = a\)): the block never sticks and slides on the circle "
        r"about \((a, 0)\) through the rest position. A stop with \(a \lt \bar x \lt 2a\) "
        r"cuts that circle: an elastic impact (\(r = 1\)) reverses the velocity and the "
        r"block goes round the rest of the circle to hit again.",
        _FAST_IMPACT),
    "4b": Story(
        r"The same fast belt with the stop left of the circle's centre, "
        r"\(0 \lt \bar x \lt a\). Between two impacts the block travels only the short arc "
        r"of the circle left of the stop, so the impacts come quickly.",
        _FAST_IMPACT),
    "5a": Story(
        r"A slow belt and an elastic stop beyond the stick limit, \(b \le \bar x \lt "
        r"x_{\max}\) (case a). The block sticks up to \(x = b\), slips forward, hits the "
        r"stop, and slips back to the belt speed, where it sticks again: one stick, two "
        r"slips and one impact per period.",
        r"b \le \bar x \lt " + _LIMIT_CYCLE),
    "5b": Story(
        r"The stop lies on the stick segment, \(a \le \bar x \lt b\) (case b): the block "
        r"rides with the belt straight into the stop at speed \(v\). The elastic impact "
        r"sends it back at \(-v\), and it slips round to the belt speed again.",
        r"x'(+) = -r\,x'(-) = -v \qquad (r = 1)"),
    "5c": Story(
        r"A stop left of the slip centre, \(2a - b \le \bar x \lt a\) (case c). After the "
        r"start the block never sticks again: it leaves the stop at \(-v\), slips round a "
        r"short arc about \((a, 0)\), and comes back at \(+v\).",
        r"(\bar x, -v) \;\to\; (\bar x, +v) \text{ on } (x - a)^2 + x'^2 = "
        r"(\bar x - a)^2 + v^2"),
    "5d": Story(
        r"Case c with the stop still farther left, \(\bar x \lt 2a - b\), left of where "
        r"the impactless cycle's stick begins. The steady motion lies wholly outside that "
        r"cycle: impact, slip arc, impact.",
        r"\bar x \lt 2a - b"),
    "6a": Story(
        r"A fast belt and an inelastic stop (\(r \lt 1\)) with \(a \lt \bar x \lt 2a\). "
        r"Each impact keeps the fraction \(r\) of the speed, and the arc back to the stop "
        r"returns at the speed it left with, so the impact speeds shrink geometrically. "
        r"The motion tends to the slip circle about \((a, 0)\) that just touches the stop "
        r"(grazing).",
        _DECAY),
    "6b": Story(
        r"The same with the stop left of the centre, \(\bar x \lt a\). The shrinking "
        r"bounces also get shorter, so infinitely many of them end at a finite time "
        r"\(t_{acc}\) (an accumulation); then the belt holds the mass pressed on the stop.",
        _ACCUMULATION),
    "7a": Story(
        r"A slow belt and an inelastic stop beyond the stick limit, \(b \le \bar x \lt "
        r"x_{\max}\) (case a). The block sticks to \(b\), slips to the stop, hits it at "
        r"the speed \(w\), rebounds at \(r w\) and slips back to the stick line: a periodic "
        r"motion.",
        r"w = \sqrt{v^2 + (b - a)^2 - (\bar x - a)^2}"),
    "7b": Story(
        r"The stop on the stick segment, \(x^* \le \bar x \lt b\) (case b). The block rides "
        r"into the stop at \(v\) and rebounds at \(-r v\); the rebound circle about "
        r"\((a, 0)\) is still big enough to reach the belt speed, so the block sticks "
        r"again. The belt's pull during the stick makes up what each impact takes.",
        _X_STAR + r" \le \bar x \lt b"),
    "7c": Story(
        r"Below the critical clearance, \(a \lt \bar x \lt x^*\) (case c): the rebound "
        r"circle no longer reaches the belt speed, so the block never sticks again. Its "
        r"impact speeds shrink by \(r\) at each impact and the motion tends to the slip "
        r"circle that grazes the stop.",
        r"w_h = r^h\,w_0, \qquad \bar x \lt " + _X_STAR),
    "7d": Story(
        r"Case c with \(\bar x \lt a\): the slip centre lies beyond the stop. The impacts "
        r"accumulate in a finite time and the mass ends at rest, pressed on the stop by "
        r"the belt with the force \(k\,(a - \bar x)\).",
        _ACCUMULATION),
    "8a": Story(
        r"An elastic stop beyond the impactless motion, \(\bar x \ge x_{\max}\), and a "
        r"start far from rest. The block may hit the stop while it settles, but the "
        r"steady motion is the stick&ndash;slip cycle of Fig. 3a, which never reaches the "
        r"stop.",
        r"\bar x \ge " + _LIMIT_CYCLE),
    "8b": Story(
        r"The stop of Fig. 5b (\(a \le \bar x \lt b\)) and a start far from rest. The "
        r"transient differs, yet the motion settles on the same cycle as Fig. 5b: stick "
        r"into the stop, rebound at \(-v\).",
        r"a \le \bar x \lt b"),
    "9a": Story(
        r"An inelastic stop beyond the impactless motion, \(\bar x \ge x_{\max}\), and a "
        r"start far from rest. Impacts happen only while the motion settles, and each takes "
        r"energy; then the block follows the impactless stick&ndash;slip cycle of Fig. 3a.",
        r"\bar x \ge " + _LIMIT_CYCLE),
    "9b": Story(
        r"The stop of Fig. 7b (\(x^* \le \bar x \lt b\)) and a start far from rest. The "
        r"transient differs, yet the motion settles on the same cycle as Fig. 7b: stick "
        r"into the stop, rebound at \(-r v\), slip back to the belt speed.",
        _X_STAR + r" \le \bar x \lt b"),
    "10": Story(
        r"A deformable stop instead of the rigid one of Fig. 7c, with "
        r"\(a \lt \bar x \le x^*\). The contact force dies down through a train of "
        r"contacts and detachments and the motion tends to graze the stop. The stop "
        r"behaves like a rigid one with \(r_{eq}\) only for deep contacts; the small ones "
        r"are nearly elastic, so the impact speeds level off at a small speed instead of "
        r"zero.",
        r"r_{eq} = \sqrt{k_{e0}/k_{c0}}, \qquad x^* = a + v\sqrt{1 - r_{eq}^2}"),
    "11": Story(
        r"A deformable stop instead of the rigid one of Fig. 7d, with \(\bar x \le a\): "
        r"the belt keeps the mass on the stop. The loops of force against overlap shrink "
        r"and the mass comes to rest inside the stop, where the stop's force balances "
        r"friction and the spring.",
        r"\varphi \to a - x \;\approx\; a - \bar x \qquad (\text{force } k\,(a - x))"),
})


def _num(value: float) -> str:
    return f"{value:.4g}"


def _belt(regime: Any, v: float, v_star: float) -> str:
    if regime.belt == "fast":
        return (rf"The belt is fast, \(v = {_num(v)} \gt v^* = {_num(v_star)}\): the block "
                r"never sticks and slides round a circle about \((a, 0)\).")
    return (rf"The belt is slow, \(v = {_num(v)} \le v^* = {_num(v_star)}\): the block "
            r"sticks to the belt whenever it reaches the belt speed with \(|x| \le b\).")


def _stop(regime: Any, q: Mapping[str, float]) -> str:
    if q["x_bar"] is None:
        return "There is no stop."
    if regime.impactless:
        return (rf"The stop, at \(\bar x = {_num(q['x_bar'])}\), lies beyond the farthest "
                r"point of the motion without it, so the steady motion never touches it.")
    where = rf"\(\bar x = {_num(q['x_bar'])}\), \(a = {_num(q['a'])}\), \(b = {_num(q['b'])}\)"
    if regime.case == "a":
        why = r"\(b \le \bar x \lt x_{\max}\) (case a): stick, slip to the stop, slip back."
    elif regime.case == "b":
        why = (rf"\(x^* = {_num(q['x_star'])} \le \bar x \lt b\) (case b): the stick runs "
               r"into the stop and the rebound reaches the belt speed again.")
    elif regime.case == "c":
        why = (rf"\(\bar x \lt x^* = {_num(q['x_star'])}\) (case c): the rebound never "
               r"reaches the belt speed again.")
    elif q["x_bar"] < q["a"]:
        why = r"\(\bar x \lt a\): the slip circle's centre lies beyond the stop."
    else:
        why = r"\(\bar x \ge a\): the slip circle can pass the stop."
    return f"With {where}: {why}"


_STEADY = {
    "periodic": "a periodic motion",
    "grazing": "grazing: ever weaker impacts, tending to a slip circle that touches the stop",
    "rest": "rest pressed on the stop, after impacts that accumulate in a finite time",
    "equilibrium": "rest where the spring and friction balance",
    "pure_slip": "endless slip on one circle",
}


def custom_story(regime: Any, q: Mapping[str, Any]) -> str:
    """The story of a state that is no scene: the regime the theory predicts and why.

    Parameters
    ----------
    regime : core.theory.Regime
        :func:`core.theory.classify` of the state (a deformable stop as its equivalent
        rigid stop, Eq. 16).
    q : mapping
        ``a``, ``b``, ``v``, ``r``, ``v_star``, ``x_star`` and ``x_bar`` (None: no stop).
    """
    parts = [_belt(regime, q["v"], q["v_star"]), _stop(regime, q)]
    if q["x_bar"] is not None and not regime.impactless:
        r = q["r"]
        kind = ("elastic" if r == 1 else "plastic" if r == 0 else "inelastic")
        parts.append(rf"The impacts are {kind}, \(r = {_num(r)}\).")
    steady = _STEADY.get(regime.expected_steady, regime.expected_steady)
    parts.append(f"So the theory predicts <b>{steady}</b>.")
    return " ".join(parts)


def custom_quantities(osc: Any, rigid: Any, x0: float, v0: float) -> dict[str, Any]:
    """The numbers :func:`custom_story` compares, from the core's oscillator and (rigid or
    equivalent rigid) stop."""
    a, b, v = osc.a, osc.b, osc.v
    r = rigid.restitution if rigid is not None else 1.0
    return {"a": a, "b": b, "v": v, "r": r, "v_star": math.hypot(x0 - a, v0),
            "x_star": a + v * math.sqrt(max(1.0 - r * r, 0.0)),
            "x_bar": rigid.clearance if rigid is not None else None}
