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


def test_a_page_passes_bokeh_s_integrity_checks_that_the_server_skips(monkeypatch):
    """A served page skips Bokeh's document validation and callback signature checks
    (app.main.DEVELOPMENT_CHECKS); here both run on a whole page. Callback signatures are
    checked as Panel and the explorer register them (with the diagnostics on), and the
    document's integrity check finds no error, and no warning but the empty layouts of the
    plot panes and control groups not yet shown or built (Panel silences those when it
    serves)."""
    from bokeh.core.validation.check import check_integrity
    from bokeh.settings import settings

    for name in ("BOKEH_VALIDATE_DOC", "BOKEH_PERFORM_ERROR_DIAGNOSTICS"):
        monkeypatch.delenv(name, raising=False)
    # (Bokeh before 3.9.2 has no switch for the signature checks: they always run.)
    diagnostics = getattr(settings, "perform_error_diagnostics", lambda: True)
    assert diagnostics() and settings.perform_document_validation()
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        template = main.create_app()
        main.serve(template, doc)
    issues = check_integrity(doc.models)
    assert issues.error == []
    others = []
    for warning in issues.warning:
        model = doc.get_model_by_id(warning.extra.split("'")[1])
        waiting = "fie-plot-pending" in model.css_classes  # a lazy plot, not yet in view
        if not (warning.name == "EMPTY_LAYOUT" and (waiting or not model.visible)):
            others.append((warning.name, warning.extra))
    assert others == []


def test_a_served_page_skips_bokeh_s_development_checks_unless_the_environment_sets_them(
        monkeypatch):
    from bokeh.settings import settings

    main = importlib.import_module("app.main")
    # Set, then removed: the monkeypatch restores the variable's absence after the test.
    monkeypatch.setenv("BOKEH_VALIDATE_DOC", "true")
    monkeypatch.delenv("BOKEH_VALIDATE_DOC")
    monkeypatch.setenv("BOKEH_PERFORM_ERROR_DIAGNOSTICS", "true")
    main.skip_development_checks()
    assert not settings.perform_document_validation()
    if hasattr(settings, "perform_error_diagnostics"):  # Bokeh 3.9.2 and later
        assert settings.perform_error_diagnostics()  # the operator's choice stays


def test_a_lost_connection_is_left_to_the_page_s_own_reconnection():
    """BokehJS neither reconnects by itself nor shows its own notice: a reconnection of its
    own raced static/reconnect.js's reload with a document rebuilt from the page's first
    address (tests/ui/test_reconnect_ui.py runs the page's way back)."""
    main = importlib.import_module("app.main")
    doc = Document()
    with set_curdoc(doc):
        main.serve(main.create_app(), doc)
    assert doc.config.reconnect_session is False
    assert doc.config.notify_connection_status is False
    # The setting goes to the browser with the document.
    sent = doc.to_json()
    config = getattr(sent, "content", sent)["config"]  # Serialized where a patch applies
    assert config["attributes"]["reconnect_session"] is False
    assert config["attributes"]["notify_connection_status"] is False
