"""A numerical method's entry point, derived from its options declared once as a dataclass.

Each method declares its options, with their defaults and checks, in one frozen dataclass
(:class:`core.event_method.EventOptions`, :class:`core.switch.SwitchOptions`);
:func:`takes_options` turns ``solve(inputs, opts)`` into ``solve(inputs, *, name=default,
...)`` with those fields as its keyword options, so the defaults a caller sees in
``help`` and ``inspect`` are the dataclass's and cannot drift from them.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
from collections.abc import Callable
from typing import Any, TypeVar

from core.result import Result
from core.solve_inputs import SolveInputs

Options = TypeVar("Options")


def takes_options(options: type[Options]) -> Callable[
        [Callable[[SolveInputs, Options], Result]], Callable[..., Result]]:
    """Decorator: ``solve(inputs, opts)`` called as ``solve(inputs, **fields)``, where the
    fields of the dataclass ``options`` are the keyword options with their defaults; an
    option that is not a field is refused by name (``TypeError``).

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Opts:
    ...     rtol: float = 1e-6
    >>> @takes_options(Opts)
    ... def solve(inputs, opts):
    ...     return opts.rtol
    >>> str(inspect.signature(solve)), solve(None, rtol=1e-3)
    ("(inputs: 'SolveInputs', *, rtol: 'float' = 1e-06) -> 'Result'", 0.001)
    """
    fields = [f for f in dataclasses.fields(options) if f.init]
    names = {f.name for f in fields}
    signature = inspect.Signature(
        [inspect.Parameter("inputs", inspect.Parameter.POSITIONAL_OR_KEYWORD,
                           annotation="SolveInputs")]
        + [inspect.Parameter(f.name, inspect.Parameter.KEYWORD_ONLY, default=f.default,
                             annotation=f.type) for f in fields],
        return_annotation="Result",
    )

    def wrap(run: Callable[[SolveInputs, Options], Result]) -> Callable[..., Result]:
        @functools.wraps(run)
        def solve(inputs: SolveInputs, **given: Any) -> Result:
            for name in given:
                if name not in names:
                    raise TypeError(
                        f"{run.__name__}() got an unexpected keyword argument {name!r}")
            return run(inputs, options(**given))

        solve.__signature__ = signature  # type: ignore[attr-defined]
        return solve

    return wrap
