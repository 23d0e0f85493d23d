"""Presentation mode: the plots fill the screen for a projector; figures for slides.

One, two, three or four plots (``present=1`` .. ``present=4`` in the address; four in a 2×2
grid, three as one wide plot over two) under a slim control strip (:mod:`app.present_strip`,
built the first time the page presents), the sidebar, the page's header, the scene's caption
and the readout hidden (``static/present.js`` gives the page's body the classes it styles by,
and the keyboard's shortcuts: P present / leave, 1-4 the layouts, F fullscreen, ? help). A
lesson open, the strip shows its step and steps it (its ◀ and ▶, the lesson's ←/→ keys), and
the lesson's box gives way to the plots but for a step's question. The
plots' panes take the window's height less the strip's (:data:`STRIP_PX`), in one row or
two, at 16:9 and at 4:3 alike. The figures are restyled by changing properties of those
already built: the mode adds no Bokeh model to the figures. Leaving it puts every property
back.

Sizes for the back of a room (one plot; :data:`FONTS` for the others): titles 26 px, axis
labels 22 px, tick labels and the strip's widgets 18 px, every line twice its width on the
page (:data:`LINE_SCALE`: the page's 1.5 px trajectories become 3 px), axes and ticks in
black at 2 px. Why: a letter is read with ease when it subtends about 10 arcmin (twice the
5 arcmin letter of 20/20 vision). On a 1080-line image 2 m high one CSS pixel is 1.85 mm,
an 18 px font's capitals ~13 px = 24 mm, which subtend 10 arcmin at 8 m (four image
heights); the 26 px titles at ~12 m. On a 768-line (4:3) projector of the same height every
pixel is 40 % larger. The four-plot grid's 15 px ticks read to ~7 m: a layout for a smaller
room or a closer look.

Figures for slides (``slides=svg`` or ``slides=png``): each figure gets a caption line under
it that states the scene and the parameters, and its save tool (the toolbar's download
button) saves a file named after them, drawn by the browser: SVG (Bokeh's
``output_backend="svg"``), or PNG at :data:`PNG_SCALE` times the figure's size (the page
draws its canvases at that pixel ratio, ``static/present.js``). The caption lines are built
the first time this is used.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from bokeh.models import GlyphRenderer, SaveTool, Title

from app.links import shown
from app.plots import (
    AXIS_LABEL_FONT,
    LABEL_FONT_PX,
    PLOT_WIDTHS,
    PRESENT_LABEL_FONT_PX,
    TICK_LABEL_FONT,
    TITLE_FONT,
)
from app.present_strip import STRIP_HEIGHT_PX, PresentStrip
from app.scenes import SCENES
from app.teach.glossary import BETAS, PLAIN

#: The presentation layouts: the address's value -> menu label (``""``: off).
MODES: Mapping[str, str] = {"1": "one large plot", "2": "two plots", "3": "three plots",
                            "4": "2×2 plots"}
#: The layouts the page's menu offers.
MENU_MODES = ("1", "4")
#: The permalink's key.
URL_KEY = "present"
#: Plots shown by layout (the first the scene shows; the animation only alone).
PLOT_COUNT: Mapping[str, int] = {"1": 1, "2": 2, "3": 3, "4": 4}
#: Rows of plots by layout.
ROWS: Mapping[str, int] = {"1": 1, "2": 1, "3": 2, "4": 2}
#: Fonts for a projector by layout: title, axis labels, tick labels, the theory's point
#: names, legends (a quarter of a 720p screen holds a 230 px plot: smaller than one large).
FONTS: Mapping[str, Mapping[str, str]] = {
    "1": {"title": "26px", "axis": "22px", "tick": "18px", "points": f"{PRESENT_LABEL_FONT_PX}px",
          "legend": "18px"},
    "2": {"title": "24px", "axis": "20px", "tick": "17px", "points": "20px",
          "legend": "16px"},
    "3": {"title": "20px", "axis": "17px", "tick": "15px", "points": "18px",
          "legend": "14px"},
    "4": {"title": "20px", "axis": "17px", "tick": "15px", "points": "18px",
          "legend": "14px"},
}
#: Ticks asked of the page's (shared) ticker by layout, and off: in a quarter of a 720p
#: screen the stacked x(t) and x'(t) plots are ~60 px high, and six 15 px tick labels
#: touched each other there; asked for 4, Bokeh's ticker still ticked x'(t) of Fig. 5a
#: (a span of 0.25) every 0.05, six labels; asked for 3 it ticks every 0.1.
TICKS: Mapping[str, int] = {"": 6, "1": 5, "2": 5, "3": 3, "4": 3}
#: Line widths are multiplied by this (a 1.5 px line is invisible from the back of a room).
LINE_SCALE = 2.0
#: Height left free above the plots [px]: the control strip's (the page's header and the
#: scene's caption are hidden; the scene is named in the strip's picker).
STRIP_PX = STRIP_HEIGHT_PX
#: Margin [px] of a plot's pane while presenting: (vertical, horizontal).
PANE_MARGIN = (1, 2)
#: High-contrast frame: axis lines and ticks in black, a darker grid.
AXIS_COLOR, GRID_COLOR = "#000000", "#9a9a9a"
#: Figure formats for slides: the address's value -> menu label.
SLIDES: Mapping[str, str] = {"svg": "SVG", "png": "PNG at 3x"}
#: The address's key for the slide format.
SLIDES_KEY = "slides"
#: Pixel ratio of a slide PNG (kept in step with ``static/present.js``).
PNG_SCALE = 3
#: Parameters the caption line names, by stop type: (state name, symbol).
CAPTION_PARAMS: Mapping[str, tuple[tuple[str, str], ...]] = {
    "none": (("belt_speed", "v"), ("mu_s", PLAIN["mu_s"]), ("mu_k", PLAIN["mu_k"]),
             ("u_s", PLAIN["u_s"])),
    "rigid": (("belt_speed", "v"), ("clearance", PLAIN["x_bar"]), ("restitution", "r"),
              ("mu_s", PLAIN["mu_s"]), ("mu_k", PLAIN["mu_k"]), ("u_s", PLAIN["u_s"])),
    "hysteretic": (("belt_speed", "v"), ("clearance", PLAIN["x_bar"]),
                   ("k_c0", PLAIN["k_c0"] + "/k"), ("k_e0", PLAIN["k_e0"] + "/k"),
                   ("limit_overlap", "D"), ("beta_c", BETAS[0]), ("beta_e", BETAS[1]),
                   ("mu_s", PLAIN["mu_s"]), ("mu_k", PLAIN["mu_k"]), ("u_s", PLAIN["u_s"])),
}
#: Parameters on the caption's first line at most (the rest go on a second line).
CAPTION_LINE_ITEMS = 6
#: The figures' usual frame, put back on leaving.
NORMAL_AXIS_COLOR, NORMAL_GRID_COLOR = "black", "#e5e5e5"


class Presentation:
    """The presentation mode of one page: its layout and slide format are the state's
    (``present``, ``slides``); this styles the figures for them.

    Parameters
    ----------
    state : ExplorerState
        The page's state.
    host : app.plots_host.PlotsHost
        The page's plots (their figures and panes, and which the state shows).
    """

    def __init__(self, state: Any, host: Any) -> None:
        self.state = state
        self.host = host
        #: Figures styled for :attr:`_styled_mode`, and each glyph's own line width.
        self._styled: set[str] = set()
        self._styled_mode = ""
        self._widths: dict[str, float] = {}
        #: Each figure's caption line once made.
        self._captions: dict[str, Title] = {}
        #: The control strip (:class:`app.present_strip.PresentStrip`), made when the page
        #: first presents.
        self.strip: Any = None
        #: The page's lessons (:class:`app.lessons.mount.LessonsMount`), stepped by the
        #: strip (set by the page).
        self.lesson: Any = None
        #: Panes of the page hidden while presenting (:meth:`hide_while_presenting`).
        self._hidden: list[Any] = []
        self._hiding = False

    @property
    def mode(self) -> str:
        return self.state.present

    @property
    def slides(self) -> str:
        return self.state.slides

    @property
    def on(self) -> bool:
        return self.mode in MODES

    def menu_items(self) -> list[tuple[str, str]]:
        """Entries of the page's menu."""
        # The layouts of one and four plots (the strip and the keys switch to any).
        items = [(f"Presentation: {MODES[key]}", f"present:{key}") for key in MENU_MODES
                 if key != self.mode]
        if self.on:
            items.append(("Leave the presentation", "present:"))
        items += [(f"Figures for slides: {label} (toolbar's save button)", f"slides:{key}")
                  for key, label in SLIDES.items() if key != self.slides]
        if self.slides:
            items.append(("Figures as on screen (no caption line)", "slides:"))
        return items

    def set_slides(self, fmt: str) -> None:
        """Figures for slides in format ``fmt`` (a key of :data:`SLIDES`, ``""``: off)."""
        self.state.slides = fmt if fmt in SLIDES else ""

    def set_mode(self, mode: str) -> None:
        """Switch to ``mode`` (a key of :data:`MODES`, or ``""`` to leave)."""
        self.state.present = mode if mode in MODES else ""

    def shown(self, visible: tuple[str, ...]) -> tuple[str, ...]:
        """The plot panes the layout shows of the ``visible`` ones."""
        if self.mode == "1":
            return visible[:1]
        if self.on:
            return tuple(p for p in visible if p != "anim")[:PLOT_COUNT[self.mode]]
        return visible

    def hide_while_presenting(self, *panes: Any) -> None:
        """Hide ``panes`` of the page while presenting (the scene's caption: the strip's
        picker names the scene)."""
        self._hidden[:] = panes
        for pane in panes if self._hiding else ():  # the page opened presenting
            pane.visible = False
        self._show_page()

    def _show_page(self) -> None:
        """The strip (made on the first entry) and the page's panes for the mode."""
        if self.on and self.strip is None:
            self.strip = PresentStrip(self.state, self.host.commit, self.set_mode, MODES,
                                      self.lesson)
            self.host.above_plots(self.strip.layout)
        if self._hiding != self.on:  # only on entering and leaving: a lesson's question
            self._hiding = self.on    # hides the same panes meanwhile
            for pane in self._hidden:
                pane.visible = not self.on
        if self.on:
            # The layout's plots are all in view: built now, not when the browser reports
            # them (a plot not yet built left its half of a row empty).
            host = self.host
            waiting = {n for n in self.shown(host.visible_plots())
                       if not host.plot_panes[n].objects}
            if waiting:
                host.build_in_view(waiting)

    # --- address ---------------------------------------------------------------------------

    def apply_query(self, query: Mapping[str, str]) -> list[str]:
        """The slide format and the layout from the address's text values; returns what
        was refused, in words."""
        refused = []
        fmt = query.get(SLIDES_KEY)
        if fmt:
            if fmt in SLIDES:
                self.set_slides(fmt)
            else:
                refused.append(f"slides must be one of {', '.join(SLIDES)} (figure formats "
                               f"for slides); got {shown(fmt)}")
        mode = query.get(URL_KEY)
        if mode in (None, "", "0"):
            return refused
        if mode not in MODES:
            refused.append(f"present must be one of {', '.join(MODES)} (presentation "
                           f"layouts: {', '.join(MODES.values())}) or 0; got {shown(mode)}")
            return refused
        self.set_mode(mode)
        return refused

    def query(self, current: Mapping[str, Any]) -> dict[str, str]:
        out = {}
        if self.on or URL_KEY in current:
            out[URL_KEY] = self.mode if self.on else "0"
        if self.slides or SLIDES_KEY in current:
            out[SLIDES_KEY] = self.slides
        return out

    # --- slides ----------------------------------------------------------------------------

    def caption(self) -> str:
        """The caption line: the scene and the parameters of the run on screen."""
        values = self.state.values()
        scene = self.state.scene
        head = (f"Fig. {scene}" if scene in SCENES
                else f"custom parameters (from Fig. {self.state.figure})")
        stop = values["stop_type"]
        items = [f"{symbol} = {values[name]:.4g}" for name, symbol in CAPTION_PARAMS[stop]]
        if values["x0"] or values["v0"]:
            items.append(f"start ({values['x0']:.4g}, {values['v0']:.4g})")
        # Two lines: a figure of the narrowest width holds some 90 characters a line.
        half = (len(items) + 1) // 2 if len(items) > CAPTION_LINE_ITEMS else len(items)
        lines = [", ".join(items[:half]), ", ".join(items[half:])]
        return f"{head}, {stop} stop: " + ",\n".join(line for line in lines if line)

    def _slides(self) -> None:
        """Caption lines, file names and drawing backend of the built figures."""
        figs = self.host.plots.figures
        if not self.slides and not self._captions:
            return
        text = self.caption() if self.slides else ""
        backend = "svg" if self.slides == "svg" else "canvas"
        st = self.state
        scene = st.scene if st.scene in SCENES else f"custom-from-{st.figure}"
        for name, fig in figs.items():
            title = self._captions.get(name)
            if title is None and self.slides:
                title = self._captions[name] = Title(
                    text=text, align="left", text_font_size="13px", text_font_style="normal")
                fig.add_layout(title, "below")
            if title is not None:
                title.update(text=text, visible=bool(self.slides))
            if fig.output_backend != backend:
                fig.output_backend = backend
            stem = re.sub(r"[^A-Za-z0-9._-]", "-", f"fie_{scene}_{name}")
            for tool in fig.toolbar.tools:
                if isinstance(tool, SaveTool):
                    tool.filename = f"{stem}.{self.slides}" if self.slides else None

    # --- styling ---------------------------------------------------------------------------

    def restyle(self) -> None:
        """Style the built figures and panes for the mode (only those not yet styled)."""
        plots = self.host.plots
        figs = plots.figures
        if self._styled_mode != self.mode:
            self._styled, self._styled_mode = set(), self.mode
        for name in set(figs) - self._styled:
            self._style_figure(figs[name])
            self._styled.add(name)
        ticks = TICKS[self.mode if self.on else ""]
        if plots.shared.ticker.desired_num_ticks != ticks:
            plots.shared.ticker.desired_num_ticks = ticks
        self._style_labels(plots.point_labels)
        # The time histories take the whole of their pane: their window stays, the
        # overview to brush it (a tool for a desk, not a projector) goes.
        plots.run_window.hide_overview(self.on)
        for div in plots.legends.values():
            size = self._font("legend") if self.on else "12px"
            if div.styles.get("font-size") != size:
                div.styles = {**div.styles, "font-size": size, "line-height": (
                    f"{int(size[:-2]) + 8}px" if self.on else "20px")}
        self._slides()
        self._show_page()
        self._layout()

    def _style_labels(self, labels: Any) -> None:
        """The theory's point names: the paper's, bold and large, when presenting."""
        if labels is None:
            return
        text, size = ("paper", self._font("points")) if self.on else (
            "name", f"{LABEL_FONT_PX}px")
        if labels.text != text or labels.text_font_size != size:
            # The browser places the labels again for the font (plots.PLACE_LABELS_JS).
            labels.update(text=text, text_font_size=size,
                          text_font_style="bold" if self.on else "normal")

    def _font(self, what: str) -> str:
        return FONTS[self.mode][what]

    def _style_figure(self, fig: Any) -> None:
        on = self.on
        fig.title.text_font_size = self._font("title") if on else TITLE_FONT
        axis_style = self._axis_style()
        for axis in (*fig.left, *fig.right, *fig.above, *fig.below):
            if hasattr(axis, "axis_label_text_font_size"):
                axis.update(**axis_style)
        for grid in fig.grid:
            grid.grid_line_color = GRID_COLOR if on else NORMAL_GRID_COLOR
        for r in fig.renderers:
            self._style_line(r)

    def _axis_style(self) -> dict[str, Any]:
        """The axes' fonts, lines and colours for the mode."""
        if not self.on:
            return {"axis_label_text_font_size": AXIS_LABEL_FONT,
                    "major_label_text_font_size": TICK_LABEL_FONT, "axis_line_width": 1,
                    "major_tick_line_width": 1, "axis_line_color": NORMAL_AXIS_COLOR,
                    "axis_label_text_color": "#444444", "major_label_text_color": "#444444"}
        return {"axis_label_text_font_size": self._font("axis"),
                "major_label_text_font_size": self._font("tick"), "axis_line_width": 2,
                "major_tick_line_width": 2, "axis_line_color": AXIS_COLOR,
                "axis_label_text_color": AXIS_COLOR, "major_label_text_color": AXIS_COLOR}

    def _style_line(self, r: Any) -> None:
        """A glyph's line :data:`LINE_SCALE` times its own width when presenting."""
        if not isinstance(r, GlyphRenderer) or not hasattr(r.glyph, "line_width"):
            return
        width = r.glyph.line_width
        if not isinstance(width, (int, float)):
            return
        base = self._widths.setdefault(r.glyph.id, float(width))
        new = base * LINE_SCALE if self.on else base
        if width != new:
            r.glyph.line_width = new

    def _layout(self) -> None:
        """Plot panes that fill the screen: heights from the window's (CSS), the figures
        stretched to them; the usual responsive grid otherwise."""
        shown = self.shown(self.host.visible_plots())
        for name, pane in self.host.plot_panes.items():
            if name not in shown or not pane.objects:
                continue
            if self.on:
                styles = self._pane_styles(shown.index(name))
                sizing, max_width, margin = "stretch_both", None, PANE_MARGIN
            else:
                styles = {"flex": f"1 1 {PLOT_WIDTHS[0] + 160}px"}
                sizing, max_width, margin = "stretch_width", PLOT_WIDTHS[1], (4, 8)
            if pane.styles != styles:
                pane.param.update(styles=styles, sizing_mode=sizing, max_width=max_width,
                                  margin=margin)
            if name != "anim":  # the animation keeps its own sizing (never presented)
                self._stretch(name, pane, sizing, max_width)

    def _pane_styles(self, index: int) -> dict[str, str]:
        """The CSS of the ``index``-th plot shown: its share of a row and its height, the
        window's height less the strip's, split in the layout's rows."""
        rows = ROWS[self.mode]
        vertical, horizontal = PANE_MARGIN
        height = f"calc((100vh - {STRIP_PX}px) / {rows} - {2 * vertical}px)"
        # One plot, or the wide first plot of three, takes a row; the others share one.
        whole = self.mode == "1" or (self.mode == "3" and index == 0)
        basis = "100%" if whole else f"calc(50% - {2 * horizontal}px)"
        return {"flex": f"1 1 {basis}", "height": height}

    def _stretch(self, name: str, pane: Any, sizing: str, max_width: int | None) -> None:
        """Let the pane's Bokeh layout and figures follow its size."""
        plots = self.host.plots
        body = pane.objects[0]
        # The plot's pane, and its figure's pane inside the column it shares with a legend.
        for part in (body, *getattr(body, "objects", ())[:1]):
            if hasattr(part, "sizing_mode") and part.sizing_mode != sizing:
                part.sizing_mode = sizing
        layout = plots.panes.get(name)
        if layout is None:
            return
        figs = [f for key, f in plots.figures.items() if key.startswith(name)]
        if layout.sizing_mode != sizing:
            layout.sizing_mode = sizing
        for fig in figs:
            # (The layout may be the figure itself: its width cap is checked on its own.)
            if fig.sizing_mode != sizing or fig.max_width != max_width:
                fig.update(sizing_mode=sizing, max_width=max_width)
