"""'Measure the trade' in the browser: every method at every preset, timed now and compared
with a reference; on scene 10 every method and preset finds the same steady state. The
solves run outside the server's process, one measurement at a time per page."""

from __future__ import annotations

import os

import pytest
from conftest import ROOT, free_port, panel_server
from trade_probe import SLOW_T_END
from uipage import Page

pytestmark = pytest.mark.ui


def test_measure_the_trade_for_the_run_on_screen(browser, server, shots):
    p = Page(browser, f"{server}?scene=10")
    try:
        assert not p.page.locator(".fie-trade-pane").first.is_visible()
        p.page.locator(".fie-measure button").first.click()
        p.page.locator(".fie-trade-pane").first.wait_for(state="visible", timeout=120_000)
        p.settle()
        p.page.screenshot(path=shots / "trade-10.png")
        rows = p.page.locator(".fie-trade tr").all_inner_texts()[1:]
        cells = [r.split("\t") for r in rows]
        assert [(c[0], c[1]) for c in cells] == [
            (m, a) for m in ("exact", "event", "switch") for a in ("draft", "standard",
                                                                  "precise")]
        assert all(c[2].endswith("ms") for c in cells)
        # Scene 10's contacts fall towards the stop's elastic speed: every method at every
        # preset says so (the switch model at draft called it periodic while the speeds
        # still fell; the note a differing verdict gets is tested in tests/app).
        assert [c[4] for c in cells] == ["grazing"] * 9
        assert not any("verdict differs" in c[5] for c in cells if len(c) > 5)
        # (The deep text puts a space after each element: "switch : The paper's ...".)
        text = p.text(".fie-trade-pane").replace(" :", ":")
        assert "switch: The paper's switch model" in text
        # Another run: the table no longer describes the picture and goes.
        box = p.page.locator(".fie-w-belt_speed input").first
        box.fill("0.06")
        box.press("Enter")
        p.page.locator(".fie-trade-pane").first.wait_for(state="hidden", timeout=30_000)
        assert p.errors == []
    finally:
        p.close()


PROBE_APP = f'''
import runpy
import app.solve.trade as trade
import trade_probe

trade.simulate = trade_probe.simulate
runpy.run_path({str(ROOT / "app" / "main.py")!r})
'''

#: Enables the measure button in the browser, as a page that sends clicks itself could.
JS_ENABLE_MEASURE = """() => {
  const model = [...Bokeh.documents[0].all_models].find(
    m => Array.isArray(m.css_classes) && m.css_classes.includes("fie-measure"));
  model.disabled = false;
}"""


@pytest.fixture(scope="module")
def probe_server(tmp_path_factory):
    script = tmp_path_factory.mktemp("trade") / "probe.py"
    pids = script.with_name("trade-pids")
    script.write_text(PROBE_APP)
    port = free_port()
    # The solver processes import the probe from tests/ui (Bokeh restores sys.path after
    # each run of the script, so the path goes in the environment).
    env = {"FIE_TRADE_PIDS": str(pids),
           "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "tests" / "ui")])}
    with panel_server(script, port, script.with_suffix(".log"), env=env) as proc:
        yield f"http://127.0.0.1:{port}/probe", pids, proc.pid


def test_a_measurement_runs_outside_the_server_and_a_second_click_is_refused(
        browser, probe_server, shots):
    """Each solve of the measurement runs in a solver process, not in the server's (it
    held the server's interpreter lock there, slowing every other page). While it runs
    the button is disabled; a click sent anyway is refused with a message, and the button
    comes back when the table arrives."""
    url, pids, server_pid = probe_server
    p = Page(browser, f"{url}?scene=5b&tend={SLOW_T_END:g}")
    try:
        pids.unlink(missing_ok=True)  # the page's own solve is closed-form, in the server
        button = p.page.locator(".fie-measure button").first
        button.click()
        p.page.locator(".fie-measure button[disabled]").first.wait_for(state="attached",
                                                                       timeout=20_000)
        assert "at most 30 s" in p.text(".fie-measure")
        p.page.evaluate(JS_ENABLE_MEASURE)
        p.page.locator(".fie-measure button:not([disabled])").first.wait_for(
            state="attached", timeout=20_000)
        button.click()
        p.page.locator(".fie-alert-box").first.wait_for(state="visible", timeout=20_000)
        alert = p.text(".fie-alert-box")
        assert "Not measured:" in alert and "already running for this page" in alert
        p.page.screenshot(path=shots / "trade-refused.png")
        p.page.locator(".fie-trade-pane").first.wait_for(state="visible", timeout=120_000)
        p.page.locator(".fie-measure button:not([disabled])").first.wait_for(
            state="attached", timeout=20_000)
        assert "Measure the trade" in p.text(".fie-measure")
        p.page.locator(".fie-alert-box").first.wait_for(state="hidden", timeout=20_000)
        lines = pids.read_text().split()
        # at most the reference and nine solves: the refused click started none
        assert 1 <= len(lines) <= 10, lines
        assert server_pid not in {int(line) for line in lines}, (server_pid, lines)
        assert p.errors == []
    finally:
        p.close()
