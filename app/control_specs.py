"""What the page's controls say and how they are bound: each slider's label, step and
tooltip, the SI boxes and the state values they convert to, the groups that join the page
when first shown, and the constraints between values.

Pure tables and texts (no widget is made here): :mod:`app.controls` builds the widgets from
them, :mod:`app.commit_rules` applies the constraints.
"""

from __future__ import annotations

from collections.abc import Mapping

from app.scenes import DEFAULT_SCENE, SCENES
from app.solve.presets import ACCURACY
from app.state import ACCURACIES, SI_NAMES, SI_STATE_KEYS
from app.teach.glossary import BETAS
from app.teach.glossary import PLAIN as _S
from app.teach.glossary import tooltip as glossary_tooltip

#: Slider label and step of each numeric state parameter, its symbols the glossary's.
SLIDERS: Mapping[str, tuple[str, float]] = {
    "belt_speed": (f"belt speed {_S['v']}", 0.001),
    "clearance": (f"clearance {_S['x_bar']}", 0.001),
    "restitution": (f"restitution {_S['r']}", 0.01),
    "mu_s": (f"static friction {_S['mu_s']}", 0.005),
    "mu_k": (f"kinetic friction {_S['mu_k']}", 0.005),
    "u_s": (f"static deflection {_S['u_s']} = {_S['F_N']}/{_S['k']}", 0.01),
    "k_c0": (f"compression stiffness {_S['k_c0']}/{_S['k']}", 1.0),
    "k_e0": (f"expansion stiffness {_S['k_e0']}/{_S['k']}", 1.0),
    "limit_overlap": (f"limit overlap {_S['D']}", 0.0005),
    "beta_c": (f"{BETAS[0]} (towards compression)", 0.5),
    "beta_e": (f"{BETAS[1]} (towards expansion)", 0.5),
    "x0": (f"initial displacement {_S['x0']}", 0.005),
    "v0": (f"initial velocity {_S['v0']}", 0.005),
    "t_end": (f"horizon {_S['t_end']}", 1.0),
    "mass": (f"mass {_S['m']} (kg)", 0.01),
    "stiffness": (f"stiffness {_S['k']} (N/m)", 1.0),
}
#: What each symbol means (the box's tooltip; the allowed range is added to it).
TOOLTIPS: Mapping[str, str] = {
    "belt_speed": "Belt speed v = v_dr / ω (a length in these units).",
    "clearance": f"Stop position {_S['x_bar']}, measured from the unstretched spring.",
    "restitution": "Newton's coefficient r: rebound speed over impact speed.",
    "mu_s": f"Static friction coefficient; b = {_S['mu_s']} {_S['u_s']} is the stick limit.",
    "mu_k": f"Kinetic friction coefficient (at most {_S['mu_s']}); a = {_S['mu_k']} "
            f"{_S['u_s']} is the slip centre.",
    "u_s": f"Static deflection {_S['u_s']} = {_S['F_N']} / k: the spring stretch the normal "
           "force makes.",
    "k_c0": "Slope of the compression envelope at zero overlap, over k (Eq. 11).",
    "k_e0": f"Slope of the expansion envelope at zero overlap, over k (at most {_S['k_c0']}; "
            "Eq. 11).",
    "limit_overlap": "Limit overlap D: both envelopes grow without bound as the overlap "
                     "nears D, so the stop cannot be pushed past it (Eq. 11).",
    "beta_c": "How fast a reloading curve approaches the compression envelope, per D "
              f"(at most {BETAS[1]}; Eq. 13).",
    "beta_e": "How fast an unloading curve approaches the expansion envelope, per D (Eq. 13).",
    "x0": "Initial displacement of the mass.",
    "v0": "Initial velocity of the mass.",
    "t_end": "Length of the simulated run (dimensionless time t = ω τ).",
    "mass": "Mass m of the oscillator.",
    "stiffness": "Stiffness k of the spring.",
    "normal_force": f"Normal force {_S['F_N']} = k L {_S['u_s']} pressing the mass on the belt.",
    "belt_speed_si": "Belt speed v_dr = ω L v.",
    "v0_si": "Initial velocity of the mass.",
    "t_end_si": "Length of the simulated run in seconds.",
    "k_c0_si": "Slope of the compression envelope at zero overlap (Eq. 11).",
    "k_e0_si": f"Slope of the expansion envelope at zero overlap (at most {_S['k_c0']}; "
               "Eq. 11).",
    "length_unit_si": "Length unit L: the length a dimensionless 1 of the scene stands for "
                      "(lengths are shown in mm, 1000 L times their number). A new L resizes "
                      f"the rig ({_S['F_N']}, v_dr and every length scale with it); the "
                      "dimensionless scene stays.",
    "clearance_si": f"Stop position {_S['x_bar']} in mm, measured from the unstretched spring.",
    "x0_si": "Initial displacement of the mass, in mm.",
    "limit_overlap_si": "Limit overlap D in mm: both envelopes grow without bound as the "
                        "overlap nears D, so the stop cannot be pushed past it (Eq. 11).",
}
# Each symbol's tooltip links to its line of the model card's glossary.
TOOLTIPS = {name: glossary_tooltip(name, text) for name, text in TOOLTIPS.items()}
#: What each reading of the contact law means (the selector's tooltip; docs/contact-law.md
#: explains both; the page says it in these words).
CONTACT_LAW_TIPS: Mapping[str, str] = {
    "paper": "the paper's reading of Eqs. 12-13, which reproduces Fig. 2b; each reversal "
             "restarts the exponential from the reversal point. Not passive: some closed "
             "overlap programs give back more energy than they took",
    "passive": "the same envelopes and exponential, but loading inside the band retraces "
               "the unloading curve (elastic inside the band, loss on the envelope): no "
               "closed overlap program returns energy",
}
#: What each method models (the method selector's tooltip).
METHOD_TIPS: Mapping[str, str] = {
    "auto": "exact where it applies",
    "exact": "closed-form slip arcs and stick segments, Newton impacts; a deformable stop's "
             "contact integrated",
    "event": "solve_ivp on the non-smooth model, stopping at each stick, slip and contact "
             "event",
    "switch": "the paper's switch model: a stick band of width eta, integrated by RKF 4(5)",
}
#: SI widgets derived from the state through ExplorerState.physical / from_physical:
#: name -> (label, step, key of ExplorerState.physical()).
SI_SLIDERS: Mapping[str, tuple[str, float, str]] = {
    name: (f"{SI_NAMES[state][1]} ({unit})", step, SI_NAMES[state][0])
    for name, (state, unit, step) in {
        "length_unit_si": ("length_unit", "mm", 0.1),
        "normal_force": ("u_s", "N", 0.01),
        "belt_speed_si": ("belt_speed", "m/s", 0.001),
        "v0_si": ("v0", "m/s", 0.001),
        "t_end_si": ("t_end", "s", 0.01),
        "k_c0_si": ("k_c0", "N/m", 1.0),
        "k_e0_si": ("k_e0", "N/m", 1.0),
        "clearance_si": ("clearance", "mm", 0.01),
        "limit_overlap_si": ("limit_overlap", "mm", 0.001),
        "x0_si": ("x0", "mm", 0.01),
    }.items()
}
#: The state value each SI value converts to (its bounds, in SI, are the SI box's).
SI_STATE_NAME: Mapping[str, str] = SI_STATE_KEYS
#: SI sliders that stand for a dimensionless one in SI mode (the SI box in its place, its
#: slider range the dimensionless one's times the factor of app.state.si_units).
SI_TWINS: Mapping[str, str] = {
    "v0_si": "v0", "t_end_si": "t_end", "k_c0_si": "k_c0", "k_e0_si": "k_e0",
    "clearance_si": "clearance", "limit_overlap_si": "limit_overlap", "x0_si": "x0",
}
#: Sliders in groups that join the page when first shown (:class:`~app.widgets.ShownLater`):
#: the deformable stop's, the SI set's and the SI twins of the start and horizon. A new
#: page makes their widgets only then.
HYSTERETIC_SLIDERS = ("k_c0", "k_c0_si", "k_e0", "k_e0_si", "limit_overlap",
                      "limit_overlap_si", "beta_c", "beta_e")
SI_BOX_SLIDERS = ("mass", "stiffness", "length_unit_si", "normal_force", "belt_speed_si")
SI_START_SLIDERS = ("clearance_si", "x0_si", "v0_si", "t_end_si")
SHOWN_LATER = frozenset(HYSTERETIC_SLIDERS + SI_BOX_SLIDERS + SI_START_SLIDERS)
#: Constraints kept by the widgets: the first may not exceed the second.
CONSTRAINTS = (("mu_k", "mu_s"), ("k_e0", "k_c0"), ("beta_c", "beta_e"))
#: Smallest mu_s the slider allows (a zero-width mu_k slider cannot be drawn).
MU_S_MIN = 0.005
#: Width of the sidebar widgets [px].
WIDGET_WIDTH = 290
#: Soft range of the SI sliders, as multiples of their current value.
SI_SOFT_SPAN = 3.0
#: The figure the reset button returns to when the page opens on custom values.
DEFAULT_FIGURE = DEFAULT_SCENE


def reset_label(scene: str) -> str:
    """The reset button's label, naming the figure it returns to.

    >>> reset_label("7c")
    'Reset to Fig. 7c'
    """
    return f"Reset to Fig. {scene}" if scene in SCENES else f"Reset to Fig. {DEFAULT_FIGURE}"


def accuracy_tip() -> str:
    """The accuracy presets in one tooltip, from :data:`app.solve.presets.ACCURACY`."""
    parts = [f"{name}: rtol {ACCURACY[name]['rtol']:g}, switch band eta "
             f"{ACCURACY[name]['eta']:g}, {ACCURACY[name]['n_samples']} samples"
             for name in ACCURACIES]
    return ("; ".join(parts) + ". The exact method on no stop or a rigid stop is closed form "
            "at every preset: only the smoothness of the curves changes. No preset promises "
            "an error: a full run that integrates has its error measured (the Solve row).")
