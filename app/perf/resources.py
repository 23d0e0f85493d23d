"""Patches of Panel's page resources (1.9): each bundle is loaded once, and MathJax only
where a model asks for it.

A first open of the page transferred 5.3 MB (1.5 MB gzipped), of which two items bought
nothing:

* **Bootstrap's CSS twice** (221 kB, 30 kB gzipped). The Bootstrap design lists
  ``bundled/bootstrap5/css/bootstrap.min.css`` for the page's ``<head>`` without a version,
  and Panel gives the same file to every component's shadow root with ``?v=<version>``
  (``panel.io.resources.patch_stylesheet``): two addresses, so the browser fetched and
  parsed it twice. :func:`version_design_css` gives the ``<head>`` link the version too.
* **MathJax** (``bokeh-mathjax.min.js``, 1.8 MB, 0.62 MB gzipped). Bokeh loads it when a
  model holds TeX (``bokeh.embed.bundle._use_mathjax``); Panel adds it whenever the page
  has any HTML pane, in case its text holds TeX (``_panel_use_mathjax``). The explorer's
  panes hold no TeX and leave their math off (Panel's default for an HTML pane), so
  :func:`mathjax_on_demand` loads it only for a page with a pane that turns math on (a
  lesson's, app.lessons) and otherwise leaves Bokeh's own test to decide.

Both are applied only where :mod:`app.perf` says so (names ``bootstrap-css-once``,
``mathjax-on-demand``); ``tests/app/test_perf_resources.py`` checks the page's resource list
and that no pane's text holds TeX.
"""

from __future__ import annotations

from typing import Any

from app.perf import applies

#: Panel's own ``Design.resolve_resources``, once :func:`version_design_css` has replaced it.
PANEL_DESIGN_RESOLVE: Any = None
#: Panel's own ``panel.io.resources._panel_use_mathjax``, once :func:`mathjax_on_demand` has
#: replaced it.
PANEL_USE_MATHJAX: Any = None


def versioned_css(url: Any, dist: str, suffix: str) -> Any:
    """``url`` with ``suffix`` where it is a CSS file of ``dist`` without a query (the
    address Panel's ``patch_stylesheet`` gives the file's shadow-root copies), else
    ``url`` unchanged."""
    if isinstance(url, str) and dist in url and "?" not in url and url.endswith(".css"):
        return url + suffix
    return url


def _resolve_versioned(self, *args, **kwargs):
    from panel.io.resources import JS_VERSION

    resources = PANEL_DESIGN_RESOLVE(self, *args, **kwargs)
    css = resources.get("css")
    if isinstance(css, dict):
        suffix = f"?v={JS_VERSION}"
        for name, url in css.items():
            css[name] = versioned_css(url, "extensions/panel/", suffix)
    return resources


def version_design_css() -> None:
    """Give the design's page-level CSS links Panel's version suffix (see the module's
    docstring); idempotent."""
    global PANEL_DESIGN_RESOLVE
    if not applies("bootstrap-css-once"):
        return
    from panel.theme.base import Design

    if Design.__dict__["resolve_resources"] is not _resolve_versioned:
        PANEL_DESIGN_RESOLVE = Design.__dict__["resolve_resources"]
        Design.resolve_resources = _resolve_versioned


def _math_in_panes(roots) -> bool:
    """Whether a Panel HTML model under ``roots`` has its math on (``disable_math=False``).

    The models are read from the roots' document, which lists them already (walking the
    roots' references would visit the whole page once more)."""
    from panel.models.markup import HTML as PanelHTML

    roots = list(roots)
    doc = roots[0].document if roots else None
    models = doc.models if doc is not None else {m for r in roots for m in r.references()}
    return any(isinstance(m, PanelHTML) and not m.disable_math for m in models)


def mathjax_on_demand() -> None:
    """Load MathJax only where Bokeh finds a model that needs it (see the module's
    docstring); idempotent."""
    global PANEL_USE_MATHJAX
    if not applies("mathjax-on-demand"):
        return
    import panel.io.resources as resources

    if resources._panel_use_mathjax is not _math_in_panes:
        PANEL_USE_MATHJAX = resources._panel_use_mathjax
        resources._panel_use_mathjax = _math_in_panes


def load_each_bundle_once() -> None:
    """Both patches of this module, where they apply."""
    version_design_css()
    mathjax_on_demand()
