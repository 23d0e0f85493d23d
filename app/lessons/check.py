"""``python -m app.lessons check DIR``: every lesson of a folder, checked as the page reads
it.

A lesson's form is read by :mod:`app.lessons.format`; each step's state is then loaded into
a page without a browser (an :class:`~app.explorer.Explorer`, solving in this process),
through the page's own reading of a permalink, so that a step is refused exactly when the
page would refuse it, with the page's words: an unknown key, a value out of its range, a
key given twice, or values the solver does not take together (the stop behind the start).
Each problem names the file, the step and what is wrong; the command exits with status 1
if there is any.
"""

from __future__ import annotations

import argparse
import sys
import urllib.parse
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import param

from app.lessons.driver import LESSON_KEYS, step_query
from app.lessons.format import Lesson, LessonError, Question, lesson_files, read_lesson
from app.links import allowed
from app.scenes import SCENES
from app.state import URL_KEYS, ExplorerState


def headless_page() -> Any:
    """A page without a browser whose solves run in this process."""
    from app.explorer import Explorer  # the whole page: only the check needs it here

    return Explorer(lazy_plots=True)


def _scene_problem(query: str) -> str | None:
    """What is wrong with a step's state beside what the page checks: it must name one of
    the paper's scenes (so that it does not depend on the step before) and no lesson."""
    given = dict(urllib.parse.parse_qsl(query, keep_blank_values=True))
    inside = [key for key in LESSON_KEYS if key in given]
    if inside:
        return f"state: a step's state cannot hold {inside[0]!r}"
    if given.get("scene") not in SCENES:
        return (f"state: must name a scene, scene=KEY with KEY one of {', '.join(SCENES)}; "
                f"got {given.get('scene', '')!r}")
    return None


def _guess_problem(question: Question | None) -> str | None:
    """A guess must read a number of the page, within that number's range."""
    if question is None or not question.guess:
        return None
    names = {**{name: name for name in URL_KEYS}, **{k: n for n, k in URL_KEYS.items()}}
    name = names.get(question.guess)
    p = ExplorerState.param[name] if name else None
    if not isinstance(p, param.Number):
        return (f"guess: {question.guess!r} is not a number the page sets (one of "
                f"{', '.join(k for n, k in URL_KEYS.items() if isinstance(ExplorerState.param[n], param.Number))})")  # noqa: E501
    low, high = p.bounds
    if question.low < low or question.high > high:
        return (f"correct: the range of {question.guess} must lie in {allowed(p)}; got "
                f"{question.low:g} to {question.high:g}")
    return None


def check_lesson(lesson: Lesson, page: Any, file: str) -> list[str]:
    """The problems of ``lesson``'s steps, loaded one after another into ``page``."""
    problems = []
    for number, step in enumerate(lesson.steps, start=1):
        own = _scene_problem(step.state) or _guess_problem(step.question)
        if own:
            problems.append(str(LessonError(file, number, own)))
            continue
        refused = list(page.apply_query(step_query(step)))
        if refused:
            problems.append(str(LessonError(file, number, "state: " + "; ".join(refused))))
        elif page.error:
            problems.append(str(LessonError(file, number,
                                            f"state: the page cannot show it: {page.error}")))
    return problems


def check_folder(folder: Path, page: Callable[[], Any] = headless_page) -> list[str]:
    """The problems of every lesson of ``folder`` (empty: all of them can be shown), each
    naming its file and step; a page from ``page()`` per lesson."""
    files = lesson_files(folder)
    if not files:
        return [f"{folder}: no lesson files (*.md besides README.md)"]
    problems = []
    for path in files:
        try:
            lesson = read_lesson(path)
        except LessonError as exc:
            problems.append(str(exc))
            continue
        problems += check_lesson(lesson, page(), path.name)
    return problems


def main(argv: Sequence[str] | None = None) -> int:
    """The command line: ``check DIR``; prints each problem, returns the exit status."""
    parser = argparse.ArgumentParser(prog="python -m app.lessons",
                                     description="Check the lessons of a folder.")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("check", help="check every lesson file of DIR").add_argument(
        "folder", metavar="DIR", type=Path)
    args = parser.parse_args(argv)
    if not args.folder.is_dir():
        print(f"{args.folder}: not a folder", file=sys.stderr)
        return 2
    problems = check_folder(args.folder)
    for problem in problems:
        print(problem, file=sys.stderr)
    files = lesson_files(args.folder)
    if problems:
        print(f"{len(problems)} problem(s) in {args.folder}", file=sys.stderr)
        return 1
    steps = sum(len(read_lesson(p).steps) for p in files)
    print(f"{len(files)} lesson(s), {steps} steps: all can be shown")
    return 0
