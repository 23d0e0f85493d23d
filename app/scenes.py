"""The paper's figures as scenes: parameters that satisfy each figure's conditions.

Every scene is one record: the state values it loads, a one-line caption of what to look for, the
plots it needs, and its conditions written in the paper's terms (docs/physics.md, "Closed-form
results") as predicates on the dimensionless parameters. The conditions are restated here from the
paper, independently of :mod:`core.theory`, so that the tests can check each scene against the
theory's own classification.

The scenes share one friction pair, ``mu_s = 0.3``, ``mu_k = 0.2``, ``u_s = 1`` (so
``a = 0.2``, ``b = 0.3`` and ``2a - b = 0.1``), and pick the belt speed and clearance that
put the response into the figure's case with margins that are visible in the phase plane.

Examples
--------
>>> SCENES["5b"].values["clearance"]
0.25
>>> all(check for _, check in SCENES["5b"].check())
True
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

#: Plot identifiers, in the order the page shows them.
PLOTS = ("phase", "time", "anim", "force", "loop", "friction", "energy", "map", "return")
#: Human names of the plots (titles of the panes).
PLOT_TITLES = MappingProxyType(
    {
        "phase": "Phase portrait",
        "time": "Time histories",
        "force": "Contact force",
        "loop": "Hysteresis loop",
        "friction": "Friction law",
        "energy": "Energy",
        "map": "Regime map",
        "anim": "Mechanism",
        "return": "Return map",
    }
)

#: Plots of a scene with no stop: no contact force is computed, so plots 3-4 are left out.
IMPACTLESS_PLOTS = ("phase", "time", "friction", "energy", "map", "anim")
#: Plots of a rigid-stop scene: those of the paper's Figs. 4-9 (impulses as stems), the
#: regime map of Sec. 4, the mechanism and the return map of the impacts (Sec. 2.5; built
#: when scrolled to, at the page's foot). The energy budget is one tick away ("show all
#: plots"); left out by default, each release repaints one figure less (10 ms less from
#: release to picture in scenes 5b and 7c, paired in one browser; benchmarks/README.md).
RIGID_PLOTS = ("phase", "time", "force", "map", "anim", "return")
#: Plots of a hysteretic-stop scene (the return map follows the contacts' speeds).
HYSTERETIC_PLOTS = ("phase", "time", "force", "loop", "energy", "anim", "return")

#: The friction pair all scenes share: ``a = mu_k u_s = 0.2``, ``b = mu_s u_s = 0.3``.
BASE = MappingProxyType(
    {
        "mu_s": 0.3,
        "mu_k": 0.2,
        "u_s": 1.0,
        "x0": 0.0,
        "v0": 0.0,
        "t_end": 60.0,
        "stop_type": "rigid",
        "restitution": 1.0,
        "program": False,
    }
)
#: Slow belt of the elastic scenes (Figs. 5, 8): ``x_max = a + sqrt((b-a)^2 + v^2) = 0.3414``.
V_SLOW_ELASTIC = 0.1
#: Slow belt of the inelastic scenes (Figs. 7, 9-11); with ``R_INELASTIC`` this puts
#: ``x* = a + v sqrt(1-r^2) = 0.2668`` between ``a`` and ``b`` and ``x_max = 0.3221`` above ``b``.
V_SLOW_INELASTIC = 0.07
#: Restitution of the inelastic scenes (also the equivalent restitution of Figs. 10-11).
R_INELASTIC = 0.3
#: Fast belt (Figs. 4, 6): above the critical speed ``v* = a = 0.2`` of natural conditions.
V_FAST = 0.3


Check = Callable[[Mapping[str, float]], bool]


def _quantities(values: Mapping[str, float]) -> dict[str, float]:
    """The paper's characteristic quantities of a scene, dimensionless (docs/physics.md,
    "Closed-form results")."""
    a = values["mu_k"] * values["u_s"]
    b = values["mu_s"] * values["u_s"]
    v = values["belt_speed"]
    r = values.get("restitution", 1.0)
    if values.get("stop_type") == "hysteretic":
        r = math.sqrt(values["k_e0"] / values["k_c0"])
    x0, v0 = values.get("x0", 0.0), values.get("v0", 0.0)
    return {
        "a": a,
        "b": b,
        "v": v,
        "r": r,
        "x_bar": values.get("clearance", math.inf),
        "v_crit": math.hypot(x0 - a, v0),  # Eq. (25)
        "x_max_slow": a + math.hypot(b - a, v),  # Eq. (23)
        # Eq. (35) as rederived in core.theory: the rebound circle reaches the stick line.
        "x_star": a + v * math.sqrt(1.0 - r * r),
        "gamma0": math.hypot(x0 - a, v0) < v,  # start inside Gamma_0, Eq. (21)
    }


@dataclass(frozen=True)
class Scene:
    """One figure of the paper as a state of the explorer.

    Attributes
    ----------
    key : str
        The figure's label, e.g. ``"7c"``.
    title : str
        What the figure shows, as in the paper's caption.
    caption : str
        One line: what to look for.
    values : Mapping[str, float | str | bool]
        State parameters the scene sets (the rest keep :data:`BASE`).
    plots : tuple of str
        The plots the scene needs, from :data:`PLOTS`.
    conditions : tuple of (str, Check)
        The figure's conditions in the paper's terms, each with a predicate on ``values``.
    expect : Mapping[str, str]
        What :func:`core.theory.classify` should say: lower-case words that must appear in
        the named field of its regime (``belt``, ``impact``, ``case``).
    """

    key: str
    title: str
    caption: str
    values: Mapping[str, float | str | bool]
    plots: tuple[str, ...]
    conditions: tuple[tuple[str, Check], ...] = ()
    expect: Mapping[str, str] = field(default_factory=dict)

    def check(self) -> list[tuple[str, bool]]:
        """Evaluate the scene's conditions: ``[(text, holds), ...]``."""
        return [(text, bool(pred(self.values))) for text, pred in self.conditions]


def _q(name: str) -> Callable[[Mapping[str, float]], float]:
    return lambda values: _quantities(values)[name]


_a, _b, _v, _xb = _q("a"), _q("b"), _q("v"), _q("x_bar")
_vc, _xm, _xs, _r = _q("v_crit"), _q("x_max_slow"), _q("x_star"), _q("r")

FAST: tuple[str, Check] = ("fast belt: v > v* (Eq. 25)", lambda s: _v(s) > _vc(s))
SLOW: tuple[str, Check] = ("slow belt: v <= v* (Eq. 25)", lambda s: _v(s) <= _vc(s))
ELASTIC: tuple[str, Check] = ("elastic impact: r = 1", lambda s: _r(s) == 1.0)
INELASTIC: tuple[str, Check] = ("inelastic impact: r < 1", lambda s: _r(s) < 1.0)
START_AHEAD: tuple[str, Check] = ("the start lies left of the stop", lambda s: s["x0"] < _xb(s))


def _scene(key, title, caption, values, plots, conditions, expect) -> Scene:
    merged = dict(BASE)
    merged.update(values)
    conds = (*conditions, START_AHEAD) if merged["stop_type"] != "none" else tuple(conditions)
    return Scene(key, title, caption, MappingProxyType(merged), plots, conds,
                 MappingProxyType(expect))


_HYST = {
    "stop_type": "hysteretic",
    # k_e0/k_c0 = 0.09 gives the equivalent restitution sqrt(0.09) = R_INELASTIC (Eq. 16).
    # The overlaps stay near 0.003, so only a sharp transition (beta * overlap / D ~ 90)
    # makes the contacts that lossy: the first contact of Fig. 10 rebounds with r ~ 0.4
    # (measured, shown in the readout), and Fig. 11 sticks to the stop.
    "k_c0": 400.0,
    "k_e0": 36.0,
    "limit_overlap": 0.01,
    "beta_c": 300.0,
    "beta_e": 300.0,
}

_SCENE_LIST = (
    _scene(
        "2b", "Fig. 2b: cyclic behaviour of the hysteretic stop",
        "Look for the thin loops of force against overlap in the hysteresis plot: their "
        "area is the energy the stop takes. Raise β_e (to 50, say) and the unloading "
        "heads for the lower envelope.",
        {"stop_type": "hysteretic", "program": True, "belt_speed": V_SLOW_INELASTIC,
         "clearance": 0.24, "k_c0": 400.0, "k_e0": 200.0, "limit_overlap": 0.02,
         "beta_c": 5.0, "beta_e": 5.0},
        ("loop", "force"),
        [("k_c0 = 2 k_e0 (paper Fig. 2b)", lambda s: s["k_c0"] == 2.0 * s["k_e0"]),
         ("beta_c = beta_e = 5", lambda s: s["beta_c"] == s["beta_e"] == 5.0)],
        {},
    ),
    _scene(
        "3a", "Fig. 3a: impactless motion, limit curves",
        "Look for the orange stick segment on the line x′ = v, from 2a − b to b, closed "
        "by one slip arc about (a, 0): the limit cycle every start is drawn to.",
        {"stop_type": "none", "belt_speed": V_SLOW_ELASTIC, "x0": 0.45, "v0": 0.25,
         "clearance": 0.5},
        IMPACTLESS_PLOTS,
        [SLOW, ("start outside Γ₀ (Eq. 21)", lambda s: not _quantities(s)["gamma0"])],
        {"belt": "slow"},
    ),
    _scene(
        "3b", "Fig. 3b: impactless motion, transient slip modes",
        "Look for the slip arcs changing their centre between (+a, 0) and (−a, 0) each "
        "time the velocity passes the belt speed, before the first stick.",
        {"stop_type": "none", "belt_speed": V_SLOW_ELASTIC, "x0": -1.0, "v0": 0.0,
         "clearance": 0.5, "t_end": 40.0},
        IMPACTLESS_PLOTS,
        [SLOW, ("|x0| > b: the first arc cannot end in stick", lambda s: abs(s["x0"]) > _b(s))],
        {"belt": "slow"},
    ),
    _scene(
        "4a", "Fig. 4a: elastic impact, fast belt, a < x̄ < 2a",
        "Look for the impacts at (x̄, ±√(x̄(2a − x̄))): the vertical jumps of the phase "
        "portrait, once per turn of the slip circle; no stick.",
        {"belt_speed": V_FAST, "clearance": 0.3, "restitution": 1.0},
        RIGID_PLOTS,
        [FAST, ELASTIC, ("a < x_bar < 2a", lambda s: _a(s) < _xb(s) < 2 * _a(s))],
        {"belt": "fast", "impact": "elastic"},
    ),
    _scene(
        "4b", "Fig. 4b: elastic impact, fast belt, x̄ < a",
        "Look for the short slip arc left of the stop between two impacts, and the "
        "impulses coming quickly.",
        {"belt_speed": V_FAST, "clearance": 0.1, "restitution": 1.0},
        RIGID_PLOTS,
        [FAST, ELASTIC, ("0 < x_bar < a", lambda s: 0 < _xb(s) < _a(s))],
        {"belt": "fast", "impact": "elastic"},
    ),
    _scene(
        "5a", "Fig. 5a: elastic impact, slow belt, case a",
        "Look for one stick segment up to b, one slip arc to the stop, one impact and the "
        "slip back to the stick line: one of each per period.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.32, "restitution": 1.0},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("case a: b <= x_bar < x_max (Eq. 31)",
                         lambda s: _b(s) <= _xb(s) < _xm(s))],
        {"belt": "slow", "impact": "elastic", "case": "a"},
    ),
    _scene(
        "5b", "Fig. 5b: elastic impact, slow belt, case b",
        "Look for the stick segment running straight into the stop, and the rebound at "
        "−v.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.25, "restitution": 1.0},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("case b: a <= x_bar < b (Eq. 32)", lambda s: _a(s) <= _xb(s) < _b(s))],
        {"belt": "slow", "impact": "elastic", "case": "b"},
    ),
    _scene(
        "5c", "Fig. 5c: elastic impact, slow belt, case c",
        "Look for no stick after the transient: the phase portrait jumps from (x̄, v) to "
        "(x̄, −v) and returns on one slip arc.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.15, "restitution": 1.0},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("case c: x_bar < a (Eq. 33)", lambda s: _xb(s) < _a(s)),
         ("x_bar >= 2a - b", lambda s: _xb(s) >= 2 * _a(s) - _b(s))],
        {"belt": "slow", "impact": "elastic", "case": "c"},
    ),
    _scene(
        "5d", "Fig. 5d: elastic impact, slow belt, case c with x̄ < 2a − b",
        "Look for the whole steady loop left of the stick segment's start 2a − b.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.05, "restitution": 1.0},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("x_bar < 2a - b (Fig. 5d)", lambda s: _xb(s) < 2 * _a(s) - _b(s))],
        {"belt": "slow", "impact": "elastic", "case": "c"},
    ),
    _scene(
        "6a", "Fig. 6a: inelastic impact, fast belt, a < x̄ < 2a",
        "Look for the impulses shrinking by the factor r at each impact (rʰ decay) and "
        "the motion closing in on the slip circle that touches the stop.",
        {"belt_speed": V_FAST, "clearance": 0.3, "restitution": 0.7},
        RIGID_PLOTS,
        [FAST, INELASTIC, ("a < x_bar < 2a", lambda s: _a(s) < _xb(s) < 2 * _a(s))],
        {"belt": "fast", "impact": "inelastic"},
    ),
    _scene(
        "6b", "Fig. 6b: inelastic impact, fast belt, x̄ < a",
        "Look for the bounces getting shorter and weaker until they end at a finite time; "
        "then the mass rests pressed on the stop.",
        {"belt_speed": V_FAST, "clearance": 0.1, "restitution": 0.7},
        RIGID_PLOTS,
        [FAST, INELASTIC, ("0 < x_bar < a", lambda s: 0 < _xb(s) < _a(s))],
        {"belt": "fast", "impact": "inelastic"},
    ),
    _scene(
        "7a", "Fig. 7a: inelastic impact, slow belt, case a",
        "Look for the stick to b, the slip to the stop, the rebound at a reduced speed "
        "and the slip back to the stick line, repeating.",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.31, "restitution": R_INELASTIC},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("case a: b <= x_bar < x_max (Eq. 34)",
                           lambda s: _b(s) <= _xb(s) < _xm(s))],
        {"belt": "slow", "impact": "inelastic", "case": "a"},
    ),
    _scene(
        "7b", "Fig. 7b: inelastic impact, slow belt, case b",
        "Look for the stick segment running into the stop and the rebound at −r v, which "
        "still reaches the stick line.",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.285, "restitution": R_INELASTIC},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("case b: x* <= x_bar < b (Eqs. 35-36)",
                           lambda s: _xs(s) <= _xb(s) < _b(s))],
        {"belt": "slow", "impact": "inelastic", "case": "b"},
    ),
    _scene(
        "7c", "Fig. 7c: inelastic impact, slow belt, case c with x̄ > a",
        "Look for the impacts shrinking as rʰ and the loops of the phase portrait closing "
        "in on the circle that grazes the stop; no stick.",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.24, "restitution": R_INELASTIC},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("case c: x_bar < x* (Eq. 37)", lambda s: _xb(s) < _xs(s)),
         ("x_bar > a (grazing)", lambda s: _xb(s) > _a(s))],
        {"belt": "slow", "impact": "inelastic", "case": "c"},
    ),
    _scene(
        "7d", "Fig. 7d: inelastic impact, slow belt, case c with x̄ < a",
        "Look for the bounces accumulating at the stop and the mass resting there, held "
        "by the force k (a − x̄).",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.15, "restitution": R_INELASTIC},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("case c: x_bar < x* (Eq. 37)", lambda s: _xb(s) < _xs(s)),
         ("x_bar < a (rest at the stop)", lambda s: _xb(s) < _a(s))],
        {"belt": "slow", "impact": "inelastic", "case": "c"},
    ),
    _scene(
        "8a", "Fig. 8a: elastic impact, slow belt, start away from rest, x̄ ≥ x_max",
        "Look for the impacts of the transient only; the steady loop is the impactless "
        "limit cycle of Fig. 3a, clear of the stop.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.36, "restitution": 1.0,
         "x0": -0.6, "v0": 0.6},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("x_bar >= x_max (Eq. 23)", lambda s: _xb(s) >= _xm(s)),
         ("a start other than rest", lambda s: (s["x0"], s["v0"]) != (0.0, 0.0))],
        {"belt": "slow"},
    ),
    _scene(
        "8b", "Fig. 8b: elastic impact, slow belt, start away from rest, x̄ < x_max",
        "Look for a different transient ending on the same loop as Fig. 5b: stick into "
        "the stop, rebound at −v.",
        {"belt_speed": V_SLOW_ELASTIC, "clearance": 0.25, "restitution": 1.0,
         "x0": -0.4, "v0": -0.3},
        RIGID_PLOTS,
        [SLOW, ELASTIC, ("a <= x_bar < b (as Fig. 5b)", lambda s: _a(s) <= _xb(s) < _b(s)),
         ("a start other than rest", lambda s: (s["x0"], s["v0"]) != (0.0, 0.0))],
        {"belt": "slow", "impact": "elastic"},
    ),
    _scene(
        "9a", "Fig. 9a: inelastic impact, slow belt, start away from rest, x̄ ≥ x_max",
        "Look for inelastic impacts in the transient only, then the impactless limit "
        "cycle.",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.34, "restitution": R_INELASTIC,
         "x0": -0.6, "v0": 0.6},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("x_bar >= x_max (Eq. 23)", lambda s: _xb(s) >= _xm(s)),
         ("a start other than rest", lambda s: (s["x0"], s["v0"]) != (0.0, 0.0))],
        {"belt": "slow"},
    ),
    _scene(
        "9b", "Fig. 9b: inelastic impact, slow belt, start away from rest, x̄ < x_max",
        "Look for a different transient ending on the same loop as Fig. 7b (stick into "
        "the stop, rebound at −r v).",
        {"belt_speed": V_SLOW_INELASTIC, "clearance": 0.285, "restitution": R_INELASTIC,
         "x0": -0.4, "v0": -0.3},
        RIGID_PLOTS,
        [SLOW, INELASTIC, ("x* <= x_bar < b (as Fig. 7b)", lambda s: _xs(s) <= _xb(s) < _b(s)),
         ("a start other than rest", lambda s: (s["x0"], s["v0"]) != (0.0, 0.0))],
        {"belt": "slow", "impact": "inelastic"},
    ),
    _scene(
        "10", "Fig. 10: hysteretic stop, slow belt, a < x̄ ≤ x*",
        "Look for what differs from Fig. 7c: the contact force dying down through a train of "
        "contacts and detachments, and the hysteresis loops getting smaller. Unlike a "
        "rigid stop's r, smaller contacts lose less (see the readout's restitution): the "
        "impact speeds level off.",
        {**_HYST, "belt_speed": V_SLOW_INELASTIC, "clearance": 0.24, "t_end": 80.0},
        HYSTERETIC_PLOTS,
        [SLOW, ("a < x_bar <= x* (x* with r_eq, Eq. 16)", lambda s: _a(s) < _xb(s) <= _xs(s))],
        {"belt": "slow"},
    ),
    _scene(
        "11", "Fig. 11: hysteretic stop, slow belt, x̄ ≤ a",
        "Look for what differs from Fig. 7d: the contact force settling just below k (a − x̄) "
        "while the loops on the stop die out, the mass at rest inside the stop. The "
        "readout says whether they have by the end of the run.",
        {**_HYST, "belt_speed": V_SLOW_INELASTIC, "clearance": 0.15, "t_end": 80.0},
        HYSTERETIC_PLOTS,
        [SLOW, ("x_bar <= a", lambda s: _xb(s) <= _a(s))],
        {"belt": "slow"},
    ),
)

#: All scenes by figure label, in the paper's order.
SCENES: Mapping[str, Scene] = MappingProxyType({s.key: s for s in _SCENE_LIST})
#: The scene a new session opens with.
DEFAULT_SCENE = "5a"
#: Label of the selector entry for a state that no longer matches a scene.
CUSTOM = "custom"
