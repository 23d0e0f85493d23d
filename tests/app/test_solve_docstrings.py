"""The examples in the docstrings of the page's solves (app/solve) run and give what they
show."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import app.solve

MODULES = sorted(m.name for m in pkgutil.iter_modules(app.solve.__path__, "app.solve."))


def test_the_package_has_its_modules():
    assert {"app.solve.pool", "app.solve.runner", "app.solve.presets", "app.solve.measure",
            "app.solve.theory", "app.solve.regime_map"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    failures, _ = doctest.testmod(importlib.import_module(name))
    assert failures == 0
