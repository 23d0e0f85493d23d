"""The model card and the scenes' stories (app.teach) without a browser: every scene has a
story with its formula, the glossary covers every symbol of the sliders and axes, no text
of the page points to a repository file, and a new page carries none of the cards' content.
"""

from __future__ import annotations

import doctest
import importlib
import re

import param
import pytest
from bokeh.document import Document
from bokeh.embed.util import contains_tex_string
from panel.io.state import set_curdoc

from app.explorer import SLIDERS, Explorer
from app.scenes import CUSTOM, SCENES
from app.teach import equations, glossary, stories, view
from app.teach.glossary import AXIS_SYMBOLS, GLOSSARY, SLIDER_SYMBOLS
from app.teach.stories import STORIES
from app.teach.view import WAITING, story_html

#: What a text on the page must not name: a file of the repository.
REPOSITORY_PATH = re.compile(r"docs/|core/|app/|\.md\b|\.py\b")
#: TeX on the page: inline \( \) or displayed $$ $$ (Bokeh's MathJax delimiters).
TEX = re.compile(r"\\\((.+?)\\\)|\$\$(.+?)\$\$", re.S)
#: The symbols a student meets on the sliders and axes, as the glossary keys them.
ISSUE_SYMBOLS = ("x_bar", "r", "v", "mu_s", "mu_k", "u_s", "a", "b", "x_star", "v_star",
                 "k_c0", "beta", "D")


def _sentences(html_text: str) -> int:
    """Sentences of a story's text, TeX and tags taken out."""
    text = re.sub(r"<[^>]+>", "", TEX.sub("X", html_text)).replace("Fig. ", "Fig ")
    return len(re.findall(r"[.!?](\s|$)", text))


@pytest.mark.parametrize("key", list(SCENES))
def test_every_scene_has_a_story_of_two_to_four_sentences_with_its_formula(key):
    story = STORIES[key]
    assert 2 <= _sentences(story.shows) <= 4, story.shows
    assert story.formula and "$" not in story.formula
    assert SCENES[key].caption.startswith("Look for ")
    page = story_html(key)
    assert contains_tex_string(page)  # Bokeh's own test: the Div asks for MathJax


def test_stories_cover_exactly_the_scenes():
    assert set(STORIES) == set(SCENES)


def _texts() -> list[str]:
    """Every text the cards can show: stories, captions, the model card."""
    return [*(story_html(k) for k in SCENES), *(s.caption for s in SCENES.values()),
            equations.model_html()]


def test_the_tex_is_well_formed():
    """Each TeX span closes, braces balance, and no '<' sits inside TeX (HTML would read
    it as a tag before MathJax sees it; the texts write \\lt)."""
    for text in _texts():
        assert text.count(r"\(") == text.count(r"\)"), text[:80]
        assert text.count("$$") % 2 == 0, text[:80]
        for m in TEX.finditer(text):
            tex = m.group(1) or m.group(2)
            assert "<" not in tex and ">" not in tex, tex
            depth = 0
            for ch in tex.replace(r"\{", "").replace(r"\}", ""):
                depth += {"{": 1, "}": -1}.get(ch, 0)
                assert depth >= 0, tex
            assert depth == 0, tex


def test_the_captions_hold_no_ascii_math():
    """The captions were ASCII math ("b <= x_bar < x_max", "r^h", "x'"): now words and
    the symbols themselves."""
    for scene in SCENES.values():
        assert not re.search(r"<=|>=|x_bar|\^h|\bmu_|\bbeta\b|sqrt\(", scene.caption), (
            scene.key, scene.caption)


def test_the_glossary_holds_every_symbol_of_the_sliders_and_axes():
    for key in ISSUE_SYMBOLS:
        entry = GLOSSARY[key]
        assert entry.meaning and entry.definition, key
    assert set(SLIDERS) - {"mass", "stiffness"} <= set(SLIDER_SYMBOLS)
    for keys in AXIS_SYMBOLS.values():
        assert all(k in GLOSSARY for k in keys)
    table = equations.glossary_html()
    assert all(f"id='fie-gl-{k}'" in table for k in GLOSSARY)


def test_a_tooltip_presses_the_model_card_s_button():
    tip = glossary.tooltip("clearance", "Stop position.")
    assert tip.startswith("Stop position. ") and "fie-glossary-link" in tip
    assert f"includes('{glossary.TEACH_BUTTONS}')" in tip and "[...m.active, 1]" in tip
    group = Explorer().teach.group
    assert glossary.TEACH_BUTTONS in group.css_classes
    assert list(group.options.values())[1] == "model"  # the second button, as the link says
    assert glossary.tooltip("normal_force", "Normal force.") == "Normal force."


def test_the_model_card_holds_every_law():
    text = equations.model_html()
    for head, _ in equations.LAWS:
        assert head in text
    for law in (r"x'' + x = s\,a", r"x' = v, \qquad |x| \le b", r"x'(+) = -r\,x'(-)",
                r"\varphi_C(\delta) = \frac{k_{c0}\,D\,\delta}{D - \delta}"):
        assert law in text
    assert "<svg" in text and "Symbols" in text and "<details" in text


@pytest.mark.parametrize("values, words", [
    ({"belt_speed": 0.3, "clearance": 0.25, "restitution": 0.7}, ("fast", "grazing")),
    ({"belt_speed": 0.07, "clearance": 0.285, "restitution": 0.3}, ("slow", "case b",
                                                                     "periodic")),
    ({"belt_speed": 0.07, "clearance": 0.15, "restitution": 0.3}, ("slow", "rest")),
    ({"stop_type": "none"}, ("slow", "no stop")),
])
def test_a_custom_state_s_story_names_the_regime_the_theory_predicts(values, words):
    state = {**SCENES["7b"].values, **values}
    text = story_html(CUSTOM, state)
    assert "Custom parameters" in text and contains_tex_string(text)
    for word in words:
        assert word in text.lower(), (word, text)


def test_a_state_the_theory_cannot_take_says_so():
    text = story_html(CUSTOM, {**SCENES["7b"].values, "mu_k": 0.5})
    assert "does not cover" in text and "mu_k" in text


#: Properties that hold code or style, not text a reader sees.
NOT_TEXT = {"code", "css", "url", "stylesheets", "tags", "esm", "importmap"}


def _strings(doc: Document) -> list[str]:
    """Every string property of every model of ``doc`` that a reader may see (texts,
    titles, labels, tooltips; not scripts or style sheets)."""
    out = []
    for model in doc.models:
        for name, value in model.properties_with_values(include_defaults=False).items():
            if name in NOT_TEXT:
                continue
            if isinstance(value, str):
                out.append(value)
            elif isinstance(value, list | tuple):
                out.extend(v for v in value if isinstance(v, str))
    return out


@pytest.fixture(scope="module")
def page():
    """(template, document) of a whole page, as a session builds it."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
        yield template, doc


def test_a_new_page_carries_the_two_buttons_and_no_text_or_tex(page):
    template, doc = page
    teach = template.explorer.teach
    assert teach.story.pane is None and teach.model.pane is None
    assert teach.math is None  # the hidden box comes with the first text
    assert not [m for m in doc.models if hasattr(m, "text") and isinstance(m.text, str)
                and contains_tex_string(m.text)]
    assert len(doc.models) <= 350


def test_no_text_of_the_page_names_a_repository_file_in_any_scene(page):
    """Every string of every model, in every scene and in a custom state, with both cards
    open (before: the contact law's tooltip and the readout named docs/contact-law.md)."""
    template, doc = page
    ex = template.explorer
    with set_curdoc(doc):
        ex.teach.group.value = ["story", "model"]
        ex.teach.math.value = "loaded"
        for key in [*SCENES, CUSTOM]:
            if key == CUSTOM:
                slider = ex.sliders["clearance"].slider
                slider.value = 0.2
                with param.edit_constant(slider):
                    slider.value_throttled = 0.2
            else:
                ex.scene_select.value = key
            assert ex.state.scene == key and ex.error is None
            bad = [s for s in _strings(doc) if REPOSITORY_PATH.search(s)]
            assert not bad, (key, [REPOSITORY_PATH.search(s).group() for s in bad])
        assert ex.state.scene == CUSTOM
        assert "Custom parameters" in ex.teach.story.pane.object


def test_a_text_is_built_when_opened_and_filled_once_mathjax_answered(monkeypatch):
    from app import perf

    # The late MathJax load is a patch (mathjax-after-load); without it the text is sent at
    # once, to the MathJax the page loaded with itself.
    monkeypatch.setenv(perf.SWITCH, "on")
    ex = Explorer()
    main, teach = ex.main_panel(), ex.teach
    assert teach.story.pane is None
    teach.group.value = ["story"]
    objects = main.objects
    # Right below the buttons, with the hidden box the browser answers in.
    assert objects[objects.index(teach.group) + 1] is teach.story.pane
    assert teach.math in objects
    # The browser has not answered yet: the text waits, with the script that loads MathJax.
    assert teach.story.pane.object.startswith(WAITING) and "<script>" in teach.story.pane.object
    assert teach.model.pane is None            # the other text stays unbuilt
    teach.math.value = "failed"                # no MathJax: the text is sent as TeX
    assert teach.story.pane.object == story_html(ex.state.scene)
    ex.scene_select.value = "7c"
    assert teach.story.pane.object == story_html("7c")
    teach.group.value = ["model", "story"]
    assert teach.model.pane.object == equations.model_html()
    objects = main.objects
    assert objects[objects.index(teach.story.pane) + 1] is teach.model.pane
    teach.group.value = ["model"]             # closed: hidden, kept
    assert not teach.story.pane.visible and teach.model.pane.visible


@pytest.mark.parametrize("module", [glossary, stories, equations, view])
def test_doctests(module):
    assert doctest.testmod(module).failed == 0


def test_a_custom_story_without_values_is_refused():
    with pytest.raises(TypeError, match="needs its values"):
        story_html(CUSTOM)
