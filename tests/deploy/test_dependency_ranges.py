"""The dependency ranges in pyproject.toml are the ones the project is tested on.

CI tests the floors (scripts/test-min-versions.sh installs them, `make test-min`) and the
pins in constraints.txt (the newest tested versions, `make test`); here: every runtime
dependency has a floor, the pins lie inside the declared ranges, and panel and bokeh, whose
internals the app patches, are capped at the minor series it was tested on.
"""

from __future__ import annotations

import importlib.util
import tomllib
from importlib.metadata import version
from pathlib import Path

from packaging.requirements import Requirement
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[2]


def _requirements() -> dict[str, Requirement]:
    with open(ROOT / "pyproject.toml", "rb") as f:
        deps = tomllib.load(f)["project"]["dependencies"]
    return {Requirement(d).name: Requirement(d) for d in deps}


def _pins() -> dict[str, Version]:
    pins = {}
    for line in (ROOT / "constraints.txt").read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, _, ver = line.partition("==")
            pins[name.strip().lower()] = Version(ver.strip())
    return pins


def _min_versions():
    spec = importlib.util.spec_from_file_location("min_versions", ROOT / "scripts" /
                                                  "min_versions.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_runtime_dependency_has_a_tested_floor():
    floors = _min_versions().minimum_pins(ROOT / "pyproject.toml")
    reqs = _requirements()
    assert sorted(p.split("==")[0] for p in floors) == sorted(reqs)
    for pin in floors:
        name, floor = pin.split("==")
        assert reqs[name].specifier.contains(floor), f"{name}: floor {floor} outside {reqs[name]}"


def test_pinned_and_installed_versions_are_inside_the_declared_ranges():
    pins = _pins()
    for name, req in _requirements().items():
        assert name in pins, f"{name} is not pinned in constraints.txt"
        assert req.specifier.contains(pins[name]), f"constraints.txt {name} {pins[name]} {req}"
        assert req.specifier.contains(version(name)), f"installed {name} {version(name)} {req}"


def test_patched_libraries_are_capped_at_the_tested_minor_series():
    reqs = _requirements()
    for name in ("panel", "bokeh"):
        caps = [s for s in reqs[name].specifier if s.operator == "<"]
        assert caps, f"{name} has no upper bound: {reqs[name]}"
        pinned = _pins()[name]
        # The cap is the next minor release after the pinned (tested) one.
        assert Version(caps[0].version) == Version(f"{pinned.major}.{pinned.minor + 1}")


#: Imported only where present, with a message naming it where missing
#: (core/sweep/__main__.py writes .parquet with it).
OPTIONAL_IMPORTS = {"pyarrow"}


def _imported_distributions() -> dict[str, set[str]]:
    """``{distribution: files}`` of every third-party module imported by core/ and app/."""
    import ast
    import sys
    from importlib.metadata import packages_distributions

    by_module = packages_distributions()
    found: dict[str, set[str]] = {}
    for package in ("core", "app"):
        for path in (ROOT / package).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Import):
                    names = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    names = [node.module]
                else:
                    continue
                for name in names:
                    top = name.split(".")[0]
                    if top in sys.stdlib_module_names or top in ("core", "app", *OPTIONAL_IMPORTS):
                        continue
                    for dist in by_module.get(top, [top]):
                        found.setdefault(dist.lower(), set()).add(str(path.relative_to(ROOT)))
    return found


def test_every_imported_distribution_is_declared():
    """A module the code imports is a declared dependency (``packaging`` was imported by
    app/perf and arrived only through bokeh's own requirements)."""
    declared = {name.lower() for name in _requirements()}
    missing = {dist: sorted(files) for dist, files in _imported_distributions().items()
               if dist not in declared}
    assert not missing, f"imported but not in pyproject.toml's dependencies: {missing}"
