"""The app reaches the solver library through ``core``'s public names only: no submodule
import (``from core.result import ...``, ``import core.deformable.law``) and no private name
(``from core import _x``, ``theory._y``), so ``core`` can move its insides freely."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import core

APP = Path(__file__).resolve().parents[2] / "app"
MODULES = sorted(APP.rglob("*.py"))


def core_import_faults(source: str) -> list[str]:
    """Each way ``source`` reaches past ``core``'s public names, as a short description."""
    faults = []
    from_core: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("core."):
                    faults.append(f"line {node.lineno}: import {alias.name}")
                elif alias.name == "core":
                    from_core.add(alias.asname or "core")
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module.startswith("core."):
                faults.append(f"line {node.lineno}: from {node.module} import ...")
            elif node.module == "core":
                for alias in node.names:
                    if alias.name.startswith("_"):
                        faults.append(f"line {node.lineno}: private name {alias.name}")
                    from_core.add(alias.asname or alias.name)
    for node in ast.walk(ast.parse(source)):
        # a private attribute of something taken from core (theory._x, core._y)
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in from_core
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            faults.append(f"line {node.lineno}: private name {node.value.id}.{node.attr}")
    return faults


def test_the_app_has_modules_to_check():
    assert len(MODULES) >= 5


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.name)
def test_app_module_imports_only_public_names_of_core(path):
    assert core_import_faults(path.read_text()) == []


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.name)
def test_every_name_the_app_takes_from_core_is_exported(path):
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module == "core":
            for alias in node.names:
                assert alias.name in core.__all__, f"{path.name} imports core.{alias.name}"


@pytest.mark.parametrize(
    "source",
    [
        "from core.result import Status",
        "import core.deformable.law",
        "from core import _private",
        "from core import theory\ntheory._grid_helper(1)",
        "def f():\n    from core.deformable.solver import effective_restitutions",
    ],
)
def test_the_check_finds_each_kind_of_fault(source):
    assert len(core_import_faults(source)) == 1


def test_the_check_passes_public_imports():
    source = "import core\nfrom core import Status, theory\ntheory.classify(1)\ncore.simulate"
    assert core_import_faults(source) == []
