"""A lesson file read into values: its steps, each with a title, a state, text and at most
one question (the format is the lessons folder's README).

Only the file's form is checked here: the fields, the plots' names, the question's parts.
Whether a step's state is one the page takes is for the page itself to say
(:mod:`app.lessons.check`, :mod:`app.lessons.player`).

Examples
--------
>>> lesson = parse_lesson("demo", '''# Demo
... One step.
... ---
... title: Stick and slip
... state: scene=3a
... plots: phase
... ---
... The mass rides on the belt at $x' = v$.
... ''')
>>> lesson.title, lesson.steps[0].state, lesson.steps[0].plots
('Demo', 'scene=3a', ('phase',))
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from app.scenes import PLOTS

#: The line that opens and closes a step's front matter.
FENCE = re.compile(r"^---\s*$", re.MULTILINE)
#: A front-matter line: ``key: value`` (a line indented by two spaces continues the value).
FIELD = re.compile(r"^([a-z]+):\s?(.*)$")
#: The fields of a step's front matter, and those a step must have.
FIELDS = ("title", "state", "plots", "highlight", "ask", "choices", "guess", "correct",
          "reason")
REQUIRED = ("title", "state")
#: A range answer: ``LOW to HIGH`` (decimal numerals).
RANGE = re.compile(r"^\s*(\S+)\s+to\s+(\S+)\s*$")
#: The suffix of a lesson file; the folder's README is not a lesson.
SUFFIX, README = ".md", "README.md"


class LessonError(ValueError):
    """A lesson the page refuses: the message names the file, the step (1-based; 0 for the
    file as a whole) and the problem.

    >>> str(LessonError("paper.md", 3, "state: unknown key 'colour'"))
    "paper.md, step 3: state: unknown key 'colour'"
    """

    def __init__(self, file: str, step: int, problem: str) -> None:
        where = f"{file}, step {step}" if step else file
        super().__init__(f"{where}: {problem}")
        self.file, self.step, self.problem = file, step, problem


@dataclass(frozen=True)
class Question:
    """Predict, then see: the question asked before the plots are shown.

    Either ``choices`` (multiple choice; ``correct`` the 1-based number of the right one) or
    ``guess`` (the permalink key of a number the student sets on the page; the answer is
    right inside ``low .. high``).
    """

    ask: str
    reason: str
    choices: tuple[str, ...] = ()
    correct: int = 0
    guess: str = ""
    low: float = 0.0
    high: float = 0.0

    def right(self, answer: int | float) -> bool:
        """Whether ``answer`` (a choice's 1-based number, or the guessed value) is right."""
        if self.choices:
            return answer == self.correct
        return self.low <= answer <= self.high


@dataclass(frozen=True)
class Step:
    """One step: its title, the page's state as a permalink query, its text (Markdown with
    ``$...$`` mathematics), the plots it is about, what to look at, and a question."""

    title: str
    state: str
    text: str
    plots: tuple[str, ...] = ()
    highlight: str = ""
    question: Question | None = None


@dataclass(frozen=True)
class Lesson:
    """A lesson: its name (the file's stem, as in ``?lesson=NAME``), title, summary, steps."""

    name: str
    title: str
    summary: str
    steps: tuple[Step, ...]


def lesson_files(folder: Path) -> list[Path]:
    """The lesson files of ``folder``, by name (its README left out)."""
    return sorted(p for p in Path(folder).glob(f"*{SUFFIX}") if p.name != README)


def read_lesson(path: Path) -> Lesson:
    """The lesson in file ``path``; raises :class:`LessonError` naming the file."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise LessonError(path.name, 0, f"cannot be read: {exc}") from None
    return parse_lesson(path.stem, text, path.name)


def parse_lesson(name: str, text: str, file: str | None = None) -> Lesson:
    """The lesson ``name`` written in ``text`` (file name ``file`` in messages).

    The text is an introduction (a ``# Title`` line, then a summary), then per step a front
    matter between two ``---`` lines and the step's Markdown. Raises :class:`LessonError`.
    """
    file = file or f"{name}{SUFFIX}"
    parts = FENCE.split(text)
    intro, rest = parts[0].strip(), parts[1:]
    if not intro.startswith("# "):
        raise LessonError(file, 0, "must begin with the lesson's title, a line '# Title'")
    title, _, summary = intro.partition("\n")
    if not rest:
        raise LessonError(file, 0, "has no steps (a step begins with a line '---')")
    if len(rest) % 2:
        raise LessonError(file, len(rest) // 2 + 1,
                          "its front matter is not closed by a line '---'")
    steps = tuple(_step(file, k // 2 + 1, rest[k], rest[k + 1])
                  for k in range(0, len(rest), 2))
    return Lesson(name, title[2:].strip(), summary.strip(), steps)


def _fields(file: str, number: int, matter: str) -> dict[str, str]:
    """The ``key: value`` fields of a step's front matter."""
    fields: dict[str, str] = {}
    last = None
    for line in matter.strip("\n").splitlines():
        if not line.strip():
            continue
        if line.startswith("  ") and last is not None:
            fields[last] += "\n" + line.strip()
            continue
        match = FIELD.match(line)
        if match is None:
            raise LessonError(file, number, f"front matter line {line.strip()!r} is not "
                                            "'field: value'")
        key, value = match.groups()
        if key not in FIELDS:
            raise LessonError(file, number, f"unknown field {key!r} (fields: "
                                            f"{', '.join(FIELDS)})")
        if key in fields:
            raise LessonError(file, number, f"field {key!r} is given twice")
        fields[key], last = value.strip(), key
    missing = [key for key in REQUIRED if not fields.get(key)]
    if missing:
        raise LessonError(file, number, f"missing field {missing[0]!r}")
    return fields


def _step(file: str, number: int, matter: str, body: str) -> Step:
    fields = _fields(file, number, matter)
    plots = tuple(p.strip() for p in fields.get("plots", "").split(",") if p.strip())
    unknown = [p for p in plots if p not in PLOTS]
    if unknown:
        raise LessonError(file, number, f"plots: unknown plot {unknown[0]!r} (plots: "
                                        f"{', '.join(PLOTS)})")
    if not body.strip():
        raise LessonError(file, number, "has no text after its front matter")
    return Step(title=fields["title"], state=fields["state"].removeprefix("?"),
                text=body.strip(), plots=plots, highlight=fields.get("highlight", ""),
                question=_question(file, number, fields))


def _question(file: str, number: int, fields: dict[str, str]) -> Question | None:
    """The step's question, or None; the parts of a question are all or nothing."""
    parts = ("ask", "choices", "guess", "correct", "reason")
    if not any(key in fields for key in parts):
        return None
    for key in ("ask", "correct", "reason"):
        if not fields.get(key):
            raise LessonError(file, number, f"a question needs the field {key!r} (ask, "
                              "choices or guess, correct, reason)")
    if ("choices" in fields) == ("guess" in fields):
        raise LessonError(file, number,
                          "a question has either 'choices' or 'guess', not both or neither")
    try:
        if "choices" in fields:
            return _choice_question(fields)
        return _guess_question(fields)
    except ValueError as exc:
        raise LessonError(file, number, str(exc)) from None


def _choice_question(fields: dict[str, str]) -> Question:
    """A multiple-choice question; ValueError names what is wrong."""
    correct = fields["correct"]
    lines = [line.strip() for line in fields["choices"].splitlines() if line.strip()]
    choices = tuple(line.removeprefix("- ").strip() for line in lines)
    if len(choices) < 2 or not all(line.startswith("- ") for line in lines):
        raise ValueError("choices: give two or more, one a line, each '  - text'")
    if not correct.isdigit() or not 1 <= int(correct) <= len(choices):
        raise ValueError(f"correct must be the number of a choice, 1 to {len(choices)}; "
                         f"got {correct!r}")
    return Question(fields["ask"], fields["reason"], choices=choices, correct=int(correct))


def _guess_question(fields: dict[str, str]) -> Question:
    """A question answered by dragging a slider to a range; ValueError names what is
    wrong."""
    correct = fields["correct"]
    match = RANGE.match(correct)
    try:
        low, high = (float(x) for x in match.groups()) if match else (None, None)
    except ValueError:
        low = high = None
    if low is None or not low <= high:
        raise ValueError(f"correct must be a range 'LOW to HIGH' with LOW <= HIGH; "
                         f"got {correct!r}")
    return Question(fields["ask"], fields["reason"], guess=fields["guess"], low=low,
                    high=high)
