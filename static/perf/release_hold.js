/* No repaint of a stale preview after a slider's release, and no restyle of the whole
 * page when a slider is pressed or released (served as /assets/perf/release_hold.js).
 *
 * While a slider is dragged the server sends cheap previews; the one for the drag's last
 * value is often still on its way when the slider is released, and painting it (~30 ms of
 * figure repaints on this page) delays the full solution right behind it. From the release
 * of a slider's handle until the full solution arrives (the hidden model with the CSS class
 * `fie-solution-arrived` changes its text with every full update, see
 * app.explorer.Explorer._draw) the figures' paints are
 * deferred; then each deferred figure paints once, with the full solution. Past
 * HOLD_MS (a slow numerical solve, an input the server rejects) the figures paint what
 * they have. `window.__fie_hold.released` settles when the hold ends: bokeh_paint.js
 * waits for it before it recomputes glyph data during a hold, so a stale preview's data
 * cost no work in the browser while the full solution is on its way.
 *
 * When a slider's handle is pressed and released, BokehJS's slider view writes
 * `user-select` into the page body's inline style (to stop text selection while dragging)
 * and noUiSlider writes the handle's cursor there. Any write to the body's inline style
 * makes the browser recompute the style of every element of the page: about 14 ms here,
 * right when the release has to be sent and its answer drawn. These three properties of
 * the body's inline style are therefore made inert; noUiSlider already blocks text
 * selection during a drag (a `selectstart` listener) and the handle keeps its own cursor.
 *
 * Every release of a slider reaches the server. BokehJS sends the released value
 * (`value_throttled`) only when it differs from the last one released; a value set on
 * the server in between (a typed number, a scene, a permalink, a tap on the map) does not
 * update it in the browser, so releasing the slider where it had last been released sent
 * nothing: the server kept the typed value while the slider showed another, under the
 * drag's draft picture. The release is now sent even when it equals the last one (and
 * app.perf.slider.keep_released_value keeps the server's released value in step with
 * what the slider shows, so that such a release is a change there).
 *
 * Written for BokehJS 3.9: with another version, or with `paint_shortcuts=off` in the page's
 * address, nothing here is applied (the console says why) and the page paints every
 * update as it comes, restyles the page on a slider's press and release, and drops a
 * release at the value last released (see app/perf/slider.py). A patch of
 * app.perf.PATCHES (`release-hold`): applied only where the server names it in this
 * script's address (off with EXPLORER_PERF_PATCHES=off).
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));
  const HOLD_MS = 400;
  const hold = (window.__fie_hold = {
    active: false, held: new Set(), timer: null, released: Promise.resolve(), release: null,
  });
  let dragging = false;

  function resume() {
    clearTimeout(hold.timer);
    hold.active = false;
    if (hold.release !== null) {
      hold.release();
      hold.release = null;
    }
    const views = [...hold.held];
    hold.held.clear();
    for (const view of views) view.request_paint();
  }

  function install(B) {
    let plot;
    try {
      plot = B.require("models/plots/plot_canvas");
    } catch (err) {
      return;
    }
    const view = plot.PlotView && plot.PlotView.prototype;
    if (!view || typeof view.paint !== "function") return;
    const paint = view.paint;
    view.paint = function () {
      if (hold.active) {
        hold.held.add(this);
        return;
      }
      paint.call(this);
    };
    // A paint request is held before BokehJS's 60 fps throttle sees it: a held paint that
    // had gone through the throttle counted as a paint there, so a figure whose preview
    // arrived within 17 ms before the full solution was repainted a frame (or two) after
    // the others (5 releases in 40 of scene 7c).
    const schedule = view.schedule_paint;
    if (typeof schedule === "function") {
      view.schedule_paint = function () {
        if (hold.active) {
          hold.held.add(this);
          return;
        }
        schedule.call(this);
      };
    }
    // Widgets live in shadow roots: look along the composed path, not at ev.target.
    document.addEventListener("pointerdown", (ev) => {
      dragging = ev.composedPath().some(
        (el) => el instanceof Element && el.classList.contains("noUi-target"));
    }, true);
    document.addEventListener("pointerup", () => {
      if (!dragging) return;
      dragging = false;
      hold.active = true;
      if (hold.release === null) {
        hold.released = new Promise((resolve) => { hold.release = resolve; });
      }
      clearTimeout(hold.timer);
      hold.timer = setTimeout(resume, HOLD_MS);
    }, true);
    (function watch(tries) {
      const doc = B.documents && B.documents[0];
      const arrived = doc && [...doc.all_models].find(
        (m) => Array.isArray(m.css_classes) && m.css_classes.includes("fie-solution-arrived"));
      if (arrived == null || arrived.properties.text == null) {
        // Not there yet (the page is loading); a page without it (after 10 s) holds
        // nothing longer than HOLD_MS.
        if (tries > 0) setTimeout(() => watch(tries - 1), 50);
        return;
      }
      arrived.properties.text.change.connect(() => { if (hold.active) resume(); });
    })(200);
  }

  function inertBodyStyle() {
    if (document.body == null) {
      document.addEventListener("DOMContentLoaded", inertBodyStyle, {once: true});
      return;
    }
    const style = document.body.style;
    const inert = {configurable: true, get: () => "", set: () => {}};
    try {
      Object.defineProperty(style, "cursor", inert);
      Object.defineProperty(style, "userSelect", inert);
      Object.defineProperty(style, "webkitUserSelect", inert);
    } catch (err) {
      // An engine that refuses the properties keeps the sliders' own behaviour.
    }
  }

  function sendEveryRelease(B, tries) {
    let sliders;
    try {
      sliders = B.require("models/widgets/sliders/abstract_slider");
    } catch (err) {
      // The widgets bundle registers after BokehJS: try again for a while.
      if (tries > 0) setTimeout(() => sendEveryRelease(B, tries - 1), 20);
      return;
    }
    const view = sliders.AbstractSliderView && sliders.AbstractSliderView.prototype;
    if (!view || typeof view._change !== "function" ||
        !String(view._change).includes("value_throttled")) {
      return;
    }
    view._change = function (values) {
      // What BokehJS does (abstract_slider.ts), without skipping an unchanged value.
      const value = this._calc_from(values);
      this.model.setv({value, value_throttled: value}, {check_eq: false});
    };
    window.__fie_release_sent = true;
  }

  if (new URLSearchParams(window.location.search).get("paint_shortcuts") === "off") return;
  if (!APPLY.has("release-hold")) {
    console.info("release_hold.js: release-hold not applied (app.perf)");
    return;
  }

  (function wait() {
    const B = window.Bokeh;
    if (B && typeof B.require === "function") {
      const [major, minor] = String(B.version).split(".").map(Number);
      if (major !== 3 || minor !== 9) {
        console.info(`release_hold.js: written for BokehJS 3.9, found ${B.version}: not applied`);
        return;
      }
      inertBodyStyle();
      install(B);
      sendEveryRelease(B, 500);
      (window.__fie_patches = window.__fie_patches || []).push("release-hold");
    } else {
      setTimeout(wait, 5);
    }
  })();
})();
