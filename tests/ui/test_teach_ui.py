"""The model card and the scenes' stories in Chromium with every host but this server
blocked (a classroom behind a firewall): their equations are typeset by MathJax, fetched
from this server only when a card is opened, and no text of the page names a repository
file in any scene.

Screenshots of the model card and of two stories at 1280x800 and 1920x1080 go to the
screenshot folder (``teach-*.png``).
"""

from __future__ import annotations

import re
from urllib.parse import urlsplit

import pytest
from uipage import JS_DEEP_TEXT, JS_READY, PAGE_TIMEOUT_MS

from app.perf import applies
from app.scenes import SCENES
from app.teach.stories import STORIES

pytestmark = pytest.mark.ui

#: JavaScript: the MathJax output elements (``mjx-container``) inside the elements of
#: class ``cls``, shadow roots included.
JS_MATH = """cls => {
  let n = 0;
  function walk(root, inside) {
    for (const el of root.querySelectorAll("*")) {
      const here = inside || el.classList.contains(cls);
      if (el.shadowRoot) walk(el.shadowRoot, here);
      if (here && el.tagName === "MJX-CONTAINER") n += 1;
    }
  }
  walk(document, false);
  return n;
}"""
#: JavaScript: the text of the elements of class ``cls``, shadow roots included.
JS_TEXT_OF = """cls => {
  const deep = """ + JS_DEEP_TEXT + """;
  const out = [];
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.classList.contains(cls)) { out.push(deep(el)); continue; }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  }
  walk(document);
  return out.join(" ");
}"""
#: TeX left as text: MathJax did not typeset it.
RAW_TEX = re.compile(r"\\\(|\\\)|\$\$|\\frac|\\bar")
#: What no text of the page may name: a file of the repository.
REPOSITORY_PATH = re.compile(r"docs/|core/|\.md\b|\.py\b")
#: Window sizes of the screenshots.
SIZES = ((1280, 800), (1920, 1080))


class OfflinePage:
    """A page of the explorer whose requests to any other host than the server fail."""

    def __init__(self, browser, url: str, size: tuple[int, int] = (1600, 1000)) -> None:
        self.host = urlsplit(url).hostname
        self.page = browser.new_page(viewport={"width": size[0], "height": size[1]})
        self.requests: list[str] = []
        self.blocked: list[str] = []
        self.errors: list[str] = []
        self.page.on("pageerror", lambda exc: self.errors.append(str(exc)))
        self.page.route("**/*", self._route)
        self.page.goto(url, timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)

    def _route(self, route) -> None:
        url = route.request.url
        self.requests.append(url)
        if urlsplit(url).hostname == self.host:
            route.continue_()
        else:
            self.blocked.append(url)
            route.abort()

    def math(self, cls: str) -> int:
        return self.page.evaluate(JS_MATH, cls)

    def text(self, cls: str) -> str:
        return self.page.evaluate(JS_TEXT_OF, cls)

    def open_card(self, key: str) -> None:
        """Press the button of ``key`` ("story", "model") and wait for its typeset text."""
        label = {"story": "What this figure shows", "model": "The model"}[key]
        self.page.locator(".fie-teach-buttons button", has_text=label).first.click()
        self.page.wait_for_function(f"cls => ({JS_MATH})(cls) > 0", arg=f"fie-{key}-text",
                                    timeout=PAGE_TIMEOUT_MS)

    def select_scene(self, key: str) -> None:
        """Load scene ``key`` and wait for its story."""
        self.page.locator(".fie-scene select").select_option(label=SCENES[key].title)
        self.page.wait_for_function(
            f"([cls, words]) => ({JS_TEXT_OF})(cls).includes(words)",
            arg=["fie-story-text", _opening(key)], timeout=PAGE_TIMEOUT_MS)
        # and for its solve: the caption names the figure once the run is drawn.
        self.page.wait_for_function(
            f"([cls, words]) => ({JS_TEXT_OF})(cls).includes(words)",
            arg=["fie-caption", f"Fig. {key}:"], timeout=PAGE_TIMEOUT_MS)
        self.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)

    def close(self) -> None:
        self.page.close()


def _opening(key: str) -> str:
    """The story's first words, before any TeX or markup."""
    return re.split(r"\\\(|<|&", STORIES[key].shows)[0][:60].strip()


@pytest.fixture(scope="module")
def page(browser, server):
    p = OfflinePage(browser, server)
    yield p
    p.close()


def test_the_model_card_is_typeset_from_this_server_when_opened(page, shots):
    # Not with the page: MathJax is fetched when a card opens. (With the patches of
    # library internals off, Panel loads it with any page that has an HTML pane.)
    on_demand = applies("mathjax-on-demand")
    assert bool([u for u in page.requests if "mathjax" in u]) is not on_demand
    page.open_card("model")
    fetched = [u for u in page.requests if "mathjax" in u]
    assert len(fetched) == 1 and urlsplit(fetched[0]).hostname == page.host
    # Every law and glossary row typeset (some 110 expressions), none left as TeX.
    assert page.math("fie-model-text") > 60
    text = page.text("fie-model-text")
    assert "Hysteretic contact law" in text and "Symbols" in text
    assert not RAW_TEX.search(text), RAW_TEX.search(text)
    assert page.blocked == [] and page.errors == []
    page.page.locator(".fie-model-text").first.screenshot(path=shots / "teach-model-text.png")


def test_every_scene_s_story_is_typeset_and_names_no_repository_file(page):
    if not page.math("fie-story-text"):
        page.open_card("story")
    assert len({_opening(k) for k in SCENES}) == len(SCENES)  # each wait is its own
    typeset = []
    for key in SCENES:
        page.select_scene(key)
        story = page.text("fie-story-text")
        if page.math("fie-story-text") > 0 and not RAW_TEX.search(story):
            typeset.append(key)
        whole = page.page.locator("body").evaluate(JS_DEEP_TEXT)
        assert not REPOSITORY_PATH.search(whole), (key, REPOSITORY_PATH.search(whole))
    assert len(typeset) >= 18, typeset
    assert page.blocked == [] and page.errors == []


def test_a_tooltip_s_link_opens_the_glossary(browser, server):
    p = OfflinePage(browser, server)
    try:
        p.page.locator(".fie-w-clearance .bk-description").first.click()  # pins the tip
        p.page.locator(".bk-tooltip-content a.fie-glossary-link").first.click()
        p.page.wait_for_function(f"cls => ({JS_MATH})(cls) > 60", arg="fie-model-text",
                                 timeout=PAGE_TIMEOUT_MS)
        assert "clearance: position of the stop" in p.text("fie-model-text")
    finally:
        p.close()


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_screenshots_of_the_model_card_and_two_stories(browser, server, shots, size):
    p = OfflinePage(browser, f"{server}?scene=7b", size)
    try:
        name = f"{size[0]}x{size[1]}"
        p.open_card("story")
        p.page.screenshot(path=shots / f"teach-story-7b-{name}.png")
        p.select_scene("10")
        p.page.screenshot(path=shots / f"teach-story-10-{name}.png")
        p.page.locator(".fie-teach-buttons button",
                       has_text="What this figure shows").first.click()  # closed again
        p.open_card("model")
        p.page.screenshot(path=shots / f"teach-model-{name}.png")
        assert p.blocked == [] and p.errors == []
    finally:
        p.close()
