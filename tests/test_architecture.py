"""The shape of the code, checked on its source: the import graph of ``core`` has no circle,
no module reaches into another's private names, ``core`` imports no UI library, modules
stay short and open with one sentence, and no function is too branched to read.

Each check parses the files (``ast``) or measures them (radon's cyclomatic complexity), so
it runs in a second and fails with the file, the name and the number that break it.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from radon.complexity import cc_visit

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("core", "app")
#: Longest module, in lines: a longer one is two concepts (cut it by concept).
MAX_LINES = 600
#: The one module allowed to be longer: the contact law, whole in one place (its branches,
#: envelopes and closed-form integrals read together; docs/contact-law.md).
LONG_MODULES = {"core/deformable/law.py"}
#: Largest cyclomatic complexity of a function, as radon counts it (``ruff``'s C901 counts
#: a little differently: boolean operators are branches here).
MAX_COMPLEXITY = 15
#: What ``core`` must never import: the app and the UI libraries it is built on.
UI_PACKAGES = {"app", "panel", "bokeh", "param"}
#: Abbreviations whose full stop does not end a sentence.
ABBREVIATIONS = re.compile(r"\b(?:e\.g|i\.e|cf|vs|Eqs?|Figs?|Secs?|al|approx)\.", re.IGNORECASE)


def _files(*packages: str) -> list[Path]:
    return sorted(p for pkg in packages for p in (ROOT / pkg).rglob("*.py"))


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {_module_name(p): p for p in _files(*PACKAGES)}


def _is_package(name: str) -> bool:
    return MODULES.get(name, Path()).name == "__init__.py"


def _absolute(module: str, node: ast.ImportFrom) -> str:
    """The module an ``ImportFrom`` in ``module`` names, relative imports resolved."""
    if not node.level:
        return node.module or ""
    base = module.split(".")
    # a package's own relative import starts at the package; a module's at its parent
    base = base if _is_package(module) else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(module: str, tree: ast.AST) -> list[tuple[str, str | None, int]]:
    """Every import anywhere in the module (also inside functions and under
    ``TYPE_CHECKING``): ``(module imported, name taken from it or None, line)``."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(alias.name, None, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            source = _absolute(module, node)
            for alias in node.names:
                sub = f"{source}.{alias.name}"
                if sub in MODULES:  # ``from core.sweep import scalar``: the module itself
                    found.append((sub, None, node.lineno))
                else:
                    found.append((source, alias.name, node.lineno))
    return found


def _trees() -> dict[str, ast.AST]:
    return {name: ast.parse(path.read_text(), filename=str(path))
            for name, path in MODULES.items()}


TREES = _trees()


def _core_graph() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for name in MODULES:
        if name.split(".")[0] != "core":
            continue
        graph[name] = {target for target, _, _ in _imports(name, TREES[name])
                       if target in MODULES and target.split(".")[0] == "core"}
    return graph


def _components(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with a circle (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in graph[v]:
                components.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return components


def _cycles(graph: dict[str, set[str]]) -> list[str]:
    """One circle per strongly connected component, and the component's other modules."""
    out = []
    for comp in _components(graph):
        circle = _circle(graph, comp)
        rest = sorted(set(comp) - set(circle))
        out.append(" -> ".join(circle) + (f" (and through {', '.join(rest)})" if rest else ""))
    return out


def _circle(graph: dict[str, set[str]], comp: list[str]) -> list[str]:
    """The shortest circle through the first module of a strongly connected component."""
    start, members = comp[0], set(comp)
    came: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v] & members):
                if w == start:
                    path = [v]
                    while path[-1] != start:
                        path.append(came[path[-1]])
                    return [start, *path[::-1][1:], start] if v != start else [start, start]
                if w not in came:
                    came[w] = v
                    nxt.append(w)
        frontier = nxt
    return [start, "..."]  # (cannot happen in a component)


def test_the_cycle_finder_finds_a_circle():
    """The check below can fail: a graph with a circle is reported with it."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(graph) == ["a -> b -> c -> a"]
    graph["c"] = {"a", "e"}
    graph["e"] = {"b"}
    assert _cycles(graph) == ["a -> b -> c -> a (and through e)"]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_core_import_graph_has_no_circle():
    circles = _cycles(_core_graph())
    assert not circles, "import circles in core:\n" + "\n".join(circles)


def _private_reaches(module: str, tree: ast.AST) -> list[str]:
    """Underscore names of other project modules that ``module`` takes: imported by name,
    or read as an attribute of an imported module."""
    found = []
    aliases: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname:
                    aliases[alias.asname] = alias.name
                else:
                    top = alias.name.split(".")[0]
                    aliases[top] = top
        elif isinstance(node, ast.ImportFrom):
            source = _absolute(module, node)
            for alias in node.names:
                if f"{source}.{alias.name}" in MODULES:
                    aliases[alias.asname or alias.name] = f"{source}.{alias.name}"
                elif (source in MODULES and source != module and _private(alias.name)):
                    found.append(f"{module}:{node.lineno}: from {source} import {alias.name}")
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            target = _dotted(node.value, aliases)
            if target in MODULES and target != module:
                found.append(f"{module}:{node.lineno}: {target}.{node.attr}")
    return found


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _dotted(node: ast.AST, aliases: dict[str, str]) -> str | None:
    """The module an expression such as ``core.steady`` or an alias of it names."""
    if isinstance(node, ast.Name):
        return aliases.get(node.id)
    if isinstance(node, ast.Attribute):
        base = _dotted(node.value, aliases)
        return None if base is None else f"{base}.{node.attr}"
    return None


def test_the_private_name_check_finds_a_reach():
    """The check below can fail: both ways of reaching a private name are found."""
    tree = ast.parse("from core.steady import _oscillation\nimport core.dense\n"
                     "core.dense._state_scale(1)\nfrom core import result as r\nr._x\n")
    found = _private_reaches("core.other", tree)
    assert sorted(f.split(": ")[1] for f in found) == [
        "core.dense._state_scale", "core.result._x", "from core.steady import _oscillation"]


def test_no_module_takes_private_names_of_another():
    found = [f for name, tree in TREES.items() for f in _private_reaches(name, tree)]
    assert not found, "private names taken across modules:\n" + "\n".join(found)


def _ui_imports(name: str, tree: ast.AST) -> list[str]:
    return [f"{name}:{line}: {target}" for target, _, line in _imports(name, tree)
            if target.split(".")[0] in UI_PACKAGES]


def test_the_ui_import_check_finds_a_guarded_import():
    """The check below can fail: an import under ``TYPE_CHECKING`` or inside a function
    counts."""
    tree = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                     "    import panel as pn\ndef f():\n    from app.plots import x\n")
    assert _ui_imports("core.x", tree) == ["core.x:3: panel", "core.x:5: app.plots"]


def test_core_imports_no_app_or_ui_library():
    found = [f for name, tree in TREES.items() if name.split(".")[0] == "core"
             for f in _ui_imports(name, tree)]
    assert not found, "core imports the app or a UI library:\n" + "\n".join(found)


def test_no_module_is_too_long():
    long = [f"{_rel(p)}: {n} lines" for p in _files(*PACKAGES)
            if (n := len(p.read_text().splitlines())) > MAX_LINES and _rel(p) not in LONG_MODULES]
    assert not long, f"modules over {MAX_LINES} lines:\n" + "\n".join(long)


def _one_sentence(paragraph: str) -> bool:
    text = ABBREVIATIONS.sub("Abbr", " ".join(paragraph.split()))
    text = re.sub(r"``.*?``|`[^`]*`", "code", text)  # literals may hold full stops
    return text.endswith(".") and not re.search(r"[.!?]\s+\S", text)


@pytest.mark.parametrize(("paragraph", "one"), [
    ("The transition log: every transition, the first ones stored.", True),
    ("Exact flight (paper Eq. 7, e.g. ``x = 0. 1``).", True),
    ("Build a result. This module is long because it holds a lot.", False),
    ("Build a result", False),
])
def test_the_sentence_check_tells_one_sentence_from_two(paragraph, one):
    assert _one_sentence(paragraph) is one


def test_core_modules_open_with_one_sentence():
    bad = []
    for name, tree in TREES.items():
        if name.split(".")[0] != "core":
            continue
        doc = ast.get_docstring(tree, clean=True)
        first = (doc or "").split("\n\n")[0]
        if not _one_sentence(first):
            bad.append(f"{_rel(MODULES[name])}: {first[:120]!r}")
    assert not bad, "core modules whose docstring does not open with one sentence:\n" + (
        "\n".join(bad))


def _complexities(source: str) -> list[tuple[str, int]]:
    """``(name, complexity)`` of every function, method and closure in ``source``."""
    out = []

    def walk(block, prefix: str) -> None:
        if hasattr(block, "methods"):  # a class
            for inner in [*block.methods, *block.inner_classes]:
                walk(inner, f"{prefix}{block.name}.")
            return
        name = f"{prefix}{block.name}"
        out.append((name, block.complexity))
        for inner in block.closures:
            walk(inner, f"{name}.")

    for block in cc_visit(source):
        if not getattr(block, "is_method", False):
            walk(block, "")
    return out


def test_the_complexity_check_counts_branches():
    source = "def f(a):\n" + "".join(f"    if a == {i}:\n        return {i}\n"
                                     for i in range(MAX_COMPLEXITY)) + "    return -1\n"
    assert _complexities(source) == [("f", MAX_COMPLEXITY + 1)]


def test_no_function_is_too_complex():
    over = [f"{_rel(p)}:{name}:{cc}" for p in _files(*PACKAGES)
            for name, cc in _complexities(p.read_text()) if cc > MAX_COMPLEXITY]
    assert not over, f"functions over cyclomatic complexity {MAX_COMPLEXITY} (radon):\n" + (
        "\n".join(over))
