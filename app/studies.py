"""The studies of the run on screen, on demand: the measured speed/accuracy trade of every
method and preset (:mod:`app.solve.trade`), and the sweep card with its bifurcation diagram
(:mod:`app.bifurcation`). Each joins the page above the plots when first used: a new page
holds none of their models.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import panel as pn
import param

from app.control_specs import WIDGET_WIDTH
from app.solve.process import Abandoned
from app.solve.trade import MEASURE_BUDGET_S, MeasureRefused, TradeRunner, trade_html
from app.state import ExplorerState
from app.widgets import on_click, set_changed

#: The label of the button that measures the speed/accuracy trade (app.solve.trade).
MEASURE_LABEL = "Measure the trade (a few seconds)"
#: The house stylesheet (panes render in shadow DOMs: each that uses its classes links it).
STYLESHEET = "assets/explorer.css"


class Studies(pn.viewable.Viewer):
    """The trade measurement and the sweeps of one page.

    Parameters
    ----------
    host : app.plots_host.PlotsHost
        The page's plots (the map the sweeps draw on, the room above the plots).
    commit : callable(dict)
        Commits a value picked on the diagram.
    notices : app.notices.Notices
        Where a refused or failed measurement is said.
    """

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, host: Any, commit: Any, notices: Any, **params: Any) -> None:
        super().__init__(**params)
        self.host, self.commit, self.notices = host, commit, notices
        self.measure = pn.widgets.Button(
            label=MEASURE_LABEL, width=WIDGET_WIDTH, css_classes=["fie-measure"],
            description="Solve this run again with every method and preset: wall time now, "
                        "error against a reference solution, steady state found (at most "
                        f"{MEASURE_BUDGET_S:g} s).")
        on_click(self.measure, lambda event: self.measure_trade())
        self.open_sweeps = pn.widgets.Button(
            label="Bifurcation diagram (sweep)", width=WIDGET_WIDTH,
            css_classes=["fie-open-sweeps"])
        on_click(self.open_sweeps, lambda event: self.sweep())
        #: The measurement of the trade, in the solver processes (one at a time).
        self.trade_runner = TradeRunner(self._measured, self._measure_failed)
        self._refusal: str | None = None
        self.trade = pn.pane.HTML("", visible=False, sizing_mode="stretch_width",
                                  css_classes=["fie-trade-pane"], stylesheets=[STYLESHEET],
                                  styles={"flex": "1 1 100%"})
        #: The solve values the trade table describes.
        self._trade_values: Mapping[str, Any] | None = None
        #: The sweep card (app.bifurcation), built when first opened.
        self.sweeps: Any = None
        # After the plots' draw (one message all the same: the page waits for its figures).
        self.state.param.watch(self._solution_shown, "solution", precedence=1)
        self.state.param.watch(self._presented, "present")

    def __panel__(self) -> pn.viewable.Viewable:
        return pn.Column(self.measure, self.open_sweeps, margin=0)

    # --- sweeps ----------------------------------------------------------------------------

    def sweep(self) -> None:
        """Build the sweep card on first use, put it above the plots and sweep the current
        scene; open it again later."""
        if self.sweeps is not None:
            self.sweeps.layout.collapsed = False
            return
        from app.bifurcation import BifurcationView

        host = self.host
        self.sweeps = BifurcationView(
            values=self.state.values, on_pick=lambda name, v: self.commit({name: v}),
            map_figure=host.map_figure, map_frame=lambda: host.map_frame(self.state.solution),
            shared=host.plots.shared, scales=self.state.scales(),
            on_layers=lambda: host.show_map_legend(covered=self.sweeps.sim_layer_shown))
        host.above_plots(self.sweeps.layout)
        self.sweeps.start()

    # --- the trade -------------------------------------------------------------------------

    def measure_trade(self) -> None:
        """Measure the speed/accuracy trade of the run on screen, in the solver processes
        (:class:`app.solve.trade.TradeRunner`); a click while one runs is refused."""
        values = dict(self.state.values())
        if values.get("program"):
            return
        try:
            self.trade_runner.start(values)
        except MeasureRefused as exc:
            self.notices.show(str(exc), lead="Not measured:", tail="")
            self._refusal = self.notices.error
            return
        self.measure.disabled = True
        self.measure.label = f"Measuring… (at most {MEASURE_BUDGET_S:g} s)"

    def _measure_ended(self) -> None:
        self.measure.disabled = False
        self.measure.label = MEASURE_LABEL
        if self._refusal is not None:
            self.notices.hide(self._refusal)  # "already running": no longer so

    def _measured(self, values: Mapping[str, Any], rows: list) -> None:
        self._measure_ended()
        if values != dict(self.state.values()):
            return  # the run changed meanwhile
        self._trade_values = values
        self.trade.object = (
            "<div class='fie-title'>Speed and accuracy, measured for this run</div>"
            + trade_html(rows))
        self.trade.visible = True
        self.host.above_plots(self.trade)

    def _measure_failed(self, exc: Exception) -> None:
        self._measure_ended()
        if not isinstance(exc, Abandoned):  # cancelled: the run changed or the page closed
            self.notices.show(f"{type(exc).__name__}: {exc}", lead="The measurement failed:",
                              tail="")

    # --- following the run on screen -------------------------------------------------------

    def _solution_shown(self, event: param.parameterized.Event) -> None:
        """A run on screen: the trade table of another run goes, and a measurement of
        another run stops; the sweep card follows the run (a new one only)."""
        sol = event.new
        if sol is None:
            return
        if self.trade.visible and self._trade_values != sol.values:
            set_changed(self.trade, visible=False)
        if self.trade_runner.running and self.trade_runner.values != dict(sol.values):
            self.trade_runner.cancel()
        if self.sweeps is not None:
            self.sweeps.set_scales(self.state.scales())
            if event.old is not sol:
                self.sweeps.on_solution(sol.values)

    def _presented(self, event: param.parameterized.Event) -> None:
        if event.new and self.trade.visible:
            self.trade.visible = False  # the plots take the room

    def close(self) -> None:
        """The page closed: stop its measurement and sweeps."""
        self.trade_runner.cancel()
        if self.sweeps is not None:
            self.sweeps.close()
