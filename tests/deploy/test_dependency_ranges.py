"""The dependency ranges in pyproject.toml are the ones the project is tested on.

CI tests the floors (scripts/test-min-versions.sh installs them, `make test-min`) and the
pins in constraints.txt (the newest tested versions, `make test`); here: every runtime
dependency has a floor, the pins lie inside the declared ranges, and panel and bokeh, whose
internals the app patches, are capped at the minor series it was tested on.
"""

from __future__ import annotations

import importlib.util
from importlib.metadata import version
from pathlib import Path

import tomllib
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
