"""Patches of two walks of a whole new page that Panel 1.9 makes and that find nothing to do.

A new session's page is ~245 Bokeh models. Listing them means walking every property of
every model (``Model.references``, ~1.5-2 ms per page); Bokeh walks them once for the
document (needed), and Panel walked them again:

* **on attach** (``fresh-roots``): the template adds each of its roots with
  ``panel.io.model.add_to_doc``, which first walks the root to take each model out of the
  document it was in before (``remove_root``). A new page's models were in no document;
  :func:`add_fresh_root` adds a root that was never attached without that walk. Had a
  model under it been in another session's document, Bokeh raises as it lists the new
  document's models ("Models must be owned by only a single document") instead of Panel
  taking it from the other page in silence: an error either way, a loud one here.
* **on the page's HTML** (``stylesheets-from-document``): for each root, Panel walks the
  root for its stylesheets to give them the server's address
  (``panel.io.server.patch_model_css``). :func:`patch_document_css` gives Panel's own
  function the document's stylesheets, read from the list the document keeps, once for
  all its roots.

Together ~15 ms of ~0.23 s of server CPU per new page (``benchmarks/page_models.py``,
``benchmarks/results/2026-11-29-page-walks.md``). Both are applied only where
:mod:`app.perf` says so; ``tests/app/test_perf_attach.py`` checks that a page comes out the
same either way.
"""

from __future__ import annotations

from typing import Any

from app.perf import applies

#: Panel's own ``add_to_doc`` of its templates, once :func:`attach_without_walks` replaced it.
PANEL_ADD_TO_DOC: Any = None
#: Panel's own ``patch_model_css`` of its HTML page, once replaced.
PANEL_PATCH_MODEL_CSS: Any = None


def add_fresh_root(obj: Any, doc: Any, hold: bool = False, skip: Any = None) -> set:
    """Panel's ``add_to_doc`` for a template's root: a root never attached to a document
    is added at once (the walk that takes its models out of their old document would find
    none); any other goes Panel's way."""
    if obj.document is not None:
        return PANEL_ADD_TO_DOC(obj, doc, hold=hold, skip=skip)
    doc.add_root(obj)
    if doc.callbacks.hold_value is None and hold:
        doc.hold()
    return set()  # no model was walked: the template's next root skips none


class _DocumentStylesheets:
    """A document's stylesheets, shaped as the root Panel's ``patch_model_css`` walks:
    ``document``, and ``select`` answering from the document's own list of its models."""

    def __init__(self, doc: Any) -> None:
        self.document = doc

    def select(self, selector: Any) -> list[Any]:
        from bokeh.models import ImportedStyleSheet

        return [m for m in self.document.models if isinstance(m, ImportedStyleSheet)]


def patch_document_css(root: Any, dist_url: str) -> None:
    """Panel's ``patch_model_css`` for each root of a session's page: the first root of a
    document patches the stylesheets of all of them, from the document's list of its
    models; the others have nothing left. A root outside a document goes Panel's way."""
    doc = root.document
    if doc is None or root not in doc.roots:
        PANEL_PATCH_MODEL_CSS(root, dist_url)
    elif root is doc.roots[0]:
        PANEL_PATCH_MODEL_CSS(_DocumentStylesheets(doc), dist_url)


def attach_without_walks() -> None:
    """Both patches of this module, where they apply; idempotent."""
    global PANEL_ADD_TO_DOC, PANEL_PATCH_MODEL_CSS
    if applies("fresh-roots"):
        import panel.template.base as template_base

        if template_base.add_to_doc is not add_fresh_root:
            PANEL_ADD_TO_DOC = template_base.add_to_doc
            template_base.add_to_doc = add_fresh_root
    if applies("stylesheets-from-document"):
        import panel.io.server as server

        if server.patch_model_css is not patch_document_css:
            PANEL_PATCH_MODEL_CSS = server.patch_model_css
            server.patch_model_css = patch_document_css
