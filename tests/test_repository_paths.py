"""The repository stands alone: every file path and docs/ section its prose names exists.

The prose is the docs (docs/*.md, README.md, benchmarks/README.md) and the comments and docstrings
of core/, app/, tests/ and benchmarks/; string literals in code are not prose (a URL the server
answers, or the name of a BokehJS module, only looks like a path). A file that moves leaves its old
path behind in the prose; these tests name it.
"""

from __future__ import annotations

import ast
import functools
import io
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Top-level directories of the repository: a path the prose names starts at one of them.
TOP_LEVEL = ("core", "app", "docs", "benchmarks", "static", "scripts", "tests", ".ci")

#: A repository path: a top-level directory, a slash, then letters, digits and ``_ . / * -``,
#: ending in a letter, digit, slash or ``*`` (so a sentence's full stop is not taken). It must
#: not follow a letter, digit, dot, slash or hyphen, so that the tail of another path
#: (``.venv/lib/.../core/x.py``) or of a URL (``https://host/static/x.js``) is not taken.
#: A ``*`` makes it a glob, which must match something (``benchmarks/results/*.txt``).
PATH = re.compile(
    r"(?<![\w./-])(?:" + "|".join(map(re.escape, TOP_LEVEL)) + r")/[\w./*-]*[\w/*]"
)

#: A cited section: ``docs/<page>.md, "<heading>"`` (the comma is optional), the heading as
#: it reads without its Markdown backticks.
SECTION = re.compile(r'(docs/[\w-]+\.md),? "([^"]+)"')

DOCS = sorted(ROOT.glob("docs/*.md")) + [ROOT / "README.md", ROOT / "benchmarks" / "README.md"]
SOURCES = sorted(
    path for top in ("core", "app", "tests", "benchmarks") for path in (ROOT / top).rglob("*.py")
)


def python_prose(source: str) -> list[str]:
    """The comments and the docstrings of a Python module, one string each."""
    tokens = tokenize.generate_tokens(io.StringIO(source).readline)
    comments = [tok.string.lstrip("#:") for tok in tokens if tok.type == tokenize.COMMENT]
    nodes = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    docstrings = [
        ast.get_docstring(node, clean=False) or ""
        for node in ast.walk(ast.parse(source))
        if isinstance(node, nodes)
    ]
    # a module's comments read as one text, so that a citation may wrap over lines
    return [" ".join(comments), *docstrings]


@functools.cache
def prose() -> tuple[tuple[str, str], ...]:
    """``(file, text)`` for every piece of prose, whitespace collapsed to single spaces."""
    pieces = [(path, path.read_text()) for path in DOCS]
    pieces += [(path, text) for path in SOURCES for text in python_prose(path.read_text())]
    return tuple((str(path.relative_to(ROOT)), " ".join(text.split())) for path, text in pieces)


def exists(path: str) -> bool:
    if "*" in path:
        return any(ROOT.glob(path))
    return (ROOT / path).exists()


def headings(page: Path) -> set[str]:
    """The Markdown headings of ``page`` without their backticks (a ``#`` in a fenced code
    block is a shell comment, not a heading)."""
    found, fenced = set(), False
    for line in page.read_text().splitlines():
        fenced ^= line.startswith("```")
        if line.startswith("#") and not fenced:
            found.add(" ".join(line.lstrip("#").replace("`", "").split()))
    return found


def test_the_prose_names_paths():
    """The extraction finds what it looks for (a regex that matched nothing would pass)."""
    named = {path for _, text in prose() for path in PATH.findall(text)}
    assert {"core/deformable/law.py", "docs/physics.md", "benchmarks/results/"} <= named


def test_every_path_named_in_the_prose_exists():
    """Each path named in the docs, comments and docstrings is in the repository."""
    missing = sorted(
        f"{name}: {path}"
        for name, text in prose()
        for path in PATH.findall(text)
        if not exists(path)
    )
    assert not missing, "\n".join(missing)


def test_every_cited_docs_section_exists():
    """``docs/<page>.md, "<heading>"`` names a heading of that page."""
    pages = {str(p.relative_to(ROOT)): headings(p) for p in ROOT.glob("docs/*.md")}
    wrong = sorted(
        f"{name}: {page}, {title!r}"
        for name, text in prose()
        for page, title in SECTION.findall(text)
        if title not in pages.get(page, set())
    )
    assert not wrong, "\n".join(wrong)
