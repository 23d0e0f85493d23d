"""The model card and the scene's story on the page, each a collapsed card whose content is
built the first time it is opened.

A new page carries only the two closed cards and one hidden box (its cost to open stays
flat; ``benchmarks/page_models.py``). Opening a card asks the browser to load Bokeh's own
MathJax bundle from this server (the page does not load it with itself: 0.6 MB gzipped, no
use to a student who never opens a card) and to say when it is ready (:data:`LOAD_MATH_JS`);
the content is then sent as Bokeh ``Div`` text with TeX, which BokehJS typesets with that
bundle (SVG: no font files, no other host).
"""

from __future__ import annotations

import html
from typing import Any

import panel as pn
import param
from bokeh.models import Div, ImportedStyleSheet

from app.teach.equations import model_html
from app.teach.glossary import MODEL_CARD
from app.teach.stories import STORIES, custom_quantities, custom_story

#: Stylesheet of the cards' text (in the Divs' shadow roots).
STYLESHEET = "assets/explorer.css"
#: What the hidden box says once the browser has tried to load MathJax.
MATH_STATES = ("loaded", "failed")
#: Shown in an open card until the browser has MathJax (a fraction of a second).
WAITING = "<p class='fie-teach-wait'>Typesetting the equations&hellip;</p>"

#: Run in the browser when a card is opened or closed (``source``: the card, ``math``: the
#: hidden box). BokehJS typesets TeX with a MathJax module of its bundle ``bokeh-mathjax``,
#: which its provider looks for once, when the page's first text pane is drawn; this page
#: does not load that bundle with itself, so the provider failed then. Here the bundle is
#: loaded from the address Bokeh's own script came from (this server), the provider asked
#: again, and the box set to "loaded" (or "failed": the texts are sent anyway, as TeX).
LOAD_MATH_JS = r"""
if (source.collapsed) { return; }
const done = (status) => { if (math.value !== status) { math.value = status; } };
let provider = null;
try { provider = window.Bokeh.require("models/text/providers").default_provider; }
catch (e) { provider = null; }
if (provider == null || typeof provider.fetch !== "function") { done("failed"); return; }
if (provider.MathJax != null) { done("loaded"); return; }
if (window.__fie_mathjax == null) {
  window.__fie_mathjax = new Promise((resolve) => {
    const own = Array.from(document.scripts).map((s) => s.src)
      .find((u) => /\/bokeh(\.min)?\.js(\?|$)/.test(u));
    if (own == null) { resolve(false); return; }
    const script = document.createElement("script");
    script.src = own.replace(/\/bokeh(\.min)?\.js(\?.*)?$/,
                             (m, min) => "/bokeh-mathjax" + (min || "") + ".js");
    script.onload = () => resolve(true);
    script.onerror = () => resolve(false);
    document.head.appendChild(script);
  }).then(async (ok) => {
    if (!ok) { return false; }
    provider.status = "not_started";
    await provider.fetch();
    return provider.MathJax != null;
  });
}
window.__fie_mathjax.then((ok) => done(ok ? "loaded" : "failed"));
"""


def story_html(scene: str, values: dict[str, Any] | None = None) -> str:
    """The story of ``scene`` (HTML with TeX); for a state that is no scene, the regime the
    theory predicts for ``values`` (the state's solve values) and why."""
    if scene in STORIES:
        story = STORIES[scene]
        return (f"<div class='fie-story'><p>{story.shows}</p>$${story.formula}$$"
                "</div>")
    return f"<div class='fie-story'><p>{_custom(values or {})}</p></div>"


def _custom(values: dict[str, Any]) -> str:
    from app.solver import equivalent_rigid
    from app.state import core_inputs
    from core import theory

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


class _LazyCard:
    """A collapsed card whose Div is made, and filled by ``text()``, once it is opened and
    the browser has answered about MathJax."""

    def __init__(self, title: str, css: str, math: pn.widgets.TextInput, text,
                 name: str | None = None) -> None:
        self._math, self._text = math, text
        self.div: Div | None = None
        self.card = pn.Card(title=title, collapsed=True, sizing_mode="stretch_width",
                            **({"name": name} if name else {}),
                            css_classes=["fie-teach-card", css], margin=(2, 10),
                            stylesheets=[STYLESHEET])
        self.card.jscallback(collapsed=LOAD_MATH_JS, args={"math": math})
        self.card.param.watch(self._opened, "collapsed")

    def _opened(self, event: param.parameterized.Event) -> None:
        if event.new or self.div is not None:
            return
        self.div = Div(text=WAITING, sizing_mode="stretch_width",
                       stylesheets=[ImportedStyleSheet(url=STYLESHEET)],
                       css_classes=["fie-teach-text"])
        self.card.objects = [pn.pane.Bokeh(self.div, sizing_mode="stretch_width")]
        self.refresh()

    def refresh(self) -> None:
        """Send the text again (a new scene), if the card was opened and MathJax tried."""
        if self.div is not None and self._math.value in MATH_STATES:
            text = self._text()
            if self.div.text != text:
                self.div.text = text


class Teach:
    """The two cards of a session: the scene's story and the model.

    Parameters
    ----------
    state : app.state.ExplorerState
        The session's state; the story follows its scene (and, for a custom state, its
        values).
    """

    def __init__(self, state: Any) -> None:
        self.state = state
        #: Where the browser says whether it has MathJax ("loaded" or "failed").
        self.math = pn.widgets.TextInput(value="", visible=False, margin=0,
                                         css_classes=["fie-teach-math"])
        self.story = _LazyCard("What this figure shows", "fie-story-card", self.math,
                               lambda: story_html(state.scene, state.values()))
        self.model = _LazyCard("The model: equations and symbols", "fie-model-card",
                               self.math, model_html, name=MODEL_CARD)
        self.math.param.watch(self._refresh, "value")
        state.param.watch(self._refresh, ["scene", "belt_speed", "clearance",
                                          "restitution", "mu_s", "mu_k", "u_s", "x0", "v0",
                                          "stop_type", "k_c0", "k_e0"])

    def _refresh(self, *events: param.parameterized.Event) -> None:
        self.story.refresh()
        self.model.refresh()

    @property
    def cards(self) -> list[Any]:
        """What the page shows: the story, the model, and the hidden box."""
        return [self.story.card, self.model.card, self.math]
