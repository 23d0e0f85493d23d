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
Applied only where :mod:`app.perf` says so (name ``immutable-defaults``).
"""

from __future__ import annotations

from typing import Any

from bokeh.core.property.descriptors import PropertyDescriptor

from app.perf import applies

#: Bokeh's own ``PropertyDescriptor._get_default``, once the patch has replaced it.
_bokeh_get_default: Any = None

#: ``(descriptor, class) -> (value,)`` of each immutable, unthemed default read so far.
_DEFAULTS: dict[tuple[PropertyDescriptor, type], tuple[Any]] = {}


def _immutable(value: Any) -> bool:
    if value is None or isinstance(value, (bool, int, float, str)):
        return True
    return type(value) is tuple and all(_immutable(v) for v in value)


def _get_default(self: PropertyDescriptor, obj: Any) -> Any:
    """Bokeh's ``_get_default`` (3.9), with immutable unthemed defaults kept per class."""
    if obj.themed_values() is not None:
        return _bokeh_get_default(self, obj)
    key = (self, obj.__class__)
    kept = _DEFAULTS.get(key)
    if kept is not None:
        return kept[0]
    value = _bokeh_get_default(self, obj)
    if not self.has_unstable_default(obj) and _immutable(value):
        _DEFAULTS[key] = (value,)
    return value


def cache_immutable_defaults() -> None:
    """Keep each immutable, unthemed property default per class (see the module's
    docstring); idempotent. Nothing is changed where the patch does not apply."""
    global _bokeh_get_default
    if not applies("immutable-defaults"):
        return
    if PropertyDescriptor._get_default is not _get_default:
        _bokeh_get_default = PropertyDescriptor._get_default
        PropertyDescriptor._get_default = _get_default
