/* Faster repaints of the explorer's Bokeh figures (served as /assets/perf/bokeh_paint.js).
 *
 * BokehJS 3.9 rewrites each renderer's positioning <style> on every paint, even when the
 * text is unchanged, and reads every line/fill/text property through getComputedStyle to
 * honour `--bk-*` CSS variables (bokeh/bokeh#15286). Each rewrite invalidates the page's
 * styles and each read then forces a full style recalculation, so on a page with many
 * widgets one figure takes ~100 ms to repaint in Chromium without a GPU. The explorer
 * defines no `--bk-*` variables, so:
 *
 *   1. a stylesheet write that would not change the text is skipped;
 *   2. the CSS-variable lookup of visual properties answers "" (what getPropertyValue
 *      returns for an unset variable) without consulting the cascade;
 *   3. a plot's base font size (the :host font-size, fixed by Bokeh's own CSS) is read
 *      once per plot view instead of once per axis and label per paint;
 *   4. a glyph renderer's positioning <style> (its data's bounding box on the page, which
 *      changes with every new data or range) is written once, at the renderer's first
 *      paint, instead of at every paint. Each rewrite invalidates the page's styles: in the
 *      middle of a figure's paint the next text it draws (a tick label: Chromium resolves
 *      a canvas font against the element's style) forced a full style recalculation, ~8 ms
 *      per glyph renderer, and deferred to the next frame the rewrites still cost one
 *      recalculation of 9-18 ms there. The element is an empty box below the canvas: the
 *      glyphs themselves are drawn on the canvas, and the explorer attaches nothing to
 *      the element, so where it sits changes nothing on screen;
 *   5. a glyph renderer takes in new data once per change of its source, not once per
 *      signal that announces it. Assigning a source's data makes BokehJS recompute the
 *      renderer's glyph data (screen-independent arrays, spatial index, visuals of six
 *      glyph variants) on the source's `change`, again when the row count changed (the
 *      view's `indices`), and again for any other property of the source (the explorer
 *      then marked each full solution in the trajectory source's `tags`): 43 recomputations for
 *      22 renderers on one release of scene 5b. The recomputation now starts in a promise
 *      callback, after the message has been applied, and every request made until then
 *      joins it. (It already ran in promise callbacks after its first few lines, and the
 *      figures paint in the next animation frame; a partial update, `patch`, is not
 *      deferred.) While release_hold.js holds the paints after a slider's release, the
 *      recomputation waits for the hold to end: a drag's last preview often arrives after
 *      the release, and its glyph data (~3-8 ms) would never be painted;
 *   6. a marker glyph (scatter) finds the points near the frame without creating Bokeh
 *      models: BokehJS builds four `Range1d` models per marker renderer and paint to hold
 *      the widened frame's bounds (`widen`, `map`), ~0.7 ms per paint of the phase
 *      portrait and garbage for the collector. The bounds are the same numbers.
 *   7. a glyph renderer's visuals (colours, widths, alphas of its six glyph variants) are
 *      not recomputed when only its masked indices (the points near the frame) changed.
 *      BokehJS sets the masked indices at every paint and after every data update, and
 *      each set fires a recomputation of all six variants' visuals, inside the paint;
 *      the visuals are computed from all indices and the data, never from the mask, and
 *      a data update recomputes them itself.
 *   8. a plot's paint does not schedule another paint of that plot by the ranges it fits
 *      itself. A figure with data ranges (the phase portrait: `DataRange1d` with
 *      `match_aspect`, fitted in the browser to the frame it lays out) updates them at
 *      the start of its paint; each changed range asks its plot for a repaint, so every
 *      release of a slider painted the phase portrait a second time, one animation frame
 *      later, with nothing left to draw (the paint in progress already drew everything
 *      with the new ranges and cleared the request). BokehJS pauses the plot around the
 *      same update after a layout (`PlotView.after_layout`); the update inside the paint
 *      is paused now too. Whatever a range change sets off elsewhere (another plot on
 *      the same range, the server's copy of the range) is unchanged;
 *   9. the theory point labels (static/point_labels.js) are placed right after the fit,
 *      inside the paint, when the fit moved the ranges. They are placed on the frame the
 *      browser lays out, so moved ranges ask for a new placement; but a `CustomJS`
 *      callback runs in a microtask, after the paint, and labels that moved were drawn
 *      a frame later by a second paint of the phase portrait (and the frame before
 *      showed them placed for the old ranges). A figure
 *      whose model carries `_fie_place_labels` (set by point_labels.js) has it called
 *      after a fit that changed its ranges, while the plot is paused: the paint in
 *      progress draws the labels where they go.
 *
 * The patches were written for BokehJS 3.9 (VERSIONS): with another version none is
 * applied and the console says so. Each is applied only if the internal it replaces
 * exists. `window.__fie_paint` lists what applied. With `paint_shortcuts=off` in the
 * page's address none is applied (nor those of release_hold.js): the UI tests compare the
 * figures both ways, pixel for pixel. Patches 3 and 6 were measured at about 0.5 ms per
 * paint each (benchmarks/README.md); they are kept because they remove work that BokehJS
 * repeats for every plot on every paint, which grows with the page. A patch of
 * app.perf.PATCHES (`paint-shortcuts`): applied only where the server names it in this
 * script's address (off with EXPLORER_PERF_PATCHES=off).
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));
  const applied = (window.__fie_paint = []);
  //: BokehJS versions the patches were written for: [lowest, first one not covered).
  const VERSIONS = [[3, 9], [3, 10]];

  function inWindow(version) {
    const [major, minor] = String(version).split(".").map(Number);
    const at = major * 1000 + minor;
    return VERSIONS[0][0] * 1000 + VERSIONS[0][1] <= at && at < VERSIONS[1][0] * 1000 + VERSIONS[1][1];
  }

  function patch(B) {
    if (!inWindow(B.version)) {
      console.info(`bokeh_paint.js: written for BokehJS 3.9, found ${B.version}: not applied`);
      return;
    }
    let dom, visual, plot, glyph, marker = {};
    try {
      dom = B.require("core/dom");
      visual = B.require("core/visuals/visual");
      plot = B.require("models/plots/plot_canvas");
      glyph = B.require("models/renderers/glyph_renderer");
    } catch (err) {
      return;
    }
    try {
      marker = B.require("models/glyphs/marker");
    } catch (err) {
      // No marker module: patch 6 is skipped, the others apply.
    }
    let ranges = {};
    try {
      ranges = B.require("models/plots/range_manager");
    } catch (err) {
      // No range manager module: patch 8 is skipped, the others apply.
    }
    const sheet = dom.InlineStyleSheet && dom.InlineStyleSheet.prototype;
    if (sheet && typeof sheet._update === "function") {
      const update = sheet._update;
      sheet._update = function (css) {
        if (this.el.textContent !== css) update.call(this, css);
      };
      applied.push("stylesheet");
    }
    const props = visual.VisualProperties && visual.VisualProperties.prototype;
    if (props && typeof props._get_css_value === "function") {
      props._get_css_value = function () { return ""; };
      applied.push("css-variables");
    }
    const view = plot.PlotView && plot.PlotView.prototype;
    const desc = view && Object.getOwnPropertyDescriptor(view, "base_font_size");
    if (desc && typeof desc.get === "function") {
      Object.defineProperty(view, "base_font_size", {
        configurable: true,
        get() {
          if (this.__fie_font_size == null) this.__fie_font_size = desc.get.call(this);
          return this.__fie_font_size;
        },
      });
      applied.push("font-size");
    }
    const glyph_view = glyph.GlyphRendererView && glyph.GlyphRendererView.prototype;
    if (glyph_view && typeof glyph_view.update_position === "function") {
      const update_position = glyph_view.update_position;
      glyph_view.update_position = function () {
        if (this.__fie_positioned) return;
        this.__fie_positioned = true;
        update_position.call(this);
      };
      applied.push("glyph-position");
    }
    if (glyph_view && typeof glyph_view.update_data === "function") {
      const update_data = glyph_view.update_data;
      glyph_view.update_data = function (indices) {
        if (indices != null) return update_data.call(this, indices);
        if (this.__fie_update == null) {
          const hold = window.__fie_hold;
          const turn = hold != null && hold.active ? hold.released : Promise.resolve();
          this.__fie_update = turn.then(() => {
            this.__fie_update = null;
            return update_data.call(this);
          });
        }
        return this.__fie_update;
      };
      applied.push("one-data-update");
    }
    if (glyph_view && typeof glyph_view._update_masked_indices === "function" &&
        typeof glyph_view.set_visuals === "function") {
      const update_masked = glyph_view._update_masked_indices;
      const set_visuals = glyph_view.set_visuals;
      glyph_view._update_masked_indices = function () {
        this.__fie_masking = true;
        try {
          return update_masked.call(this);
        } finally {
          this.__fie_masking = false;
        }
      };
      glyph_view.set_visuals = function () {
        if (this.__fie_masking && this.__fie_visuals) return Promise.resolve();
        this.__fie_visuals = true;
        return set_visuals.call(this);
      };
      applied.push("mask-visuals");
    }
    const marker_view = marker.MarkerView && marker.MarkerView.prototype;
    if (marker_view && typeof marker_view._mask_data === "function" &&
        String(marker_view._mask_data).includes("widen(this.max_size)")) {
      // Range1d.widen: away from the middle by v at both ends (a reversed range too).
      const widen = ({start, end}, v) => start > end ? [start + v, end - v] : [start - v, end + v];
      marker_view._mask_data = function () {
        const {x_target, y_target} = this.renderer.plot_view.frame;
        const {xscale, yscale} = this.renderer;
        const [x0, x1] = widen(x_target, this.max_size);
        const [y0, y1] = widen(y_target, this.max_size);
        return this.index.indices({
          x0: xscale.invert(x0), x1: xscale.invert(x1),
          y0: yscale.invert(y0), y1: yscale.invert(y1),
        });
      };
      applied.push("marker-mask");
    }
    const manager = ranges.RangeManager && ranges.RangeManager.prototype;
    if (manager && typeof manager.update_dataranges === "function" && view &&
        typeof view.pause === "function" && typeof view.unpause === "function") {
      const update_dataranges = manager.update_dataranges;
      const bounds = (frame) => [...frame.x_ranges.values(), ...frame.y_ranges.values()]
        .map((r) => `${r.start} ${r.end}`).join(" ");
      manager.update_dataranges = function () {
        const plot_view = this.parent;
        if (!(plot_view instanceof plot.PlotView)) return update_dataranges.call(this);
        const before = bounds(plot_view.frame);
        // As PlotView.after_layout does: the caller paints (or is about to) with the
        // ranges fitted here; unpause(true) requests no paint of its own. The labels are
        // placed while paused too: the paint to come draws them.
        plot_view.pause();
        try {
          return update_dataranges.call(this);
        } finally {
          try {
            const place = plot_view.model._fie_place_labels;
            if (typeof place === "function" && bounds(plot_view.frame) !== before) place();
          } finally {
            plot_view.unpause(true);
          }
        }
      };
      applied.push("range-fit-paint");
    }
    if (applied.length) (window.__fie_patches = window.__fie_patches || []).push("paint-shortcuts");
  }

  if (new URLSearchParams(window.location.search).get("paint_shortcuts") === "off") return;
  if (!APPLY.has("paint-shortcuts")) {
    console.info("bokeh_paint.js: paint-shortcuts not applied (app.perf)");
    return;
  }

  (function wait() {
    const B = window.Bokeh;
    if (B && typeof B.require === "function") patch(B);
    else setTimeout(wait, 5);
  })();
})();
