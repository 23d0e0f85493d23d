"""The explorer's UI state: one ``param.Parameterized`` that maps to the core's inputs.

The state holds the dimensionless parameters of the core (docs/physics.md, "Dimensionless form")
whatever the units shown: in SI mode the widgets for the normal force ``F_N`` [N] and the belt speed
``v_dr`` [m/s] convert through :meth:`core.Oscillator.from_physical` with the mass ``m`` [kg] and
stiffness ``k`` [N/m] kept here too, and those for the initial velocity [m/s] and the horizon [s]
through ``omega = sqrt(k/m)``.
In SI mode a dimensionless length stands for the length unit ``L`` [m] (``length_unit``), and
the page shows lengths in millimetres (docs/physics.md, "The page's SI units").

Examples
--------
>>> state = ExplorerState(belt_speed=0.1, clearance=0.25, restitution=1.0)
>>> osc, stop = state.core_inputs()[:2]
>>> round(osc.a, 12), stop.clearance
(0.2, 0.25)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import param

from app.scenes import CUSTOM, DEFAULT_SCENE, SCENES
from app.teach.glossary import PLAIN as _S
from app.teach.glossary import subscripted
from core import HystereticStop, Oscillator, RigidStop, check_range, check_start

#: Stop types offered in the page.
STOP_TYPES = ("none", "rigid", "hysteretic")
#: Unit systems offered in the page.
UNITS = ("dimensionless", "SI")
#: Accuracy presets; their method settings live in :data:`app.solve.presets.ACCURACY`.
ACCURACIES = ("draft", "standard", "precise")
#: Methods: ``auto`` picks the exact solver where it applies (no stop, rigid stop).
METHODS = ("auto", "exact", "event", "switch")
#: Readings of the deformable stop's contact law (``HystereticStop.law``,
#: docs/contact-law.md).
CONTACT_LAWS = ("paper", "passive")

#: Parameters that change the physics or the solve (a change triggers a new solve).
SOLVE_PARAMS = (
    "belt_speed", "clearance", "restitution", "mu_s", "mu_k", "u_s", "stop_type",
    "k_c0", "k_e0", "limit_overlap", "beta_c", "beta_e", "contact_law", "x0", "v0", "t_end",
    "accuracy", "method", "program",
)
#: Of those, how the motion is solved, not which motion: a scene keeps its name (title,
#: caption) under any of them, as loading a scene keeps the ones chosen.
SOLVER_CHOICES = ("accuracy", "method")
#: Of those, how long the motion is watched, not which motion: a scene keeps its name and
#: caption over any horizon (a long run of a figure is still that figure).
HORIZON_CHOICES = ("t_end",)
#: SI values the state converts from (:meth:`ExplorerState.from_physical`): mass [kg],
#: stiffness [N/m], normal force [N], belt speed [m/s], initial velocity [m/s], horizon [s],
#: the deformable stop's initial compression and expansion stiffnesses [N/m], the length
#: unit L and the clearance, initial displacement and limit overlap [mm].
SI_KEYS = ("m", "k", "normal_force", "belt_speed", "v0", "t_end", "k_c0", "k_e0", "L",
           "clearance", "x0", "limit_overlap")
#: Lengths among the state's values: shown in millimetres in SI, ``1e3 L`` times the number.
LENGTHS = ("clearance", "x0", "limit_overlap")
#: Default length unit L [m] of SI mode: the scenes' u_s = 1 is a static deflection of 10 mm,
#: a normal force F_N = k L u_s = 2 N on the default 200 N/m spring (a bench rig).
DEFAULT_LENGTH_UNIT = 0.01
#: Length unit [m] of an SI link that names none: before the page had one, an SI link read
#: its lengths in metres (its speeds and the normal force too).
LEGACY_LENGTH_UNIT = 1.0
#: Millimetres per metre: SI mode shows lengths in millimetres.
MM_PER_M = 1e3
#: Stop stiffnesses: the state holds them over k (docs/physics.md, "Dimensionless form"),
#: SI shows them in N/m.
STOP_STIFFNESSES = ("k_c0", "k_e0")
#: Parameters that only change how results are shown.
VIEW_PARAMS = ("units", "mass", "stiffness", "length_unit", "show_all")
#: Parameter name -> query-string key of the permalink (short keys keep URLs readable).
#: ``figure`` is written only beside ``scene=custom``: a paper scene is its own figure.
URL_KEYS: Mapping[str, str] = {
    "scene": "scene", "belt_speed": "v", "clearance": "xbar", "restitution": "r",
    "mu_s": "mus", "mu_k": "muk", "u_s": "us", "stop_type": "stop", "k_c0": "kc0",
    "k_e0": "ke0", "limit_overlap": "D", "beta_c": "bc", "beta_e": "be", "x0": "x0",
    "v0": "v0", "t_end": "tend", "accuracy": "acc", "method": "method", "program": "prog",
    "units": "units", "mass": "m", "stiffness": "k", "length_unit": "L", "show_all": "all",
    "contact_law": "law", "figure": "fig",
}


@dataclass(frozen=True)
class Scales:
    """Factors from the core's dimensionless output to the units shown, and axis labels.

    In SI mode, with the length unit ``L`` [m], lengths are ``1e3 L x`` [mm], time is
    ``tau = t / omega`` [s], velocities ``omega L x'`` [m/s], forces ``k L`` times the core's
    force-over-``k`` lengths [N], impulses ``m omega L`` times the core's impulse [N s],
    energies ``k L^2`` times the core's energy-over-``k`` [J].
    """

    time: float = 1.0
    length: float = 1.0
    velocity: float = 1.0
    force: float = 1.0
    impulse: float = 1.0
    energy: float = 1.0
    time_label: str = "t (dimensionless)"
    length_label: str = "x"
    velocity_label: str = "x′"
    force_label: str = "φ/k"
    impulse_label: str = "impulse / (m ω)"
    energy_label: str = "energy / k"
    friction_label: str = "friction force / k"
    #: What follows a length's number: " mm" in SI, nothing in dimensionless units.
    length_unit_text: str = ""
    si: bool = False
    #: Mass m [kg], stiffness k [N/m] and length unit L [m] of SI units (``None`` in
    #: dimensionless ones).
    mass: float | None = None
    stiffness: float | None = None
    length_unit: float | None = None


DIMENSIONLESS = Scales()


def si_scales(mass: float, stiffness: float,
              length_unit: float = DEFAULT_LENGTH_UNIT) -> Scales:
    """The factors and labels of SI units with mass ``m`` [kg], stiffness ``k`` [N/m] and
    length unit ``L`` [m] (docs/physics.md, "The page's SI units": ``omega = sqrt(k/m)``,
    a dimensionless length is ``L``, shown in mm).

    >>> s = si_scales(4.0, 100.0, 0.5)
    >>> s.length, s.time, s.velocity, s.force, s.impulse, s.energy
    (500.0, 0.2, 2.5, 50.0, 10.0, 25.0)
    """
    omega = math.sqrt(stiffness / mass)
    return Scales(
        time=1.0 / omega, length=MM_PER_M * length_unit, velocity=omega * length_unit,
        force=stiffness * length_unit, impulse=mass * omega * length_unit,
        energy=stiffness * length_unit**2,
        time_label="time (s)", length_label="x (mm)", velocity_label="dx/dt (m/s)",
        force_label="contact force (N)", impulse_label="impulse (N s)",
        energy_label="energy (J)", friction_label="friction force (N)",
        length_unit_text=" mm", si=True, mass=mass, stiffness=stiffness,
        length_unit=length_unit,
    )


class ExplorerState(param.Parameterized):
    """All the user can set; defaults are the scene :data:`app.scenes.DEFAULT_SCENE`.

    Bounds are hard limits of the typed entry; soft bounds are the sliders' ranges. The
    page's components watch one state each (app.explorer): besides the user's values it
    holds what the page shows (``solution``, a drag's ``preview``, the presentation) and
    the events of what went stale (``stale``, ``pinned``).
    """

    scene = param.Selector(default=DEFAULT_SCENE, objects=[*SCENES, CUSTOM], doc="""
        The paper's figure last loaded, or 'custom' once a parameter was changed.""")
    units = param.Selector(default="dimensionless", objects=list(UNITS))
    belt_speed = param.Number(0.1, bounds=(0.0, 10.0), softbounds=(0.0, 0.6), doc="""
        Dimensionless belt speed v = v_dr / omega (a length).""")
    clearance = param.Number(0.32, bounds=(-10.0, 10.0), softbounds=(-0.2, 0.8), doc="""
        Stop position x_bar from the unstretched spring position.""")
    restitution = param.Number(1.0, bounds=(0.0, 1.0), doc="Newton's restitution r.")
    mu_s = param.Number(0.3, bounds=(0.0, 5.0), softbounds=(0.0, 1.0))
    mu_k = param.Number(0.2, bounds=(0.0, 5.0), softbounds=(0.0, 1.0))
    u_s = param.Number(1.0, bounds=(1e-6, 100.0), softbounds=(0.05, 3.0), doc="""
        Static deflection u_s = F_N / k (a length).""")
    stop_type = param.Selector(default="rigid", objects=list(STOP_TYPES))
    k_c0 = param.Number(400.0, bounds=(1e-3, 1e6), softbounds=(1.0, 2000.0), doc="""
        Initial compression stiffness over k.""")
    k_e0 = param.Number(36.0, bounds=(1e-3, 1e6), softbounds=(1.0, 2000.0), doc="""
        Initial expansion stiffness over k (<= k_c0).""")
    limit_overlap = param.Number(0.01, bounds=(1e-6, 10.0), softbounds=(0.001, 0.2))
    beta_c = param.Number(300.0, bounds=(1e-3, 1e5), softbounds=(0.5, 1000.0))
    beta_e = param.Number(300.0, bounds=(1e-3, 1e5), softbounds=(0.5, 1000.0))
    contact_law = param.Selector(default="paper", objects=list(CONTACT_LAWS), doc="""
        Reading of the deformable stop's law (Eqs. 12-13): the paper's, which reproduces
        Fig. 2b, or the passive one (docs/contact-law.md).""")
    x0 = param.Number(0.0, bounds=(-100.0, 100.0), softbounds=(-1.5, 1.5))
    v0 = param.Number(0.0, bounds=(-100.0, 100.0), softbounds=(-1.5, 1.5))
    t_end = param.Number(60.0, bounds=(0.1, 5000.0), softbounds=(1.0, 300.0), doc="""
        Horizon (dimensionless time; in SI mode the widget shows seconds).""")
    accuracy = param.Selector(default="standard", objects=list(ACCURACIES))
    method = param.Selector(default="auto", objects=list(METHODS))
    program = param.Boolean(False, doc="""
        Drive the stop with the overlap program of paper Fig. 2b instead of the oscillator.""")
    # SI defaults of a bench rig: a 0.5 kg block on a 200 N/m spring (omega = 20 rad/s,
    # a period of 0.31 s).
    mass = param.Number(0.5, bounds=(1e-6, 1e6), softbounds=(0.1, 10.0), doc="Mass m [kg].")
    stiffness = param.Number(200.0, bounds=(1e-6, 1e9), softbounds=(1.0, 1000.0), doc="""
        Spring stiffness k [N/m].""")
    length_unit = param.Number(DEFAULT_LENGTH_UNIT, bounds=(1e-6, 1e3), doc="""
        Length unit L [m] of SI mode: the length a dimensionless 1 stands for (the scenes'
        u_s = 1 is then a static deflection of L); changing it resizes the rig, the
        dimensionless scene stays.""")
    show_all = param.Boolean(False, doc="Show every plot, not only the scene's.")

    # --- what the page shows (set by the page, watched by its components) ------------------

    solution = param.Parameter(None, doc="""
        The full run on screen (an ``app.solve.solution.Solution``), set once it is solved; every
        view of it (plots, readout, comparison, tools) follows this event.""")
    preview = param.Dict(None, allow_None=True, doc="""
        Solve values a slider being dragged stands at (not committed), or None: the page
        shows their draft while a drag lasts, and the full run again when it ends without
        a new value.""")
    pinned = param.Event(doc="""
        The pinned runs changed (a pin came, went or was solved).""")
    stale = param.Event(doc="""
        A slider's release has arrived: a drag's draft not yet drawn is stale (the full
        run of the release follows).""")
    figure = param.Selector(default=DEFAULT_SCENE, objects=list(SCENES), doc="""
        The paper's figure last loaded (the reset button returns to it).""")
    present = param.Selector(default="", objects=["", "1", "2", "3", "4"], doc="""
        Presentation layout: '' off, or the number of plots shown ('4': a 2x2 grid).""")
    slides = param.Selector(default="", objects=["", "svg", "png"], doc="""
        Figures for slides: '' as on screen, or the format their save tool writes.""")

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        if self.scene in SCENES:
            self.figure = self.scene

    @param.depends("scene", watch=True)
    def _follow_scene(self) -> None:
        if self.scene in SCENES:
            self.figure = self.scene

    # --- core inputs ---------------------------------------------------------------------

    def values(self) -> dict[str, Any]:
        """The solve parameters as a plain dict (what :mod:`app.solve` keys its cache on)."""
        return {name: getattr(self, name) for name in SOLVE_PARAMS}

    def core_inputs(self, **overrides: Any):
        """``(osc, stop, x0, v0, t_end)`` for :func:`core.simulate`; raises ``ValueError``.

        ``overrides`` replace state values (a slider being dragged).
        """
        return core_inputs({**self.values(), **overrides})

    # --- units ---------------------------------------------------------------------------

    @property
    def omega(self) -> float:
        """Natural circular frequency ``sqrt(k/m)`` [rad/s] of the SI view."""
        return math.sqrt(self.stiffness / self.mass)

    def scales(self) -> Scales:
        """Conversion factors and labels for the units selected."""
        return (si_scales(self.mass, self.stiffness, self.length_unit) if self.units == "SI"
                else DIMENSIONLESS)

    def physical(self, length_unit: float | None = None) -> dict[str, float]:
        """SI values of the current state, as the SI boxes show them: ``normal_force`` [N],
        ``belt_speed`` [m/s], ``v0`` [m/s], ``t_end`` [s], ``k_c0`` and ``k_e0`` [N/m], the
        length unit ``L`` and the lengths ``clearance``, ``x0``, ``limit_overlap`` [mm], ...

        Each is the state's number times its factor of :func:`si_units` (docs/physics.md,
        "The page's SI units"), with the state's length unit or ``length_unit`` [m].
        """
        length_unit = self.length_unit if length_unit is None else length_unit
        omega = math.sqrt(self.stiffness / self.mass)
        factors = si_units(self.mass, self.stiffness, length_unit)
        phys = {"m": self.mass, "k": self.stiffness, "omega": omega, "mu_s": self.mu_s,
                "mu_k": self.mu_k, "L": length_unit * MM_PER_M}
        for name, (si_key, _) in SI_NAMES.items():
            if name not in ("mass", "stiffness", "length_unit"):
                phys[si_key] = getattr(self, name) * factors[name][2]
        return phys

    def from_physical(self, **si: float) -> dict[str, float]:
        """The state values that SI values give (any of :data:`SI_KEYS`, as
        :meth:`physical` gives them); the others keep their SI values (a new ``k`` keeps
        the stop's stiffnesses in N/m, so their ratios change), except under a new length
        unit ``L`` [mm] alone, which resizes the rig: the dimensionless values stay. The
        normal force and belt speed go through :meth:`core.Oscillator.from_physical`;
        raises ``ValueError`` on bad input, naming the parameter and its bounds. Nothing is
        set (see :meth:`set_physical`).

        >>> s = ExplorerState(belt_speed=0.1, t_end=60.0, mass=1.0, stiffness=100.0,
        ...                   length_unit=1.0)
        >>> s.physical()["t_end"], s.physical()["belt_speed"]  # omega = 10 rad/s
        (6.0, 1.0)
        >>> v = s.from_physical(k=400.0)  # omega = 20 rad/s: the same seconds and m/s
        >>> v["t_end"], v["belt_speed"]
        (120.0, 0.05)
        >>> s.from_physical(L=10.0)  # the same scene, a rig a hundred times smaller
        {'length_unit': 0.01}
        """
        unknown = set(si) - set(SI_KEYS)
        if unknown:
            raise ValueError(f"unknown SI value(s) {sorted(unknown)}; expected {SI_KEYS}")
        length_unit = self.length_unit
        if "L" in si:
            message = si_bound_error("length_unit", si["L"] / MM_PER_M, self.mass,
                                     self.stiffness)
            if message:
                raise ValueError(message)
            length_unit = si["L"] / MM_PER_M
        merged = {key: value for key, value in self.physical(length_unit).items()
                  if key in SI_KEYS}
        merged.update(si)
        values = _state_values(merged, set(si), self.mu_s, min(self.mu_k, self.mu_s),
                               length_unit)
        if "L" in si and not {"m", "k"} & set(si):
            # A new length unit resizes the rig: only the values given in SI are new.
            given = {SI_STATE_KEYS[key] for key in si}
            values = {name: value for name, value in values.items() if name in given}
        values = {name: snap_to_bounds(name, value) for name, value in values.items()}
        # A bound is told in the units of the box the user typed in (with the new m and k).
        for name, value in values.items():
            message = si_bound_error(name, value, merged["m"], merged["k"], length_unit)
            if message:
                raise ValueError(message)
        return values

    def set_physical(self, **si: float) -> None:
        """Set the state from SI values (see :meth:`from_physical`) in one batch; raises
        ``ValueError`` on bad input, naming the parameter and its bounds.

        >>> s = ExplorerState(length_unit=1.0)
        >>> s.set_physical(m=1.0, k=100.0, normal_force=50.0, belt_speed=0.5)
        >>> round(s.u_s, 12), round(s.belt_speed, 12)
        (0.5, 0.05)
        """
        self.param.update(**self.from_physical(**si))

    # --- scenes --------------------------------------------------------------------------

    def load_scene(self, key: str) -> None:
        """Set every physics parameter from scene ``key`` in one batch (one solve); the
        accuracy and method chosen stay."""
        values = scene_values(key, accuracy=self.accuracy, method=self.method)
        self.param.update(**values, scene=key)



#: State values a permalink in SI units holds in SI (:func:`si_units`); the others
#: (ratios, coefficients, and lengths, in units of the link's ``L``) read the same in both
#: unit systems.
URL_SI_PARAMS = ("belt_speed", "v0", "t_end", "k_c0", "k_e0")


#: The SI value (a key of :meth:`ExplorerState.physical`) each state value is shown as,
#: and its name in the page's boxes and messages (symbols as the glossary prints them).
SI_NAMES: Mapping[str, tuple[str, str]] = {
    "mass": ("m", "mass m"), "stiffness": ("k", "stiffness k"),
    "u_s": ("normal_force", f"normal force {_S['F_N']}"),
    "belt_speed": ("belt_speed", f"belt speed {subscripted('v', 'dr')}"),
    "v0": ("v0", f"initial velocity {_S['v0']}"), "t_end": ("t_end", f"horizon {_S['t_end']}"),
    "k_c0": ("k_c0", f"compression stiffness {_S['k_c0']}"),
    "k_e0": ("k_e0", f"expansion stiffness {_S['k_e0']}"),
    "length_unit": ("L", "length unit L"), "clearance": ("clearance", f"clearance {_S['x_bar']}"),
    "x0": ("x0", f"initial displacement {_S['x0']}"),
    "limit_overlap": ("limit_overlap", f"limit overlap {_S['D']}"),
}
#: The state value each SI value (a key of :meth:`ExplorerState.physical`) converts to.
SI_STATE_KEYS: Mapping[str, str] = {
    "m": "mass", "k": "stiffness", **{si: name for name, (si, _) in SI_NAMES.items()}}


#: The state values that read in other units in SI: the unit, and the factor of :class:`Scales` from
#: the core's number to it (docs/physics.md, "The page's SI units": lengths ``1e3 L x`` mm,
#: velocities ``omega L x'``, times ``t / omega``, the stop's stiffnesses ``k`` times their
#: ratio, the normal force ``k L u_s``). Ratios and coefficients read the same in both.
SI_CONVERSIONS: Mapping[str, tuple[str, str]] = {
    "u_s": ("N", "force"), "belt_speed": ("m/s", "velocity"), "v0": ("m/s", "velocity"),
    "t_end": ("s", "time"), **{name: ("N/m", "stiffness") for name in STOP_STIFFNESSES},
    **{name: ("mm", "length") for name in LENGTHS},
}
#: State values whose SI reading depends on the length unit L (their range says it).
L_DEPENDENT = frozenset(name for name, (_, factor) in SI_CONVERSIONS.items()
                        if factor in ("force", "velocity", "length"))


def si_units(mass: float, stiffness: float, length_unit: float = DEFAULT_LENGTH_UNIT
             ) -> dict[str, tuple[str, str, float]]:
    """Each state value's SI name in the page, unit and the factor from the state's number
    to it (:data:`SI_CONVERSIONS`), with mass ``m`` [kg], stiffness ``k`` [N/m] and length
    unit ``L`` [m].

    >>> si_units(1.0, 100.0, 1.0)["belt_speed"], si_units(1.0, 100.0)["t_end"]
    (('belt speed v_dr', 'm/s', 10.0), ('horizon t_end', 's', 0.1))
    >>> si_units(1.0, 100.0, 0.01)["clearance"]
    ('clearance x̄', 'mm', 10.0)
    """
    scales = si_scales(mass, stiffness, length_unit)
    units = {"mass": ("kg", 1.0), "stiffness": ("N/m", 1.0), "length_unit": ("mm", MM_PER_M),
             **{name: (unit, getattr(scales, factor))
                for name, (unit, factor) in SI_CONVERSIONS.items()}}
    return {name: (SI_NAMES[name][1], unit, factor) for name, (unit, factor) in units.items()}


def _state_values(si: Mapping[str, float], given: set[str], mu_s: float, mu_k: float,
                  length_unit: float) -> dict[str, float]:
    """The state values of the SI values ``si`` (every key of :data:`SI_KEYS`; ``given``:
    those the user gave), with the length unit ``length_unit`` [m]; the normal force and
    belt speed through :meth:`core.Oscillator.from_physical`, which checks them."""
    m, k = si["m"], si["k"]
    osc = Oscillator.from_physical(m=m, k=k, normal_force=si["normal_force"], mu_s=mu_s,
                                   mu_k=mu_k, belt_speed=si["belt_speed"])
    omega = math.sqrt(k / m)
    values = {"mass": m, "stiffness": k, "length_unit": length_unit,
              "u_s": osc.u_s / length_unit, "belt_speed": osc.belt_speed / length_unit,
              "v0": si["v0"] / (omega * length_unit), "t_end": si["t_end"] * omega}
    # A ratio is recomputed only when k or the stiffness itself is new: (k_c0 k) / k need
    # not give back k_c0's last bit; so is a length only when it is given.
    values.update({name: si[name] / k for name in STOP_STIFFNESSES
                   if name in given or "k" in given})
    values.update({name: si[name] / (length_unit * MM_PER_M) for name in LENGTHS
                   if name in given})
    return values


def snap_to_bounds(name: str, value: float) -> float:
    """A state value converted from SI onto the bound it misses by rounding only (1e-12
    relative): 0.01 s is 0.1 / omega but 0.01 * 10 may not give back 0.1.

    >>> snap_to_bounds("t_end", 0.09999999999999999), snap_to_bounds("t_end", 0.09)
    (0.1, 0.09)
    """
    for bound in ExplorerState.param[name].bounds:
        if bound is not None and value != bound and math.isclose(value, bound, rel_tol=1e-12):
            return float(bound)
    return value


def si_bound_error(name: str, value: float, mass: float, stiffness: float,
                   length_unit: float = DEFAULT_LENGTH_UNIT) -> str | None:
    """The message, in SI (:func:`si_units`), for a state value outside its bounds, or
    ``None`` if it is inside.

    >>> si_bound_error("t_end", 1500.0 * 5.0, 2.0, 50.0)
    'horizon t_end must lie in [0.02, 1000] s with m = 2 kg, k = 50 N/m; got 1500 s'
    >>> si_bound_error("length_unit", -0.001, 2.0, 50.0)
    'length unit L must lie in [0.001, 1e+06] mm; got -1 mm'
    """
    low, high = ExplorerState.param[name].bounds
    if low <= snap_to_bounds(name, value) <= high:
        return None
    si_name, unit, factor = si_units(mass, stiffness, length_unit)[name]
    return (f"{si_name} must lie in {si_range(name, mass, stiffness, length_unit)}; "
            f"got {value * factor:.6g} {unit}")


def si_range(name: str, mass: float, stiffness: float,
             length_unit: float = DEFAULT_LENGTH_UNIT) -> str:
    """The SI range of state value ``name`` with mass ``m`` [kg], stiffness ``k`` [N/m] and
    length unit ``L`` [m], naming those it depends on.

    >>> si_range("t_end", 2.0, 50.0)
    '[0.02, 1000] s with m = 2 kg, k = 50 N/m'
    >>> si_range("clearance", 2.0, 50.0, 0.01)
    '[-100, 100] mm with L = 10 mm'
    """
    low, high = ExplorerState.param[name].bounds
    _, unit, factor = si_units(mass, stiffness, length_unit)[name]
    given = []
    if name not in LENGTHS and name != "length_unit":
        given += [f"m = {mass:g} kg", f"k = {stiffness:g} N/m"]
    if name in L_DEPENDENT:
        given.append(f"L = {length_unit * MM_PER_M:g} mm")
    return (f"[{low * factor:.4g}, {high * factor:.4g}] {unit}"
            + (f" with {', '.join(given)}" if given else ""))


def scene_values(key: str, **overrides: Any) -> dict[str, Any]:
    """All solve parameters of scene ``key``: the state's defaults, then the scene's values.

    >>> scene_values("7c")["restitution"]
    0.3
    """
    values = {name: ExplorerState.param[name].default for name in SOLVE_PARAMS}
    values.update(SCENES[key].values)
    values.update(overrides)
    return values


def core_inputs(values: Mapping[str, Any]):
    """Build ``(osc, stop, x0, v0, t_end)`` from state values; raises ``ValueError``.

    The core validates every value (:mod:`core.validation`), so its messages name the
    parameter and the allowed range, the stop's position relative to the start included.
    """
    osc = Oscillator(mu_s=values["mu_s"], mu_k=values["mu_k"],
                     belt_speed=values["belt_speed"], u_s=values["u_s"])
    stop_type = values["stop_type"]
    if stop_type == "rigid":
        stop = RigidStop(clearance=values["clearance"], restitution=values["restitution"])
    elif stop_type == "hysteretic":
        stop = HystereticStop(
            clearance=values["clearance"], k_c0=values["k_c0"], k_e0=values["k_e0"],
            limit_overlap=values["limit_overlap"], beta_c=values["beta_c"],
            beta_e=values["beta_e"], law=values.get("contact_law", "paper"),
        )
    else:
        stop = None
    x0, v0 = float(values["x0"]), float(values["v0"])
    if stop is not None and not values.get("program"):
        # The explorer starts the mass outside either stop (its scenes and sliders are
        # laid out so), hence the rigid stop's rule, in the core's words, for both.
        check_start(x0, stop.clearance)
    t_end = float(values["t_end"])
    check_range("t_end", t_end, 0.0, low_open=True)
    return osc, stop, x0, v0, t_end
