"""How the page reads on small screens and by keyboard: the viewport, the focus ring every
control draws, and the phone layout of the main column.

The page-level rules (the drawer, the columns, text sizes) are in ``static/explorer.css``;
Panel draws each widget in a shadow root that no page-level rule reaches, so the focus ring
comes with the page's design (:class:`ExplorerDesign`), which links every widget's and
HTML pane's shadow root to the same small sheet (``static/widgets.css``).
"""

from __future__ import annotations

import param
from panel.pane import HTML
from panel.theme import Bootstrap
from panel.theme.base import Inherit, Theme
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


def with_resolved_sheets(theme: type[Theme]) -> type[Theme]:
    """``theme`` with the paths of its two style sheets (``base_css``, ``css``) found once.

    Panel's themes declare them as file-name parameters, and a file-name parameter looks
    its file up on the disk at every read; the design reads both for every widget, pane
    and layout of a new page (~160 reads, ~4 % of a page's server CPU). The same paths as
    plain strings give the page the same style sheets."""
    found = theme()
    return type(theme.__name__, (theme,), {
        "__doc__": theme.__doc__,
        "base_css": param.String(default=found.base_css, allow_None=True),
        "css": param.String(default=found.css, allow_None=True),
    })


class ExplorerDesign(Bootstrap):
    """Panel's Bootstrap design, with :data:`SHADOW_CSS` in every widget and HTML pane:
    a focus ring on every control, and text of at least 14 px on a phone; its themes'
    style sheets are found once (:func:`with_resolved_sheets`)."""

    modifiers = {
        **Bootstrap.modifiers,
        Widget: {"stylesheets": [Inherit, SHADOW_CSS]},
        HTML: {"stylesheets": [Inherit, SHADOW_CSS]},
    }
    # Panel's designs name their themes in this mapping (panel.theme.Bootstrap's own).
    _themes = {name: with_resolved_sheets(theme) for name, theme in Bootstrap._themes.items()}
