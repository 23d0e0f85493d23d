"""The page: app.main builds a session's document in one pass."""

from __future__ import annotations

import importlib

from bokeh.document import Document
from panel.io.state import set_curdoc


def test_a_page_attached_in_one_pass_lists_every_model_of_its_roots():
    """The template is attached with the document's model list frozen (app.main.serve):
    once it is attached the list must hold exactly the models its roots reach."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
    reachable = {m.id for root in doc.roots for m in root.references()}
    assert len(doc.roots) >= 2 and len(reachable) > 200  # a whole page, not a stub
    assert {m.id for m in doc.models} == reachable
    figure = template.explorer.plots.figures["phase"]
    assert doc.get_model_by_id(figure.id) is figure
