"""Lessons (app.lessons): the format, the check command, and the player on a page without a
browser (tests/ui/test_lessons_ui.py walks the paper's lesson in Chromium)."""

from __future__ import annotations

import html
import re
import subprocess
import sys
from pathlib import Path

import pytest
from panel.io.location import Location

from app.explorer import Explorer
from app.lessons.check import check_folder
from app.lessons.driver import step_query, with_lesson
from app.lessons.format import LessonError, lesson_files, parse_lesson, read_lesson
from app.lessons.mount import LESSONS_DIR
from app.lessons.player import HIDDEN_STYLE
from app.lessons.text import lesson_html
from app.scenes import SCENES
from app.state import URL_KEYS

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = Path(__file__).resolve().parent / "lesson_fixtures"
#: Each broken fixture: the step its message names and words of the problem.
BROKEN = {
    "unknown_key.md": (2, "unknown key 'colour'"),
    "out_of_range.md": (1, "r (restitution) must be a number in [0, 1]; got '1.5'"),
    "unclosed.md": (2, "front matter is not closed"),
    "bad_choice.md": (1, "correct must be the number of a choice, 1 to 2; got '3'"),
    "no_scene.md": (1, "must name a scene"),
    "behind_the_start.md": (1, "x0 must not lie beyond the stop"),
    "unknown_plot.md": (1, "unknown plot 'spectrum'"),
    "twice.md": (1, "r (restitution) must be given once"),
}


def _run_check(folder: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "app.lessons", "check", str(folder)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_the_check_command_passes_on_the_shipped_lessons():
    done = _run_check(ROOT / "app" / "lessons")
    assert done.returncode == 0, done.stderr
    assert "all can be shown" in done.stdout


def test_the_check_command_names_file_step_and_problem_of_every_broken_lesson():
    assert sorted(p.name for p in lesson_files(FIXTURES)) == sorted(BROKEN)
    done = _run_check(FIXTURES)
    assert done.returncode == 1
    lines = done.stderr.splitlines()
    for file, (step, problem) in BROKEN.items():
        mine = [line for line in lines if line.startswith(f"{file}, step {step}: ")]
        assert len(mine) == 1, (file, lines)
        assert problem in mine[0]
    assert f"{len(BROKEN)} problem(s)" in lines[-1]


def test_the_readme_example_is_a_lesson_the_page_takes(tmp_path):
    readme = (LESSONS_DIR / "README.md").read_text()
    example = re.search(r"```markdown\n(.*?)```", readme, re.S).group(1)
    (tmp_path / "example.md").write_text(example)
    assert check_folder(tmp_path) == []
    lesson = read_lesson(tmp_path / "example.md")
    assert len(lesson.steps) == 2 and lesson.steps[1].question.correct == 2


@pytest.mark.parametrize("text, step, problem", [
    ("no title\n---\ntitle: t\nstate: scene=5a\n---\nx", 0, "must begin with"),
    ("# T\nsummary", 0, "has no steps"),
    ("# T\n---\ntitle: t\nstate: scene=5a\ncolour: red\n---\nx", 1, "unknown field 'colour'"),
    ("# T\n---\ntitle: t\ntitle: u\nstate: scene=5a\n---\nx", 1, "given twice"),
    ("# T\n---\ntitle: t\n---\nx", 1, "missing field 'state'"),
    ("# T\n---\ntitle: t\nstate: scene=5a\njust words\n---\nx", 1, "is not 'field: value'"),
    ("# T\n---\ntitle: t\nstate: scene=5a\n---\n", 1, "has no text"),
    ("# T\n---\ntitle: t\nstate: scene=5a\nask: q\ncorrect: 1\nreason: r\n---\nx", 1,
     "either 'choices' or 'guess'"),
    ("# T\n---\ntitle: t\nstate: scene=5a\nask: q\nguess: xbar\ncorrect: 0.3 to 0.2\n"
     "reason: r\n---\nx", 1, "LOW <= HIGH"),
    ("# T\n---\ntitle: t\nstate: scene=5a\nask: q\nchoices:\n  - a\ncorrect: 1\n"
     "reason: r\n---\nx", 1, "two or more"),
])
def test_a_malformed_lesson_is_refused_naming_its_step(text, step, problem):
    with pytest.raises(LessonError) as caught:
        parse_lesson("bad", text)
    assert caught.value.step == step and problem in caught.value.problem
    assert str(caught.value).startswith("bad.md")


def test_the_paper_lesson_tells_the_story_in_order():
    """Stick-slip without a stop, elastic impacts, inelastic ones, grazing, Zeno, the map,
    the deformable stop: at least 10 steps, with predict steps of both kinds."""
    lesson = read_lesson(LESSONS_DIR / "paper.md")
    assert len(lesson.steps) >= 10
    scenes = [dict(re.findall(r"(\w+)=([^&]*)", s.state))["scene"] for s in lesson.steps]
    order = ["3a", "5a", "7a", "7c", "7d", "2b", "11"]
    assert [scenes.index(key) for key in order] == sorted(scenes.index(k) for k in order)
    assert any("map" in s.plots for s in lesson.steps)
    questions = [s.question for s in lesson.steps if s.question is not None]
    assert any(q.choices for q in questions) and any(q.guess for q in questions)


def test_the_trade_lesson_shows_each_method_and_asks_to_measure():
    lesson = read_lesson(LESSONS_DIR / "trade.md")
    methods = {dict(re.findall(r"(\w+)=([^&]*)", s.state)).get("method") for s in lesson.steps}
    assert {"exact", "switch", "event"} <= methods
    assert any("Measure the trade" in s.text for s in lesson.steps)


def test_the_guess_step_s_answer_is_the_grazing_band_of_its_scene():
    """The grazing band a <= x_bar < x* of the guess step, from the closed forms
    (docs/physics.md, "Closed-form results"), computed here from the scene's values."""
    step = next(s for s in read_lesson(LESSONS_DIR / "paper.md").steps
                if s.question is not None and s.question.guess)
    values = SCENES["7b"].values
    a = values["mu_k"] * values["u_s"]
    x_star = a + values["belt_speed"] * (1 - values["restitution"] ** 2) ** 0.5
    q = step.question
    assert q.guess == "xbar" and q.low == pytest.approx(a)
    assert a < q.high < x_star and x_star - q.high < 1e-3  # the band, written to 4 digits


@pytest.mark.parametrize("path", lesson_files(LESSONS_DIR), ids=lambda p: p.name)
def test_lesson_text_is_mathematics_and_names_no_file(path):
    lesson = read_lesson(path)
    for step in lesson.steps:
        for text in (step.text, step.title, step.highlight,
                     *(() if step.question is None else (step.question.ask,
                                                         step.question.reason))):
            html = lesson_html(text)
            assert "$" not in html, (step.title, text)  # every dollar paired, typeset
            assert not re.search(r"\b(app|core|docs|tests)/|\.py\b|\.md\b", text)
    assert any("\\(" in lesson_html(s.text) for s in lesson.steps)


def test_a_step_query_gives_the_same_state_whatever_the_page_showed_before():
    step = read_lesson(LESSONS_DIR / "paper.md").steps[8]
    fresh, used = Explorer(), Explorer()
    used.state.param.update(units="SI", method="switch", show_all=True, accuracy="draft",
                            belt_speed=0.4, scene="custom")
    for page in (fresh, used):
        assert page.apply_query(step_query(step)) == []
    names = [n for n in URL_KEYS if n != "scene"]
    assert [getattr(used.state, n) for n in names] == [getattr(fresh.state, n) for n in names]
    assert used.state.scene == fresh.state.scene == "7c"


def test_with_lesson_keeps_the_other_keys():
    assert with_lesson("?a=1&lesson=x&step=9&b=2", "paper", 2) == "?a=1&b=2&lesson=paper&step=2"


def test_a_page_without_a_lesson_builds_no_player():
    page = Explorer()
    page.sync_url(Location(search="?scene=7c"))
    assert page.lessons.player is None and page.lessons.panels == []
    assert "fie-open-lessons" in page.lessons.button.css_classes


@pytest.fixture()
def lesson_page():
    page = Explorer()
    page.main()
    location = Location(search="?lesson=paper&step=4")
    page.sync_url(location)
    return page, page.lessons.player, location


def test_a_step_link_loads_its_state_and_steps_write_the_address(lesson_page):
    page, player, location = lesson_page
    steps = player.lesson.steps
    assert player.index == 3 and page.state.scene == "5a"
    assert "lesson=paper" in location.search and "step=4" in location.search
    player.keys.forward += 1  # the → key
    assert player.index == 4 and page.state.scene == "5b" and "step=5" in location.search
    player.keys.back += 1  # the ← key
    player.keys.back += 1
    assert player.index == 2 and "step=3" in location.search
    assert page.state.belt_speed == 0.3 and steps[2].question is not None


def test_back_to_this_step_restores_the_state_after_the_student_moved(lesson_page):
    page, player, _ = lesson_page
    before = page.state.values()
    x_before = page.plots.sources["traj"].data["x"].copy()
    page.state.clearance = 0.4
    assert page.state.values() != before
    player.restore.clicks += 1
    assert page.state.values() == before
    assert (page.plots.sources["traj"].data["x"] == x_before).all()


def _shown(panes) -> list[bool]:
    return [pane.styles.get("display") != HIDDEN_STYLE["display"] for pane in panes]


def test_a_question_hides_the_answer_until_it_is_answered(lesson_page):
    page, player, _ = lesson_page
    hidden = page.lessons.hidden
    assert len(hidden) == 3 and _shown(hidden) == [True] * 3
    player.go(2)  # "A faster belt": multiple choice
    assert _shown(hidden) == [False] * 3
    assert not player.text.visible and not player.look.visible  # they say the answer
    player.question.check.clicks += 1  # no choice made: still hidden
    assert _shown(hidden) == [False] * 3
    player.question.choices.value = player.question.choices.options[0]
    player.question.check.clicks += 1
    assert _shown(hidden) == [True] * 3 and player.text.visible and player.look.visible
    assert "Not quite" in player.question.answer.object
    player.go(7)  # the guess: drag x_bar into the grazing band
    assert _shown(hidden) == [False] * 3
    page.state.clearance = 0.25
    player.question.check.clicks += 1
    assert "Right." in player.question.answer.object and _shown(hidden) == [True] * 3
    player.go(8)
    assert _shown(hidden) == [True] * 3


def test_the_page_refuses_a_broken_lesson_naming_file_step_and_problem(tmp_path):
    (tmp_path / "broken.md").write_text((FIXTURES / "out_of_range.md").read_text())
    (tmp_path / "torn.md").write_text((FIXTURES / "unclosed.md").read_text())
    page = Explorer()
    page.main()
    page.lessons.folder = tmp_path
    page.sync_url(Location(search="?lesson=broken"))
    message = page.lessons.player.message
    assert message.visible and ("broken.md, step 1: state: r (restitution) must be a number "
                                "in [0, 1]; got '1.5'") in html.unescape(message.object)
    assert page.state.scene == "7c"  # the rest of the step's state is taken
    page.lessons.player.open("torn", 1)
    assert "torn.md, step 2: its front matter is not closed" in message.object
    page.lessons.player.open_address([("lesson", "nope")])
    assert ("unknown lesson 'nope' (lessons: broken, torn)"
            in html.unescape(message.object))


def test_a_page_with_a_lesson_loads_mathjax_from_its_own_server(monkeypatch):
    """The page loads MathJax only where a pane turns math on (app.perf.resources): a
    lesson's panes do, and the bundle is Bokeh's own, served by the page's server."""
    import panel.io.resources as panel_resources
    from bokeh.document import Document
    from bokeh.resources import Resources
    from panel.io.state import set_curdoc

    from app import perf
    from app.perf import resources

    monkeypatch.setenv(perf.SWITCH, "on")
    # Panel's own test comes back after this one (`make test` runs tests/app with the
    # patches off too).
    monkeypatch.setattr(panel_resources, "_panel_use_mathjax",
                        panel_resources._panel_use_mathjax)
    monkeypatch.setattr(resources, "PANEL_USE_MATHJAX", resources.PANEL_USE_MATHJAX)
    resources.mathjax_on_demand()
    bundles = {}
    for search in ("?scene=7c", "?lesson=paper&step=4"):
        doc = Document()
        with set_curdoc(doc):
            page = Explorer()
            page.sync_url(Location(search=search))
            doc.add_root(page.main_panel().get_root(doc))
            bundle = panel_resources.bundle_resources(doc.roots, Resources(mode="server"))
        bundles[search] = [str(f) for f in bundle.js_files if "mathjax" in str(f)]
    assert bundles["?scene=7c"] == []
    [mathjax] = bundles["?lesson=paper&step=4"]
    assert mathjax.startswith("static/js/bokeh-mathjax")  # the server's own, no CDN


@pytest.mark.parametrize("text", ["99", "0", "2.5", "two"])
def test_a_step_out_of_the_lesson_is_refused_in_the_page_and_the_first_step_shown(text):
    """The refusal was written, then cleared by the step shown after it."""
    page = Explorer()
    page.sync_url(Location(search=f"?lesson=paper&step={text}"))
    player = page.lessons.player
    n = len(player.lesson.steps)
    assert player.index == 0 and page.state.scene == "3a"
    assert player.message.visible
    assert (f"step must be a whole number in [1, {n}]; got '{text}'"
            in html.unescape(player.message.object))
