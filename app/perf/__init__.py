"""Every patch of a Panel or Bokeh internal, in one package, each with the versions it was
written for.

The explorer runs on public Panel and Bokeh APIs. A few measured delays, the bundles a
page loads, and the quiet refusal of values from the browser that no user can give could
only be had by reaching into library internals; each such patch lives here
(:mod:`app.perf.websocket`, :mod:`app.perf.slider`, :mod:`app.perf.defaults`,
:mod:`app.perf.resources`, :mod:`app.perf.browser_values`), names the library versions it
was written and tested for (:data:`PATCHES`), and is applied only

* inside that version window (checked when the server starts; outside it a log line says
  the patch was left out), and
* unless the environment variable ``EXPLORER_PERF_PATCHES`` is ``off`` (all of them).

The page's JavaScript patches (``static/perf/``) check their BokehJS version in the browser,
with ``paint_shortcuts=off`` in the page's address as their switch. The explorer works fully
without any patch (without ``browser-values`` a script's malformed value is still refused,
but by Panel, with a traceback in the log, and a radio index of -1 picks the last option);
``benchmarks/README.md`` has a paired measurement of what they buy, and the findings worth
reporting upstream.
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
PATCHES = {
    patch.name: patch for patch in (
        Patch("tcp-nodelay", "bokeh", "3.9", "3.10",
              "TCP_NODELAY on the session's websocket (found through the server's "
              "connection objects)"),
        Patch("write-lock", "bokeh", "3.9", "3.10",
              "a release's update waits for the websocket's write lock instead of Panel's "
              "10 ms retry"),
        Patch("inline-arrays", "bokeh", "3.9", "3.10",
              "a document update is one message of three frames (patch_doc.create)"),
        Patch("immutable-defaults", "bokeh", "3.9", "3.10",
              "an unset property's immutable, unthemed default is computed once per model "
              "class, not on every read; a container default is copied from the class's; "
              "whether a default is per instance is asked once per class; a model without "
              "a theme says so without an exception"),
        Patch("bootstrap-css-once", "panel", "1.9", "1.10",
              "the design's page-level CSS links carry Panel's version suffix, as the "
              "shadow roots' copies do: one address, one download"),
        Patch("mathjax-on-demand", "panel", "1.9", "1.10",
              "MathJax is loaded where Bokeh finds TeX, not for every HTML pane"),
        Patch("slider-release", "panel", "1.9", "1.10",
              "a slider's release is processed at once, not after the drag's debounce"),
        Patch("browser-values", "panel", "1.9", "1.10",
              "a value from the browser that a widget cannot hold (outside a slider's "
              "range, a select's options, a radio group's buttons) is refused at the "
              "widget in one rate-limited WARNING line, and the browser set back"),
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
        _say(f"perf patch {name!r} not applied: {SWITCH} is off")
        return False
    if not _in_window(patch):
        _say(f"perf patch {name!r} not applied: it was written for {patch.library} "
             f">={patch.low},<{patch.high}; {_installed(patch.library)} is installed")
        return False
    return True


@cache
def _in_window(patch: Patch) -> bool:
    return patch.in_window()


@cache
def _say(message: str) -> None:
    log.warning(message)


def report() -> dict[str, bool]:
    """``{name: applied}`` for every patch (logs each left out)."""
    return {name: applies(name) for name in PATCHES}
