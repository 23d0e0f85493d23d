"""Tests of the app reach its objects through their public names only.

A test that reads or calls ``obj._name`` of an app object pins the object's insides: the
next refactoring breaks it though the page behaves the same, and a component's private
method called from outside is how a page's parts came to depend on each other's insides.
This scans every test module of tests/app (with ``ast``) and lists each such access as
file:line.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

#: The test modules scanned.
TESTS = sorted(Path(__file__).parent.glob("*.py"))


def _foreign_names(tree: ast.Module) -> set[str]:
    """Names bound by imports of modules outside ``app`` (``pn``, ``np``, ``bokeh``...):
    their private parts are the libraries' business, not the app's."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update((a.asname or a.name).split(".")[0] for a in node.names
                         if a.name.split(".")[0] != "app")
        elif isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] != "app":
            names.update(a.asname or a.name for a in node.names)
    return names


def _root(node: ast.expr) -> str | None:
    while isinstance(node, ast.Attribute | ast.Subscript | ast.Call):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


def private_accesses(path: Path) -> list[str]:
    """``file:line: expression`` of each access to a private attribute of an app object."""
    tree = ast.parse(path.read_text(), filename=str(path))
    foreign = _foreign_names(tree)
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        name = node.attr
        if not name.startswith("_") or (name.startswith("__") and name.endswith("__")):
            continue
        if _root(node.value) in foreign:
            continue
        found.append(f"{path.name}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_the_scan_finds_a_private_access_and_passes_a_library_s():
    """The scanner itself: an app object's private attribute is found, a dunder, a
    library's private part are not."""
    source = ("import panel as pn\nfrom app.explorer import Explorer\n"
              "ex = Explorer()\nex._commit({})\nex.__class__\npn.state._location\n"
              )
    path = Path(__file__).parent / "_scan_probe.txt"
    try:
        path.write_text(source)
        assert private_accesses(path) == ["_scan_probe.txt:4: ex._commit"]
    finally:
        path.unlink()


@pytest.mark.parametrize("path", TESTS, ids=lambda p: p.name)
def test_no_test_reads_a_private_attribute_of_an_app_object(path):
    found = private_accesses(path)
    assert not found, "private attributes of app objects used:\n" + "\n".join(found)
