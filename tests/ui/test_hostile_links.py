"""A shared link must not run code: hostile query strings show as text in the error box.

Every case opens the page with a query built to inject markup or script (script tags, event
attributes, ``javascript:`` links, Markdown links, very long values, unicode) and checks
that no dialog opens, that no element the value tried to add exists anywhere in the page
(shadow DOMs included), and that the message names the parameter and shows the value.
"""

from __future__ import annotations

from urllib.parse import parse_qs, quote, urlparse

import pytest
from uipage import Page

pytestmark = pytest.mark.ui

#: JavaScript: elements of the page (shadow roots included) that a payload could add: any
#: inline event handler, a ``javascript:`` link, a script, image, svg, iframe or <b>/<i>
#: inside the error box.
JS_INJECTED = """() => {
  const found = [];
  function walk(root, inAlert) {
    for (const el of root.querySelectorAll("*")) {
      const alert = inAlert || (el.classList && el.classList.contains("fie-alert"));
      for (const a of el.getAttributeNames()) {
        if (a.startsWith("on")) found.push(el.tagName + "[" + a + "]");
      }
      const href = el.getAttribute("href") || "";
      if (href.trim().toLowerCase().startsWith("javascript:")) found.push("a[javascript:]");
      if (["IMG", "SVG", "IFRAME", "SCRIPT", "A", "I", "U", "MARQUEE"].includes(
          el.tagName.toUpperCase()) && alert) found.push(el.tagName);
      if (el.shadowRoot) walk(el.shadowRoot, alert);
    }
  }
  walk(document, false);
  return found;
}"""

LONG = "<" * 3000 + "script>alert(3)</script>"
#: (query, URL key named in the message, a fragment of the value shown as text).
CASES = [
    ("scene=5a&xbar=<img src=x onerror=alert(document.domain)>", "xbar",
     "<img src=x onerror=alert(document.domain)>"),
    ("scene=5a&units=<b>bold</b>", "units", "<b>bold</b>"),
    ("scene=5a&method=<script>alert(1)</script>", "method", "<script>alert(1)</script>"),
    ("scene=5a&stop=\"><svg onload=alert(2)>", "stop", "<svg onload=alert(2)>"),
    ("scene=5a&x0=click [here](javascript:alert(4))", "x0", "[here](javascript:alert(4))"),
    ("scene=5a&v=javascript:alert(5)", "v", "javascript:alert(5)"),
    ("scene=5a&tend=" + LONG, "tend", "characters"),
    ("scene=5a&mus=ünïcødé 😀 <i>x</i>", "mus", "ünïcødé 😀 <i>x</i>"),
    ("scene=5a&fig=<img src=x onerror=alert(7)>", "fig", "<img src=x onerror=alert(7)>"),
]
#: JavaScript: true once every image of the page (shadow roots included) has loaded or failed.
JS_IMAGES_DONE = """() => {
  function done(node) {
    for (const el of node.querySelectorAll("*")) {
      if (el.shadowRoot && !done(el.shadowRoot)) return false;
      if (el.tagName === "IMG" && !el.complete) return false;
    }
    return true;
  }
  return done(document);
}"""


@pytest.mark.parametrize(("query", "key", "shown"), CASES,
                         ids=[c[1] for c in CASES])
def test_hostile_link_shows_text(browser, server, shots, query, key, shown):
    url = server + "?" + "&".join(
        f"{k}={quote(v, safe='')}" for k, v in (p.split("=", 1) for p in query.split("&")))
    dialogs: list[str] = []
    p = Page.__new__(Page)
    p.page = browser.new_page(viewport={"width": 1280, "height": 800})
    p.errors = []
    p.page.on("dialog", lambda d: (dialogs.append(d.message), d.dismiss()))
    p.page.on("pageerror", lambda exc: p.errors.append(f"pageerror: {exc}"))
    try:
        from uipage import JS_READY, PAGE_TIMEOUT_MS
        p.page.goto(url, timeout=PAGE_TIMEOUT_MS)
        p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        alert = p.page.locator(".fie-alert").first
        alert.wait_for(state="visible", timeout=30_000)
        # An injected image's onerror fires once it failed to load: wait until every image
        # of the page, shadow roots included, has loaded or failed.
        p.page.wait_for_function(JS_IMAGES_DONE, timeout=30_000)
        p.settle()
        p.page.screenshot(path=shots / f"hostile-{key}.png")
        assert dialogs == []
        assert p.page.evaluate(JS_INJECTED) == []
        text = p.text(".fie-alert")
        assert "could not be applied" in text and f"{key} (" in text
        assert shown in text
        assert "Fig. 5a" in p.text(".fie-caption")  # the rest of the link still applies
        assert p.errors == []
    finally:
        p.page.close()


HUGE = "9" * 4400
#: (query, what the message must say): values of the wrong type for the numbers, choices
#: and switches the page reads, Panel's own guesses (``true`` a bool, ``[..]`` a list), a
#: key given twice, numerals past Python's 4,300-digit int-string limit (they failed in
#: Panel's address parsing, before the page was built), and the pins' codec.
WRONG_TYPES = [
    ("tend=true", "tend (t_end) must be a number in [0.1, 5000]; got 'true'"),
    ("v=false", "v (belt_speed) must be a number in [0, 10]; got 'false'"),
    ("xbar=true", "xbar (clearance) must be a number in [-10, 10]; got 'true'"),
    ("mus=true&muk=false", "muk (mu_k) must be a number in [0, 5]; got 'false'"),
    ("x0=true&v0=false", "v0 (v0) must be a number in [-100, 100]; got 'false'"),
    ("r=true&us=true&kc0=true", "kc0 (k_c0) must be a number in [0.001, 1e+06]; got 'true'"),
    ("D=null&bc=[1,2]&be={\"a\":1}", "be (beta_e) must be a number in [0.001, 100000]"),
    ("m=NaN&k=inf&units=true", "units (units) must be one of 'dimensionless', 'SI'"),
    ("stop=false&law=1&acc=-1&method=&all=1&prog=2", "all (show_all) must be true or false"),
    ("fig=custom", "fig (figure) must be one of '2b', '3a'"),
    ("r=0.5&r=0.7", "r (restitution) must be given once; got 2 values: '0.5', '0.7'"),
    ("tend=" + HUGE, "tend (t_end) must be a number in [0.1, 5000]; got '999"),
    ("present=" + "1" * 4400, "present must be one of 1, 2, 3, 4"),
    ("zz=" + HUGE + "&slides=" + HUGE, "slides must be one of"),
    ("pins=5a,prog=yes", "pins: the pinned runs could not be restored: pin 1 ('5a,prog=yes'): "
                         "prog (program) must be true or false; got 'yes'"),
    ("pins=5a,tend=" + HUGE, "pin 1 ('5a,tend=999"),
]


@pytest.mark.parametrize(("query", "said"), WRONG_TYPES,
                         ids=[q.split("=")[0] + "=" + q.split("=")[1][:8] for q, _ in WRONG_TYPES])
def test_a_link_of_wrong_values_opens_a_working_page(browser, server, shots, query, said):
    """``?tend=true`` left a white page (a bool in a slider), ``?r=true`` opened r = 1
    without a word, and a value past 4,300 digits failed in Panel before the page was
    built. The page opens, says what it refused with the allowed range, and works: a
    slider's release solves and draws again."""
    url = server + "?scene=5a&" + "&".join(
        f"{k}={quote(v, safe='')}" for k, v in (p.split("=", 1) for p in query.split("&")))
    p = Page(browser, url, viewport={"width": 1280, "height": 800})
    try:
        alert = p.page.locator(".fie-alert").first
        alert.wait_for(state="visible", timeout=30_000)
        text = p.text(".fie-alert")
        assert "could not be applied" in text and said in text
        assert "Fig. 5a" in p.text(".fie-caption")  # the rest of the link applied
        # The page works: a slider's release solves and redraws (the readout follows),
        # and the address is the page's own again.
        readout = p.text(".fie-readout-pane")
        p.drag_slider("clearance", 40)
        p.wait_text_change(".fie-readout-pane", readout)
        p.page.wait_for_function("() => location.search.includes('scene=custom')",
                                 timeout=10_000)
        # The keys the page reads hold its own values again (a key it does not read stays
        # as it came).
        written = parse_qs(urlparse(p.page.url).query, keep_blank_values=True)
        assert all(len(v[0]) < 100 for k, v in written.items() if k != "zz")
        assert p.errors == []
    finally:
        p.page.screenshot(path=shots / f"wrong-link-{query.split('=')[0]}.png")
        p.close()
