"""The window of a long run that the time histories show, and the overview of the whole run
whose brush moves it.

A run of hundreds of periods drawn whole is a solid block (true envelopes, but a block):
the time histories then show the last :data:`WINDOW_PERIODS` periods, and a small overview
of the whole run below them holds a brush (Bokeh's ``RangeTool``) on their time axis, and
a box above it takes a number N: the window becomes the last N periods (1 to the run's
number of periods, :func:`period_count`). A short run is shown whole, without an overview.
"""

from __future__ import annotations

import math
from typing import Any

from bokeh.core.properties import validate
from bokeh.models import NumericInput, Range1d, RangeTool
from bokeh.plotting import figure

from app.deferred import later
from app.glyphs import add_glyph
from app.plots.ranges import set_range
from app.plots.style import PLOT_WIDTHS, TICK_LABEL_FONT, TITLE_FONT
from app.solve.solution import Solution
from core import SteadyKind

#: Periods the window shows of a long run: enough to see the cycle repeat, few enough
#: that each slip arc keeps some hundred pixels at the page's widths.
WINDOW_PERIODS = 5
#: A run longer than this many periods is shown through the window (a shorter one whole:
#: 20 periods of 1600 px keep 80 px per period, still readable).
LONG_RUN_PERIODS = 20
#: A slip arc turns at one radian per unit of dimensionless time (paper Eq. 7): the
#: period of a motion with no periodic steady state is taken as one turn.
TURN = 2.0 * math.pi
#: Steady states that settle: the motion stops, or shrinks on the stop. Their last periods
#: are still (scene 11's last five, 0.8 time units of a mass pressed on the stop, drew flat
#: lines), so such a run is shown whole: the transient, then the decay.
SETTLING = frozenset({SteadyKind.REST, SteadyKind.EQUILIBRIUM, SteadyKind.OSCILLATION,
                      SteadyKind.CONTACT_TRAIN})
#: Height [px] of the overview.
OVERVIEW_HEIGHT = 110
#: The brush's shade: strong, over a light line, since five periods of a run of a
#: thousand are a few pixels of the overview.
BRUSH_STYLE = {"fill_color": "#d62728", "fill_alpha": 0.35, "line_color": "#d62728",
               "line_width": 2}
#: The whole run's line under it.
OVERVIEW_LINE = {"line_color": "#9a9a9a", "line_width": 1}
#: Width [px] of the "last N periods" box.
PERIODS_BOX_WIDTH = 260


def run_period(sol: Solution) -> float:
    """The period of the run's steady state (dimensionless time), or one :data:`TURN`.

    >>> from types import SimpleNamespace as NS
    >>> run_period(NS(result=NS(steady=NS(period=5.5)))), run_period(NS(result=None))
    (5.5, 6.283185307179586)
    """
    res = sol.result
    period = res.steady.period if res is not None else math.nan
    return float(period) if math.isfinite(period) and period > 0 else TURN


def period_count(sol: Solution) -> int:
    """The whole periods of the run (:func:`run_period`), at least one.

    >>> from types import SimpleNamespace as NS
    >>> period_count(NS(result=NS(steady=NS(period=2.0)), t_end=101.0))
    50
    """
    return max(1, math.floor(sol.t_end / run_period(sol)))


def last_periods(sol: Solution, n: Any) -> tuple[float, float]:
    """The window of the last ``n`` periods of the run (dimensionless times); ``n`` must be
    a whole number from 1 to :func:`period_count`.

    >>> from types import SimpleNamespace as NS
    >>> last_periods(NS(result=NS(steady=NS(period=2.0)), t_end=100.0), 3)
    (94.0, 100.0)
    """
    count = period_count(sol)
    whole = isinstance(n, (int, float)) and not isinstance(n, bool) and float(n).is_integer()
    if not whole or not 1 <= n <= count:
        raise ValueError(f"last periods must be a whole number in [1, {count}] (the run's "
                         f"periods); got {n!r}")
    return max(0.0, sol.t_end - int(n) * run_period(sol)), sol.t_end


def periods_title(count: int) -> str:
    """The title of the "last N periods" box of a run of ``count`` periods."""
    return f"Show the last N periods (1–{count})"


def default_window(sol: Solution) -> tuple[float, float] | None:
    """The last :data:`WINDOW_PERIODS` periods of a run longer than
    :data:`LONG_RUN_PERIODS` periods (dimensionless times), else ``None`` (shown whole, as
    is a run that settles, :data:`SETTLING`).

    >>> from types import SimpleNamespace as NS
    >>> default_window(NS(result=NS(steady=NS(period=2.0, kind="periodic")), t_end=100.0))
    (90.0, 100.0)
    >>> default_window(NS(result=NS(steady=NS(period=2.0, kind="periodic")), t_end=30.0))
    >>> default_window(NS(result=NS(steady=NS(period=2.0, kind="rest")), t_end=100.0))
    """
    res = sol.result
    if res is not None and res.steady.kind in SETTLING:
        return None
    period = run_period(sol)
    if sol.t_end <= LONG_RUN_PERIODS * period:
        return None
    return sol.t_end - WINDOW_PERIODS * period, sol.t_end


def build_overview(traj: Any, window_range: Range1d) -> tuple[Any, Any]:
    """The overview figure of the whole run (x(t) of the ``traj`` source) with a brush on
    ``window_range`` (the time histories' time axis); returns ``(figure, brush)``."""
    fig = figure(title="Whole run: drag across it to choose the window above, or move the "
                 "shaded one", height=OVERVIEW_HEIGHT, width=PLOT_WIDTHS[0],
                 sizing_mode="stretch_width", min_width=PLOT_WIDTHS[0],
                 max_width=PLOT_WIDTHS[1], x_range=Range1d(0.0, 1.0),
                 y_range=Range1d(0.0, 1.0), tools="", toolbar_location=None,
                 output_backend="canvas")
    fig.title.text_font_size = TITLE_FONT
    fig.yaxis.visible = False
    fig.ygrid.visible = False
    fig.xaxis.major_label_text_font_size = TICK_LABEL_FONT
    add_glyph(fig, "line", "t", "x", source=traj, **OVERVIEW_LINE)
    brush = RangeTool(x_range=window_range, start_gesture="pan")
    brush.overlay.update(**BRUSH_STYLE)
    fig.add_tools(brush)
    return fig, brush


#: Delay [ms] after the brush (or a pan or zoom of the time axis) last moved before the
#: histories are sampled again for the new window: one resampling per gesture.
FOLLOW_DELAY_MS = 150
#: A window edge that moved less than this fraction of the run is the same window (the
#: server's own range update coming back, float32 rounding).
SAME_WINDOW = 1e-6


class RunWindow:
    """The window the time histories show of the run on screen, and the overview.

    Parameters
    ----------
    follow : callable()
        Draws the histories for a new :attr:`window` (the brush or the box moved it).
    """

    def __init__(self, follow: Any) -> None:
        self.follow = follow
        #: ``(t_lo, t_hi)`` in dimensionless time, or ``None``: the whole run.
        self.window: tuple[float, float] | None = None
        self.overview: Any = None
        self.brush: Any = None
        #: The box that takes N, the window's last N periods (built with the overview).
        self.periods_box: Any = None
        #: The N of the window's last N periods, or ``None`` (brushed, or shown whole).
        self.periods: int | None = None
        self._sol: Solution | None = None
        self._syncing = False
        #: Whether the overview is kept hidden (a projector's layouts have no room for it).
        self.hidden = False
        self._time_range: Range1d | None = None
        self._t_end: float | None = None
        self._unit = 1.0
        self._brushed = False
        self._pending: Any = None
        self._placing = False

    def choose(self, sol: Solution) -> None:
        """The window for a new solution: if the horizon is the same, the one brushed or
        the last N periods typed (of the new run); else :func:`default_window`."""
        same = sol.t_end == self._t_end
        if default_window(sol) is None:
            self.window, self._brushed, self.periods = None, False, None
        elif not (self._brushed and self.window is not None and same):
            n = self.periods if same and self.periods is not None else WINDOW_PERIODS
            n = min(n, period_count(sol))
            self.window, self._brushed, self.periods = last_periods(sol, n), False, n
        self._t_end, self._sol = sol.t_end, sol
        self._show_periods()

    def show_last(self, n: Any) -> None:
        """Show the last ``n`` periods of the run on screen (a whole number from 1 to its
        :func:`period_count`: else a ``ValueError`` says so, the window unchanged)."""
        if self._sol is None or self.window is None:
            raise ValueError("last periods: the run on screen is shown whole (no window)")
        self.window = last_periods(self._sol, n)
        self.periods, self._brushed = int(n), False
        self._show_periods()
        if self._time_range is not None:
            self.place(self._time_range, self.shown(self._unit))
        self.follow()

    def _typed(self, attr: str, old: Any, new: Any) -> None:
        """A number typed in the box: its last periods, or the box says why not."""
        if self._syncing or new is None:
            return
        try:
            self.show_last(new)
        except ValueError:
            # Short, to fit the box's width (the API's message names the parameter).
            count = period_count(self._sol) if self._sol is not None else 0
            self._show_periods(f"N must be from 1 to {count}; got {new!r}")

    def _show_periods(self, refusal: str = "") -> None:
        """The box: the run's number of periods, the window's N (empty once brushed), and
        its title, or what was refused in its place."""
        box, sol = self.periods_box, self._sol
        if box is None or sol is None:
            return
        count = period_count(sol)
        values = {"value": self.periods, "title": refusal or periods_title(count)}
        changed = {k: v for k, v in values.items() if getattr(box, k) != v}
        if changed:
            self._syncing = True
            try:
                box.update(**changed)
            finally:
                self._syncing = False

    def shown(self, unit: float) -> tuple[float, float] | None:
        """The window in shown time units (``unit`` per dimensionless unit)."""
        self._unit = unit
        return None if self.window is None else (self.window[0] * unit, self.window[1] * unit)

    def hide_overview(self, hidden: bool) -> None:
        """Keep the overview hidden (``hidden``) or show it again where the run has a
        window."""
        self.hidden = hidden
        self._set_visible(not hidden and self.window is not None)

    def _set_visible(self, shown: bool) -> None:
        for model in (self.overview, self.periods_box):
            if model is not None and model.visible != shown:
                model.visible = shown

    def show_overview(self, layout: Any, time_range: Range1d, traj: Any,
                      t_span: tuple[float, float], x_span: tuple[float, float]) -> None:
        """Show the overview below the time histories' ``layout`` (built the first time a
        long run is shown) over ``t_span`` and ``x_span``; hide it for a short run, and
        while :attr:`hidden`."""
        if self.window is None or self.hidden:
            self._set_visible(False)
            return
        if self.overview is None:
            # Built with Bokeh's checks on, also under a caller's ``validate(False)``: they
            # turn values such as a title's text into models.
            with validate(True):
                self.overview, self.brush = build_overview(traj, time_range)
                # No ``low`` or ``high``: BokehJS would clamp a number out of range to the
                # bound without a word, and where the bound was N already the box kept
                # showing the number typed (-2) beside the last N periods drawn. The
                # server refuses it instead, in the box's title, and puts N back.
                self.periods_box = NumericInput(
                    mode="int", placeholder="N", width=PERIODS_BOX_WIDTH,
                    margin=(4, 10, 0, 10), css_classes=["fie-last-periods"])
            self._show_periods()
            self.periods_box.on_change("value", self._typed)
            layout.children.extend([self.periods_box, self.overview])
            self._time_range = time_range
            time_range.on_change("start", self._moved)
            time_range.on_change("end", self._moved)
        self._set_visible(True)
        fig = self.overview
        for rng, (lo, hi) in ((fig.x_range, t_span), (fig.y_range, x_span)):
            if (rng.start, rng.end) != (lo, hi):
                rng.update(start=lo, end=hi)

    def place(self, rng: Range1d, shown: tuple[float, float]) -> None:
        """Set the time histories' range ``rng`` to the window ``shown`` (shown units):
        the server's own move, which the brush's handler does not follow (Bokeh calls it
        once per edge, between which the range holds one old and one new edge)."""
        self._placing = True
        try:
            set_range(rng, (shown,), 0.0)
        finally:
            self._placing = False

    def _moved(self, attr: str, old: Any, new: Any) -> None:
        """The time axis moved (the brush, a pan or zoom): follow it once it rests (both
        edges are read then, as the browser left them)."""
        if self._placing or self.window is None:
            return
        if self._pending is not None:
            self._pending.cancel()
        self._pending = later(self._follow, FOLLOW_DELAY_MS)

    def _follow(self) -> None:
        self._pending = None
        rng = self._time_range
        if self.window is None or self._t_end is None or rng.start is None or rng.end is None:
            return
        lo, hi = sorted((float(rng.start) / self._unit, float(rng.end) / self._unit))
        lo, hi = max(lo, 0.0), min(hi, self._t_end)
        tol = SAME_WINDOW * self._t_end
        if hi <= lo or (abs(lo - self.window[0]) <= tol and abs(hi - self.window[1]) <= tol):
            return
        self.window, self._brushed, self.periods = (lo, hi), True, None
        self._show_periods()
        self.follow()
