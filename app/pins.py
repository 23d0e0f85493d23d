"""The pinned runs in the permalink: what a pin is (:class:`PinSpec`: its scene, its solve
values, the mass and stiffness of its units) and its text in the address, both ways.

Examples
--------
>>> from app.state import scene_values
>>> decode_pins(encode_pins([PinSpec("7c", scene_values("7c"))]))[0].scene
'7c'
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

from app.links import allowed, parse_value, shown
from app.scenes import CUSTOM, SCENES
from app.state import SOLVE_PARAMS, URL_KEYS, ExplorerState, core_inputs
from app.state import scene_values as _scene_values

#: Pinned runs kept at most.
MAX_PINS = 3
#: The permalink's key for the pins.
URL_KEY = "pins"
#: Separators of the pins' URL value: between pins, between a pin's items.
PIN_SEP, ITEM_SEP = "|", ","
#: Mass m [kg] and stiffness k [N/m] of a pin whose permalink names none (the page's are
#: passed in their place, :func:`decode_pins`).
MASS, STIFFNESS = ExplorerState.param["mass"].default, ExplorerState.param["stiffness"].default

# --- the address -----------------------------------------------------------------------------

class PinSpec(NamedTuple):
    """What a pin is: its scene, its solve values (the core's dimensionless ones) and the
    mass m [kg] and stiffness k [N/m] of the page it was pinned on, which make it one
    physical run: the SI page shows it in its own seconds, m/s and newtons."""

    scene: str
    values: dict[str, Any]
    mass: float = MASS
    stiffness: float = STIFFNESS


def encode_pins(pins: Sequence[PinSpec], mass: float = MASS,
                stiffness: float = STIFFNESS) -> str:
    """The pins as the permalink's value: per pin its scene, then the values that differ
    from that scene's (``key=value`` with the permalink's keys), then its mass ``m`` and
    stiffness ``k`` where they differ from the page's (``mass``, ``stiffness``).

    >>> from app.state import scene_values
    >>> elastic = {**scene_values("7c"), "restitution": 1.0}
    >>> encode_pins([PinSpec("7c", scene_values("7c")), PinSpec("7c", elastic, mass=4.0)])
    '7c|7c,r=1.0,m=4.0'
    """
    parts = []
    for pin in pins:
        base = _scene_values(pin.scene) if pin.scene in SCENES else _defaults()
        items = [pin.scene]
        for name in SOLVE_PARAMS:
            if name in ("accuracy", "method"):
                continue  # a pin is solved with the page's accuracy and method
            if pin.values[name] != base[name]:
                items.append(f"{URL_KEYS[name]}={_text(pin.values[name])}")
        for name, value, page in (("mass", pin.mass, mass),
                                  ("stiffness", pin.stiffness, stiffness)):
            if value != page:
                items.append(f"{URL_KEYS[name]}={_text(float(value))}")
        parts.append(ITEM_SEP.join(items))
    return PIN_SEP.join(parts)


def _text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def _defaults() -> dict[str, Any]:
    return {name: ExplorerState.param[name].default for name in SOLVE_PARAMS}


def decode_pins(raw: str, accuracy: str = "standard", method: str = "auto",
                mass: float = MASS, stiffness: float = STIFFNESS) -> list[PinSpec]:
    """Read the permalink's pins back (:func:`encode_pins`); raises ``ValueError`` naming
    the pin and the item it could not read, and what is allowed. Each value is read as the
    address's are (:func:`app.links.parse_value`: a number is a finite decimal numeral, a
    switch ``true`` or ``false``), and each key is given once. A pin that names no mass or
    stiffness has the page's (``mass``, ``stiffness``: so did every pin of the links
    written before pins kept their own).

    >>> decode_pins("5b,r=0.5")[0].values["restitution"]
    0.5
    >>> decode_pins("5b,m=4", mass=2.0, stiffness=100.0)[0][2:]
    (4.0, 100.0)
    >>> decode_pins("5b,r=2")
    Traceback (most recent call last):
    ...
    ValueError: pin 1 ('5b,r=2'): r (restitution) must be a number in [0, 1]; got '2'
    """
    pins = []
    for i, chunk in enumerate(p for p in str(raw).split(PIN_SEP) if p):
        if len(pins) == MAX_PINS:
            raise ValueError(f"at most {MAX_PINS} pins; the address names more")
        where = f"pin {i + 1} ({shown(chunk)})"
        scene, *items = chunk.split(ITEM_SEP)
        if scene not in SCENES and scene != CUSTOM:
            raise ValueError(f"{where}: scene must be one of {', '.join(SCENES)} or custom; "
                             f"got {shown(scene)}")
        values = _scene_values(scene) if scene in SCENES else _defaults()
        values.update(accuracy=accuracy, method=method)
        units = {"mass": float(mass), "stiffness": float(stiffness)}
        for name, value in _pin_items(items, where).items():
            if name in units:
                units[name] = value
            else:
                values[name] = value
        try:
            core_inputs(values)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        pins.append(PinSpec(scene, values, units["mass"], units["stiffness"]))
    return pins


def _pin_items(items: Sequence[str], where: str) -> dict[str, Any]:
    """The values a pin's ``key=value`` items set, by parameter; raises ``ValueError``
    naming the pin (``where``) and the item."""
    names = {key: name for name, key in URL_KEYS.items()}
    out: dict[str, Any] = {}
    for item in items:
        key, _, text = item.partition("=")
        name = names.get(key)
        if name not in (*SOLVE_PARAMS, "mass", "stiffness") or name in ("accuracy", "method"):
            raise ValueError(f"{where}: unknown parameter {shown(key)}")
        if name in out:
            raise ValueError(f"{where}: {key} ({name}) must be given once")
        p = ExplorerState.param[name]
        try:
            value = parse_value(p, text)
            ExplorerState(**{name: value})
        except Exception:  # noqa: BLE001 - any refusal is said in one message
            raise ValueError(f"{where}: {key} ({name}) must be {allowed(p)}; "
                             f"got {shown(text)}") from None
        out[name] = value
    return out
