"""How the page reads on small screens and by keyboard: the viewport, the focus ring every
control draws, and the phone layout of the main column.

The page-level rules (the drawer, the columns, text sizes) are in ``static/explorer.css``;
Panel draws each widget in a shadow root that no page-level rule reaches, so the focus ring
comes with the page's design (:class:`ExplorerDesign`), which links every widget's and
HTML pane's shadow root to the same small sheet (``static/widgets.css``).
"""

from __future__ import annotations

from panel.pane import HTML
from panel.theme import Bootstrap
from panel.theme.base import Inherit
from panel.widgets.base import Widget

#: A phone draws the page at its own width (without it, a phone lays the page out 980 px
#: wide and shrinks it: text of ~5 px).
VIEWPORT = "width=device-width, initial-scale=1"

#: Below this window width [px] the page is one column and the controls are a drawer
#: (static/explorer.css and static/drawer.js use the same number).
PHONE_MAX_WIDTH = 700

#: Every widget's and HTML pane's own sheet: the focus ring, and text of at least 14 px on
#: a phone. One address: one style sheet model per page, linked into every shadow root.
SHADOW_CSS = "assets/widgets.css"

#: The main column on a phone: the plots (the phase portrait first) before the readout's
#: table, which would otherwise fill the first screen.
MAIN_COLUMN_CSS = f"""
@media (max-width: {PHONE_MAX_WIDTH}px) {{
  :host > .fie-readout-pane {{ order: 1; }}
}}
"""


class ExplorerDesign(Bootstrap):
    """Panel's Bootstrap design, with :data:`SHADOW_CSS` in every widget and HTML pane:
    a focus ring on every control, and text of at least 14 px on a phone."""

    modifiers = {
        **Bootstrap.modifiers,
        Widget: {"stylesheets": [Inherit, SHADOW_CSS]},
        HTML: {"stylesheets": [Inherit, SHADOW_CSS]},
    }
