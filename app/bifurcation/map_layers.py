"""The regime map's simulated layers: computed on demand, drawn over the map, said in words.

Two check boxes ask for the simulated steady states and for the cells where simulation and
theory disagree; the map is simulated once per scene and frame (:mod:`app.bifurcation.sim_map`)
in chunks of belt speeds (:class:`app.bifurcation.chunks.ChunkedSweep`), and drawn as two
RGBA images between the theory's image and the current point's marker.
"""

from __future__ import annotations

import html
import threading
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource

from app import sweep_budget as budget
from app.bifurcation.chunks import CHUNK_SECONDS, ChunkedSweep
from app.bifurcation.sim_map import (
    SIM_MAP_CELLS,
    SimMap,
    compare_map,
    map_cells,
    rgba,
    simulate_map_rows,
)
from app.bifurcation.spec import closed_form, sweep_cost
from app.bifurcation.style import LABEL_COLORS
from app.state import DIMENSIONLESS, Scales


class MapLayers:
    """The simulated layers of one session's regime map and their check boxes.

    Parameters
    ----------
    values : callable() -> Mapping
        The explorer's current solve values.
    map_figure : callable() -> figure or None
        The explorer's regime map figure, built if need be (``None`` if it cannot show).
    map_frame : callable() -> (v_hi, x_lo, x_hi)
        The regime map's axes.
    shared : app.plots.SharedModels, optional
        The page's shared models.
    on_layers : callable(), optional
        Called when the layers appear or go (the map's legend says which colours are on
        top).
    """

    def __init__(self, values: Callable[[], Mapping[str, Any]], map_figure: Callable[[], Any],
                 map_frame: Callable[[], tuple], shared: Any = None,
                 on_layers: Callable[[], None] | None = None) -> None:
        self._values, self._map_figure, self._map_frame = values, map_figure, map_frame
        self._shared, self._on_layers = shared, on_layers
        self.scales: Scales = DIMENSIONLESS
        self.sim_layer = pn.widgets.Checkbox(
            label="regime map: from simulation", value=False, css_classes=["fie-bif-sim"])
        self.disagree_layer = pn.widgets.Checkbox(
            label="regime map: where simulation and theory disagree", value=False,
            css_classes=["fie-bif-disagree"])
        self.status = pn.pane.HTML("", sizing_mode="stretch_width",
                                   css_classes=["fie-bif-map-status"])
        self.sim_layer.param.watch(lambda e: self.changed(), "value")
        self.disagree_layer.param.watch(lambda e: self.changed(), "value")
        self.job = ChunkedSweep(self._work, self._on_chunk, self._failed, self._cut)
        self._rows: list[np.ndarray] = []
        self._key: tuple | None = None
        self._spec: tuple | None = None
        #: The last simulated map (``None`` until one is complete).
        self.sim_map: SimMap | None = None
        #: The sources of the two layers' images, by name ("sim", "disagree"), once drawn.
        self.sources: dict[str, ColumnDataSource] = {}
        #: The two layers' renderers (simulated labels, disagreement), once drawn.
        self.renderers: tuple[Any, Any] | None = None
        self._fig: Any = None
        self._title_text: str | None = None

    @property
    def wanted(self) -> bool:
        """Whether a layer is asked for."""
        return bool(self.sim_layer.value or self.disagree_layer.value)

    @property
    def sim_layer_shown(self) -> bool:
        """Whether the simulated steady states cover the regime map now."""
        return bool(self.renderers is not None and self.renderers[0].visible)

    def close(self) -> None:
        """Stop a running simulation (a chunk in a solver process is stopped)."""
        self.job.cancel()

    def changed(self) -> None:
        """Draw (computing if need be) or hide the simulated layers of the regime map."""
        if not self.wanted:
            self._hide()
            return
        values = self._values()
        frame = tuple(self._map_frame())
        # The point's own belt speed and clearance are the map's axes: moving it changes
        # nothing of the map.
        key = (tuple(sorted((k, v) for k, v in values.items()
                            if k not in ("belt_speed", "clearance"))), frame)
        if key == self._key and self.sim_map is not None:
            self.show()
            return
        if key == self._key and self.job.running:
            return
        self._key, self.sim_map, self._rows = key, None, []
        self._simulate(values, frame)

    def _hide(self) -> None:
        self.job.cancel()
        if self.renderers is not None:
            for r in self.renderers:
                r.visible = False
            self._set_title(None)
        self.status.object = ""

    def _simulate(self, values: Mapping[str, Any], frame: tuple) -> None:
        kind = "closed" if closed_form(values) else "integrated"
        cells = SIM_MAP_CELLS[kind]
        try:
            budget.check_cost(cells * cells, **sweep_cost(values))
        except ValueError as exc:
            self.job.cancel()
            self.status.object = (
                "<div class='fie-bif-error'>The regime map is not simulated: its "
                f"{cells} x {cells} cells exceed the sweep's budget ({html.escape(str(exc))})"
                "</div>")
            return
        speeds, clearances = map_cells(frame, cells)
        self._spec = (values, frame, clearances)
        self.status.object = self._note(values, cells, 0)
        self.job.start(self._spec, speeds, cells if kind == "closed" else 1, values,
                       CHUNK_SECONDS[kind], budget.SWEEP_BUDGET_S)

    @staticmethod
    def _work(spec, speeds: np.ndarray, cancelled: threading.Event) -> np.ndarray:
        values, _, clearances = spec
        return simulate_map_rows(values, speeds, clearances, cancelled)

    def _on_chunk(self, done: int, total: int, rows: np.ndarray) -> None:
        self._rows.append(rows)
        values, frame, _ = self._spec
        self.status.object = self._note(values, total, done)
        if done < total:
            return
        self.sim_map = compare_map(values, frame, np.concatenate(self._rows, axis=0))
        self.show()

    def _cut(self, done: int, total: int) -> None:
        self.status.object = (
            f"<div class='fie-bif-error'>The simulated map stopped at the sweep's budget of "
            f"{budget.SWEEP_BUDGET_S:g} s after {done} of {total} belt speeds: not drawn. A "
            "shorter horizon t_end finishes within it.</div>")

    def _failed(self, exc: Exception) -> None:
        self.status.object = (f"<div class='fie-bif-error'>The simulated map failed: "
                              f"{html.escape(type(exc).__name__)}: "
                              f"{html.escape(str(exc))}</div>")

    @staticmethod
    def _note(values, cells: int, done: int) -> str:
        deformable = values["stop_type"] == "hysteretic"
        note = (" A deformable stop has no closed form: core.sweep simulates it point by "
                f"point, so this map is a coarse {cells} x {cells} grid, compared with the "
                "theory of its equivalent rigid stop (r_eq = sqrt(k_e0/k_c0), Eq. 16)."
                if deformable else "")
        cost = budget.budget_note(budget.estimate_s(cells * cells, **sweep_cost(values)),
                                  partial=False)
        return (f"<div class='fie-bif-running'>Simulating the regime map: {done} of {cells} "
                f"belt speeds ({cost}).{html.escape(note)}</div>")

    def show(self) -> None:
        """Draw the last simulated map's layers that are asked for (in the page's units)."""
        sim = self.sim_map
        fig = self._map_figure()
        if fig is None or sim is None:
            return
        v_hi, x_lo, x_hi = sim.frame
        sim_img, dis_img = rgba(sim)
        # On the map's axes: its belt speeds in the page's units (app.plots).
        length = self.scales.length
        geometry = {"x": [0.0], "y": [x_lo * length], "dw": [v_hi * self.scales.velocity],
                    "dh": [(x_hi - x_lo) * length]}
        with pn.io.hold():
            if self.renderers is None:
                self._add_renderers(fig, sim_img, dis_img, geometry)
            else:
                self.sources["sim"].data = {"image": [sim_img], **geometry}
                self.sources["disagree"].data = {"image": [dis_img], **geometry}
            self.renderers[0].visible = self.sim_layer.value
            self.renderers[1].visible = self.disagree_layer.value
            self._set_title(fig)
            self.status.object = self._summary(sim)

    def _add_renderers(self, fig: Any, sim_img, dis_img, geometry: Mapping[str, list]) -> None:
        self.sources = {"sim": ColumnDataSource({"image": [sim_img], **geometry}),
                        "disagree": ColumnDataSource({"image": [dis_img], **geometry})}
        sim_r, dis_r = (fig.image_rgba(image="image", x="x", y="y", dw="dw", dh="dh",
                                       source=self.sources[name])
                        for name in ("sim", "disagree"))
        # Over the theory's image, under the current point's marker.
        base = [r for r in fig.renderers if r is not sim_r and r is not dis_r]
        fig.renderers = [base[0], sim_r, dis_r, *base[1:]]
        self.renderers, self._fig = (sim_r, dis_r), fig
        if self._shared is not None:
            self._shared.lighten(fig)
            for src in self.sources.values():
                src.selection_policy = self._shared.policy

    def _set_title(self, fig: Any) -> None:
        """Say on the map which layers it shows (its legend below names the theory's)."""
        fig = fig if fig is not None else self._fig
        if fig is None:
            return
        if self._title_text is None:
            self._title_text = fig.title.text
        shown = [name for name, on in (("steady states", self.sim_layer.value),
                                       ("disagreement in red", self.disagree_layer.value))
                 if on]
        fig.title.text = self._title_text + (
            f"; simulated: {', '.join(shown)}" if shown else "")
        if self._on_layers is not None:
            self._on_layers()

    def _summary(self, sim: SimMap) -> str:
        n = sim.labels.size
        bad = int(sim.disagree.sum())
        found = sorted(set(sim.labels.ravel().tolist()))
        swatches = "".join(
            f"<span style='margin-right:10px;white-space:nowrap'><i style='display:inline-"
            f"block;width:11px;height:11px;background:{LABEL_COLORS.get(k, '#000')};"
            f"margin-right:3px'></i>{html.escape(k)}</span>" for k in found)
        unsettled = int(np.sum(sim.labels == "none"))
        where = (f"Simulation and theory disagree in {bad} of {n} cells (red)."
                 if bad else "Simulation and theory agree in every cell that settled.")
        if unsettled:
            unit = " s" if self.scales.si else ""
            where += (f" {unsettled} cells had not settled by t = "
                      f"{sim.t_end * self.scales.time:.4g}{unit} (grey, not compared).")
        lesson = ""
        if sim.deformable:
            lesson = " The theory is that of the equivalent rigid stop (Eq. 16)" + (
                ": where they differ, the stop's compliance and hysteresis change the "
                "motion." if bad else ".")
        return (f"<div class='fie-bif-done'>Simulated steady states: {swatches}<br>"
                f"{where}{html.escape(lesson)}</div>")
