"""The mechanism drawn and animated in the browser: belt, spring, mass, stop.

The animation runs entirely client-side: a ``requestAnimationFrame`` loop in BokehJS reads
the trajectory source (``t`` in the shown units, ``x``, ``v``, ``mode``) that the phase
portrait already received, interpolates the state at the animation time and moves the mass,
the spring, the belt's marks, a marker in the phase portrait and a cursor in the time
histories. The sources and annotations it writes are ``syncable=False``, so a playing
animation sends nothing to the server; only Play/Pause and the speed slider are widgets.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, Grid, Label, Range1d, Span
from bokeh.plotting import figure

from app.glyphs import add_glyph
from app.plots import MODE_COLORS, SharedModels
from app.solve.solution import Solution
from app.state import DIMENSIONLESS, Scales

#: Size of the mechanism figure [px].
ANIM_SIZE = (560, 230)
#: Coils of the drawn spring.
SPRING_COILS = 9
#: Marks on the belt (they move at the belt speed).
BELT_MARKS = 24
#: Mass block width as a fraction of the motion's extent.
MASS_WIDTH = 0.3
#: Dimensionless time played per second of real time at speed 1 (half a slip circle).
TIME_PER_SECOND = np.pi
#: Vertical layout of the drawing (arbitrary units): belt, mass and spring heights.
BELT_BOTTOM, BELT_TOP = -0.3, 0.0
MASS_BOTTOM, MASS_TOP = 0.02, 0.62
SPRING_Y, SPRING_AMPLITUDE = 0.32, 0.12
STOP_TOP = 0.85

#: The drawing of the mechanism at the animation time ``st.t``, in the time histories' units
#: (``tscale`` per dimensionless time unit; shared by the frame loop,
#: the time slider and the step buttons). ``state`` lives on ``window`` so that all the
#: callbacks share it.
_JS_DRAW = """
const key = mass.id;
const all = (window.__fie_anim = window.__fie_anim || {});
const st = (all[key] = all[key] || {t: 0.0, running: false, last: null});
function interp(T, Y, t, lo, hi) {
  const dt = T[hi] - T[lo];
  return dt > 0 ? Y[lo] + (Y[hi] - Y[lo]) * (t - T[lo]) / dt : Y[lo];
}
function draw() {
  const d = traj.data, T = d.t, X = d.x, V = d.v, M = d.mode;
  const n = T.length;
  if (n < 2) { return; }
  if (st.t > T[n - 1] || st.t < T[0]) { st.t = T[0]; }
  let lo = 0, hi = n - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= st.t) lo = mid; else hi = mid; }
  const x = interp(T, X, st.t, lo, hi), v = interp(T, V, st.t, lo, hi);
  const g = geom.data, w = g.w[0], wall = g.wall[0];
  const m = mass.data;
  m.left[0] = x - w / 2; m.right[0] = x + w / 2; m.color[0] = colors[M[lo]] || colors[0];
  mass.change.emit();
  const sp = spring.data, k = sp.x.length;
  for (let i = 0; i < k; i++) { sp.x[i] = wall + (x - w / 2 - wall) * i / (k - 1); }
  spring.change.emit();
  const b = belt.data, gap = g.gap[0], shift = ((g.v[0] * st.t / g.tscale[0]) % gap + gap) % gap;
  for (let i = 0; i < b.x0.length; i++) { b.x0[i] = b.x1[i] = g.belt0[0] + i * gap + shift; }
  belt.change.emit();
  marker.data.x[0] = x; marker.data.v[0] = v; marker.change.emit();
  cursor.location = st.t;
  clock.text = "t = " + st.t.toFixed(2) + " of " + T[n - 1].toPrecision(4) + g.tunit[0];
}
"""
#: The frame loop (one per mass source; Play toggles it).
_JS_PLAY = _JS_DRAW + """
function frame(now) {
  if (!st.running) { return; }
  if (st.last !== null) {
    st.t += (now - st.last) / 1000 * rate * speed.value * geom.data.tscale[0];
  }
  draw();
  st.last = now;
  window.requestAnimationFrame(frame);
}
st.running = play.active;
st.last = null;
if (st.running) { window.requestAnimationFrame(frame); }
"""
#: The time slider: pause and show the fraction ``scrub.value`` of the run.
_JS_SCRUB = _JS_DRAW + """
st.running = false; play.active = false;
const T = traj.data.t;
if (T.length > 1) { st.t = T[0] + scrub.value * (T[T.length - 1] - T[0]); draw(); }
"""
#: A step button: pause and move by ``dir`` steps of the run's length over ``steps``.
_JS_STEP = _JS_DRAW + """
st.running = false; play.active = false;
const T = traj.data.t, n = T.length;
if (n > 1) {
  const t = st.t + dir * (T[n - 1] - T[0]) / steps;
  st.t = Math.min(Math.max(t, T[0]), T[n - 1]);
  draw();
}
"""
#: Steps of the step buttons over the whole run.
STEPS = 200


class Animation:
    """The mechanism figure, its Play/Pause toggle and speed slider.

    A new page makes only what the first row of plots carries (the marker of the phase
    portrait, the cursor of the time histories); the figure, its sources and its controls
    are made with the mechanism's pane (:meth:`panel`), which a lazy page builds when the
    browser reports it in view.

    Parameters
    ----------
    traj : ColumnDataSource
        The trajectory source of :class:`app.plots.PlotSet` (columns ``t``, ``x``,
        ``v``, ``mode``).
    """

    def __init__(self, traj: ColumnDataSource, shared: SharedModels | None = None) -> None:
        self._traj = traj
        self._shared = shared if shared is not None else SharedModels()
        #: Current state marker for the phase portrait (added by :meth:`attach_phase`).
        self.marker = self._shared.source({"x": [0.0], "v": [0.0]}, syncable=False)
        self.cursor = Span(location=0.0, dimension="height", line_color="#555555",
                           line_dash="dashed", syncable=False)
        #: The mechanism's figure, once built (:meth:`panel`).
        self.figure: Any = None

    def _build(self) -> None:
        """Make the figure, its sources and controls (once)."""
        if self.figure is not None:
            return
        shared = self._shared
        fig = figure(
            width=ANIM_SIZE[0], height=ANIM_SIZE[1], tools="save", toolbar_location="right",
            x_range=Range1d(-1, 1), y_range=Range1d(BELT_BOTTOM - 0.05, 1.0),
            title="Mechanism: belt, spring, mass, stop",
        )
        fig.toolbar.logo = None
        fig.title.text_font_size = "13px"
        # No y axis and no grid (a drawing, not a graph): not built rather than hidden.
        fig.left = []
        fig.center = [r for r in fig.center if not isinstance(r, Grid)]
        fig.xaxis.axis_label = "x"
        source = shared.source
        self.geom = source(_geometry(0.0, 1.0, 0.5, False, 0.0, DIMENSIONLESS))
        self.static = source({"left": [], "right": [], "bottom": [], "top": [], "color": []})
        self.mass = source({"left": [-0.1], "right": [0.1], "bottom": [MASS_BOTTOM],
                            "top": [MASS_TOP], "color": [MODE_COLORS[0]]}, syncable=False)
        self.spring = source(_spring(-1.0, -0.1), syncable=False)
        self.belt = source({"x0": [], "x1": []}, syncable=False)
        add_glyph(fig, "quad", left="left", right="right", bottom="bottom", top="top",
                  color="color", source=self.static)
        add_glyph(fig, "segment", x0="x0", x1="x1", y0=BELT_BOTTOM + 0.04, y1=BELT_TOP - 0.04,
                  source=self.belt, line_color="#ffffff", line_width=2)
        add_glyph(fig, "line", "x", "y", source=self.spring, line_color="#333333", line_width=2)
        add_glyph(fig, "quad", left="left", right="right", bottom="bottom", top="top",
                  fill_color="color", line_color="#000000", source=self.mass)
        # In the frame, over the stop's top: x in pixels from the frame's left edge (past the
        # wall), y in the drawing's units.
        self.clock = Label(x=24, y=0.98, x_units="screen", y_units="data", text="t = 0",
                           text_baseline="top", text_font_size="13px",
                           background_fill_color="#ffffff", background_fill_alpha=0.85,
                           syncable=False)
        fig.add_layout(self.clock)
        shared.lighten(fig)
        self.play = pn.widgets.Toggle(label="Play / pause", color="primary", width=120)
        self.speed = pn.widgets.FloatSlider(label="speed", start=0.1, end=5.0, step=0.1,
                                            value=1.0, width=160)
        self.scrub = pn.widgets.FloatSlider(label="time (drag to scrub)", start=0.0, end=1.0,
                                            step=0.01,
                                            value=0.0, show_value=False, width=300,
                                            css_classes=["fie-anim-scrub"])
        self.back = pn.widgets.Button(label="◀ step", width=70, css_classes=["fie-anim-back"])
        self.forward = pn.widgets.Button(label="step ▶", width=70,
                                         css_classes=["fie-anim-forward"])
        colors = [MODE_COLORS[m] for m in sorted(MODE_COLORS)]
        args = {"traj": self._traj, "geom": self.geom, "mass": self.mass,
                "spring": self.spring, "belt": self.belt, "marker": self.marker,
                "cursor": self.cursor, "clock": self.clock, "speed": self.speed,
                "play": self.play, "scrub": self.scrub, "colors": colors,
                "rate": float(TIME_PER_SECOND), "steps": STEPS}
        self.play.jscallback(value=_JS_PLAY, args=args)
        self.scrub.jscallback(value=_JS_SCRUB, args=args)
        self.back.jscallback(clicks=_JS_STEP, args={**args, "dir": -1})
        self.forward.jscallback(clicks=_JS_STEP, args={**args, "dir": 1})
        self.figure = fig

    def attach_phase(self, phase_fig: Any) -> None:
        """Show the animated state in the phase portrait."""
        add_glyph(phase_fig, "scatter", "x", "v", source=self.marker, size=11, marker="circle",
                          fill_color="#ffd400", line_color="#000000", line_width=1.5)

    def attach_time(self, time_figs: tuple[Any, ...]) -> None:
        """Show the animation time as a cursor in the time histories."""
        for fig in time_figs:
            fig.add_layout(self.cursor)

    def panel(self) -> pn.Column:
        """The figure with its controls (made on the first call)."""
        self._build()
        # The controls wrap on a narrow page (in one row the speed slider was cut at 800 px).
        return pn.Column(self.figure, pn.Row(self.play, self.back, self.forward, self.speed,
                                             styles={"flex-wrap": "wrap"}),
                         self.scrub, margin=0)

    def update(self, sol: Solution, scales: Scales) -> None:
        """Redraw the mechanism at the start of the new motion (call under ``pn.io.hold``)."""
        self._build()
        res = sol.result
        # Drawn in the page's units, those of the trajectory source the frames read.
        length = scales.length
        x = (np.asarray(res.x) if res is not None and len(res.x) else np.array([sol.x0])) * length
        clearance = sol.stop.clearance * length if sol.stop is not None else None
        lo = float(min(x.min(), sol.x0 * length))
        hi = float(max(x.max(), clearance if clearance is not None else x.max()))
        extent = max(hi - lo, 1e-6)
        g = _geometry(lo, extent, clearance if clearance is not None else hi,
                      clearance is not None, sol.osc.v * length, scales)
        self.geom.data = g
        w, wall = g["w"][0], g["wall"][0]
        self.figure.x_range.update(start=wall - 0.05 * extent,
                                   end=hi + w / 2 + 0.3 * extent)
        self.figure.xaxis.axis_label = scales.length_label
        quads = {"left": [wall - 0.06 * extent, g["belt0"][0] - g["gap"][0]],
                 "right": [wall, g["belt0"][0] + (BELT_MARKS + 1) * g["gap"][0]],
                 "bottom": [0.0, BELT_BOTTOM], "top": [0.9, BELT_TOP],
                 "color": ["#555555", "#8c8c8c"]}
        if clearance is not None:
            for key, val in (("left", clearance + w / 2), ("right", clearance + w / 2 +
                             0.08 * extent), ("bottom", 0.0), ("top", STOP_TOP),
                             ("color", "#222222")):
                quads[key].append(val)
        self.static.data = quads
        x_start = float(x[0])
        self.mass.data = {"left": [x_start - w / 2], "right": [x_start + w / 2],
                          "bottom": [MASS_BOTTOM], "top": [MASS_TOP],
                          "color": [MODE_COLORS[int(res.mode[0]) if res is not None and
                                                len(res.mode) else 0]]}
        self.spring.data = _spring(wall, x_start - w / 2)
        marks = g["belt0"][0] + g["gap"][0] * np.arange(BELT_MARKS)
        self.belt.data = {"x0": marks.tolist(), "x1": marks.tolist()}
        v_start = float(res.v[0]) * scales.velocity if res is not None and len(res.v) else 0.0
        self.marker.data = {"x": [x_start], "v": [v_start]}


def _geometry(lo: float, extent: float, stop_at: float, has_stop: bool, belt_speed: float,
              scales: Scales) -> dict[str, list]:
    """Fixed dimensions of the drawing for a motion over ``[lo, lo + extent]``."""
    w = MASS_WIDTH * extent
    wall = lo - w / 2 - 0.9 * extent
    gap = (stop_at + w / 2 + 0.4 * extent - wall) / BELT_MARKS
    return {"w": [w], "wall": [wall], "gap": [gap], "belt0": [wall - gap],
            "v": [belt_speed], "has_stop": [has_stop], "tscale": [scales.time],
            "tunit": [" s" if scales.si else ""]}


def _spring(wall: float, end: float) -> dict[str, list]:
    """Zigzag from the wall to the mass: ``2 * SPRING_COILS + 2`` vertices."""
    n = 2 * SPRING_COILS + 2
    xs = np.linspace(wall, end, n)
    ys = np.full(n, SPRING_Y)
    ys[1:-1] += SPRING_AMPLITUDE * np.where(np.arange(1, n - 1) % 2 == 0, 1.0, -1.0)
    return {"x": xs.tolist(), "y": ys.tolist()}
