"""Patch of Bokeh's property system (3.9): an immutable default is computed once per class.

Bokeh answers a read of a property that was never set through
``PropertyDescriptor._get_default``, which computes the class's default again on every read:
the overridden defaults looked up, the default copied and validated (``prepare_value``).
Only mutable defaults are kept, per instance (bokeh/bokeh#13174). Building a page reads every
unset property of its ~330 models several times: each walk of the model graph
(``Document`` and Panel list the models it references), the first serialization. For an
unthemed default that is a plain immutable value (``None``, a number, a string, a tuple of
these) the answer is the same for every instance of the class, so
:func:`cache_immutable_defaults` keeps it per (property, class): a new session's page costs
~15 % less server CPU (benchmarks/README.md, "A new session's page"), and the page's JSON is
the same.

Left to Bokeh: themed reads (a theme's value may differ per document), defaults that are
callables or containers (Bokeh's "unstable" ones, kept per instance), and any other value
(a ``Field`` or ``Value`` of a data spec is a mutable object: each instance gets its own copy).
Three more of Bokeh's per-read costs go the same way, each answering what Bokeh computes:

* a default that Bokeh keeps per instance because it is a container (a model's ``tags``,
  ``styles``, ``children``, a source's ``data``: some 40 per model, each computed when the
  model is made) is made from the container kept for the class, a fresh copy per instance,
  where its items are immutable (nearly always: it is empty);
* whether a property's default is kept per instance depends on the property and the class
  only (``PropertyDescriptor.has_unstable_default``, asked for every property of every new
  model), so it is answered once per (property, class);
* ``HasProps.themed_values`` asked for an attribute that is missing unless a theme applies,
  and each miss went through ``HasProps.__getattr__`` and an exception: it reads the
  instance's dictionary instead.

Applied only where :mod:`app.perf` says so (name ``immutable-defaults``).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from bokeh.core.has_props import HasProps
from bokeh.core.property.descriptors import PropertyDescriptor
from bokeh.core.property.wrappers import (
    PropertyValueColumnData,
    PropertyValueDict,
    PropertyValueList,
)

from app.perf import applies

#: Bokeh's own ``PropertyDescriptor._get_default``, once the patch has replaced it.
BOKEH_GET_DEFAULT: Any = None
#: Bokeh's own ``PropertyDescriptor.has_unstable_default``, once the patch has replaced it.
BOKEH_HAS_UNSTABLE_DEFAULT: Any = None
#: Bokeh's own ``HasProps.themed_values``, once the patch has replaced it.
BOKEH_THEMED_VALUES: Any = None

#: ``(descriptor, class) -> (value,)`` of each immutable, unthemed default read so far.
_DEFAULTS: dict[tuple[PropertyDescriptor, type], tuple[Any]] = {}
#: ``(descriptor, class) -> (container type, items)`` of each unthemed default that Bokeh
#: keeps per instance and that is a container of immutable items.
_CONTAINERS: dict[tuple[PropertyDescriptor, type], tuple[type, Any]] = {}
#: ``(descriptor, class) -> bool``: Bokeh's ``has_unstable_default``.
_UNSTABLE: dict[tuple[PropertyDescriptor, type], bool] = {}
#: The containers Bokeh wraps a container default in, and how each copies its items.
_CONTAINER_TYPES = {PropertyValueList: list, PropertyValueDict: dict,
                    PropertyValueColumnData: dict}


def _immutable(value: Any) -> bool:
    if value is None or isinstance(value, (bool, int, float, str)):
        return True
    return type(value) is tuple and all(_immutable(v) for v in value)


def _container(value: Any) -> tuple[type, Any] | None:
    """``(type, items)`` of a container default whose copies can stand for Bokeh's own, or
    None."""
    copy = _CONTAINER_TYPES.get(type(value))
    if copy is None:
        return None
    items = list(value.items()) if copy is dict else list(value)
    if not all(_immutable(item) for item in items):
        return None
    return type(value), copy(value)


def get_default(self: PropertyDescriptor, obj: Any) -> Any:
    """Bokeh's ``_get_default`` (3.9), with immutable unthemed defaults kept per class and
    container defaults copied from the class's."""
    if obj.__dict__.get("__themed_values__") is not None:
        return BOKEH_GET_DEFAULT(self, obj)
    key = (self, obj.__class__)
    kept = _DEFAULTS.get(key)
    if kept is not None:
        return kept[0]
    own = obj._unstable_default_values
    name = self.name
    if name in own:
        return own[name]
    container = _CONTAINERS.get(key)
    if container is not None:
        kind, items = container
        value = kind(_CONTAINER_TYPES[kind](items))
        value._register_owner(obj, self)
        own[name] = value
        return value
    value = BOKEH_GET_DEFAULT(self, obj)
    if self.has_unstable_default(obj):
        container = _container(value)
        if container is not None:
            _CONTAINERS[key] = container
    elif _immutable(value):
        _DEFAULTS[key] = (value,)
    return value


def has_unstable_default(self: PropertyDescriptor, obj: Any) -> bool:
    """Bokeh's ``has_unstable_default`` (3.9), answered once per (property, class): it
    reads the property and the class's overridden defaults only."""
    key = (self, obj.__class__)
    unstable = _UNSTABLE.get(key)
    if unstable is None:
        unstable = _UNSTABLE[key] = BOKEH_HAS_UNSTABLE_DEFAULT(self, obj)
    return unstable


def themed_values(self: HasProps) -> dict[str, Any] | None:
    """Bokeh's ``themed_values`` (3.9): the theme's values set on the instance, or None."""
    return self.__dict__.get("__themed_values__")


def kept_defaults() -> Mapping[tuple[PropertyDescriptor, type], tuple[Any]]:
    """``(descriptor, class) -> (value,)`` of each immutable default kept so far (read-only)."""
    return MappingProxyType(_DEFAULTS)


def kept_containers() -> Mapping[tuple[PropertyDescriptor, type], tuple[type, Any]]:
    """``(descriptor, class) -> (container type, items)`` of each container default kept
    so far (read-only)."""
    return MappingProxyType(_CONTAINERS)


def forget_kept() -> None:
    """Forget every default and answer kept so far: the next reads compute them again."""
    _DEFAULTS.clear()
    _CONTAINERS.clear()
    _UNSTABLE.clear()


def cache_immutable_defaults() -> None:
    """Keep each immutable, unthemed property default per class (see the module's
    docstring); idempotent. Nothing is changed where the patch does not apply."""
    global BOKEH_GET_DEFAULT, BOKEH_HAS_UNSTABLE_DEFAULT, BOKEH_THEMED_VALUES
    if not applies("immutable-defaults"):
        return
    if PropertyDescriptor._get_default is not get_default:
        BOKEH_GET_DEFAULT = PropertyDescriptor._get_default
        PropertyDescriptor._get_default = get_default
    if PropertyDescriptor.has_unstable_default is not has_unstable_default:
        BOKEH_HAS_UNSTABLE_DEFAULT = PropertyDescriptor.has_unstable_default
        PropertyDescriptor.has_unstable_default = has_unstable_default
    if HasProps.themed_values is not themed_values:
        BOKEH_THEMED_VALUES = HasProps.themed_values
        HasProps.themed_values = themed_values
