"""The model card and the scene's story on the page: two buttons of one widget, each
opening its text below them, built the first time it is opened.

A new page carries only the buttons (its cost to open stays near flat;
``benchmarks/page_models.py``). Opening one asks the browser to load Bokeh's own MathJax
bundle from this server (the page does not load it with itself: 0.6 MB gzipped, no use to a
student who never opens one) and to say, in a hidden box sent with the first text, when it
is ready (:data:`LOAD_MATH_JS`); the text is then sent as HTML with TeX, which BokehJS
typesets with that bundle (SVG: no font files, no other host).
"""

from __future__ import annotations

import html
from typing import Any

import panel as pn
import param

from app.perf import applies
from app.state import core_inputs
from app.teach.equations import model_html
from app.teach.glossary import TEACH_BUTTONS
from app.teach.stories import STORIES, custom_quantities, custom_story
from core import equivalent_rigid, theory

#: Stylesheet of the texts (in the panes' shadow roots).
STYLESHEET = "assets/explorer.css"
#: What the hidden box says once the browser has tried to load MathJax.
MATH_STATES = ("loaded", "failed")
#: Class of the hidden box (the browser finds it by this class).
MATH_BOX = "fie-teach-math"
#: Shown in an opened text until the browser has MathJax (a fraction of a second).
WAITING = "<p class='fie-teach-wait'>Typesetting the equations&hellip;</p>"
#: How long the browser looks for the hidden box once MathJax is loaded [ms].
BOX_WAIT_MS = 20_000

#: Run in the browser with the first text shown (a script in it; Panel's HTML pane runs
#: the scripts of its text). BokehJS typesets TeX with a MathJax module of its bundle
#: ``bokeh-mathjax``, which its provider looks for once, when the page's first text pane is
#: drawn; this page does not load that bundle with itself, so the provider failed then. Here
#: the bundle is loaded from the address Bokeh's own script came from (this server), the
#: provider asked again, and the hidden box set to "loaded" (or "failed": the texts are sent
#: anyway, as TeX). A JavaScript callback on the buttons would do the same, but any such
#: link makes Panel look through the whole page for linked models each time a page opens.
LOAD_MATH_JS = r"""
(function () {
  let provider = null;
  try { provider = window.Bokeh.require("models/text/providers").default_provider; }
  catch (e) { provider = null; }
  if (window.__fie_mathjax == null) {
    window.__fie_mathjax = new Promise((resolve) => {
      if (provider == null || typeof provider.fetch !== "function") { resolve(false); return; }
      if (provider.MathJax != null) { resolve(true); return; }
      const own = Array.from(document.scripts).map((s) => s.src)
        .find((u) => /\/bokeh(\.min)?\.js(\?|$)/.test(u));
      if (own == null) { resolve(false); return; }
      const script = document.createElement("script");
      script.src = own.replace(/\/bokeh(\.min)?\.js(\?.*)?$/,
                               (m, min) => "/bokeh-mathjax" + (min || "") + ".js");
      script.onload = () => {
        provider.status = "not_started";
        provider.fetch().then(() => resolve(provider.MathJax != null), () => resolve(false));
      };
      script.onerror = () => resolve(false);
      document.head.appendChild(script);
    });
  }
  window.__fie_mathjax.then((ok) => {
    const status = ok ? "loaded" : "failed";
    const until = Date.now() + BOX_WAIT_MS;
    const tell = () => {
      const doc = window.Bokeh.documents[0];
      const box = [...doc.all_models].find((m) => (m.css_classes || []).includes(MATH_BOX));
      if (box != null) { if (box.value !== status) { box.value = status; } }
      else if (Date.now() < until) { setTimeout(tell, 50); }
    };
    tell();
  });
})();
""".replace("BOX_WAIT_MS", str(BOX_WAIT_MS)).replace("MATH_BOX", repr(MATH_BOX))


def story_html(scene: str, values: dict[str, Any] | None = None) -> str:
    """The story of ``scene`` (HTML with TeX); for a state that is no scene, the regime the
    theory predicts for ``values`` (the state's solve values, needed then) and why."""
    if scene in STORIES:
        story = STORIES[scene]
        return f"<div class='fie-story'><p>{story.shows}</p>$${story.formula}$$</div>"
    if values is None:
        raise TypeError(f"story_html: a state that is no scene ({scene!r}) needs its values")
    return f"<div class='fie-story'><p>{_custom(values)}</p></div>"


def _custom(values: dict[str, Any]) -> str:
    try:
        osc, stop, x0, v0, _ = core_inputs(values)
        rigid = equivalent_rigid(stop)
        regime = theory.classify(osc, rigid, x0, v0)
    except ValueError as exc:
        return f"The theory does not cover these values: {html.escape(str(exc))}"
    head = ("Custom parameters. " if values.get("stop_type") != "hysteretic" else
            r"Custom parameters; the deformable stop is read as a rigid stop with "
            r"\(r_{eq} = \sqrt{k_{e0}/k_{c0}}\). ")
    return head + custom_story(regime, custom_quantities(osc, rigid, x0, v0))


class _Text:
    """A text put below the buttons, and filled by ``text()``, once its button is pressed
    and the browser has answered about MathJax."""

    def __init__(self, key: str, teach: Teach, text) -> None:
        self.key, self._teach, self._text = key, teach, text
        self.pane: pn.pane.HTML | None = None

    def show(self, on: bool) -> None:
        """Show the text (made the first time) or hide it."""
        if self.pane is None and on:
            # BokehJS's MathJax provider is internal (app.perf patch "mathjax-after-load"):
            # without the patch the page has loaded MathJax with itself (Panel's default).
            first = (f"{WAITING}<script>{LOAD_MATH_JS}</script>"
                     if applies("mathjax-after-load") else "")
            self.pane = pn.pane.HTML(first,
                                     disable_math=False, sizing_mode="stretch_width",
                                     css_classes=["fie-teach-text", f"fie-{self.key}-text"],
                                     margin=(0, 14, 6, 14), stylesheets=[STYLESHEET])
            self._teach.show_below(self.pane)
            self.refresh()
        elif self.pane is not None:
            self.pane.visible = on

    def refresh(self) -> None:
        """Send the text again (a new scene), if it was opened and MathJax tried."""
        if self.pane is not None and self._teach.math_answered():
            text = self._text()
            if self.pane.object != text:
                self.pane.object = text


class Teach:
    """The buttons of a session's story and model, and their texts.

    Parameters
    ----------
    state : app.state.ExplorerState
        The session's state; the story follows its scene (and, for a custom state, its
        values).
    """

    def __init__(self, state: Any) -> None:
        self.state = state
        #: The column the buttons are in (:meth:`attach`); the texts go below them.
        self.host: Any = None
        #: Where the browser says whether it has MathJax ("loaded" or "failed"): made and
        #: put on the page with the first text.
        self.math: pn.widgets.TextInput | None = None
        self.story = _Text("story", self, lambda: story_html(state.scene, state.values()))
        self.model = _Text("model", self, model_html)
        # One widget for both (each widget is ~3 ms of a page's open).
        self.group = pn.widgets.CheckButtonGroup(
            options={"What this figure shows": "story",
                     "The model: equations and symbols": "model"},
            value=[], color="light", margin=(2, 10), css_classes=[TEACH_BUTTONS],
            stylesheets=[STYLESHEET])
        self.group.param.watch(self._pressed, "value")
        state.param.watch(self._refresh, ["scene", "belt_speed", "clearance",
                                          "restitution", "mu_s", "mu_k", "u_s", "x0", "v0",
                                          "stop_type", "k_c0", "k_e0"])

    def _pressed(self, event: param.parameterized.Event) -> None:
        for text in (self.story, self.model):
            text.show(text.key in event.new)

    def _refresh(self, *events: param.parameterized.Event) -> None:
        self.story.refresh()
        self.model.refresh()

    @property
    def buttons(self) -> list[Any]:
        """What the page shows at first: the buttons."""
        return [self.group]

    def attach(self, host: Any) -> None:
        """Put the texts in ``host``, the column the buttons are in."""
        self.host = host

    def math_answered(self) -> bool:
        """Whether the browser has said if it has MathJax (it has, with the page, without
        the patch that loads it later)."""
        if not applies("mathjax-after-load"):
            return True
        return self.math is not None and self.math.value in MATH_STATES

    def show_below(self, pane: Any) -> None:
        """Put ``pane`` below the buttons, the story above the model (and the hidden box
        with the first text)."""
        objects = list(self.host.objects)
        at = objects.index(self.group) + 1
        if pane is self.model.pane and self.story.pane in objects:
            at += 1
        objects.insert(at, pane)
        if self.math is None:
            self.math = pn.widgets.TextInput(value="", visible=False, margin=0,
                                             css_classes=[MATH_BOX])
            self.math.param.watch(self._refresh, "value")
            objects.append(self.math)
        self.host.objects = objects
