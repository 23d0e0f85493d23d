"""One session's long solve does not hold up another session of the same server process.

The server runs the explorer with one change (``slow_solve.py``): a solve with the horizon
:data:`SLOW_T_END` first computes in Python, holding the interpreter's lock as long
integrations do, until the test has measured the other session's replies: like the stiff
deformable-stop solves that take seconds (``k_c0=1e5, k_e0=1e3, beta=1000, D=0.001`` at
"precise" took 3.1 s). The slow
session integrates (``event``), so its solve runs in a child process of the server
(``app/solve/process.py``); the other session's scene is solved in closed form.
"""

from __future__ import annotations

import itertools
import os
import statistics

import pytest
from conftest import ROOT, free_port, panel_server
from slow_solve import SLOW_T_END
from uipage import Page

pytestmark = pytest.mark.ui

#: Largest delay [ms] the slow solve may add to the other session's reply (median of the
#: replies during the solve minus the median of those before and after it). Solved on the
#: event loop, the slow solve answers nothing until the test lets it end: the test fails
#: there by a timeout. Solved in a worker thread, it shared the interpreter's lock with the
#: event loop: measured 114-556 ms on the shared test machine (load average 8-11). In a
#: child process it holds only a core, at a lower priority than the server; the two cores
#: are shared with the browser's two pages, so the reply can still wait for a core: 195 ms
#: at load average 7, 336 ms on a fresh 2-core machine with the page's patches off, 463 ms
#: with four other test runs on the machine. The goal, GOAL_MS, is printed against the
#: measurement; the assertion leaves room for a busy machine.
MAX_DELAY_MS = 1000.0
GOAL_MS = 100.0
#: Releases measured before, during and after the slow solve; releases not measured first
#: (the first ones compute what later ones find cached).
RELEASES, WARM_UP = 5, 2
#: How often [ms] a page is asked about its busy marks (a page in the background gets no
#: animation frames, Playwright's default).
POLL_MS = 50

SLOW_APP = f'''
import runpy
import app.solve.pool as pool
import slow_solve

# the slow session waits for its answer
pool.SOLVER = pool.Solver(simulate=slow_solve.simulate, budget_s=600.0)
runpy.run_path({str(ROOT / "app" / "main.py")!r})
'''

#: Records, in the page, the time from each ``pointerup`` until the full solution's
#: trajectory (more points than a preview's) arrives from the server.
JS_REPLY_PROBE = """() => {
  // A full solution's arrival is the page's own signal (app/explorer.py's hidden
  // `fie-solution-arrived` pane, whose text counts arrivals); counting points of the
  // trajectory instead missed replies whose drawing has few points.
  const doc = Bokeh.documents[0];
  const arrived = [...doc.all_models].find(
    m => Array.isArray(m.css_classes) && m.css_classes.includes("fie-solution-arrived"));
  const r = (window.__reply = {up: null, ms: []});
  document.addEventListener("pointerup", () => { r.up = performance.now(); }, true);
  arrived.properties.text.change.connect(() => {
    if (r.up !== null) {
      r.ms.push(performance.now() - r.up);
      r.up = null;
    }
  });
}"""

#: The plots marked busy (Panel's ``loading``: class ``pn-loading``), shadow roots included.
JS_BUSY_PLOTS = """() => {
  const found = [];
  (function walk(node) {
    if (node.classList && node.classList.contains("fie-plot") &&
        node.classList.contains("pn-loading")) found.push(node.className);
    if (node.shadowRoot) walk(node.shadowRoot);
    for (const child of node.children || []) walk(child);
  })(document.body);
  return found;
}"""


@pytest.fixture(scope="module")
def slow_server(tmp_path_factory):
    script = tmp_path_factory.mktemp("slow") / "slow.py"
    done_file, go_file = script.with_name("slow-solve-done"), script.with_name("slow-go")
    script.write_text(SLOW_APP)
    port = free_port()
    # The server's solver processes import the stand-in from tests/ui (Bokeh restores
    # sys.path after each run of the script, so the path goes in the environment).
    env = {"FIE_SLOW_DONE_FILE": str(done_file), "FIE_SLOW_GO_FILE": str(go_file),
           "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "tests" / "ui")])}
    with panel_server(script, port, script.with_suffix(".log"), env=env):
        yield f"http://127.0.0.1:{port}/slow", done_file, go_file


def _release(p: Page) -> float:
    """Drag the clearance right or left (by turns, so that every release is a new value and
    the handle stays between two places), release, and return the reply time [ms]."""
    dx = 12 if next(_TURNS) % 2 == 0 else -12
    done = p.page.evaluate("() => window.__reply.ms.length")
    p.drag_slider("clearance", dx, steps=4)
    p.page.wait_for_function(f"() => window.__reply.ms.length > {done}", timeout=20_000)
    return p.page.evaluate("() => window.__reply.ms.at(-1)")


_TURNS = itertools.count()


def _releases(p: Page, n: int) -> list[float]:
    """Reply times [ms] of ``n`` releases."""
    return [_release(p) for _ in range(n)]


def test_a_long_solve_does_not_delay_another_session(browser, slow_server, shots):
    url, done_file, go_file = slow_server
    slow, other = Page(browser, url + "?method=event"), Page(browser, url)
    try:
        other.page.evaluate(JS_REPLY_PROBE)
        _releases(other, WARM_UP)
        before = _releases(other, RELEASES)
        readout = slow.text(".fie-readout-pane")
        box = slow.page.locator(".fie-w-t_end input").first
        box.fill(f"{SLOW_T_END:g}")
        box.press("Enter")
        # The session that waits for its solve marks the plots that solve will replace.
        slow.page.wait_for_function(f"() => ({JS_BUSY_PLOTS})().length > 0",
                                    polling=POLL_MS, timeout=20_000)
        busy = slow.page.evaluate(JS_BUSY_PLOTS)
        slow.page.screenshot(path=shots / "busy-plots.png")
        assert slow.text(".fie-readout-pane") == readout and not done_file.exists()
        during = _releases(other, RELEASES)
        still_solving = not done_file.exists()  # every reply measured while it ran
        go_file.touch()
        # The answer replaces the picture and the busy marks.
        slow.wait_text_change(".fie-readout-pane", readout, timeout=60_000)
        slow.page.wait_for_function(f"() => ({JS_BUSY_PLOTS})().length === 0",
                                    polling=POLL_MS, timeout=20_000)
        after = _releases(other, RELEASES)
    finally:
        slow.close()
        other.close()
    delay = statistics.median(during) - statistics.median(before + after)
    print(f"replies before the slow solve {before} ms, during it {during} ms, after it "
          f"{after} ms; delay {delay:.0f} ms (goal {GOAL_MS:.0f} ms)")
    assert "fie-plot fie-plot-phase pn-loading" in " ".join(busy), busy
    assert still_solving, during
    assert delay <= MAX_DELAY_MS, (before, during, after)
