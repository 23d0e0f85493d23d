"""The page's scripts apply exactly the patches the server names (app.perf.page).

Run by ``make test`` with the patches on, and once more with ``EXPLORER_PERF_PATCHES=off``:
the page then applies none of them, and the browser's own ``history.pushState`` and pixel
ratio are left in place. ``make test-min`` runs this file on the lowest versions the project
declares: a real page opens there with its scripts' patches active.
"""

from __future__ import annotations

import pytest
from uipage import PAGE_TIMEOUT_MS, Page

from app.perf import PATCHES, applies

pytestmark = pytest.mark.ui

#: JavaScript: the patches the page's scripts applied (each script lists its own).
JS_APPLIED = "() => [...(window.__fie_patches || [])].sort()"


def test_the_page_applies_the_patches_the_server_names(browser, server):
    expected = sorted(name for name, patch in PATCHES.items()
                      if patch.in_page and applies(name))
    p = Page(browser, server + "?scene=7c&slides=png")
    try:
        # The scripts that wait for BokehJS's widget bundle apply their patches a little
        # after the page is idle: wait until each has said what it applied.
        p.page.wait_for_function(f"() => (window.__fie_patches || []).length >= "
                                 f"{len(expected)}", timeout=PAGE_TIMEOUT_MS)
        assert p.page.evaluate(JS_APPLIED) == expected
        native_push = p.page.evaluate(
            "() => String(history.pushState).includes('[native code]')")
        assert native_push == ("address-in-place" not in expected)
        # Headless Chromium's own ratio is 1; slides=png asks for 3 where the patch applies.
        ratio = p.page.evaluate("() => window.devicePixelRatio")
        assert ratio == (3 if "slide-pixel-ratio" in expected else 1)
        named = p.page.locator(".noUi-handle[aria-label]").count()
        assert (named > 0) == ("slider-handle-names" in expected)
        assert p.errors == []
    finally:
        p.close()
