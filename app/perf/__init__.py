"""Every patch of a Panel or Bokeh internal, in one package, each with the versions it was
written for.

The explorer runs on public Panel and Bokeh APIs. A few measured delays, the bundles a
page loads, and the quiet refusal of values from the browser that no user can give could
only be had by reaching into library internals; each such patch lives here
(:mod:`app.perf.websocket`, :mod:`app.perf.slider`, :mod:`app.perf.defaults`,
:mod:`app.perf.resources`, :mod:`app.perf.attach`, :mod:`app.perf.browser_values`), names
the library versions it was written and tested for (:data:`PATCHES`), and is applied only

* inside that version window (checked when the server starts; outside it a log line says
  the patch was left out), and
* unless the environment variable ``EXPLORER_PERF_PATCHES`` is ``off`` (all of them).

The page's scripts that override BokehJS internals or browser methods that Panel and
BokehJS call (``static/perf/``, ``static/a11y.js``, ``static/url_history.js``,
``static/present.js``) are in :data:`PATCHES` too, with the same window and switch: the
server names in each script's address the patches of that script that apply
(:func:`app.perf.page.page_scripts`), and the script applies only those; the repaint
shortcuts also check their BokehJS version in the browser and take ``paint_shortcuts=off``
in the page's address as a switch of their own. The explorer works without any patch
(without ``browser-values`` a script's malformed value is still refused, but by Panel, with
a traceback in the log, and a radio index of -1 picks the last option; without the page's,
the sliders' handles have no accessible name and rounded aria values, the help icons
are out of the keyboard's reach, each change of the address is a history
entry and a slide's PNG has the screen's pixel ratio); ``benchmarks/README.md`` has a
paired measurement of what they buy, and the findings worth reporting upstream.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass
from functools import cache
from importlib.metadata import version

from packaging.version import Version

log = logging.getLogger(__name__)

#: Environment variable that turns every Python patch off (``off``, ``0``, ``false``, ``no``).
SWITCH = "EXPLORER_PERF_PATCHES"
_OFF = {"off", "0", "false", "no"}


@dataclass(frozen=True)
class Patch:
    """A patch of ``library``'s internals, written for versions ``low <= v < high``."""

    name: str
    library: str
    low: str
    high: str
    what: str
    #: Files that hold the patch (Python in app/perf/, scripts of the page in static/).
    where: tuple[str, ...] = ()
    #: The library internals it replaces or writes, as ``Owner.member``.
    overrides: tuple[str, ...] = ()

    @property
    def in_page(self) -> bool:
        """Whether the patch is a script of the page (``static/``)."""
        return all(path.startswith("static/") for path in self.where) and bool(self.where)

    def in_window(self, installed: str | None = None) -> bool:
        """Whether ``installed`` (default: the installed version) is inside the window."""
        v = Version(installed if installed is not None else _installed(self.library))
        return Version(self.low) <= v < Version(self.high)


@cache
def _installed(library: str) -> str:
    # Read once: importlib.metadata scans the path's distributions (milliseconds), and the
    # patches ask on every release.
    return version(library)


#: The patches, by name. Windows: the versions the patches were written and tested with.
#: ``where``: the files that hold the patch; ``overrides``: each library internal it
#: replaces or writes, as ``Owner.member`` (tests/app/test_patch_registry.py finds every
#: such override in app/ and static/ and fails on one that no patch lists).
PATCHES = {
    patch.name: patch for patch in (
        Patch("tcp-nodelay", "bokeh", "3.9", "3.10",
              "TCP_NODELAY on the session's websocket (found through the server's "
              "connection objects)",
              ("app/perf/websocket.py",),
              ("ServerSession._subscribed_connections", "ServerConnection._socket")),
        Patch("write-lock", "bokeh", "3.9", "3.10",
              "a release's update waits for the websocket's write lock instead of Panel's "
              "10 ms retry",
              ("app/perf/websocket.py",), ("WSHandler.write_lock",)),
        Patch("inline-arrays", "bokeh", "3.9", "3.10",
              "a document update is one message of three frames (patch_doc.create)",
              ("app/perf/websocket.py",), ("patch_doc.create",)),
        Patch("immutable-defaults", "bokeh", "3.9", "3.10",
              "an unset property's immutable, unthemed default is computed once per model "
              "class, not on every read; a container default is copied from the class's; "
              "whether a default is per instance is asked once per class; a model without "
              "a theme says so without an exception",
              ("app/perf/defaults.py",),
              ("PropertyDescriptor._get_default", "PropertyDescriptor.has_unstable_default",
               "HasProps.themed_values")),
        Patch("bootstrap-css-once", "panel", "1.9", "1.10",
              "the design's page-level CSS links carry Panel's version suffix, as the "
              "shadow roots' copies do: one address, one download",
              ("app/perf/resources.py",), ("Design.resolve_resources",)),
        Patch("fresh-roots", "panel", "1.9", "1.10",
              "a template's root that was never in a document is added to the session's "
              "without Panel's walk that takes its models out of their old document",
              ("app/perf/attach.py",), ("panel.template.base.add_to_doc",)),
        Patch("stylesheets-from-document", "panel", "1.9", "1.10",
              "the page's HTML gives the stylesheets the server's address from the "
              "document's list of its models, not by walking each root",
              ("app/perf/attach.py",), ("panel.io.server.patch_model_css",)),
        Patch("mathjax-on-demand", "panel", "1.9", "1.10",
              "MathJax is loaded where Bokeh finds TeX, not for every HTML pane",
              ("app/perf/resources.py",), ("panel.io.resources._panel_use_mathjax",)),
        Patch("slider-release", "panel", "1.9", "1.10",
              "a slider's release is processed at once, not after the drag's debounce; the "
              "model's read-only released value follows a value set on the server",
              ("app/perf/slider.py",),
              ("Syncable._priority_changes", "Syncable._server_change",
               "Syncable._change_coroutine", "state._change_callbacks",
               "Slider._property_values")),
        Patch("slider-not-busy", "panel", "1.9", "1.10",
              "a slider's values are not counted in Panel's busy counter (the page shows "
              "no busy indicator)",
              ("app/perf/slider.py",), ("Syncable._busy__ignore",)),
        Patch("browser-values", "panel", "1.9", "1.10",
              "a value from the browser that a widget cannot hold (outside a slider's "
              "range, a select's options, a radio group's buttons) is refused at the "
              "widget in one rate-limited WARNING line, and the browser set back",
              ("app/perf/browser_values.py",), ("Syncable._process_property_change",)),
        Patch("mathjax-after-load", "bokeh", "3.9", "3.10",
              "a text with TeX opened after the page loaded (the model card, a story) "
              "loads Bokeh's own MathJax bundle from this server then and asks BokehJS's "
              "MathJax provider again (it looked once, when the page's first HTML pane was "
              "drawn); without it such a text waits for MathJax loaded with every page",
              ("app/teach/view.py",), ("default_provider.fetch",)),
        # The page's scripts (static/): the server names in each script's address the
        # patches of that script that apply (app.perf.page), the script applies only those.
        Patch("paint-shortcuts", "bokeh", "3.9", "3.10",
              "repaint shortcuts 1-9 of BokehJS's figures",
              ("static/perf/bokeh_paint.js",),
              ("InlineStyleSheet.prototype._update",
               "VisualProperties.prototype._get_css_value",
               "PlotView.prototype.base_font_size",
               "GlyphRendererView.prototype.update_position",
               "GlyphRendererView.prototype.update_data",
               "GlyphRendererView.prototype._update_masked_indices",
               "GlyphRendererView.prototype.set_visuals",
               "MarkerView.prototype._mask_data",
               "RangeManager.prototype.update_dataranges")),
        Patch("release-hold", "bokeh", "3.9", "3.10",
              "no repaint of a stale preview after a slider's release, an inert body style, "
              "every release sent",
              ("static/perf/release_hold.js",),
              ("PlotView.prototype.paint", "PlotView.prototype.schedule_paint",
               "AbstractSliderView.prototype._change", "document.body.style.cursor",
               "document.body.style.userSelect", "document.body.style.webkitUserSelect")),
        Patch("slider-handle-names", "bokeh", "3.9", "3.10",
              "every slider's handle is named after its parameter (aria-label) whenever "
              "BokehJS draws its title",
              ("static/a11y.js",), ("AbstractSliderView.prototype._update_title",)),
        Patch("slider-aria-values", "bokeh", "3.9", "3.10",
              "every slider handle's aria-valuenow, -valuemin, -valuemax and -valuetext "
              "carry its value and limits in full (noUiSlider rounds them to one and two "
              "decimals), after each of noUiSlider's updates",
              ("static/a11y.js",), ("AbstractSliderView.prototype.render",)),
        Patch("help-keys", "bokeh", "3.9", "3.10",
              "an input's help icon is a named button the keyboard reaches: focus shows "
              "its tooltip, Enter or Space keeps it, Escape hides it",
              ("static/a11y.js",), ("InputWidgetView.prototype._build_description_el",)),
        Patch("control-names", "bokeh", "3.9", "3.10",
              "the arrow of a split menu button is named after the button (aria-label), "
              "a checkbox after its label (aria-labelledby)",
              ("static/a11y.js",),
              ("DropdownView.prototype.render", "CheckboxView.prototype.render")),
        Patch("address-in-place", "panel", "1.9", "1.10",
              "a new address that differs only in its query replaces the history entry "
              "instead of adding one (Panel's Location writes with history.pushState)",
              ("static/url_history.js",), ("window.history.pushState",)),
        Patch("slide-pixel-ratio", "bokeh", "3.9", "3.10",
              "with slides=png in the address the page reports a device pixel ratio of at "
              "least 3, so BokehJS draws and saves its canvases at that resolution",
              ("static/present.js",), ("window.devicePixelRatio",)),
    )
}


def enabled() -> bool:
    """Whether the Python patches are switched on (:data:`SWITCH`)."""
    return os.environ.get(SWITCH, "on").strip().lower() not in _OFF


def applies(name: str) -> bool:
    """Whether patch ``name`` is to be applied: switched on and inside its version window.
    Says once in the log why a patch is left out."""
    patch = PATCHES[name]
    if not enabled():
        say_once(f"perf patch {name!r} not applied: {SWITCH} is off")
        return False
    if not _in_window(patch):
        say_once(f"perf patch {name!r} not applied: it was written for {patch.library} "
                 f">={patch.low},<{patch.high}; {_installed(patch.library)} is installed")
        return False
    return True


@cache
def _in_window(patch: Patch) -> bool:
    return patch.in_window()


@cache
def say_once(message: str) -> None:
    """Log ``message`` as a WARNING the first time only (``say_once.cache_clear()`` forgets
    what was said)."""
    log.warning(message)


def report() -> dict[str, bool]:
    """``{name: applied}`` for every patch (logs each left out)."""
    return {name: applies(name) for name in PATCHES}
