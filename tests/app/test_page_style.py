"""The phone's width limit is one number in every file that lays the page out by it."""

from __future__ import annotations

from pathlib import Path

from app.page_style import MAIN_COLUMN_CSS, PHONE_MAX_WIDTH
from app.widgets import SLIDER_CSS

ROOT = Path(__file__).resolve().parents[2]


def test_every_phone_rule_uses_the_same_width():
    query = f"(max-width: {PHONE_MAX_WIDTH}px)"
    for path in ("static/explorer.css", "static/widgets.css", "static/drawer.js"):
        assert query in (ROOT / path).read_text(), path
    assert query in SLIDER_CSS and query in MAIN_COLUMN_CSS
