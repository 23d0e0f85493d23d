"""How many Bokeh models a new session's default page holds (each costs server time to build,
serialise and send, and browser time to render)."""

from __future__ import annotations

import importlib

from bokeh.document import Document
from panel.io.state import set_curdoc

#: Models allowed on a new session's default page: the classroom target of
#: ``benchmarks/load.py``. The page had 946 with Bokeh legends drawn from stand-in renderers
#: (234 of them), 678 with HTML legends, 541 once figures were built only when first shown
#: (the rigid default scene shows no loop, friction law or energy), 432 with one ticker,
#: formatter, label policy, scale, index filter and selection policy shared by all figures,
#: and 347 once the sliders a state does not show (deformable stop, SI units) and the
#: sliders' message boxes joined the page only when first needed, 325 with one empty
#: selection shared by all data sources (no figure has a selection tool). Most of the rest
#: are the shown sliders (a text input, its tooltip, the slider, a column) and six figures.
MODEL_BUDGET = 350


def count_models() -> int:
    """Models of a new session's page, built and attached as the server does."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        main.serve(main.create_app(), doc)
    return len(doc.models)


def test_a_new_page_stays_within_its_model_budget():
    models = count_models()
    print(f"a new session's default page: {models} Bokeh models (budget {MODEL_BUDGET})")
    assert 100 < models <= MODEL_BUDGET
