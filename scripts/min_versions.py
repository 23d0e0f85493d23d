"""Print the declared minimum version of every runtime dependency, one ``name==version`` a line.

Reads ``[project] dependencies`` of pyproject.toml; every entry must have a lower bound
(``>=``), which is what `scripts/test-min-versions.sh` installs to test it. An entry without
one is an error, because a range with no tested floor is not a range the project is tested on.

    python scripts/min_versions.py [pyproject.toml]
"""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

LOWER = re.compile(r">=\s*([0-9][0-9A-Za-z.]*)")
NAME = re.compile(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)")


def minimum_pins(pyproject: Path) -> list[str]:
    with open(pyproject, "rb") as f:
        deps = tomllib.load(f)["project"]["dependencies"]
    pins = []
    for dep in deps:
        name, lower = NAME.match(dep), LOWER.search(dep)
        if name is None or lower is None:
            raise SystemExit(f"{pyproject}: dependency {dep!r} has no lower bound (>=)")
        pins.append(f"{name.group(1)}=={lower.group(1)}")
    return pins


if __name__ == "__main__":
    path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[1] / "pyproject.toml"
    print("\n".join(minimum_pins(path)))
