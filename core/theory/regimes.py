"""The closed forms of each regime with a rigid stop (paper Sec. 4, Appendix; docs/physics.md,
"Closed-form results"): x*, the periods, the transition points, the descriptions.

The regime itself comes from :func:`core.theory.grid.decide`; this module only computes
what that regime's closed forms give.
"""

from __future__ import annotations

import math

from core.params import Oscillator, RigidStop
from core.result import SteadyKind
from core.scene_checks import check_oscillator, check_rigid_stop, check_state
from core.theory.accumulation import accumulation_time
from core.theory.grid import (
    CASE_A,
    CASE_B,
    FAST,
    FIRST_SLIP,
    IMPACTLESS,
    STEADY_NAMES,
    STILL,
    decide_point,
    impact_label,
)
from core.theory.impactless import critical_speed, impactless_limit_cycle, x_max_impactless
from core.theory.values import (
    IMPACT,
    SLIP_STICK,
    STICK_IMPACT,
    STICK_SLIP,
    TWO_PI,
    Analysis,
    Regime,
)
from core.validation import check_range


def x_star(osc: Oscillator, restitution: float) -> float:
    """Critical clearance ``x* = a + v sqrt(1 - r^2)`` (Eq. 35, rederived).

    For a slow belt with ``x_bar < b`` the mass sticks into the stop at speed ``v`` and
    rebounds at ``r v``; the rebound circle about ``(a, 0)`` reaches the stick line again,
    and the motion is periodic (case b), iff ``x_bar >= x*``. Below ``x*`` the impacts
    repeat with speeds ``r^h v`` (case c). The extracted text's ``a + v / sqrt(1 - r^2)``
    is not what the geometry gives; see the module docstring.

    Parameters
    ----------
    osc : Oscillator
    restitution : float
        ``0 <= r <= 1``.

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> round(x_star(osc, 0.6), 12), x_star(osc, 1.0) == osc.a
    (0.28, True)
    """
    check_oscillator(osc)
    r = check_range("restitution", restitution, 0.0, 1.0)
    return osc.a + osc.v * math.sqrt((1.0 - r) * (1.0 + r))


def _arc_to_stick(a: float, x_bar: float, w_out: float, x_stick: float, v: float) -> float:
    """Slip time from the rebound ``(x_bar, -w_out)`` (``x_bar >= a``) to ``(x_stick, v)``.

    Angles on a circle about ``(a, 0)`` are ``theta = atan2(-x', x - a)``, growing at unit
    rate. The rebound point sits at ``delta = atan2(w_out, x_bar - a)`` in ``[0, pi/2]``, the
    stick point (upper left, ``x_stick <= a``) at ``pi + atan2(v, a - x_stick)``.
    """
    return math.pi + math.atan2(v, a - x_stick) - math.atan2(w_out, x_bar - a)


def _impact_slip_cycle(a: float, x_bar: float, w: float) -> float:
    """Period of the cycle impact ``(x_bar, w) -> (x_bar, -w)`` + one slip arc back.

    ``2 pi - 2 atan2(w, x_bar - a)``; for natural initial conditions (``w^2 = x_bar (2a -
    x_bar)``) this is ``2 arccos(1 - x_bar/a)``, twice the printed value of Sec. 4.1.
    """
    if x_bar < a:  # the short arc left of the centre; this form keeps tiny periods exact
        return 2.0 * math.atan2(w, a - x_bar)
    return TWO_PI - 2.0 * math.atan2(w, x_bar - a)


def analyse(osc: Oscillator, stop: RigidStop | None, x0: float, v0: float) -> Analysis:
    """Everything the public functions report about a scene, computed once: the regime
    from :func:`core.theory.grid.decide_point` (the one decision tree, on one point),
    then the closed forms of that regime."""
    x0, v0 = check_state(osc, x0, v0)
    check_rigid_stop(stop, x0)
    x_bar = stop.clearance if stop is not None else 0.0
    d = decide_point(osc, stop, x0, v0)
    branch, kind = d.branch, SteadyKind(STEADY_NAMES[d.steady])
    belt = "fast" if d.fast else "slow"
    if branch == IMPACTLESS:
        return _impactless(osc, x0, v0, belt, x_max_impactless(osc, x0, v0), stop is None, kind)
    a = osc.a
    label = impact_label(stop.restitution)
    if branch == FAST:
        # Squares as products, as in decide: x ** 2 (libm pow) and x * x can differ in
        # the last bit.
        vc, dx = critical_speed(osc, x0, v0), x_bar - a
        w = math.sqrt(max(vc * vc - dx * dx, 0.0))
        ref = f"Sec. 4.1, Fig. {'4a' if x_bar >= a else '4b'}"
        return _impact_cycle_or_decay(
            osc, stop, w, belt, None, "x_bar < x_max = a + v*", "x_bar < a", ref, kind
        )
    if branch == STILL:
        return Analysis(
            belt,
            label,
            None,
            False,
            SteadyKind.EQUILIBRIUM,
            "Belt at rest (v = 0): the swings die out and the mass comes to rest "
            "(equilibrium; the closed forms of Sec. 4 assume a moving belt)",
        )
    if branch == FIRST_SLIP:
        w = math.sqrt(max(x_bar * (2.0 * a - x_bar), 0.0))
        where = "stop hit before the first stick (x_bar < a - sqrt(a^2 - v^2))"
        return _impact_cycle_or_decay(osc, stop, w, belt, "c", where, where, "Sec. 4.6", kind)
    if branch == CASE_A:
        return _slow_case_a(osc, stop, label, kind)
    if branch == CASE_B:
        return _slow_case_b(osc, stop, label)
    return _slow_case_c(osc, stop, label, kind)


def _impactless(
    osc: Oscillator,
    x0: float,
    v0: float,
    belt: str,
    x_max: float,
    no_stop: bool,
    kind: SteadyKind,
) -> Analysis:
    where = "no stop" if no_stop else "the stop lies beyond x_max"
    cycle: dict = {}
    if kind is SteadyKind.EQUILIBRIUM and osc.v == 0.0:
        text = (
            f"Belt at rest (v = 0), {where}: the mass comes to rest (equilibrium; the "
            "limit v -> 0 of Sec. 3.1)"
        )
    elif kind is SteadyKind.EQUILIBRIUM:  # a fast belt, started at the centre (a, 0)
        text = (
            f"Fast belt, {where}: the start is the centre (a, 0) of the slip circles, "
            "the mass stays at rest (Sec. 3.1)"
        )
    elif kind is not SteadyKind.PERIODIC:
        kind, cycle = SteadyKind.PURE_SLIP, {"period": TWO_PI}
        text = (
            f"Fast belt (v > v*), {where}: pure slip on the circle about (a, 0) through "
            "the start, period 2 pi (Sec. 3.1, Eq. 22, Fig. 3a)"
        )
    else:
        lc = impactless_limit_cycle(osc)
        x_max = lc.x_max
        cycle = {
            "period": lc.period,
            "sequence": (STICK_SLIP, SLIP_STICK),
            "points": {"P_stick_start": lc.stick_start, "P_stick_end": lc.stick_end},
        }
        text = (
            f"Slow belt (v <= v*), {where}: stick-slip limit cycle (Sec. 3.1, Eqs. 23-24, "
            "Fig. 3a)"
        )
    return Analysis(belt, "none", None, True, kind, text, x_max=x_max, **cycle)


def _impact_cycle_or_decay(
    osc: Oscillator,
    stop: RigidStop,
    w: float,
    belt: str,
    case: str | None,
    where: str,
    rest_text: str,
    ref: str,
    kind: SteadyKind,
) -> Analysis:
    """Impacts on a slip circle that never reaches the stick line (Secs. 4.1, 4.3, 4.6).

    ``w`` is the approach speed of the first impact (Eqs. A.1, A.5). Elastic: the impact-
    slip cycle repeats. Otherwise the rebound speeds fall as ``r^h w`` (:func:`_decay`).
    """
    x_bar = stop.clearance
    if kind is SteadyKind.PERIODIC:
        return Analysis(
            belt,
            "elastic",
            case,
            False,
            SteadyKind.PERIODIC,
            f"{belt.capitalize()} belt, elastic impact, {where}: periodic impact-slip cycle "
            f"({ref})",
            period=_impact_slip_cycle(osc.a, x_bar, w),
            x_max=x_bar,
            impact_speed=w,
            sequence=(IMPACT,),
            points={"P_impact_in": (x_bar, w), "P_impact_out": (x_bar, -w)},
            first_impact_speed=w,
        )
    note = ", Sec. 4.6" if case is not None else ""
    return _decay(osc, stop, w, belt, case, "a <= x_bar < x_max", rest_text, kind, note)


def _decay(
    osc: Oscillator,
    stop: RigidStop,
    w: float,
    belt: str,
    case: str | None,
    grazing_text: str,
    rest_text: str,
    kind: SteadyKind,
    note: str = "",
) -> Analysis:
    """Impact speeds ``r^h w`` with no stick in between (Eqs. A.5-A.6, A.12).

    Grazing when ``x_bar >= a`` (the limit circle about ``(a, 0)`` touches the stop);
    otherwise the impacts accumulate in finite time (:func:`accumulation_time`) and the
    mass rests pressed on the stop. ``w = 0`` means the mass already sits on the stop.
    ``grazing_text`` / ``rest_text`` name the clearance range for the readout.
    """
    a, x_bar, r = osc.a, stop.clearance, stop.restitution
    label = impact_label(r)
    limit = {"P_limit": (x_bar, 0.0)}
    section = "Sec. 4.3, Fig. 6" if belt == "fast" else "Sec. 4.4, Fig. 7"
    head = f"{belt.capitalize()} belt, {label} impact"
    if kind is SteadyKind.GRAZING:
        what = (
            "the mass leaves the stop at zero speed on the slip circle that grazes it"
            if label == "plastic"
            else "impact speeds fall as r^h and the motion tends to the slip circle that "
            "grazes the stop"
        )
        sub = "a" if belt == "fast" else "c"
        return Analysis(
            belt,
            label,
            case,
            False,
            SteadyKind.GRAZING,
            f"{head}, {grazing_text}: {what} ({section}{sub}{note})",
            x_max=x_bar,
            impact_speed=0.0,
            sequence=(IMPACT,),
            points=limit,
            first_impact_speed=w,
        )
    if label == "plastic" or w == 0.0:
        what, t_acc = "the mass stays pressed on the stop", 0.0
    else:
        what = "impacts accumulate in finite time, then the mass rests pressed on the stop"
        t_acc = accumulation_time(r * w, r, a - x_bar)
    sub = "b" if belt == "fast" else "d"
    return Analysis(
        belt,
        label,
        case,
        False,
        SteadyKind.REST,
        f"{head}, {rest_text}: {what} ({section}{sub}{note})",
        x_max=x_bar,
        impact_speed=0.0,
        points=limit,
        first_impact_speed=w,
        accumulation_time=t_acc,
    )


def _slow_case_a(osc: Oscillator, stop: RigidStop, label: str, kind: SteadyKind) -> Analysis:
    """Case a, ``b <= x_bar < x_max`` (Eqs. 31, 34; A.2, A.7-A.9)."""
    a, b, v = osc.a, osc.b, osc.v
    x_bar, r = stop.clearance, stop.restitution
    lc = impactless_limit_cycle(osc)
    w = math.sqrt(max((lc.radius - (x_bar - a)) * (lc.radius + (x_bar - a)), 0.0))  # A.7
    # Rebound circle radius^2 - v^2, the radicand of A.9: (x_bar-a)^2 + r^2 w^2 - v^2 with
    # w^2 = (b-a)^2 + v^2 - (x_bar-a)^2, grouped so that r = 1 gives (b-a)^2 exactly. The
    # rebound circle reaches the stick line x' = v iff it is >= 0.
    d, e = x_bar - a, r * (b - a)
    disc = (1.0 - r) * (1.0 + r) * (d * d - v * v) + e * e
    if kind is not SteadyKind.PERIODIC:  # disc < 0
        where = (
            "case a (b <= x_bar < x_max) with x* > b, where the rebound circle misses the "
            "stick line"
        )
        return _decay(osc, stop, w, "slow", "a", where, where, kind)
    x_stick = a - math.sqrt(max(disc, 0.0))
    arc_in = math.atan2(v, b - a) - math.atan2(w, x_bar - a)
    ref = "Sec. 4.2, Fig. 5a" if label == "elastic" else "Sec. 4.4, Fig. 7a"
    return _stick_impact_cycle(
        osc, stop, label, "a", "b <= x_bar < x_max", "stick-slip-impact-slip", ref,
        x_stick=x_stick, stick_end=b, w=w, arc_in=arc_in,
        sequence=(STICK_SLIP, IMPACT, SLIP_STICK),
    )


def _slow_case_b(osc: Oscillator, stop: RigidStop, label: str) -> Analysis:
    """Case b, ``x* <= x_bar < b`` (Eqs. 32, 36; A.3-A.4, A.10-A.11)."""
    a, v = osc.a, osc.v
    x_bar, r = stop.clearance, stop.restitution
    d = x_bar - a
    disc = max(d * d - (1.0 - r) * (1.0 + r) * v * v, 0.0)  # >= 0 above x*
    x_stick = a - math.sqrt(disc)  # A.4 (r = 1: 2a - x_bar), A.11
    if label == "elastic":
        bound, ref = "a", "Sec. 4.2, Fig. 5b"
    else:
        bound, ref = "x*", "Sec. 4.4, Fig. 7b"
    return _stick_impact_cycle(
        osc, stop, label, "b", f"{bound} <= x_bar < b", "stick-impact-slip", ref,
        x_stick=x_stick, stick_end=x_bar, w=v, arc_in=0.0, sequence=(STICK_IMPACT, SLIP_STICK),
    )


def _stick_impact_cycle(
    osc: Oscillator,
    stop: RigidStop,
    label: str,
    case: str,
    bounds: str,
    cycle: str,
    ref: str,
    *,
    x_stick: float,
    stick_end: float,
    w: float,
    arc_in: float,
    sequence: tuple[str, ...],
) -> Analysis:
    """The slow belt's periodic cycles of cases a and b: stick from ``x_stick`` to
    ``stick_end``, (case a: slip along ``arc_in``,) impact at ``x_bar`` with speed ``w``,
    rebound at ``-r w`` and slip back to the stick line at ``x_stick`` (A.8-A.11)."""
    a, v = osc.a, osc.v
    x_bar, r = stop.clearance, stop.restitution
    return Analysis(
        "slow",
        label,
        case,
        False,
        SteadyKind.PERIODIC,
        f"Slow belt, {label} impact, case {case} ({bounds}): periodic {cycle} cycle ({ref})",
        period=(stick_end - x_stick) / v + arc_in + _arc_to_stick(a, x_bar, r * w, x_stick, v),
        x_max=x_bar,
        impact_speed=w,
        sequence=sequence,
        points={
            "P_stick_start": (x_stick, v),
            "P_stick_end": (stick_end, v),
            "P_impact_in": (x_bar, w),
            "P_impact_out": (x_bar, -r * w),
        },
        first_impact_speed=w,
    )


def _slow_case_c(osc: Oscillator, stop: RigidStop, label: str, kind: SteadyKind) -> Analysis:
    """Case c, ``x_bar < a`` (elastic) or ``x_bar < x*`` (Eqs. 33, 37; A.3, A.12).

    The mass sticks into the stop at speed ``v``. Elastic: the rebound circle through
    ``(x_bar, -v)`` returns to ``(x_bar, v)`` exactly on the stick line, so the cycle is one
    impact and one slip arc. Otherwise the impacts decay (:func:`_decay`).
    """
    a, b, v = osc.a, osc.b, osc.v
    x_bar = stop.clearance
    if kind is not SteadyKind.PERIODIC:
        return _decay(
            osc, stop, v, "slow", "c", "case c (a <= x_bar < x*)", "case c (x_bar < a)", kind
        )
    fig = "5d" if x_bar < 2.0 * a - b else "5c"
    return Analysis(
        "slow",
        label,
        "c",
        False,
        SteadyKind.PERIODIC,
        f"Slow belt, elastic impact, case c (x_bar < a): periodic impact-slip cycle through "
        f"(x_bar, +-v) (Sec. 4.2, Fig. {fig})",
        period=_impact_slip_cycle(a, x_bar, v),
        x_max=x_bar,
        impact_speed=v,
        sequence=(IMPACT,),
        points={"P_impact_in": (x_bar, v), "P_impact_out": (x_bar, -v)},
        first_impact_speed=v,
    )


def classify(osc: Oscillator, stop: RigidStop | None, x0: float = 0.0, v0: float = 0.0) -> Regime:
    """Name the paper's regime of a scene (Secs. 3.2, 4.1-4.4; Eqs. 25, 31-37).

    Boundaries, with ``x_max`` the impactless steady maximum (:func:`x_max_impactless`):

    * no stop, or ``x_bar >= x_max``: impactless; pure slip (fast), the stick-slip limit
      cycle (slow), or equilibrium (``v = 0`` or a start at the centre ``(a, 0)``).
    * fast belt (Secs. 4.1, 4.3): elastic -> periodic impact-slip cycle; otherwise
      grazing for ``x_bar >= a`` and rest at the stop for ``x_bar < a`` (accumulation of
      impacts for ``0 < r < 1``, at once for ``r = 0``).
    * slow belt (Secs. 4.2, 4.4): case a ``b <= x_bar < x_max``; case b ``x* <= x_bar < b``
      (``x* = a`` when elastic); case c below. Case c is periodic when elastic, else
      grazing (``x_bar >= a``) or rest (``x_bar < a``). When ``x* > b`` case b is empty,
      and the lower part of case a grazes too: see the module docstring.
    * ``r = 0`` (plastic) follows the inelastic rules: after the impact the mass sits at
      the stop; it stays there iff ``a >= x_bar``, else leaves on the circle about
      ``(a, 0)`` that touches the stop and sticks again iff ``x_bar - a >= v``.

    The impact cases follow the paper in assuming the mass reaches the stop from its
    natural path (for a slow belt, from the stick phase). Other starts only change the
    fast-belt circle radius here; for a slow belt they may settle on a different,
    coexisting attractor (Sec. 4.5).

    Parameters
    ----------
    osc : Oscillator
    stop : RigidStop or None
    x0, v0 : float
        Initial state; the stop must not lie behind ``x0``.

    Returns
    -------
    Regime

    Examples
    --------
    >>> osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    >>> reg = classify(osc, RigidStop(clearance=0.29, restitution=0.6))
    >>> reg.belt, reg.impact, reg.case, reg.expected_steady
    ('slow', 'inelastic', 'b', 'periodic')
    """
    an = analyse(osc, stop, x0, v0)
    return Regime(
        belt=an.belt,
        impact=an.impact,
        case=an.case,
        impactless=an.impactless,
        expected_steady=an.kind.value,
        description=an.description,
    )
