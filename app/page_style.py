"""How the page reads on small screens and by keyboard: the viewport, the focus ring every
control draws, and the phone layout of the main column.

The page-level rules (the drawer, the columns, text sizes) are in ``static/explorer.css``;
Panel draws each widget in a shadow root that no page-level rule reaches, so the focus ring
comes with the page's design (:class:`ExplorerDesign`), which gives every widget's shadow
root the same small sheet.
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

#: A ring of 3 px around whichever control has the keyboard's focus. Bootstrap draws a
#: button's focus as a shadow of the button's own colour, which the default grey buttons
#: leave invisible; a button in a group is lifted above its neighbours so that its ring
#: is not drawn under them. Only keyboard focus (``:focus-visible``): a click draws none.
FOCUS_CSS = """
:focus-visible { outline: 3px solid #1f6feb !important; outline-offset: 2px; }
.bk-btn:focus-visible { position: relative; z-index: 2; }
"""
#: A widget's text on a phone: at least 14 px (Bootstrap's buttons are 0.8 rem, 12.8 px;
#: the rest follows ``--bokeh-font-size``, static/explorer.css).
WIDGET_PHONE_CSS = f"""
@media (max-width: {PHONE_MAX_WIDTH}px) {{ .bk-btn {{ font-size: 14px; }} }}
"""
#: An HTML pane's text on a phone: at least 14 px, over a size the pane sets on itself
#: (the plots' legends are 12 px).
PANE_PHONE_CSS = f"""
@media (max-width: {PHONE_MAX_WIDTH}px) {{ :host {{ font-size: max(14px, 1em) !important; }} }}
"""

#: The main column on a phone: the plots (the phase portrait first) before the readout's
#: table, which would otherwise fill the first screen.
MAIN_COLUMN_CSS = f"""
@media (max-width: {PHONE_MAX_WIDTH}px) {{
  :host > .fie-readout-pane {{ order: 1; }}
}}
"""


class ExplorerDesign(Bootstrap):
    """Panel's Bootstrap design, with the focus ring (:data:`FOCUS_CSS`) in every widget
    and text of at least 14 px on a phone."""

    modifiers = {
        **Bootstrap.modifiers,
        Widget: {"stylesheets": [Inherit, FOCUS_CSS + WIDGET_PHONE_CSS]},
        HTML: {"stylesheets": [Inherit, PANE_PHONE_CSS]},
    }
