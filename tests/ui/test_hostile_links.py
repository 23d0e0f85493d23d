"""A shared link must not run code: hostile query strings show as text in the error box.

Every case opens the page with a query built to inject markup or script (script tags, event
attributes, ``javascript:`` links, Markdown links, very long values, unicode) and checks
that no dialog opens, that no element the value tried to add exists anywhere in the page
(shadow DOMs included), and that the message names the parameter and shows the value.
"""

from __future__ import annotations

from urllib.parse import quote

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
]


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
        p.page.wait_for_timeout(300)  # an image's onerror fires once it failed to load
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
