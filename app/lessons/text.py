"""A lesson's text as HTML whose mathematics the page typesets.

Lessons write mathematics between dollars (``$x' = v$``, ``$$...$$`` for a display). The
page's HTML panes typeset TeX with Bokeh's own MathJax bundle, which the Bokeh server
serves itself, and find it between ``\\(...\\)`` and ``\\[...\\]``: the dollars are turned
into those, and the mathematics is kept out of the Markdown renderer, which would read its
``_`` and ``*`` as emphasis.

Examples
--------
>>> lesson_html("Slip about $(a, 0)$ with *no* stick.")
'<p>Slip about \\\\((a, 0)\\\\) with <em>no</em> stick.</p>\\n'
>>> lesson_html("$$x_{max} = a + R$$")
'<p><span class="fie-lesson-display">\\\\[x_{max} = a + R\\\\]</span></p>\\n'
"""

from __future__ import annotations

import re

from markdown_it import MarkdownIt

#: ``$$display$$`` or ``$inline$`` (a dollar escaped as ``\\$`` is a dollar).
MATH = re.compile(r"(?<!\\)\$\$(.+?)(?<!\\)\$\$|(?<!\\)\$(.+?)(?<!\\)\$", re.DOTALL)
#: What stands in for a piece of mathematics while the Markdown is rendered.
PLACEHOLDER = "\ue000{}\ue001"  # private-use characters: never in a text

#: TeX for the characters that HTML reserves.
TEX_NAMES = str.maketrans({"<": r"\lt ", ">": r"\gt ", "&": r"\&"})

_MARKDOWN = MarkdownIt("commonmark", {"html": False})


def lesson_html(text: str) -> str:
    """The HTML of a lesson's Markdown ``text``, its ``$...$`` as TeX for MathJax (raw HTML
    in the text is shown as text, not run)."""
    pieces: list[str] = []

    def keep(match: re.Match) -> str:
        display, inline = match.groups()
        # TeX's own names for the characters HTML reserves: the HTML stays well formed.
        tex = (display if display is not None else inline).translate(TEX_NAMES)
        pieces.append(f'<span class="fie-lesson-display">\\[{tex}\\]</span>'
                      if display is not None else f"\\({tex}\\)")
        return PLACEHOLDER.format(len(pieces) - 1)

    rendered = _MARKDOWN.render(MATH.sub(keep, text).replace("\\$", "$"))
    return re.sub("\ue000(\\d+)\ue001", lambda m: pieces[int(m.group(1))], rendered)


def plain_math(text: str) -> str:
    """``text`` with its ``$...$`` typeset by the page, as HTML inline (no paragraph)."""
    out = lesson_html(text).strip()
    return out.removeprefix("<p>").removesuffix("</p>")
