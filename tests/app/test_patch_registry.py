"""Every override of a library internal, in Python or in the page's scripts, is a patch of
:data:`app.perf.PATCHES`: with its version window, under the switch ``EXPLORER_PERF_PATCHES``
and in docs/perf-patches.md.

The overrides are found in the source, not listed by hand:

* ``app/``: an assignment to an attribute of a Bokeh, Panel or Tornado object (a name
  imported from them, or a module fetched by name), a write into ``_property_values``, and a
  method or class attribute of a class that has the name of a private member of Panel's or
  Bokeh's component classes (a mixin overriding ``_server_change``);
* ``static/``: an assignment of a function to a member (``view._update_title = function``),
  any assignment to a ``.prototype.`` member or to ``window.history``, an
  ``Object.defineProperty``, and any use of ``devicePixelRatio``.

Each is named by the member it overrides; a patch lists it in ``overrides`` as
``Owner.member`` and its file in ``where``.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import bokeh.model
import panel.layout.base
import panel.pane.base
import panel.reactive
import panel.viewable
import panel.widgets.base

from app.perf import PATCHES

ROOT = Path(__file__).resolve().parents[2]
#: Libraries whose objects the explorer must not change outside the registry.
LIBRARIES = ("bokeh", "panel", "tornado")
#: Panel's and Bokeh's component classes: a class of app/ that defines one of their private
#: members overrides it (directly or as a mixin put before them).
COMPONENTS = (panel.reactive.Syncable, panel.reactive.Reactive, panel.widgets.base.Widget,
              panel.viewable.Viewable, panel.viewable.Viewer, panel.pane.base.PaneBase,
              panel.layout.base.ListPanel, bokeh.model.Model)
PRIVATE = {name for cls in COMPONENTS for name in dir(cls)
           if name.startswith("_") and not name.startswith("__")}


def _member(override: str) -> str:
    return override.rsplit(".", 1)[-1]


def _library_names(tree: ast.AST) -> set[str]:
    """Names bound to a library's module or object: imports, and a module fetched by name
    (``importlib.import_module("bokeh...")``)."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            module = node.module if isinstance(node, ast.ImportFrom) else None
            for alias in node.names:
                full = module or alias.name
                if full.split(".")[0] in LIBRARIES:
                    names.add(alias.asname or alias.name.split(".")[0])
        elif isinstance(node, ast.Assign) and any(
                isinstance(c, ast.Constant) and isinstance(c.value, str)
                and c.value.split(".")[0] in LIBRARIES for c in ast.walk(node.value)):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return names


def _root_and_members(target: ast.expr) -> tuple[ast.expr, list[str]]:
    members = []
    while isinstance(target, ast.Attribute | ast.Subscript | ast.Call):
        if isinstance(target, ast.Attribute):
            members.append(target.attr)
        target = target.func if isinstance(target, ast.Call) else target.value
    return target, members


def python_overrides(path: Path) -> set[str]:
    """Members of library objects that the module at ``path`` overrides or writes."""
    tree = ast.parse(path.read_text())
    library = _library_names(tree)
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign | ast.AugAssign | ast.AnnAssign):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                root, members = _root_and_members(target)
                if members and isinstance(root, ast.Name) and root.id in library:
                    found.add(members[-1])
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef):
                    names = [item.name]
                elif isinstance(item, ast.Assign):
                    names = [t.id for t in item.targets if isinstance(t, ast.Name)]
                else:
                    names = []
                found.update(name for name in names if name in PRIVATE)
        if (isinstance(node, ast.Attribute) and node.attr == "_property_values") or (
                isinstance(node, ast.Constant) and node.value == "_property_values"):
            found.add("_property_values")  # read, then written in place
    return found


#: Comments of a script (its header says what it patches, in words).
JS_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
JS_OVERRIDES = (
    # view._update_title = function ..., manager.update = () => ...
    re.compile(r"[\w$\]]\.([\w$]+)\s*=\s*(?:function\b|async\b|\([^()]*\)\s*=>|[\w$]+\s*=>)"),
    re.compile(r"\.prototype\.([\w$]+)\s*=[^=]"),
    re.compile(r"\bwindow\.history\.([\w$]+)\s*=[^=]"),
    re.compile(r"\bObject\.defineProperty\(\s*[^,]+,\s*[\"']([\w$]+)[\"']"),
    re.compile(r"\b(devicePixelRatio)\b"),
)
#: Assignments that name their member only at run time: a script must write each one out.
JS_HIDDEN = (re.compile(r"\bObject\.defineProperty\(\s*[^,]+,\s*[^\"'\s]"),
             re.compile(r"\bhistory\s*\[[^\]]+\]\s*=[^=]"))


def js_overrides(path: Path) -> set[str]:
    """Members that the script at ``path`` overrides; a hidden one fails here."""
    code = JS_COMMENT.sub("", path.read_text())
    for pattern in JS_HIDDEN:
        hidden = pattern.search(code)
        assert hidden is None, f"{path}: an override without its member's name: {hidden[0]!r}"
    return {member for pattern in JS_OVERRIDES for member in pattern.findall(code)
            if not member.startswith(("_fie", "__fie"))}  # the explorer's own names


def _sources() -> list[Path]:
    return sorted([*(ROOT / "app").rglob("*.py"), *(ROOT / "static").rglob("*.js")])


def _registered() -> dict[str, set[str]]:
    """``{file: members}`` the registry lists."""
    out: dict[str, set[str]] = {}
    for patch in PATCHES.values():
        for where in patch.where:
            out.setdefault(where, set()).update(_member(o) for o in patch.overrides)
    return out


def test_every_override_of_a_library_internal_is_registered():
    registered = _registered()
    missing = {}
    for path in _sources():
        rel = str(path.relative_to(ROOT))
        found = python_overrides(path) if path.suffix == ".py" else js_overrides(path)
        unlisted = found - registered.get(rel, set())
        if unlisted:
            missing[rel] = sorted(unlisted)
    assert not missing, f"overrides of library internals not in app.perf.PATCHES: {missing}"


def test_every_registered_override_is_in_its_files():
    """A patch removed from the code leaves the registry too."""
    for patch in PATCHES.values():
        text = "".join((ROOT / where).read_text() for where in patch.where)
        assert patch.where, patch.name
        for override in patch.overrides:
            assert _member(override) in text, (patch.name, override)


def test_every_patch_has_a_window_and_a_line_in_the_docs():
    docs = (ROOT / "docs" / "perf-patches.md").read_text()
    for patch in PATCHES.values():
        assert patch.library in ("bokeh", "panel") and patch.in_window(patch.low), patch
        assert not patch.in_window(patch.high), patch
        assert f"| `{patch.name}`" in docs, f"{patch.name} has no row in docs/perf-patches.md"


def test_the_scanner_finds_what_it_is_for(tmp_path):
    """Each kind of override is found (a scanner that finds nothing passes vacuously)."""
    py = tmp_path / "p.py"
    py.write_text("from bokeh.core.has_props import HasProps\n"
                  "HasProps.themed_values = None\n"
                  "class M:\n    def _server_change(self): pass\n"
                  "def f(m):\n    m._property_values['value_throttled'] = 1\n")
    assert python_overrides(py) == {"themed_values", "_server_change", "_property_values"}
    js = tmp_path / "p.js"
    js.write_text("view._update_title = function () {};\n"
                  "A.prototype.x = 1;\nwindow.history.pushState = push;\n"
                  "Object.defineProperty(window, \"devicePixelRatio\", {});\n"
                  "// a.b = function () {} in a comment\n")
    assert js_overrides(js) == {"_update_title", "x", "pushState", "devicePixelRatio"}


def test_each_patching_script_is_told_which_of_its_patches_apply(monkeypatch):
    """The server writes into each patching script's address the names of its patches that
    apply: all of them inside their windows, none with the switch off; other scripts keep
    their address."""
    import app.perf as perf
    from app.main import JS_FILES
    from app.perf.page import page_scripts

    monkeypatch.setenv(perf.SWITCH, "on")  # make test runs tests/app with it off too
    on = page_scripts(JS_FILES)
    assert on["fie_a11y"] == ("assets/a11y.js?apply=slider-handle-names,slider-aria-values,"
                              "help-keys,control-names")
    assert on["fie_paint"] == "assets/perf/bokeh_paint.js?apply=paint-shortcuts"
    assert on["fie_lazy_plots"] == JS_FILES["fie_lazy_plots"]
    told = {name for url in on.values() if "?apply=" in url
            for name in url.split("?apply=")[1].split(",")}
    assert told == {name for name, patch in PATCHES.items() if patch.in_page}
    monkeypatch.setenv(perf.SWITCH, "off")
    off = page_scripts(JS_FILES)
    assert off["fie_a11y"] == "assets/a11y.js?apply="
    assert all(url.endswith("?apply=") for name, url in off.items() if "?" in on[name])
